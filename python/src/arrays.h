// Checks and conversions between numpy arrays and the library's records (Ray, Hit, TraversalStats): every shape,
// dtype and value problem becomes a Python TypeError or ValueError that names the argument, never a crash.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <span>
#include <string>

#include "rayaccel/core/ray.h"

namespace rayaccel::python {

namespace py = pybind11;

/// The exception types the bindings raise besides rayaccel::Error (which becomes ValueError).
struct TypeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct ValueError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A C-contiguous float32 array (numpy converts float64 to it when asked to).
using FloatRows = py::array_t<float, py::array::c_style | py::array::forcecast>;

/// "float32", "int64", ... for messages.
std::string dtype_name(const py::array& array);
/// "(3, 4)" for messages.
std::string shape_text(const py::array& array);

/// An (N, columns) float32 C-contiguous array: `object` itself when it already is one (no copy), else a float32
/// copy of a float32/float64 array. Throws TypeError for other dtypes or a non-array, ValueError for another shape.
FloatRows float_rows(const py::handle& object, py::ssize_t columns, const char* what);

/// Rays of an (N, 8) float32 C-contiguous array in the .rays layout, viewed in place.
std::span<const Ray> ray_view(const FloatRows& rays);
/// Throws ValueError naming the first ray (and field) with a non-finite origin or direction, a zero direction or a
/// NaN t bound. Parallel; call without the GIL.
void check_rays(std::span<const Ray> rays);

}  // namespace rayaccel::python
