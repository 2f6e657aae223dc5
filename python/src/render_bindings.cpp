// Cameras and images for Python: the CLI's pinhole camera as ray arrays, its default camera for a scene, the
// secondary rays of the bench (diffuse, shadow), the renderer (normals, ambient occlusion, heat map) and the
// heat-map colour ramp, all returning numpy arrays.
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <optional>
#include <filesystem>
#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/render/colormap.h"
#include "rayaccel/render/image_limits.h"
#include "rayaccel/render/renderer.h"
#include "rayaccel/render/workloads.h"

namespace rayaccel::python {

namespace {

Vec3 to_vec3(const std::array<float, 3>& v) { return {v[0], v[1], v[2]}; }
std::array<float, 3> from_vec3(const Vec3& v) { return {v.x, v.y, v.z}; }

Camera make_camera(const std::array<float, 3>& eye, const std::array<float, 3>& at, const std::array<float, 3>& up,
                   float fov) {
  Camera camera;
  camera.eye = to_vec3(eye);
  camera.at = to_vec3(at);
  camera.up = to_vec3(up);
  camera.fov_degrees = fov;
  return camera;
}

void check_size(int width, int height) {
  if (width <= 0 || height <= 0) {
    throw ValueError("image size must be positive, not " + std::to_string(width) + " x " + std::to_string(height));
  }
  if (width > kMaxImageSide || height > kMaxImageSide) {
    throw ValueError("image size " + std::to_string(width) + " x " + std::to_string(height) + " is too large: " +
                     "width and height must be at most " + std::to_string(kMaxImageSide));
  }
}

py::array_t<float> ray_array(const std::vector<Ray>& rays, std::vector<py::ssize_t> shape) {
  shape.push_back(8);
  py::array_t<float> out(shape);
  std::memcpy(out.mutable_data(), rays.data(), rays.size() * sizeof(Ray));
  return out;
}

py::array_t<float> camera_rays(const std::array<float, 3>& eye, const std::array<float, 3>& at,
                               const std::array<float, 3>& up, float fov, int width, int height) {
  check_size(width, height);
  const std::vector<Ray> rays = primary_rays(make_camera(eye, at, up, fov), width, height);
  return ray_array(rays, {height, width});
}

/// The CLI's default camera: the MANIFEST camera of a shared scene file, else one framing the scene's bounds.
py::tuple default_camera(const std::string& spec, const Scene& scene) {
  Camera camera;
  std::optional<Camera> standard;
  if (spec.rfind("builtin:", 0) != 0 && !spec.empty()) standard = standard_camera(std::filesystem::path(spec));
  if (standard) {
    camera = *standard;
  } else {
    camera = Camera::framing(scene.bounds().is_empty() ? AABB(Vec3{-1.0f}, Vec3{1.0f}) : scene.bounds());
  }
  return py::make_tuple(from_vec3(camera.eye), from_vec3(camera.at), from_vec3(camera.up), camera.fov_degrees);
}

/// Secondary rays of the bench from primary rays and their hit records (one per hit, in hit order).
py::array_t<float> secondary_rays(const Scene& scene, const py::handle& rays_object,
                                  const py::array_t<std::uint8_t, py::array::c_style>& records, const std::string& kind,
                                  float max_distance, std::uint64_t seed) {
  const auto rays_array = float_rows(rays_object, 8, "rays");
  const std::span<const Ray> rays = ray_view(rays_array);
  if (records.ndim() != 2 || records.shape(1) != 16 || static_cast<std::size_t>(records.shape(0)) != rays.size()) {
    throw ValueError("hit records must have shape (N, 16) with N = the number of rays");
  }
  const std::span<const Hit> hits(reinterpret_cast<const Hit*>(records.data()), rays.size());
  for (const Hit& h : hits) {
    if (h.found() && h.prim_id >= scene.primitive_count()) throw ValueError("hit records name a primitive not in the scene");
  }
  std::vector<Ray> out;
  {
    py::gil_scoped_release release;
    if (kind == "diffuse") {
      out = diffuse_rays(scene, rays, hits, seed);
    } else if (kind == "shadow") {
      out = shadow_rays(scene, rays, hits, max_distance, seed);
    } else {
      throw ValueError("unknown secondary ray kind '" + kind + "' (diffuse, shadow)");
    }
  }
  return ray_array(out, {static_cast<py::ssize_t>(out.size())});
}

/// heat_colour() of each value of a float array in [0, 1]: shape (..., 3) uint8.
py::array_t<std::uint8_t> heat_colours(const py::array_t<float, py::array::c_style | py::array::forcecast>& t) {
  std::vector<py::ssize_t> shape(t.shape(), t.shape() + t.ndim());
  shape.push_back(3);
  py::array_t<std::uint8_t> out(shape);
  std::uint8_t* o = out.mutable_data();
  for (py::ssize_t i = 0; i < t.size(); ++i) {
    const Rgb c = heat_colour(t.data()[i]);
    o[3 * i] = c.r;
    o[3 * i + 1] = c.g;
    o[3 * i + 2] = c.b;
  }
  return out;
}

}  // namespace

Image render_image(const Accelerator& accel, const Scene& scene, const RenderRequest& request) {
  check_size(request.width, request.height);
  RenderSettings settings;
  settings.width = request.width;
  settings.height = request.height;
  settings.mode = parse_shading_mode(request.mode);
  settings.ao_samples = request.ao_samples;
  settings.ao_distance_fraction = request.ao_distance;
  settings.seed = request.seed;
  return render(accel, scene, make_camera(request.eye, request.at, request.up, request.fov), settings).image;
}

py::array_t<std::uint8_t> image_array(const Image& image) {
  py::array_t<std::uint8_t> out({static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width),
                                 py::ssize_t{3}});
  std::memcpy(out.mutable_data(), image.rgb.data(), image.rgb.size());
  return out;
}

void bind_render(py::module_& m) {
  m.def("_camera_rays", &camera_rays, py::arg("eye"), py::arg("at"), py::arg("up"), py::arg("fov"), py::arg("width"),
        py::arg("height"));
  m.def("_default_camera", &default_camera, py::arg("spec"), py::arg("scene"));
  m.def("_secondary_rays", &secondary_rays, py::arg("scene"), py::arg("rays"), py::arg("records"), py::arg("kind"),
        py::arg("max_distance"), py::arg("seed"));
  m.def("_heat_colours", &heat_colours, py::arg("t"));
  m.def("packet_tile_order", [](int width, int height) {
    check_size(width, height);
    const std::vector<std::size_t> order = packet_tile_order(width, height);
    py::array_t<std::int64_t> out(static_cast<py::ssize_t>(order.size()));
    std::copy(order.begin(), order.end(), out.mutable_data());
    return out;
  }, py::arg("width"), py::arg("height"),
        "Indices into a width x height image's rays (row-major) such that each run of eight is a 4 x 2 pixel tile: "
        "the order in which intersect(packets=True) traces camera rays fastest.");
}

}  // namespace rayaccel::python
