// Scenes for Python: triangle meshes from numpy arrays (checked, converted once), mesh files and built-in scenes
// through load_scene(), and spheres. The C++ Scene owns its arrays, so input arrays are copied once into it; Python
// reads them back as read-only numpy views (vertices, triangles, centers, radii) that keep the scene alive.
#include <pybind11/stl.h>

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "rayaccel/scene/builtin_scenes.h"
#include "rayaccel/scene/import.h"

namespace rayaccel::python {

namespace {

template <class Real>
std::vector<Vec3> convert_vertices(const py::array& array, bool allow_nonfinite) {
  const auto rows = py::array_t<Real, py::array::c_style>::ensure(array);  // no copy when already C-contiguous
  if (!rows) throw py::error_already_set();
  const Real* data = rows.data();
  std::vector<Vec3> vertices(static_cast<std::size_t>(rows.shape(0)));
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    vertices[i] = {static_cast<float>(data[3 * i]), static_cast<float>(data[3 * i + 1]),
                   static_cast<float>(data[3 * i + 2])};
    if (!allow_nonfinite && !is_finite(vertices[i])) {
      throw ValueError("vertices[" + std::to_string(i) + "] is not finite in float32 (NaN, infinite or too large); pass " +
                       "allow_nonfinite=True to keep such triangles (they are never hit)");
    }
  }
  return vertices;
}

/// Converts (N, 3) float32/float64 vertices into the scene's own array in one pass.
std::vector<Vec3> read_vertices(const py::handle& object, bool allow_nonfinite) {
  if (!py::isinstance<py::array>(object)) throw TypeError("vertices must be a numpy array");
  const auto array = py::reinterpret_borrow<py::array>(object);
  if (array.ndim() != 2 || array.shape(1) != 3) {
    throw ValueError("vertices must have shape (N, 3), not " + shape_text(array));
  }
  if (array.dtype().equal(py::dtype::of<float>())) return convert_vertices<float>(array, allow_nonfinite);
  if (array.dtype().equal(py::dtype::of<double>())) return convert_vertices<double>(array, allow_nonfinite);
  throw TypeError("vertices must be float32 or float64, not " + dtype_name(array));
}

std::shared_ptr<Scene> mesh_scene(const py::handle& vertices, const py::handle& triangles, std::string name,
                                  bool allow_nonfinite) {
  TriangleMesh mesh;
  mesh.vertices = read_vertices(vertices, allow_nonfinite);
  mesh.triangles = read_triangles(triangles, mesh.vertices.size());
  if (mesh.vertices.size() > std::numeric_limits<std::uint32_t>::max()) throw ValueError("too many vertices");
  py::gil_scoped_release release;
  return std::make_shared<Scene>(Scene::from_mesh(std::move(mesh), std::move(name)));
}

/// The deleter of a scene over the caller's arrays: holds a reference to both (released under the GIL), so they live
/// as long as the scene; the scene's views find them through std::get_deleter.
struct KeepArrays {
  py::object vertices, triangles;
  void operator()(Scene* scene) {
    delete scene;
    py::gil_scoped_acquire gil;
    vertices = py::object();
    triangles = py::object();
  }
};

/// A scene over the caller's arrays, read in place (Scene::from_buffers): float32 (N, 3) and int32/uint32 (M, 3),
/// both C-contiguous, kept alive by the scene (KeepArrays).
std::shared_ptr<Scene> mesh_scene_in_place(const py::handle& vertices, const py::handle& triangles, std::string name,
                                           bool allow_nonfinite) {
  if (!py::isinstance<py::array>(vertices)) throw TypeError("vertices must be a numpy array");
  if (!py::isinstance<py::array>(triangles)) throw TypeError("triangles must be a numpy array");
  const auto v = py::reinterpret_borrow<py::array>(vertices);
  const auto t = py::reinterpret_borrow<py::array>(triangles);
  const bool v_ok = v.dtype().equal(py::dtype::of<float>()) && v.ndim() == 2 && v.shape(1) == 3 &&
                    (v.flags() & py::array::c_style);
  const bool t_ok =
      (t.dtype().equal(py::dtype::of<std::int32_t>()) || t.dtype().equal(py::dtype::of<std::uint32_t>())) &&
      t.ndim() == 2 && t.shape(1) == 3 && (t.flags() & py::array::c_style);
  if (!v_ok || !t_ok) {
    throw ValueError("copy=False reads the arrays in place and needs C-contiguous float32 (N, 3) vertices and "
                     "int32/uint32 (M, 3) triangles, not " + dtype_name(v) + " " + shape_text(v) + " and " +
                     dtype_name(t) + " " + shape_text(t));
  }
  const auto* xyz = static_cast<const float*>(v.data());
  if (!allow_nonfinite) {
    for (py::ssize_t i = 0; i < 3 * v.shape(0); ++i) {
      if (!std::isfinite(xyz[i])) {
        throw ValueError("vertices[" + std::to_string(i / 3) + "] is not finite (allow_nonfinite=True keeps it)");
      }
    }
  }
  if (t.dtype().equal(py::dtype::of<std::int32_t>())) {
    const auto* index = static_cast<const std::int32_t*>(t.data());
    for (py::ssize_t i = 0; i < 3 * t.shape(0); ++i) {
      if (index[i] < 0) {
        throw ValueError("triangles[" + std::to_string(i / 3) + ", " + std::to_string(i % 3) + "] = " +
                         std::to_string(index[i]) + " is out of range: there are " + std::to_string(v.shape(0)) +
                         " vertices");
      }
    }
  }
  MeshBuffers buffers;
  buffers.vertices = xyz;
  buffers.vertex_count = static_cast<std::size_t>(v.shape(0));
  buffers.indices = t.data();  // nonnegative int32 indices read as uint32; from_buffers checks the upper end
  buffers.triangle_count = static_cast<std::size_t>(t.shape(0));
  buffers.index_type = IndexType::uint32;
  auto* scene = new Scene(Scene::from_buffers(buffers, std::move(name)));
  return std::shared_ptr<Scene>(scene, KeepArrays{v, t});
}

std::shared_ptr<Scene> sphere_scene(const py::handle& centers, const py::handle& radii, std::string name) {
  const auto rows = float_rows(centers, 3, "centers");
  const auto count = static_cast<std::size_t>(rows.shape(0));
  std::vector<Sphere> spheres(count);
  // radii: one float for every sphere, or an (N,) float array.
  if (py::isinstance<py::array>(radii)) {
    const auto array = py::reinterpret_borrow<py::array>(radii);
    if (!array.dtype().equal(py::dtype::of<float>()) && !array.dtype().equal(py::dtype::of<double>())) {
      throw TypeError("radii must be float32 or float64, not " + dtype_name(array));
    }
    if (array.ndim() != 1 || static_cast<std::size_t>(array.shape(0)) != count) {
      throw ValueError("radii must have shape (" + std::to_string(count) + ",) to match centers, not " +
                       shape_text(array));
    }
    const auto values = FloatRows::ensure(array);
    if (!values) throw py::error_already_set();
    for (std::size_t i = 0; i < count; ++i) spheres[i].radius = values.data()[i];
  } else {
    const float radius = radii.cast<float>();
    for (auto& s : spheres) s.radius = radius;
  }
  for (std::size_t i = 0; i < count; ++i) {
    const float* c = rows.data() + 3 * i;
    spheres[i].center = {c[0], c[1], c[2]};
    if (!is_finite(spheres[i].center)) throw ValueError("centers[" + std::to_string(i) + "] is not finite");
    if (!(spheres[i].radius > 0.0f) || !std::isfinite(spheres[i].radius)) {
      throw ValueError("radius of sphere " + std::to_string(i) + " is " + std::to_string(spheres[i].radius) +
                       ": radii must be finite and > 0");
    }
  }
  py::gil_scoped_release release;
  return std::make_shared<Scene>(Scene::from_spheres(std::move(spheres), std::move(name)));
}

/// load_scene(spec, geometries), with FileNotFound for a missing file.
std::shared_ptr<Scene> load(const std::string& spec, GeometryTable* geometries = nullptr) {
  if (spec.rfind("builtin:", 0) != 0) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(spec, ec)) {
      throw FileNotFound("scene file '" + spec + "' does not exist (or is not a file)");
    }
  }
  py::gil_scoped_release release;
  return std::make_shared<Scene>(load_scene(spec, geometries));
}

