// Array checks and conversions for the bindings (see arrays.h).
#include "arrays.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rayaccel::python {

std::string dtype_name(const py::array& array) { return py::str(array.dtype()).cast<std::string>(); }

std::string shape_text(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t i = 0; i < array.ndim(); ++i) {
    if (i > 0) text += ", ";
    text += std::to_string(array.shape(i));
  }
  return text + (array.ndim() == 1 ? ",)" : ")");
}

FloatRows float_rows(const py::handle& object, py::ssize_t columns, const char* what) {
  if (!py::isinstance<py::array>(object)) {
    throw TypeError(std::string(what) + " must be a numpy array, not " +
                    py::str(py::type::of(object).attr("__name__")).cast<std::string>());
  }
  const auto array = py::reinterpret_borrow<py::array>(object);
  if (!array.dtype().equal(py::dtype::of<float>()) && !array.dtype().equal(py::dtype::of<double>())) {
    throw TypeError(std::string(what) + " must be float32 or float64, not " + dtype_name(array));
  }
  if (array.ndim() != 2 || array.shape(1) != columns) {
    throw ValueError(std::string(what) + " must have shape (N, " + std::to_string(columns) + "), not " +
                     shape_text(array));
  }
  // ensure() keeps the same object when dtype and layout already match, else converts (float64 is rounded).
  auto rows = FloatRows::ensure(array);
  if (!rows) throw py::error_already_set();
  return rows;
}

std::span<const Ray> ray_view(const FloatRows& rays) {
  return {reinterpret_cast<const Ray*>(rays.data()), static_cast<std::size_t>(rays.shape(0))};
}

namespace {

/// Empty when the ray is acceptable, else what is wrong with it.
const char* ray_problem(const Ray& r) {
  if (!is_finite(r.origin)) return "a NaN or infinite origin";
  if (!is_finite(r.direction)) return "a NaN or infinite direction";
  if (r.direction.x == 0.0f && r.direction.y == 0.0f && r.direction.z == 0.0f) return "a zero direction";
  if (std::isnan(r.t_min)) return "a NaN t_min";
  if (std::isnan(r.t_max)) return "a NaN t_max";
  return nullptr;
}

/// ray_problem(r) == nullptr, without branches, so a block of rays is checked at memory speed: each of the eight
/// floats must be finite, except t_min and t_max, which need only not be NaN.
bool ray_is_acceptable(const float* f) {
  constexpr float kMax = std::numeric_limits<float>::max();
  bool ok = true;
  for (int k = 0; k < 8; ++k) {
    const bool t_bound = k == 3 || k == 7;
    ok &= (std::fabs(f[k]) <= kMax) | (t_bound & (f[k] == f[k]));
  }
  return ok & ((f[4] != 0.0f) | (f[5] != 0.0f) | (f[6] != 0.0f));
}

}  // namespace

void check_rays(std::span<const Ray> rays) {
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  const float* floats = reinterpret_cast<const float*>(rays.data());
  const std::size_t first_bad = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, rays.size(), 1 << 14), kNone,
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t found) {
        if (found < range.begin()) return found;
        bool all_ok = true;
        for (std::size_t i = range.begin(); i < range.end(); ++i) all_ok &= ray_is_acceptable(floats + 8 * i);
        if (all_ok) return found;
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          if (ray_problem(rays[i]) != nullptr) return std::min(found, i);
        }
        return found;
      },
      [](std::size_t a, std::size_t b) { return std::min(a, b); });
  if (first_bad != kNone) {
    throw ValueError("ray " + std::to_string(first_bad) + " has " + ray_problem(rays[first_bad]) +
                     " (pass check=False to trace such rays as misses, as the C++ library does)");
  }
}

}  // namespace rayaccel::python
