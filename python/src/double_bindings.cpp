// The double-precision path for Python: mesh_double() and load_double() make a DoubleScene, build_double() a
// double structure queried with (N, 8) float64 rays (.rays64) into (N, 32) uint8 records (.hits64), the CLI's
// files byte for byte.
#include <pybind11/stl.h>

#include <array>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "locked_structure.h"
#include "rayaccel/core/ray_d.h"
#include "rayaccel/double/double_accelerator.h"
#include "rayaccel/double/double_scene.h"
#include "rayaccel/double/double_scene_load.h"

namespace rayaccel::python {

namespace {

// The numpy records are the library's own: RayD is the .rays64 record, HitD the .hits64 one (its padding word is
// zeroed after tracing).
static_assert(sizeof(RayD) == 64 && offsetof(RayD, t_min) == 24 && offsetof(RayD, t_max) == 56);
static_assert(sizeof(HitD) == 32 && offsetof(HitD, prim_id) == 8 && offsetof(HitD, u) == 16 && offsetof(HitD, v) == 24);
constexpr std::size_t kPaddingOffset = offsetof(HitD, prim_id) + sizeof(std::uint32_t);

/// A DoubleScene from (N, 3) float64 vertices and (M, 3) int32/uint32/int64 triangles (copied once); DoubleScene
/// checks the double domain and names the vertex at fault.
std::shared_ptr<DoubleScene> mesh_double(const py::handle& vertices, const py::handle& triangles) {
  if (!py::isinstance<py::array>(vertices)) throw TypeError("vertices must be a numpy array");
  const auto array = py::reinterpret_borrow<py::array>(vertices);
  if (!array.dtype().equal(py::dtype::of<double>())) {
    throw TypeError("vertices must be float64 (the double path keeps every bit; float32 ones have lost them "
                    "already), not " + dtype_name(array));
  }
  if (array.ndim() != 2 || array.shape(1) != 3) {
    throw ValueError("vertices must have shape (N, 3), not " + shape_text(array));
  }
  const auto rows = py::array_t<double, py::array::c_style>::ensure(array);  // no copy when already C-contiguous
  if (!rows) throw py::error_already_set();
  const auto count = static_cast<std::size_t>(rows.shape(0));
  if (count > std::numeric_limits<std::uint32_t>::max()) throw ValueError("too many vertices");
  TriangleMeshD mesh;
  mesh.vertices.resize(count);
  const double* xyz = rows.data();
  for (std::size_t i = 0; i < count; ++i) mesh.vertices[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  mesh.triangles = read_triangles(triangles, count);
  py::gil_scoped_release release;
  return std::make_shared<DoubleScene>(std::move(mesh));
}

/// Nothing when the ray is acceptable, else what is wrong with it (such rays are void: traced as misses).
const char* ray_problem(const RayD& r) {
  if (!in_double_domain(r.origin)) {
    return "an origin component outside the double domain (NaN, infinite, or nonzero with magnitude outside "
           "[2^-64, 2^64])";
  }
  if (!in_double_domain(r.direction)) {
    return "a direction component outside the double domain (NaN, infinite, or nonzero with magnitude outside "
           "[2^-64, 2^64])";
  }
  if (r.direction.x == 0.0 && r.direction.y == 0.0 && r.direction.z == 0.0) return "a zero direction";
  if (std::isnan(r.t_min)) return "a NaN t_min";
  if (std::isnan(r.t_max)) return "a NaN t_max";
  return nullptr;
}

/// rayaccel.load_double(): a mesh file (PLY coordinates as read, every bit of `property double` kept; other formats
/// through the float loader) or builtin spec, moved by `offset`.
std::shared_ptr<DoubleScene> load_double(const py::handle& spec_object, const std::array<double, 3>& offset) {
  const std::string spec = py::str(py::module_::import("os").attr("fspath")(spec_object));
  std::error_code ec;
  if (spec.rfind("builtin:", 0) != 0 && !std::filesystem::is_regular_file(spec, ec)) {
    throw FileNotFound("scene file '" + spec + "' does not exist (or is not a file)");
  }
  py::gil_scoped_release release;
  return std::make_shared<DoubleScene>(load_mesh_double(spec, {offset[0], offset[1], offset[2]}).mesh);
}

}  // namespace

void trace_checked(std::span<const RayD> rays, bool check, const std::function<void(std::size_t, std::size_t)>& trace) {
  if (check) {
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if (const char* problem = ray_problem(rays[i])) {
        throw ValueError("ray " + std::to_string(i) + " has " + problem +
                         " (pass check=False to trace such rays as misses, as the C++ library does)");
      }
    }
  }
  trace(0, rays.size());
}

namespace {

/// One double structure over one DoubleScene (queries shared, build exclusive: see LockedStructure).
class PyDoubleAccelerator : public LockedStructure<PyDoubleAccelerator, DoubleAccelerator, DoubleScene> {
 public:
  explicit PyDoubleAccelerator(const std::string& spec) : LockedStructure(make_double_accelerator(spec)) {}