py::array_t<float> bounds_array(const Scene& scene) {
  py::array_t<float> out({2, 3});
  const AABB& b = scene.bounds();
  for (int a = 0; a < 3; ++a) {
    out.mutable_at(0, a) = b.is_empty() ? std::numeric_limits<float>::quiet_NaN() : b.lo[a];
    out.mutable_at(1, a) = b.is_empty() ? std::numeric_limits<float>::quiet_NaN() : b.hi[a];
  }
  return out;
}

/// A read-only (rows, columns) numpy view of Scalar data `stride` bytes apart per row, whose base is the Python
/// Scene of `scene` (so the view keeps the scene alive); columns == 0 gives a 1-D (rows,) view.
template <class Scalar>
py::array readonly_view(const std::shared_ptr<Scene>& scene, const void* data, std::size_t rows, py::ssize_t columns,
                        py::ssize_t stride) {
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(rows)}, strides{stride};
  if (columns > 0) {
    shape.push_back(columns);
    strides.push_back(sizeof(Scalar));
  }
  py::array view(py::dtype::of<Scalar>(), shape, strides, data, py::cast(scene));
  view.attr("setflags")(py::arg("write") = false);
  return view;
}

/// A read-only view of one of the caller's arrays of a copy=False scene, as `dtype` (int32 indices read as uint32,
/// as the scene reads them; they were checked to be nonnegative).
py::array readonly_view_of(const py::object& array, const py::dtype& dtype) {
  py::array view = array.attr("view")(dtype);
  view.attr("setflags")(py::arg("write") = false);
  return view;
}

