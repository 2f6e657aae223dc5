// Array checks and conversions for the bindings (see arrays.h).
#include "arrays.h"

#include <emmintrin.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
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

template <class Real>
RealRows<Real> real_rows(const py::handle& object, py::ssize_t columns, const char* what) {
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
  // ensure() keeps the same object when dtype and layout already match, else converts (float64 to float32 rounded).
  auto rows = RealRows<Real>::ensure(array);
  if (!rows) throw py::error_already_set();
  return rows;
}

template RealRows<float> real_rows<float>(const py::handle&, py::ssize_t, const char*);
template RealRows<double> real_rows<double>(const py::handle&, py::ssize_t, const char*);

std::span<const Ray> ray_view(const FloatRows& rays) {
  return {reinterpret_cast<const Ray*>(rays.data()), static_cast<std::size_t>(rays.shape(0))};
}

namespace {

template <class Index>
void copy_triangles(const py::array& array, std::size_t vertex_count,
                    std::vector<std::array<std::uint32_t, 3>>& out) {
  const auto rows = py::array_t<Index, py::array::c_style>::ensure(array);
  if (!rows) throw py::error_already_set();
  const Index* data = rows.data();
  for (std::size_t i = 0; i < out.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const Index index = data[3 * i + k];
      if (index < 0 || static_cast<std::uint64_t>(index) >= vertex_count) {
        throw ValueError("triangles[" + std::to_string(i) + ", " + std::to_string(k) + "] = " +
                         std::to_string(index) + " is out of range: there are " + std::to_string(vertex_count) +
                         " vertices");
      }
      out[i][k] = static_cast<std::uint32_t>(index);
    }
  }
}

}  // namespace

std::vector<std::array<std::uint32_t, 3>> read_triangles(const py::handle& object, std::size_t vertex_count) {
  if (!py::isinstance<py::array>(object)) throw TypeError("triangles must be a numpy array");
  const auto array = py::reinterpret_borrow<py::array>(object);
  if (array.ndim() != 2 || array.shape(1) != 3) {
    throw ValueError("triangles must have shape (M, 3), not " + shape_text(array));
  }
  std::vector<std::array<std::uint32_t, 3>> triangles(static_cast<std::size_t>(array.shape(0)));
  if (array.dtype().equal(py::dtype::of<std::int32_t>())) {
    copy_triangles<std::int32_t>(array, vertex_count, triangles);
  } else if (array.dtype().equal(py::dtype::of<std::uint32_t>())) {
    copy_triangles<std::uint32_t>(array, vertex_count, triangles);
  } else if (array.dtype().equal(py::dtype::of<std::int64_t>())) {
    copy_triangles<std::int64_t>(array, vertex_count, triangles);
  } else {
    throw TypeError("triangles must be int32, uint32 or int64, not " + dtype_name(array));
  }
  return triangles;
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

}  // namespace

bool rays_acceptable(std::span<const Ray> rays) {
  // ray_problem(r) == nullptr for every ray, in SSE2 without a branch per ray: |x| <= FLT_MAX for the six origin
  // and direction components (false for NaN and infinities), |t| <= inf for t_min and t_max (false only for NaN),
  // and some direction component != 0.
  constexpr float kMax = std::numeric_limits<float>::max();
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 limit = _mm_setr_ps(kMax, kMax, kMax, kInf);  // ox oy oz tmin, and dx dy dz tmax
  const __m128 zero = _mm_setzero_ps();
  __m128 finite = _mm_cmpeq_ps(zero, zero);
  int direction_nonzero = 1;
  const float* f = reinterpret_cast<const float*>(rays.data());
  for (std::size_t i = 0; i < rays.size(); ++i, f += 8) {
    const __m128 origin_tmin = _mm_loadu_ps(f);
    const __m128 direction_tmax = _mm_loadu_ps(f + 4);
    finite = _mm_and_ps(finite, _mm_cmple_ps(_mm_and_ps(origin_tmin, abs_mask), limit));
    finite = _mm_and_ps(finite, _mm_cmple_ps(_mm_and_ps(direction_tmax, abs_mask), limit));
    direction_nonzero &= (_mm_movemask_ps(_mm_cmpneq_ps(direction_tmax, zero)) & 7) != 0;
  }
  return _mm_movemask_ps(finite) == 0xF && direction_nonzero != 0;
}

void check_rays(std::span<const Ray> rays) {
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  const std::size_t first_bad = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, rays.size(), 1 << 14), kNone,
      [&](const tbb::blocked_range<std::size_t>& range, std::size_t found) {
        if (found < range.begin() || rays_acceptable(rays.subspan(range.begin(), range.size()))) return found;
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

void trace_checked(std::span<const Ray> rays, bool check, const std::function<void(std::size_t, std::size_t)>& trace) {
  if (!check) {
    trace(0, rays.size());
    return;
  }
  std::atomic<bool> failed{false};
  tbb::task_group_context context(tbb::task_group_context::bound,
                                  tbb::task_group_context::default_traits | tbb::task_group_context::fp_settings);
  const std::size_t blocks = (rays.size() + kCheckBlock - 1) / kCheckBlock;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, blocks, 1),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t b = range.begin(); b < range.end() && !failed.load(std::memory_order_relaxed); ++b) {
          const std::size_t begin = b * kCheckBlock, end = std::min(begin + kCheckBlock, rays.size());
          if (!rays_acceptable(rays.subspan(begin, end - begin))) {
            failed = true;
            return;
          }
          trace(begin, end);
        }
      },
      context);
  if (failed) check_rays(rays);
}

}  // namespace rayaccel::python
