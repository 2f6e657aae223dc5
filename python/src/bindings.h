// The pieces of the _core module, one function per bindings file, called by module.cpp.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/render/image.h"

namespace rayaccel::python {

namespace py = pybind11;

/// A missing scene file (becomes FileNotFoundError).
struct FileNotFound : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What render() draws: a pinhole camera, an image size and the renderer's settings (see rayaccel/render/renderer.h).
struct RenderRequest {
  std::array<float, 3> eye{}, at{}, up{};
  float fov = 45.0f;
  int width = 0, height = 0;
  std::string mode = "normals";
  int ao_samples = 8;
  float ao_distance = 0.1f;
  std::uint64_t seed = 1;
};
/// Renders through the library's renderer; call without the GIL. Throws ValueError for a bad size or mode.
Image render_image(const Accelerator& accel, const Scene& scene, const RenderRequest& request);
/// (height, width, 3) uint8 copy of an image.
py::array_t<std::uint8_t> image_array(const Image& image);

void bind_scene(py::module_& m);        // scene_bindings.cpp
void bind_accelerator(py::module_& m);  // accel_bindings.cpp
void bind_render(py::module_& m);       // render_bindings.cpp
void bind_double(py::module_& m);       // double_bindings.cpp
void bind_instances(py::module_& m);    // instance_bindings.cpp
void bind_saved(py::module_& m);        // saved_bindings.cpp

}  // namespace rayaccel::python