void require_kind(const Scene& scene, PrimitiveKind kind, const char* what) {
  if (scene.kind() == kind) return;
  const std::string has = scene.kind() == PrimitiveKind::spheres ? " (a sphere scene has centers and radii)"
                          : scene.kind() == PrimitiveKind::triangles ? " (a triangle scene has vertices and triangles)"
                                                                     : "";
  throw py::attribute_error("a scene of " + std::string(to_string(scene.kind())) + " has no " + what + has);
}

py::array vertices_view(const std::shared_ptr<Scene>& scene) {
  require_kind(*scene, PrimitiveKind::triangles, "vertices");
  if (const auto* keep = std::get_deleter<KeepArrays>(scene)) {
    return readonly_view_of(keep->vertices, py::dtype::of<float>());
  }
  const auto& vertices = scene->mesh().vertices;
  static_assert(sizeof(Vec3) == 3 * sizeof(float));
  return readonly_view<float>(scene, vertices.data(), vertices.size(), 3, sizeof(Vec3));
}

py::array triangles_view(const std::shared_ptr<Scene>& scene) {
  require_kind(*scene, PrimitiveKind::triangles, "triangles");
  if (const auto* keep = std::get_deleter<KeepArrays>(scene)) {
    return readonly_view_of(keep->triangles, py::dtype::of<std::uint32_t>());
  }
  const auto& triangles = scene->mesh().triangles;
  return readonly_view<std::uint32_t>(scene, triangles.data(), triangles.size(), 3, sizeof(triangles[0]));
}