  static std::string not_built(const DoubleAccelerator& accel) {
    return "double accelerator '" + accel.spec() + "' is not built: call build(scene) first";
  }

  void build(std::shared_ptr<DoubleScene> scene) {
    if (!scene) throw TypeError("build() needs a rayaccel.DoubleScene, not None");
    build_over(std::move(scene));
  }

  /// Closest hits: (N, 32) uint8 records in the .hits64 layout.
  py::array_t<std::uint8_t> intersect(const py::handle& rays_object, bool check) const {
    const BatchRays<RayD> batch(rays_object);
    auto [records, hits] = record_array<HitD>(batch.rays.size(), py::none());
    std::uint8_t* bytes = records.mutable_data();
    trace(batch.rays, check, [&](const DoubleAccelerator& accel, std::size_t begin, std::size_t end) {
      accel.intersect(batch.rays.subspan(begin, end - begin), hits.subspan(begin, end - begin));
      for (std::size_t i = begin; i < end; ++i) std::memset(bytes + i * sizeof(HitD) + kPaddingOffset, 0, 4);
    });
    return records;
  }

  /// Any hits: (N,) bool.
  py::array_t<bool> occluded(const py::handle& rays_object, bool check) const {
    const BatchRays<RayD> batch(rays_object);
    auto [answers, out] = answer_array(batch.rays.size());
    trace(batch.rays, check, [&](const DoubleAccelerator& accel, std::size_t begin, std::size_t end) {
      accel.occluded(batch.rays.subspan(begin, end - begin), out.subspan(begin, end - begin));
    });
    return answers;
  }
};

}  // namespace

void bind_double(py::module_& m) {
  py::class_<DoubleScene, std::shared_ptr<DoubleScene>>(m, "DoubleScene",
                                                        "A triangle mesh in double (rayaccel.mesh_double()).")
      .def("__len__", &DoubleScene::triangle_count)
      .def_property_readonly("memory_bytes", &DoubleScene::memory_bytes)
      .def("__repr__", [](const DoubleScene& s) {
        return "<rayaccel.DoubleScene: " + std::to_string(s.triangle_count()) + " triangles>";
      });
  m.def("_mesh_double", &mesh_double, py::arg("vertices"), py::arg("triangles"));
  m.def("load_double", &load_double, py::arg("spec"), py::arg("offset") = std::array<double, 3>{0.0, 0.0, 0.0},
        "A DoubleScene from a mesh file or \"builtin:NAME[:k=v,...]\" spec, every vertex moved by offset (3 floats): a "
        "PLY file's coordinates as read (property double keeps its 53 bits), other formats and builtins through the "
        "float loader (exact in double). FileNotFoundError for a missing file, ValueError for one that is not a "
        "triangle mesh.");
  py::class_<PyDoubleAccelerator>(m, "_DoubleAccelerator")
      .def(py::init<const std::string&>(), py::arg("spec"))
      .def("build", &PyDoubleAccelerator::build, py::arg("scene"))
      .def_property_readonly("spec", &PyDoubleAccelerator::spec)
      .def_property_readonly("scene", &PyDoubleAccelerator::scene)
      .def_property_readonly("memory_bytes", &PyDoubleAccelerator::memory_bytes)
      .def("validate", &PyDoubleAccelerator::validate)
      .def("_intersect", &PyDoubleAccelerator::intersect, py::arg("rays"), py::arg("check"))
      .def("_occluded", &PyDoubleAccelerator::occluded, py::arg("rays"), py::arg("check"));
}

}  // namespace rayaccel::python
