// Python's query controls (skip, skip_geometry, mask, geometry_mask, enabled) as numpy arrays behind a QueryContext:
// checked against the rays and the scene once, then sliced to each block of rays the batch traces.
#pragma once

#include <pybind11/numpy.h>

#include <cstddef>
#include <cstdint>
#include <memory>

#include "rayaccel/core/query_context.h"
#include "rayaccel/scene/geometry_table.h"
#include "rayaccel/scene/scene.h"

namespace rayaccel::python {

namespace py = pybind11;

/// A flat C-contiguous numpy array of T (what the controls are converted to once).
template <class T>
using FlatArray = py::array_t<T, py::array::c_style | py::array::forcecast>;

class ContextArrays {
 public:
  /// Reads the controls (each None or an array: uint32 per ray for skip, skip_geometry and mask; uint32 per geometry
  /// of `geometries` for geometry_mask, one entry without a table; bool or uint8 per primitive for enabled). Throws
  /// ValueError naming the argument for a size that does not match the rays, the geometries or the scene.
  ContextArrays(const py::object& skip, const py::object& skip_geometry, const py::object& mask,
                const py::object& geometry_mask, const std::shared_ptr<GeometryTable>& geometries,
                const py::object& enabled, std::size_t ray_count, const Scene& scene);

  /// The context of rays [begin, end) (per-ray arrays sliced; the others whole).
  QueryContext slice(std::size_t begin, std::size_t end) const;

 private:
  FlatArray<std::uint32_t> skip_, skip_geometry_, mask_, geometry_mask_;
  FlatArray<std::uint8_t> enabled_;
  std::shared_ptr<GeometryTable> geometries_;
  QueryContext context_;
};

}  // namespace rayaccel::python
