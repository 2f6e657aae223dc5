// Internals of `rayaccel bench` shared by its files: options (bench_command.cpp), workloads (bench_workloads.cpp),
// measuring (bench_run.cpp), the check against a reference (bench_check.cpp), table and JSON (bench_report.cpp) and
// the HTML page (bench_html.cpp).
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/brute_force.h"
#include "rayaccel/render/camera.h"
#include "rayaccel/render/heatmap.h"
#include "rayaccel/scene/scene.h"
#include "progress.h"

namespace rayaccel::cli {

/// shadow: short ambient-occlusion rays from pbrt-tight origins; occlusion: longer ones from origins a fixed epsilon
/// off the surface; light: rays to a point light; packet: the primary rays reordered so that each run of eight is a
/// 4 x 2 pixel tile (packet_tile_order()); light_packet: the light rays of the primary hits in that order. The _skip
/// kinds are the diffuse, shadow, occlusion and light rays again, each traced under a QueryContext that skips the
/// primitive its origin lies on (what a renderer knows of a secondary ray; not in the default set, since their
/// answers differ from the plain kinds' only where a ray would re-hit its own surface). bench_command.cpp's footer
/// gives the lengths. beam: the primary rays traced by beams (generalized::trace_beams()), not in the default set.
enum class RayKind {
  primary,
  diffuse,
  shadow,
  occlusion,
  light,
  packet,
  light_packet,
  diffuse_skip,
  shadow_skip,
  occlusion_skip,
  light_skip,
  beam
};
const char* to_string(RayKind kind);
/// Packet kinds are traced eight rays at a time (beam: by beams, whole images) and take no statistics.
inline bool is_packet_kind(RayKind kind) {
  return kind == RayKind::packet || kind == RayKind::light_packet || kind == RayKind::beam;
}
/// The _skip kinds are traced under a QueryContext and take no statistics either.
inline bool is_skip_kind(RayKind kind) {
  return kind == RayKind::diffuse_skip || kind == RayKind::shadow_skip || kind == RayKind::occlusion_skip ||
         kind == RayKind::light_skip;
}

/// One set of rays traced the same way for every structure: intersect() for primary and diffuse, occluded() for
/// shadow, occlusion and light rays, intersect_packets() for packet rays, occluded_packets() for light_packet rays;
/// the _skip kinds as their plain kind, under a QueryContext with `skip` as its skip_primitive.
struct Workload {
  RayKind kind = RayKind::primary;
  std::vector<Ray> rays;
  std::vector<std::uint32_t> skip;  ///< the _skip kinds: per ray, the primitive its origin lies on; else empty
  const Scene* scene = nullptr;      ///< beam: the scene, for the structure's beams
  CameraFrame frame;                 ///< beam: the image whose pixel rays `rays` are, row by row
  bool any_hit() const {
    return kind == RayKind::shadow || kind == RayKind::occlusion || kind == RayKind::light ||
           kind == RayKind::light_packet || kind == RayKind::shadow_skip || kind == RayKind::occlusion_skip ||
           kind == RayKind::light_skip;
  }
  bool packets() const { return is_packet_kind(kind); }
  bool skips() const { return is_skip_kind(kind); }
};

/// Traces `rays` (the workload's rays, or some of them with `skip` their entries of w.skip) the way w's kind is traced,
/// into `hits` (closest-hit kinds) or `occluded` (any-hit kinds), sized as `rays`; `packets` traces them eight at a time
/// (the packet kinds' whole workload only). The one dispatch of the timed passes and the check.
void trace_rays(const Accelerator& accel, const Workload& w, std::span<const Ray> rays,
                std::span<const std::uint32_t> skip, std::span<Hit> hits, std::span<std::uint8_t> occluded,
                bool packets);
/// The answers of `accel` to rays `ids` of workload `w`, as its kind is traced: closest hits (`hits`) or occlusion
/// (`occluded`), the _skip kinds under a QueryContext skipping each ray's origin primitive. Packet workloads are traced
/// whole with intersect_packets() or occluded_packets() (a subset's rays put together would not be its packets),
/// unless `ray_by_ray` (the reference's answers: one ray at a time, whatever the kind). Returns the rays `ids`.
std::vector<Ray> trace_workload(const Accelerator& accel, const Workload& w, const std::vector<std::size_t>& ids,
                                std::vector<Hit>& hits, std::vector<std::uint8_t>& occluded, bool ray_by_ray = false);

/// The kinds named in --rays ("primary,shadow,..."), in the given order, each once; UsageError for an unknown one.
std::vector<RayKind> parse_kinds(const std::string& text);
/// The workloads of `kinds` over the N x N `primary` rays of `camera` and their closest hits `primary_hits`.
std::vector<Workload> make_workloads(const Scene& scene, const Camera& camera, const std::vector<RayKind>& kinds,
                                     int resolution, const std::vector<Ray>& primary,
                                     const std::vector<Hit>& primary_hits);

/// What the command line asks of a run.
struct BenchArgs {
  std::vector<std::string> scenes;
  std::string accel;  ///< empty: the default structure; "all": every variant; else a comma list of specs
  std::string rays = "primary,diffuse,shadow,occlusion,light,packet,light_packet";
  int resolution = 256;
  int threads = 0;
  int repeat = 5;
  std::string compare;
  std::string json;
  std::string images;  ///< set by --images, or to REPORT/images by --report
  std::string report;
  std::uint64_t heat_max = 0;  ///< 0: every heat map of the run on one shared scale, drawn at the end
};

/// A heat map waiting for the run's shared colour scale.
struct PendingHeatMap {
  std::filesystem::path file;
  HeatFrame frame;
};

/// The file name of a structure's "normals" or "heatmap" image for one scene.
std::string bench_image_name(const std::string& scene_name, const std::string& spec, const char* mode_name);

struct KindResult {
  RayKind kind = RayKind::primary;
  std::size_t rays = 0;
  std::vector<double> trace_ms;
  double mrays_s_median = 0.0;
  double nodes_per_ray = -1.0;  ///< -1 when the structure reports no statistics (Embree; packet rays)
  double prims_per_ray = -1.0;
  std::size_t checked = 0;              ///< rays compared against the reference
  std::size_t mismatches = 0;           ///< rays where the structure disagrees with the oracle
  std::size_t reference_differences = 0;  ///< Embree disagreed but the structure matches brute force
  std::size_t foreign_differences = 0;    ///< Embree's row: sampled rays where Embree breaks the foreign-kernel rule
};

struct StructureResult {
  std::string spec;
  bool is_embree = false;
  std::string failure;  ///< build or trace error; the row has no figures then
  std::vector<double> build_ms;
  double build_ms_median = 0.0;
  std::size_t memory_bytes = 0;        ///< the structure's own data
  std::size_t input_memory_bytes = 0;  ///< the input queries read besides it (Accelerator::input_memory_bytes)
  std::vector<BuildStatistic> build_statistics;
  std::vector<std::string> validate_problems;
  std::vector<KindResult> kinds;
  std::size_t mismatches() const;
  bool failed() const { return !failure.empty() || !validate_problems.empty() || mismatches() > 0; }
};

struct SceneReport {
  std::string spec;
  std::string name;
  std::string kind;
  std::uint32_t primitives = 0;
  int threads = 0;
  int resolution = 0;
  std::string reference;  ///< "embree (all rays)" or "brute_force (sample of N rays)"
  double scene_preparation_ms = 0.0;  ///< included in the build times of rayaccel's structures
  std::vector<StructureResult> rows;
};

/// Measures every structure of `specs` (and Embree with --compare embree) on one scene.
SceneReport bench_scene(const std::string& scene_spec, const std::vector<std::string>& specs,
                        const std::vector<RayKind>& kinds, const BenchArgs& args, Progress& progress,
                        std::vector<PendingHeatMap>& heat_maps);
/// Draws every kept heat map on one scale, the shared_cost_range() of all of them, and writes them; returns the
/// scale (empty when there were none).
CostRange write_shared_heat_maps(std::vector<PendingHeatMap>& heat_maps, Progress& progress);

/// The reference every structure is checked against before timing: Embree's answers for every ray when it is
/// available (every ray where the structure names another primitive or hit/miss is then settled by brute force,
/// the oracle, and so is a brute-force sample of every workload, where the structure and Embree could be wrong
/// alike), else brute force on a sample. A closest hit agrees with the oracle when it names the same primitive or
/// another one at exactly the same t (a tie); every closest hit must also carry the kernel's own t, u, v for the
/// primitive it names (kernel_fault()). Embree's own row is checked on the sample by the rule that fits a foreign
/// kernel (check_foreign()).
class ReferenceCheck {
 public:
  /// `embree` may be null. `sample_size` bounds the brute-force sample per workload.
  ReferenceCheck(const Scene& scene, const std::vector<Workload>& workloads, const Accelerator* embree,
                 std::size_t sample_size);
  /// Compares `accel` with the reference on every workload; fills checked / mismatches / reference_differences
  /// of `kinds` (one per workload) and prints the first mismatches to stderr. Packet workloads are traced whole
  /// with intersect_packets() or occluded_packets() (so the packets are the timed ones) and compared with the
  /// reference's single-ray answers.
  void check(const Accelerator& accel, std::vector<KindResult>& kinds) const;
  /// Embree's row (`foreign`, another triangle kernel): its answers on the brute-force sample must hit or miss (be
  /// occluded or not) as brute force does, closest hits at a t within kForeignRelativeT of brute force's t on any
  /// primitive; its t, u, v are not compared bit for bit, since its kernel rounds differently and, without
  /// RTC_SCENE_FLAG_ROBUST, is not watertight. Fills checked / foreign_differences of `kinds` and prints the first
  /// differences; they are reported, not failures (the bench measures Embree, it does not certify it). Needs Embree
  /// as the reference (there is no sample otherwise): does nothing without it.
  void check_foreign(const Accelerator& foreign, std::vector<KindResult>& kinds) const;
  std::string description() const;
  /// Relative t tolerance of check_foreign(), the one tests/compare holds Embree to against brute force.
  static constexpr float kForeignRelativeT = 1e-4f;

