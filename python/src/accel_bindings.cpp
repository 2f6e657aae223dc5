// Accelerators for Python: any registry spec, built over a Scene, queried with numpy ray arrays through the C++
// batch API (the GIL released, TBB threads) into numpy arrays laid out as the .hits / .occ records, so results
// need no conversion and equal the CLI's files byte for byte.
#include <pybind11/stl.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "arrays.h"
#include "bindings.h"
#include "locked_structure.h"
#include "query_context_arrays.h"
#include "rayaccel/render/shading.h"
#include "rayaccel/accel/default_spec.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/query/inside.h"
#include "rayaccel/query/signed_distance.h"
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

/// Points of an (N, 3) float32 C-contiguous array, viewed in place.
std::span<const Vec3> point_view(const FloatRows& points) {
  static_assert(sizeof(Vec3) == 3 * sizeof(float));
  return {reinterpret_cast<const Vec3*>(points.data()), static_cast<std::size_t>(points.shape(0))};
}

/// One registry structure over one Scene (queries shared, build/update/load exclusive: see LockedStructure).
class PyAccelerator : public LockedStructure<PyAccelerator, Accelerator, Scene> {
 public:
  explicit PyAccelerator(const std::string& spec) : LockedStructure(make_accelerator(spec)) {}

  static std::string not_built(const Accelerator& accel) {
    return "accelerator '" + accel.spec() + "' is not built: call build(scene) first";
  }

  void build(std::shared_ptr<Scene> scene) {
    if (!scene) throw TypeError("build() needs a rayaccel.Scene, not None");
    build_over(std::move(scene));
  }

  /// After the scene's vertices moved (arrays written in place, then Scene.arrays_changed()): refits where the
  /// structure can, else rebuilds; "refitted" or "rebuilt".
  std::string update() {
    return change(true, [&](std::unique_ptr<Accelerator>& accel, std::shared_ptr<Scene>& scene) {
      require_built();
      return to_string(accel->update(*scene));
    });
  }
  void save(const std::string& path) const {
    query([&](const Accelerator& accel, const Scene&) { accel.save(path); });
  }
  /// Replaces this structure by the one saved in `path` (of the kind the file names) over `scene`.
  void load(const std::string& path, std::shared_ptr<Scene> scene) {
    if (!scene) throw TypeError("load() needs a rayaccel.Scene, not None");
    change(true, [&](std::unique_ptr<Accelerator>& accel, std::shared_ptr<Scene>& current) {
      std::unique_ptr<Accelerator> loaded = load_accelerator(path, *scene);
      accel = std::move(loaded);
      current = std::move(scene);
    });
  }
  bool supports_refit() const {
    return read([](const Accelerator& accel) { return accel.supports_refit(); });
  }
  bool supports_save() const {
    return read([](const Accelerator& accel) { return accel.supports_save(); });
  }
  py::dict build_statistics() const {
    return read_built([](const Accelerator& accel) {
      py::dict out;
      for (const auto& s : accel.build_statistics()) out[py::str(s.name)] = s.value;
      return out;
    });
  }

  /// Closest hits: (N, 16) uint8 records in the .hits layout, and (N, 2) uint64 statistics or None.
  /// `out`: None, or an (N, 16) uint8 C-contiguous writable array the records are written into (and returned).
  py::tuple intersect(const py::handle& rays_object, bool with_stats, bool packets, bool check,
                      const py::object& out) const {
    return trace_batch(
        rays_object, with_stats, packets, check, [&](std::size_t n) { return record_array<Hit>(n, out); },
        [](const Accelerator& accel, auto rays, auto hits, auto stats) { accel.intersect(rays, hits, stats); },
        [](const Accelerator& accel, auto rays, auto hits) { accel.intersect_packets(rays, hits); });
  }

  /// Any hits: (N,) bool, and (N, 2) uint64 statistics or None.
  py::tuple occluded(const py::handle& rays_object, bool with_stats, bool packets, bool check) const {
    return trace_batch(
        rays_object, with_stats, packets, check, [](std::size_t n) { return answer_array(n); },
        [](const Accelerator& accel, auto rays, auto answers, auto stats) { accel.occluded(rays, answers, stats); },
        [](const Accelerator& accel, auto rays, auto answers) { accel.occluded_packets(rays, answers); });
  }

