// Python: one scene from several meshes with each mesh's geometry id (rayaccel.meshes), and GeometryTable, which maps
// hits' primitive ids to (geometry id, primitive within the geometry) over whole numpy arrays.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "rayaccel/scene/geometry_table.h"

namespace rayaccel::python {
namespace {

using Ids = py::array_t<std::uint32_t, py::array::c_style | py::array::forcecast>;

/// Applies `map` to every id of an unsigned integer array of any shape; the result has the same shape.
template <class Map>
Ids map_ids(const py::handle& object, Map map) {
  const auto given = py::array::ensure(object);  // any array-like, as numpy functions take (a list, a scalar)
  if (!given) throw TypeError("prim_id must be an array of integers");
  if (given.dtype().kind() != 'u' && given.dtype().kind() != 'i') {
    throw TypeError("prim_id must be an integer array, not " + dtype_name(given));
  }
  const Ids ids = Ids::ensure(given);
  Ids out(std::vector<py::ssize_t>(given.shape(), given.shape() + given.ndim()));
  const std::uint32_t* in = ids.data();
  std::uint32_t* result = out.mutable_data();
  for (py::ssize_t i = 0; i < ids.size(); ++i) result[i] = map(in[i]);
  return out;
}

/// (Scene, GeometryTable) from a list of (vertices, triangles) pairs, as rayaccel.mesh() reads each pair.
py::tuple meshes_scene(const py::list& pairs, std::string name) {
  std::vector<TriangleMesh> meshes;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto pair = pairs[k].cast<py::tuple>();
    if (pair.size() != 2) throw ValueError("mesh " + std::to_string(k) + ": expected (vertices, triangles)");
    const FloatRows vertices = float_rows(pair[0], 3, "vertices");
    TriangleMesh mesh;
    mesh.vertices.resize(static_cast<std::size_t>(vertices.shape(0)));
    const float* v = vertices.data();
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      mesh.vertices[i] = Vec3{v[3 * i], v[3 * i + 1], v[3 * i + 2]};
      if (!is_finite(mesh.vertices[i])) {
        throw ValueError("mesh " + std::to_string(k) + ": vertex " + std::to_string(i) + " is not finite");
      }
    }
    try {
      mesh.triangles = read_triangles(pair[1], mesh.vertices.size());
    } catch (const ValueError& e) {
      throw ValueError("mesh " + std::to_string(k) + ": " + e.what());
    }
    meshes.push_back(std::move(mesh));
  }
  auto table = std::make_shared<GeometryTable>();
  std::shared_ptr<Scene> scene;
  {
    py::gil_scoped_release release;
    scene = std::make_shared<Scene>(scene_from_meshes(meshes, *table, std::move(name)));
  }
  return py::make_tuple(scene, table);
}

}  // namespace

void bind_geometry(py::module_& m) {
  py::class_<GeometryTable, std::shared_ptr<GeometryTable>>(m, "GeometryTable",
      "Which mesh each primitive of a scene from rayaccel.meshes() came from: mesh k owns primitive ids "
      "first_primitive(k) to first_primitive(k + 1) - 1.")
      .def_property_readonly("geometry_count", &GeometryTable::geometry_count)
      .def("first_primitive", &GeometryTable::first_primitive, py::arg("geom_id"),
           "The scene-wide primitive id of mesh geom_id's first triangle.")
      .def("geometry_of", [](const GeometryTable& t, const py::handle& ids) {
        return map_ids(ids, [&](std::uint32_t id) { return t.geometry_of(id); });
      }, py::arg("prim_id"), "Geometry ids of an array of scene-wide primitive ids (hits.prim_id); MISS for a miss.")
      .def("local_primitive", [](const GeometryTable& t, const py::handle& ids) {
        return map_ids(ids, [&](std::uint32_t id) { return t.local_primitive(id); });
      }, py::arg("prim_id"), "Each primitive's index within its mesh; MISS for a miss.");
  m.def("_meshes", &meshes_scene, py::arg("meshes"), py::arg("name"));
}

}  // namespace rayaccel::python