py::array centers_view(const std::shared_ptr<Scene>& scene) {
  require_kind(*scene, PrimitiveKind::spheres, "centers");
  const auto& spheres = scene->spheres();
  return readonly_view<float>(scene, spheres.data(), spheres.size(), 3, sizeof(Sphere));
}

py::array radii_view(const std::shared_ptr<Scene>& scene) {
  require_kind(*scene, PrimitiveKind::spheres, "radii");
  const auto& spheres = scene->spheres();
  static_assert(sizeof(Sphere) == 4 * sizeof(float) && offsetof(Sphere, radius) == 3 * sizeof(float));
  return readonly_view<float>(scene, reinterpret_cast<const char*>(spheres.data()) + offsetof(Sphere, radius),
                              spheres.size(), 0, sizeof(Sphere));
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", py::dynamic_attr(), "Primitives to build structures over (see rayaccel.mesh, "
                                                        "rayaccel.load, rayaccel.spheres). Immutable from Python.")
      .def_property_readonly("name", &Scene::name)
      .def_property_readonly("kind", [](const Scene& s) { return std::string(to_string(s.kind())); })
      .def_property_readonly("primitive_count", &Scene::primitive_count)
      .def_property_readonly("valid_count", &Scene::valid_count)
      .def_property_readonly("invalid_count", &Scene::invalid_count)
      .def_property_readonly("degenerate_count", &Scene::degenerate_count)
      .def_property_readonly("memory_bytes", &Scene::memory_bytes)
      .def_property_readonly("borrows_arrays", &Scene::borrows_buffers,
                             "True for a scene made with mesh(..., copy=False), which reads the arrays in place")
      .def("arrays_changed", &Scene::buffers_changed,
           "After writing new vertex positions into the arrays of a copy=False scene: re-reads them (then rebuild)")
      .def_property_readonly("bounds", &bounds_array, "(2, 3) float32: min and max corner (NaN when empty)")
      .def_property_readonly("vertices", &vertices_view,
                             "(V, 3) float32, read-only, no copy: the triangle scene's vertices (a copy=False scene's "
                             "own array). AttributeError for a sphere scene")
      .def_property_readonly("triangles", &triangles_view,
                             "(T, 3) uint32, read-only, no copy: vertex indices of each triangle (primitive id = row)")
      .def_property_readonly("centers", &centers_view,
                             "(N, 3) float32, read-only, no copy: the sphere scene's centers. AttributeError for a "
                             "triangle scene")
      .def_property_readonly("radii", &radii_view, "(N,) float32, read-only, no copy: the sphere scene's radii")
      .def("__len__", [](const Scene& s) { return s.primitive_count(); })
      .def("__repr__", [](const Scene& s) {
        return "<rayaccel.Scene '" + s.name() + "': " + std::to_string(s.primitive_count()) + " " +
               to_string(s.kind()) + ">";
      });

  m.def("_mesh", &mesh_scene, py::arg("vertices"), py::arg("triangles"), py::arg("name"),
        py::arg("allow_nonfinite"));
  m.def("_mesh_in_place", &mesh_scene_in_place, py::arg("vertices"), py::arg("triangles"), py::arg("name"),
        py::arg("allow_nonfinite"));
  m.def("_spheres", &sphere_scene, py::arg("centers"), py::arg("radii"), py::arg("name"));
  m.def("_load", [](const std::string& spec) { return load(spec); }, py::arg("spec"));
  m.def(
      "_load_with_geometries",
      [](const std::string& spec) {
        auto table = std::make_shared<GeometryTable>();
        std::shared_ptr<Scene> scene = load(spec, table.get());
        return py::make_tuple(scene, table);
      },
      py::arg("spec"));
  m.def("_builtin_scenes", [] {
    py::list out;
    for (const auto& info : builtin_scenes()) {
      out.append(py::dict(py::arg("name") = info.name, py::arg("description") = info.description,
                          py::arg("defaults") = info.defaults));
    }
    return out;
  });
}

}  // namespace rayaccel::python