  /// Closest hits ((N, 16) uint8 records, written into `out` when given) or, with `any`, any hits ((N,) bool) under
  /// the query controls (see ContextArrays): skipped primitives and geometries, masks, primitive switches. With
  /// `packets`, through the packet forms (intersect_packets(), occluded_packets()).
  py::object trace_in_context(const py::handle& rays_object, bool any, bool packets, bool check, const py::object& out,
                              const py::object& skip, const py::object& skip_geometry, const py::object& mask,
                              const py::object& geometry_mask, const std::shared_ptr<GeometryTable>& geometries,
                              const py::object& enabled) const {
    const BatchRays<Ray> batch(rays_object);
    const std::span<const Ray> rays = batch.rays;
    const std::shared_ptr<Scene> built_over = scene();
    if (!built_over) read_built([](const Accelerator&) {});  // raises the not-built ValueError
    const ContextArrays controls(skip, skip_geometry, mask, geometry_mask, geometries, enabled, rays.size(),
                                 *built_over);
    if (any) {
      auto [answers, answer_span] = answer_array(rays.size());
      trace(rays, check, [&](const Accelerator& accel, std::size_t begin, std::size_t end) {
        const QueryContext context = controls.slice(begin, end);
        const auto block = rays.subspan(begin, end - begin);
        const auto answers_block = answer_span.subspan(begin, end - begin);
        if (packets) {
          accel.occluded_packets(context, block, answers_block);
        } else {
          accel.occluded(context, block, answers_block);
        }
      });
      return answers;
    }
    auto [records, hits] = record_array<Hit>(rays.size(), out);
    trace(rays, check, [&](const Accelerator& accel, std::size_t begin, std::size_t end) {
      const QueryContext context = controls.slice(begin, end);
      const auto block = rays.subspan(begin, end - begin);
      const auto hits_block = hits.subspan(begin, end - begin);
      if (packets) {
        accel.intersect_packets(context, block, hits_block);
      } else {
        accel.intersect(context, block, hits_block);
      }
    });
    return records;
  }

  /// Hit points (recomputed from the primitive) and unit geometric normals, (N, 3) float32 each, NaN at misses.
  py::tuple surface(const py::handle& rays_object, const py::array_t<std::uint8_t, py::array::c_style>& records) const {
    const BatchRays<Ray> batch(rays_object);
    const std::span<const Ray> rays = batch.rays;
    if (records.ndim() != 2 || records.shape(1) != 16 || static_cast<std::size_t>(records.shape(0)) != rays.size()) {
      throw ValueError("hit records must have shape (N, 16) with N = the number of rays");
    }
    const auto n = static_cast<py::ssize_t>(rays.size());
    py::array_t<float> points({n, py::ssize_t{3}});
    py::array_t<float> normals({n, py::ssize_t{3}});
    const Hit* hits = reinterpret_cast<const Hit*>(records.data());
    float* p = points.mutable_data();
    float* nrm = normals.mutable_data();
    query([&](const Accelerator&, const Scene& scene) {
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
    });
    return py::make_tuple(points, normals);
  }

