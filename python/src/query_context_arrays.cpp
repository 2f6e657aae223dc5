// ContextArrays: numpy query controls checked and held for a batch (see query_context_arrays.h).
#include "query_context_arrays.h"

#include <string>

#include "arrays.h"

namespace rayaccel::python {

namespace {
/// `object` as a flat C-contiguous array of T (integers cast), or an empty one for None; ValueError naming `what`
/// unless it has `size` entries.
template <class T>
FlatArray<T> flat_array(const py::object& object, std::size_t size, const char* what, const char* per) {
  if (object.is_none()) return FlatArray<T>(0);
  FlatArray<T> a = FlatArray<T>::ensure(object);
  if (!a) throw TypeError(std::string(what) + " must be an array of integers");
  if (static_cast<std::size_t>(a.size()) != size) {
    throw ValueError(std::string(what) + " has " + std::to_string(a.size()) + " entries, expected " +
                     std::to_string(size) + " (one per " + per + ")");
  }
  return a;
}
template <class T>
std::span<const T> view(const FlatArray<T>& a) {
  return {a.data(), static_cast<std::size_t>(a.size())};
}
}  // namespace

ContextArrays::ContextArrays(const py::object& skip, const py::object& skip_geometry, const py::object& mask,
                             const py::object& geometry_mask, const std::shared_ptr<GeometryTable>& geometries,
                             const py::object& enabled, std::size_t ray_count, const Scene& scene)
    : geometries_(geometries) {
  if (geometries_ && geometries_->primitive_count() != scene.primitive_count()) {
    throw ValueError("geometries has " + std::to_string(geometries_->primitive_count()) +
                     " primitives but the scene " + std::to_string(scene.primitive_count()) +
                     " (the GeometryTable of another scene?)");
  }
  const std::size_t geometry_count = geometries_ ? geometries_->geometry_count() : 1;
  skip_ = flat_array<std::uint32_t>(skip, ray_count, "skip", "ray");
  skip_geometry_ = flat_array<std::uint32_t>(skip_geometry, ray_count, "skip_geometry", "ray");
  mask_ = flat_array<std::uint32_t>(mask, ray_count, "mask", "ray");
  geometry_mask_ = flat_array<std::uint32_t>(geometry_mask, geometry_count, "geometry_mask",
                                             geometries_ ? "geometry" : "geometry; one without geometries");
  enabled_ = flat_array<std::uint8_t>(enabled, scene.primitive_count(), "enabled", "primitive of the scene");
  context_.skip_primitive = view(skip_);
  context_.skip_geometry = view(skip_geometry_);
  context_.ray_mask = view(mask_);
  context_.geometry_mask = view(geometry_mask_);
  context_.primitive_enabled = view(enabled_);
  if (geometries_) context_.geometry_starts = geometries_->starts();
}

QueryContext ContextArrays::slice(std::size_t begin, std::size_t end) const {
  QueryContext c = context_;
  auto cut = [&](std::span<const std::uint32_t>& s) {
    if (!s.empty()) s = s.subspan(begin, end - begin);
  };
  cut(c.skip_primitive);
  cut(c.skip_geometry);
  cut(c.ray_mask);
  return c;
}

}  // namespace rayaccel::python
