// Accelerators for Python: any registry spec, built over a Scene, queried with numpy ray arrays through the C++
// batch API (the GIL released, TBB threads) into numpy arrays laid out as the .hits / .occ records, so results
// need no conversion and equal the CLI's files byte for byte.
#include <pybind11/stl.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "rayaccel/render/shading.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/render/workloads.h"

namespace rayaccel::python {

namespace {

/// A zeroed (n, 2) uint64 array of per-ray traversal statistics (stored in `array`) and the records it holds (the
/// traversal adds to them).
std::span<TraversalStats> statistics_array(std::size_t n, py::object& array) {
  py::array_t<std::uint64_t> s({static_cast<py::ssize_t>(n), py::ssize_t{2}});
  std::fill_n(s.mutable_data(), s.size(), std::uint64_t{0});
  array = s;
  return {reinterpret_cast<TraversalStats*>(s.mutable_data()), n};
}

/// One structure, built over one scene that it keeps alive. Queries take a shared lock and build() an exclusive
/// one, so a rebuild from one Python thread never runs under another thread's batch (both run without the GIL).
class PyAccelerator {
 public:
  explicit PyAccelerator(const std::string& spec) : accel_(make_accelerator(spec)) {}

  void build(std::shared_ptr<Scene> scene) {
    if (!scene) throw TypeError("build() needs a rayaccel.Scene, not None");
    py::gil_scoped_release release;
    std::unique_lock lock(mutex_);
    scene_.reset();
    const auto start = std::chrono::steady_clock::now();
    accel_->build(*scene);
    build_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    scene_ = std::move(scene);
  }

  // Accessors run with the GIL held; they wait for a build running in another thread (which needs no GIL until
  // it ends), never the other way round.
  bool built() const {
    std::shared_lock lock(mutex_);
    return scene_ != nullptr;
  }
  const std::string& spec() const { return accel_->spec(); }
  std::shared_ptr<Scene> scene() const {
    std::shared_lock lock(mutex_);
    return scene_;
  }
  double build_ms() const {
    std::shared_lock lock(mutex_);
    return build_ms_;
  }
  std::size_t memory_bytes() const {
    std::shared_lock lock(mutex_);
    return require_built().memory_bytes();
  }
  std::vector<std::string> validate() const {
    py::gil_scoped_release release;
    std::shared_lock lock(mutex_);
    return require_built().validate();
  }
  py::dict build_statistics() const {
    std::shared_lock lock(mutex_);
    py::dict out;
    for (const auto& s : require_built().build_statistics()) out[py::str(s.name)] = s.value;
    return out;
  }

  /// Closest hits: (N, 16) uint8 records in the .hits layout, and (N, 2) uint64 statistics or None.
  /// `out`: None, or an (N, 16) uint8 C-contiguous writable array the records are written into (and returned).
  py::tuple intersect(const py::handle& rays_object, bool with_stats, bool packets, bool check,
                      const py::object& out) const {
    const auto rays_array = float_rows(rays_object, 8, "rays");
    const std::span<const Ray> rays = ray_view(rays_array);
    if (packets && with_stats) throw ValueError("packets=True gives no per-ray statistics (stats=False)");
    py::array_t<std::uint8_t> records;
    if (out.is_none()) {
      records = py::array_t<std::uint8_t>({static_cast<py::ssize_t>(rays.size()), py::ssize_t{16}});
    } else {
      const auto given = py::reinterpret_borrow<py::array>(out);
      if (!py::isinstance<py::array_t<std::uint8_t>>(out) || given.ndim() != 2 || given.shape(1) != 16 ||
          static_cast<std::size_t>(given.shape(0)) != rays.size() || !(given.flags() & py::array::c_style) ||
          !given.writeable()) {
        throw ValueError("out must hold one writable, C-contiguous hit record per ray (" + std::to_string(rays.size()) +
                         " rays)");
      }
      records = py::reinterpret_borrow<py::array_t<std::uint8_t>>(out);
    }
    py::object stats_array = py::none();
    const std::span<TraversalStats> stats =
        with_stats ? statistics_array(rays.size(), stats_array) : std::span<TraversalStats>{};
    const std::span<Hit> hits(reinterpret_cast<Hit*>(records.mutable_data()), rays.size());
    {
      py::gil_scoped_release release;
      std::shared_lock lock(mutex_);
      const Accelerator& accel = require_built();
      trace_checked(rays, check, [&](std::size_t begin, std::size_t end) {
        const auto block = rays.subspan(begin, end - begin);
        if (packets) {
          accel.intersect_packets(block, hits.subspan(begin, end - begin));
        } else {
          accel.intersect(block, hits.subspan(begin, end - begin),
                          stats.empty() ? stats : stats.subspan(begin, end - begin));
        }
      });
    }
    return py::make_tuple(records, stats_array);
  }

  /// Any hits: (N,) bool, and (N, 2) uint64 statistics or None.
  py::tuple occluded(const py::handle& rays_object, bool with_stats, bool check) const {
    const auto rays_array = float_rows(rays_object, 8, "rays");
    const std::span<const Ray> rays = ray_view(rays_array);
    py::array_t<bool> answers(static_cast<py::ssize_t>(rays.size()));
    py::object stats_array = py::none();
    const std::span<TraversalStats> stats =
        with_stats ? statistics_array(rays.size(), stats_array) : std::span<TraversalStats>{};
    static_assert(sizeof(bool) == 1);
    const std::span<std::uint8_t> out(reinterpret_cast<std::uint8_t*>(answers.mutable_data()), rays.size());
    {
      py::gil_scoped_release release;
      std::shared_lock lock(mutex_);
      const Accelerator& accel = require_built();
      trace_checked(rays, check, [&](std::size_t begin, std::size_t end) {
        accel.occluded(rays.subspan(begin, end - begin), out.subspan(begin, end - begin),
                       stats.empty() ? stats : stats.subspan(begin, end - begin));
      });
    }
    return py::make_tuple(answers, stats_array);
  }

