// Checks and conversions between numpy arrays and the library's records (Ray, Hit, TraversalStats): every shape,
// dtype and value problem becomes a Python TypeError or ValueError that names the argument, never a crash.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

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

/// A C-contiguous float32 (or float64) array (numpy converts the other float type to it when asked to).
template <class Real>
using RealRows = py::array_t<Real, py::array::c_style | py::array::forcecast>;
using FloatRows = RealRows<float>;

/// "float32", "int64", ... for messages.
std::string dtype_name(const py::array& array);
/// "(3, 4)" for messages.
std::string shape_text(const py::array& array);

/// An (N, columns) C-contiguous array of Real (float or double): `object` itself when it already is one (no copy),
/// else a Real copy of a float32/float64 array. Throws TypeError for other dtypes or a non-array, ValueError for
/// another shape.
template <class Real>
RealRows<Real> real_rows(const py::handle& object, py::ssize_t columns, const char* what);
inline FloatRows float_rows(const py::handle& object, py::ssize_t columns, const char* what) {
  return real_rows<float>(object, columns, what);
}

/// (M, 3) int32/uint32/int64 triangles as the library's index triples; TypeError for another dtype or a non-array,
/// ValueError naming the shape, or the entry and its value for an index outside [0, vertex_count).
std::vector<std::array<std::uint32_t, 3>> read_triangles(const py::handle& object, std::size_t vertex_count);

/// Rays of an (N, 8) float32 C-contiguous array in the .rays layout, viewed in place.
std::span<const Ray> ray_view(const FloatRows& rays);
/// False when a ray has a non-finite origin or direction, a zero direction or a NaN t bound (rays the library would
/// trace as misses). No branch per ray: a block is checked at the speed of reading it.
bool rays_acceptable(std::span<const Ray> rays);
/// Throws ValueError naming the first such ray and what is wrong with it. Parallel; call without the GIL.
void check_rays(std::span<const Ray> rays);
/// Runs trace(begin, end) over [0, rays.size()): with `check`, in parallel blocks of kCheckBlock rays (a multiple of
/// the packet size), each checked just before it is traced, while it is in cache, and check_rays() when one fails
/// (the other blocks' results are then unspecified); without, as one call. Blocks run in the caller's
/// floating-point environment, as the library's batches do. Call without the GIL.
void trace_checked(std::span<const Ray> rays, bool check, const std::function<void(std::size_t, std::size_t)>& trace);
inline constexpr std::size_t kCheckBlock = 4096;

}  // namespace rayaccel::python
