// Instanced scenes for Python (instance/instanced_scene.h, instanced_accelerator.h): geometries are rayaccel
// Scenes (shared with Python, kept alive), transforms (3, 4) or (4, 4) arrays, and batches traced through the C++
// two-level structure without the GIL into records in the .ihits layout (instance/instance_hits_file.h).
#include <pybind11/stl.h>

#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <span>
#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "locked_structure.h"
#include "rayaccel/instance/instance_hits_file.h"
#include "rayaccel/instance/instanced_accelerator.h"

namespace rayaccel::python {

namespace {

/// An object to world transform from a (3, 4) or (4, 4) array of numbers; the last row of a (4, 4) one must be
/// 0 0 0 1 (an affine transform). Finiteness and invertibility are the scene's checks.
Affine3 affine_from(const py::handle& object) {
  if (!py::isinstance<py::array>(object) && !py::isinstance<py::sequence>(object)) {
    throw TypeError("transform must be a (3, 4) or (4, 4) array, not " + std::string(Py_TYPE(object.ptr())->tp_name));
  }
  const auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!array) throw TypeError("transform must be an array of numbers");
  if (array.ndim() != 2 || array.shape(1) != 4 || (array.shape(0) != 3 && array.shape(0) != 4)) {
    throw ValueError("transform must have shape (3, 4) or (4, 4), not " + shape_text(array));
  }
  const double* m = array.data();
  if (array.shape(0) == 4 && !(m[12] == 0.0 && m[13] == 0.0 && m[14] == 0.0 && m[15] == 1.0)) {
    throw ValueError("transform's last row must be 0 0 0 1 (an affine transform), not " + std::to_string(m[12]) +
                     " " + std::to_string(m[13]) + " " + std::to_string(m[14]) + " " + std::to_string(m[15]));
  }
  Affine3 out;
  for (std::size_t i = 0; i < 12; ++i) out.m[i] = m[i];
  return out;
}

py::array_t<double> transform_array(const Affine3& a) {
  py::array_t<double> out({py::ssize_t{3}, py::ssize_t{4}});
  for (std::size_t i = 0; i < 12; ++i) out.mutable_data()[i] = a.m[i];
  return out;
}

/// The scene and the structures built over it share one lock: changes (set_transform, add_*) take it exclusively,
/// batches (which run without the GIL) shared, so no change lands in the middle of a batch or a rebuild.
struct SharedScene {
  InstancedScene scene;
  std::vector<std::shared_ptr<Scene>> keep_alive;  // the Python Scenes the geometries are
  std::shared_mutex mutex;
};

class PyInstancedScene {
 public:
  PyInstancedScene() : shared_(std::make_shared<SharedScene>()) {}

  std::uint32_t add_geometry(std::shared_ptr<Scene> scene) {
    if (!scene) throw TypeError("add_geometry() needs a rayaccel.Scene, not None");
    std::unique_lock lock(shared_->mutex);
    shared_->keep_alive.push_back(scene);
    return shared_->scene.add_geometry(std::shared_ptr<const Scene>(scene));
  }
  std::uint32_t add_instance(std::uint32_t geometry, const py::handle& transform,
                             std::optional<std::uint32_t> instance_id) {
    const Affine3 a = affine_from(transform);
    std::unique_lock lock(shared_->mutex);
    InstancedScene& s = shared_->scene;
    return instance_id ? s.add_instance(geometry, a, *instance_id) : s.add_instance(geometry, a);
  }
  void set_transform(std::uint32_t index, const py::handle& transform) {
    const Affine3 a = affine_from(transform);
    std::unique_lock lock(shared_->mutex);
    shared_->scene.set_transform(index, a);
  }
  py::array_t<double> transform(std::uint32_t index) const {
    std::shared_lock lock(shared_->mutex);
    return transform_array(instance(index).transform);
  }
  std::uint32_t geometry_of(std::uint32_t index) const {
    std::shared_lock lock(shared_->mutex);
    return instance(index).geometry;
  }
  std::uint32_t instance_id(std::uint32_t index) const {
    std::shared_lock lock(shared_->mutex);
    return instance(index).instance_id;
  }
  std::shared_ptr<Scene> geometry(std::uint32_t index) const {
    std::shared_lock lock(shared_->mutex);
    if (index >= shared_->keep_alive.size()) {
      throw ValueError("geometry " + std::to_string(index) + " is out of range (the scene has " +
                       std::to_string(shared_->keep_alive.size()) + " geometries)");
    }
    return shared_->keep_alive[index];
  }
  std::uint32_t geometry_count() const {
    std::shared_lock lock(shared_->mutex);
    return shared_->scene.geometry_count();
  }
  std::uint32_t instance_count() const {
    std::shared_lock lock(shared_->mutex);
    return shared_->scene.instance_count();
  }
  const std::shared_ptr<SharedScene>& shared() const { return shared_; }

 private:
  const Instance& instance(std::uint32_t index) const {
    if (index >= shared_->scene.instance_count()) {
      throw ValueError("instance " + std::to_string(index) + " is out of range (the scene has " +
                       std::to_string(shared_->scene.instance_count()) + " instances)");
    }
    return shared_->scene.instance(index);
  }

  std::shared_ptr<SharedScene> shared_;
};

/// The two-level structure over one InstancedScene, under that scene's lock (see LockedStructure, SharedScene).
class PyInstancedAccelerator : public LockedStructure<PyInstancedAccelerator, InstancedAccelerator, InstancedScene> {
 public:
  PyInstancedAccelerator(const std::string& bottom, const std::string& top)
      : LockedStructure(std::make_unique<InstancedAccelerator>(InstancedAcceleratorOptions{bottom, top})),
        bottom_(bottom),
        top_(top) {}