 private:
  struct Answers {
    std::vector<std::size_t> indices;  ///< rays with a reference answer
    std::vector<std::size_t> sample;   ///< with Embree: positions in `indices` that brute force always decides
    std::vector<Hit> hits;             ///< per index (closest-hit workloads)
    std::vector<std::uint8_t> occluded;  ///< per index (any-hit workloads)
  };
  const Scene& scene_;
  const std::vector<Workload>& workloads_;
  bool from_embree_ = false;
  std::size_t sample_size_ = 0;
  /// Brute force's answer to a ray on which a structure and Embree disagreed.
  struct Settled {
    Hit hit;
    bool occluded = false;
  };
  /// Settles the given disagreements of one workload (indices into its Answers) by brute force, once per ray.
  void settle(std::size_t workload, const std::vector<std::size_t>& indices) const;

  BruteForce oracle_;
  std::vector<Answers> answers_;
  mutable std::vector<std::unordered_map<std::size_t, Settled>> settled_;  ///< per workload: ray index -> answer
};

/// Empty when `hit` is what the scene's own kernel (the one brute force uses) gives for the primitive it names,
/// bit for bit in t, u and v (a miss: t = +inf, u = v = 0); else what differs.
std::string kernel_fault(const Scene& scene, const Ray& ray, const Hit& hit);

/// The Embree the bench builds, as its reference and its row: plain "embree", or, when a _skip kind is asked for,
/// kEmbreeWithFilter, whose scene takes the context filter the skip queries go through.
inline constexpr const char* kEmbreeWithFilter = "embree:filter=1";
std::string bench_embree_spec(const std::vector<RayKind>& kinds);
/// The bench's own Embree row (the one ratios are taken to) when it was measured without failing, else null.
const StructureResult* embree_row(const SceneReport& report);
/// Two decimals, or three significant digits for small values (brute force runs at thousandths of a Mray/s).
std::string number(double value);

/// The per-scene tables on stdout (build and memory; Mrays/s; traversal cost), each aligned and narrow enough for
/// a terminal, with ratios to the Embree row when there is one.
void print_table(const SceneReport& report);
nlohmann::json to_json(const SceneReport& report);

/// The run as one self-contained HTML page, DIR/index.html: per scene the table, bar charts (inline SVG) and every
/// structure's normals and heat-map images (`images`, relative to DIR) on the run's shared colour scale `heat`,
/// with the machine and the commit. Nothing is fetched from the network.
void write_html_report(const std::filesystem::path& dir, const std::vector<SceneReport>& reports,
                       const std::filesystem::path& images, const CostRange& heat, const BenchArgs& args);

}  // namespace rayaccel::cli