  /// Every crossing of each ray: (counts (N,) uint32 before the cap, records (M, 16) uint8 in the .hits layout, the
  /// kept crossings ray after ray, each ray's by t).
  py::tuple all_hits(const py::handle& rays_object, std::uint64_t max_hits, bool check) const {
    const BatchRays<Ray> batch(rays_object);
    const std::span<const Ray> rays = batch.rays;
    py::array_t<std::uint32_t> counts(static_cast<py::ssize_t>(rays.size()));
    std::vector<std::vector<Hit>> per_ray(rays.size());
    std::uint32_t* count = counts.mutable_data();
    trace(
        rays, check,
        [&](const Accelerator& accel, std::size_t begin, std::size_t end) {
          detail::parallel_for_rays(end - begin, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = begin + b; i < begin + e; ++i) {
              count[i] = static_cast<std::uint32_t>(accel.all_hits(rays[i], per_ray[i], max_hits));
            }
          });
        },
        require_queries);
    std::size_t total = 0;
    for (const auto& h : per_ray) total += h.size();
    py::array_t<std::uint8_t> records({static_cast<py::ssize_t>(total), py::ssize_t{16}});
    Hit* out = reinterpret_cast<Hit*>(records.mutable_data());
    for (const auto& h : per_ray) out = std::copy(h.begin(), h.end(), out);
    return py::make_tuple(counts, records);
  }

  /// Crossings per ray, (N,) uint32.
  py::array_t<std::uint32_t> count_hits(const py::handle& rays_object, bool check) const {
    const BatchRays<Ray> batch(rays_object);
    const std::span<const Ray> rays = batch.rays;
    py::array_t<std::uint32_t> counts(static_cast<py::ssize_t>(rays.size()));
    const std::span<std::uint32_t> out(counts.mutable_data(), rays.size());
    trace(
        rays, check,
        [&](const Accelerator& accel, std::size_t begin, std::size_t end) {
          accel.count_hits(rays.subspan(begin, end - begin), out.subspan(begin, end - begin));
        },
        require_queries);
    return counts;
  }

  /// Closest points: (N, 28) uint8 records in the .closest layout.
  py::array_t<std::uint8_t> closest_points(const py::handle& points_object, float max_distance) const {
    const auto points_array = float_rows(points_object, 3, "points");
    const std::span<const Vec3> points = point_view(points_array);
    static_assert(sizeof(ClosestPoint) == 28, "the .closest record");
    auto [records, out] = record_array<ClosestPoint>(points.size(), py::none());
    query([&](const Accelerator& accel, const Scene&) {
      require_queries(accel).closest_points(points, out, max_distance);
    });
    return records;
  }

  /// Crossing-parity inside test, (N,) bool.
  py::array_t<bool> inside(const py::handle& points_object, int ray_count) const {
    const auto points_array = float_rows(points_object, 3, "points");
    const std::span<const Vec3> points = point_view(points_array);
    auto [answers, out] = answer_array(points.size());
    query([&](const Accelerator& accel, const Scene&) {
      inside_by_parity(require_queries(accel), points, out, {.ray_count = ray_count});
    });
    return answers;
  }

  /// Signed distances, (N,) float32 (negative inside).
  py::array_t<float> signed_distance(const py::handle& points_object, int ray_count) const {
    const auto points_array = float_rows(points_object, 3, "points");
    const std::span<const Vec3> points = point_view(points_array);
    py::array_t<float> distances(static_cast<py::ssize_t>(points.size()));
    const std::span<float> out(distances.mutable_data(), points.size());
    query([&](const Accelerator& accel, const Scene&) {
      signed_distances(require_queries(accel), points, out, {}, {.ray_count = ray_count});
    });
    return distances;
  }

  /// An image through the library's renderer, (height, width, 3) uint8.
  py::array_t<std::uint8_t> render(const RenderRequest& request) const {
    const Image image =
        query([&](const Accelerator& accel, const Scene& scene) { return render_image(accel, scene, request); });
    return image_array(image);
  }

 private:
  /// The one batch body of intersect() and occluded(): `make_out(n)` gives the result array and its per-ray span,
  /// filled block by block by `single(accel, rays, out, stats)` or, with `packets`, `grouped(accel, rays, out)`;
  /// returns (results, (N, 2) uint64 statistics or None).
  template <class MakeOut, class Single, class Grouped>
  py::tuple trace_batch(const py::handle& rays_object, bool with_stats, bool packets, bool check, MakeOut make_out,
                  Single single, Grouped grouped) const {
    const BatchRays<Ray> batch(rays_object);
    const std::span<const Ray> rays = batch.rays;
    if (packets && with_stats) throw ValueError("packets=True gives no per-ray statistics (stats=False)");
    auto [results, out] = make_out(rays.size());
    py::object stats_array = py::none();
    const std::span<TraversalStats> stats =
        with_stats ? statistics_array(rays.size(), stats_array) : std::span<TraversalStats>{};
    trace(rays, check, [&](const Accelerator& accel, std::size_t begin, std::size_t end) {
      const auto block = rays.subspan(begin, end - begin);
      const auto out_block = out.subspan(begin, end - begin);
      if (packets) {
        grouped(accel, block, out_block);
      } else {
        single(accel, block, out_block, stats.empty() ? stats : stats.subspan(begin, end - begin));
      }
    });
    return py::make_tuple(results, stats_array);
  }

  /// `accel` when it answers all-hits and closest-point queries (ValueError naming it otherwise).
  static const Accelerator& require_queries(const Accelerator& accel) {
    if (!accel.supports_queries()) {
      throw ValueError("'" + accel.spec() + "' does not answer all-hits, closest-point or inside queries; build "
                       "brute_force, bvh[:...] or bvh_wide[:...]");
    }
    return accel;
  }
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
      .def("update", &PyAccelerator::update,
           "After the scene's arrays moved in place (Scene.arrays_changed()): refit where the structure can (bvh, "
           "bvh_wide), else rebuild; returns 'refitted' or 'rebuilt'")
      .def("save", &PyAccelerator::save, py::arg("path"),
           "Write the built structure (bvh, bvh_wide) to a versioned file checked against the scene on load")
      .def("load", &PyAccelerator::load, py::arg("path"), py::arg("scene"),
           "Replace this structure by the one saved in path (its kind read from the file), built over scene; "
           "ValueError naming the file for a truncated, foreign, stale or wrong-version one")
      .def_property_readonly("supports_refit", &PyAccelerator::supports_refit)
      .def_property_readonly("supports_save", &PyAccelerator::supports_save)
      .def("_intersect", &PyAccelerator::intersect, py::arg("rays"), py::arg("stats"), py::arg("packets"),
           py::arg("check"), py::arg("out"))
      .def("_occluded", &PyAccelerator::occluded, py::arg("rays"), py::arg("stats"), py::arg("packets"),
           py::arg("check"))
      .def("_trace_in_context", &PyAccelerator::trace_in_context, py::arg("rays"), py::arg("any"), py::arg("packets"),
           py::arg("check"),
           py::arg("out"), py::arg("skip"), py::arg("skip_geometry"), py::arg("mask"), py::arg("geometry_mask"),
           py::arg("geometries"), py::arg("enabled"))
      .def("_surface", &PyAccelerator::surface, py::arg("rays"), py::arg("records"))
      .def("_all_hits", &PyAccelerator::all_hits, py::arg("rays"), py::arg("max_hits"), py::arg("check"))
      .def("_count_hits", &PyAccelerator::count_hits, py::arg("rays"), py::arg("check"))
      .def("_closest_points", &PyAccelerator::closest_points, py::arg("points"), py::arg("max_distance"))
      .def("_inside", &PyAccelerator::inside, py::arg("points"), py::arg("ray_count"))
      .def("_signed_distance", &PyAccelerator::signed_distance, py::arg("points"), py::arg("ray_count"))
      .def("_render", [](const PyAccelerator& self, const std::array<float, 3>& eye, const std::array<float, 3>& at,
                         const std::array<float, 3>& up, float fov, int width, int height, const std::string& mode,
                         int ao_samples, float ao_distance, std::uint64_t seed) {
        return self.render({eye, at, up, fov, width, height, mode, ao_samples, ao_distance, seed});
      });
  m.def("_structures", &structures);
  m.def("_winding_numbers", [](const std::shared_ptr<Scene>& scene, const py::handle& points_object) {
    if (!scene) throw TypeError("winding_numbers() needs a rayaccel.Scene, not None");
    const auto points_array = float_rows(points_object, 3, "points");
    const std::span<const Vec3> points = point_view(points_array);
    py::array_t<double> winding(static_cast<py::ssize_t>(points.size()));
    const std::span<double> out(winding.mutable_data(), points.size());
    {
      py::gil_scoped_release release;
      winding_numbers(*scene, points, out);
    }
    return winding;
  });
  m.def("default_spec", &default_accelerator_spec,
        "The spec build() and Accelerator() use when none is given (the catalog's fastest structure).");
  m.def("specs", &accelerator_variant_names,
        "Every spec `rayaccel list --names` prints, in registry order (each one accepted by build()).");
}

}  // namespace rayaccel::python