  /// Hit points (recomputed from the primitive) and unit geometric normals, (N, 3) float32 each, NaN at misses.
  py::tuple surface(const py::handle& rays_object, const py::array_t<std::uint8_t, py::array::c_style>& records) const {
    const auto rays_array = float_rows(rays_object, 8, "rays");
    const std::span<const Ray> rays = ray_view(rays_array);
    if (records.ndim() != 2 || records.shape(1) != 16 || static_cast<std::size_t>(records.shape(0)) != rays.size()) {
      throw ValueError("hit records must have shape (N, 16) with N = the number of rays");
    }
    const auto n = static_cast<py::ssize_t>(rays.size());
    py::array_t<float> points({n, py::ssize_t{3}});
    py::array_t<float> normals({n, py::ssize_t{3}});
    const Hit* hits = reinterpret_cast<const Hit*>(records.data());
    float* p = points.mutable_data();
    float* nrm = normals.mutable_data();
    {
      py::gil_scoped_release release;
      std::shared_lock lock(mutex_);
      require_built();
      const Scene& scene = *scene_;
      const std::uint32_t count = scene.primitive_count();
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 4096), [&](const auto& range) {
        constexpr float nan = std::numeric_limits<float>::quiet_NaN();
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          Vec3 point{nan}, normal{nan};
          if (hits[i].found() && hits[i].prim_id < count) {
            point = surface_point(scene, rays[i], hits[i]).point;
            normal = geometric_normal(scene, rays[i], hits[i]);
          }
          for (int a = 0; a < 3; ++a) {
            p[3 * i + a] = point[a];
            nrm[3 * i + a] = normal[a];
          }
        }
      });
    }
    return py::make_tuple(points, normals);
  }

  /// An image through the library's renderer, (height, width, 3) uint8.
  py::array_t<std::uint8_t> render(const RenderRequest& request) const {
    Image image;
    {
      py::gil_scoped_release release;
      std::shared_lock lock(mutex_);
      image = render_image(require_built(), *scene_, request);
    }
    return image_array(image);
  }

 private:
  const Accelerator& require_built() const {
    if (!scene_) throw ValueError("accelerator '" + accel_->spec() + "' is not built: call build(scene) first");
    return *accel_;
  }

  std::unique_ptr<Accelerator> accel_;
  std::shared_ptr<Scene> scene_;
  mutable std::shared_mutex mutex_;
  double build_ms_ = 0.0;
};

py::list structures() {
  py::list out;
  for (const auto& info : accelerator_registry()) {
    if (info.comparison) continue;  // another library (Embree): buildable by spec, not one of rayaccel's structures
    py::list options;
    for (const auto& o : info.options) {
      options.append(py::dict(py::arg("key") = o.key, py::arg("type") = to_string(o.type),
                              py::arg("default") = o.default_value, py::arg("description") = o.description,
                              py::arg("choices") = o.choices, py::arg("range") = o.range));
    }
    const std::vector<std::string> variants = info.variants.empty() ? std::vector{info.name} : info.variants;
    out.append(py::dict(py::arg("name") = info.name, py::arg("description") = info.description,
                        py::arg("options") = options, py::arg("variants") = variants));
  }
  return out;
}

}  // namespace

void bind_accelerator(py::module_& m) {
  py::class_<PyAccelerator>(m, "_Accelerator")
      .def(py::init<const std::string&>(), py::arg("spec"))
      .def("build", &PyAccelerator::build, py::arg("scene"))
      .def_property_readonly("built", &PyAccelerator::built)
      .def_property_readonly("spec", &PyAccelerator::spec)
      .def_property_readonly("scene", &PyAccelerator::scene)
      .def_property_readonly("build_ms", &PyAccelerator::build_ms)
      .def_property_readonly("memory_bytes", &PyAccelerator::memory_bytes)
      .def("build_statistics", &PyAccelerator::build_statistics)
      .def("validate", &PyAccelerator::validate)
      .def("_intersect", &PyAccelerator::intersect, py::arg("rays"), py::arg("stats"), py::arg("packets"),
           py::arg("check"), py::arg("out"))
      .def("_occluded", &PyAccelerator::occluded, py::arg("rays"), py::arg("stats"), py::arg("check"))
      .def("_surface", &PyAccelerator::surface, py::arg("rays"), py::arg("records"))
      .def("_render", [](const PyAccelerator& self, const std::array<float, 3>& eye, const std::array<float, 3>& at,
                         const std::array<float, 3>& up, float fov, int width, int height, const std::string& mode,
                         int ao_samples, float ao_distance, std::uint64_t seed) {
        return self.render({eye, at, up, fov, width, height, mode, ao_samples, ao_distance, seed});
      });
  m.def("_structures", &structures);
  m.def("specs", &accelerator_variant_names,
        "Every spec `rayaccel list --names` prints, in registry order (each one accepted by build()).");
}

}  // namespace rayaccel::python