  static std::string not_built(const InstancedAccelerator&) { return kNotBuilt; }
  /// The scene's lock; its SharedScene is bound (with the GIL held) by the first build() and never changes.
  std::shared_mutex& mutex() const {
    if (!shared_) throw ValueError(kNotBuilt);
    return shared_->mutex;
  }

  /// Builds over `scene`; again over the same scene after geometries were added (another scene needs another
  /// structure, so that batches running on other threads always see one scene's lock).
  void build(const PyInstancedScene& scene) {
    if (shared_ && shared_ != scene.shared()) {
      throw ValueError("this instanced accelerator is built over another InstancedScene: use build_instanced()");
    }
    shared_ = scene.shared();
    build_over(std::shared_ptr<InstancedScene>(shared_, &shared_->scene));
  }
  void rebuild_top() {
    change(false, [&](std::unique_ptr<InstancedAccelerator>& accel, auto&) {
      require_built();
      accel->rebuild_top();
    });
  }
  std::string update_top() {
    return change(false, [&](std::unique_ptr<InstancedAccelerator>& accel, auto&) {
      require_built();
      return to_string(accel->update_top());
    });
  }
  void set_enabled(std::uint32_t instance, bool enabled) {
    change(false, [&](std::unique_ptr<InstancedAccelerator>& accel, auto&) {
      require_built();
      accel->set_enabled(instance, enabled);
    });
  }
  bool is_enabled(std::uint32_t instance) const {
    return read_built([&](const InstancedAccelerator& accel) { return accel.is_enabled(instance); });
  }
  // Fixed at construction: no lock needed.
  const std::string& bottom() const { return bottom_; }
  const std::string& top() const { return top_; }

  /// Closest hits: (N, 24) uint8 records in the .ihits layout.
  py::array_t<std::uint8_t> intersect(const py::handle& rays_object, bool check) const {
    const BatchRays<Ray> batch(rays_object);
    const std::span<const Ray> rays = batch.rays;
    auto [records, out] = record_array<InstanceHitRecord>(rays.size(), py::none());
    trace(rays, check, [&](const InstancedAccelerator& accel, std::size_t begin, std::size_t end) {
      detail::parallel_for_rays(end - begin, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = begin + b; i < begin + e; ++i) out[i] = to_record(accel.intersect(rays[i]));
      });
    });
    return records;
  }

  /// Any hits, (N,) bool.
  py::array_t<bool> occluded(const py::handle& rays_object, bool check) const {
    const BatchRays<Ray> batch(rays_object);
    const std::span<const Ray> rays = batch.rays;
    auto [answers, out] = answer_array(rays.size());
    trace(rays, check, [&](const InstancedAccelerator& accel, std::size_t begin, std::size_t end) {
      accel.occluded(rays.subspan(begin, end - begin), out.subspan(begin, end - begin));
    });
    return answers;
  }

 private:
  static constexpr const char* kNotBuilt = "instanced accelerator is not built: call build(instanced_scene) first";

  std::string bottom_, top_;
  std::shared_ptr<SharedScene> shared_;
};

}  // namespace

void bind_instances(py::module_& m) {
  py::class_<PyInstancedScene>(m, "_InstancedScene")
      .def(py::init<>())
      .def("add_geometry", &PyInstancedScene::add_geometry, py::arg("scene"))
      .def("_add_instance", &PyInstancedScene::add_instance, py::arg("geometry"), py::arg("transform"),
           py::arg("instance_id"))
      .def("set_transform", &PyInstancedScene::set_transform, py::arg("index"), py::arg("transform"),
           "Moves instance index (a (3, 4) or (4, 4) object-to-world transform); structures see it after "
           "rebuild_top() or update_top()")
      .def("transform", &PyInstancedScene::transform, py::arg("index"), "Instance index's transform, (3, 4) float64")
      .def("geometry_of", &PyInstancedScene::geometry_of, py::arg("index"), "The geometry instance index places")
      .def("instance_id", &PyInstancedScene::instance_id, py::arg("index"), "The id hits on instance index report")
      .def("geometry", &PyInstancedScene::geometry, py::arg("index"), "Geometry index (the Scene added)")
      .def_property_readonly("geometry_count", &PyInstancedScene::geometry_count)
      .def_property_readonly("instance_count", &PyInstancedScene::instance_count);
  py::class_<PyInstancedAccelerator>(m, "_InstancedAccelerator")
      .def(py::init<const std::string&, const std::string&>(), py::arg("bottom"), py::arg("top"))
      .def("build", &PyInstancedAccelerator::build, py::arg("scene"))
      .def("rebuild_top", &PyInstancedAccelerator::rebuild_top,
           "Rebuilds the top level from the scene's current transforms (the bottom levels stay)")
      .def("update_top", &PyInstancedAccelerator::update_top,
           "Refits the top level to the scene's current transforms ('refitted'), or rebuilds it when instances "
           "were added ('rebuilt')")
      .def("set_enabled", &PyInstancedAccelerator::set_enabled, py::arg("index"), py::arg("enabled"),
           "Shows or hides instance index from later queries, without a rebuild")
      .def("is_enabled", &PyInstancedAccelerator::is_enabled, py::arg("index"))
      .def_property_readonly("bottom", &PyInstancedAccelerator::bottom)
      .def_property_readonly("top", &PyInstancedAccelerator::top)
      .def_property_readonly("memory_bytes", &PyInstancedAccelerator::memory_bytes)
      .def("validate", &PyInstancedAccelerator::validate)
      .def("_intersect", &PyInstancedAccelerator::intersect, py::arg("rays"), py::arg("check"))
      .def("_occluded", &PyInstancedAccelerator::occluded, py::arg("rays"), py::arg("check"));
}

}  // namespace rayaccel::python
