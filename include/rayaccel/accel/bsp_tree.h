// General BSP tree with arbitrary split planes (Ize, Wald & Parker 2008, "Ray tracing with the BSP tree"): cells
// are convex polytopes, candidate planes come from the primitives' own planes and 13 fixed k-DOP directions, chosen
// by SAH over the clipped polytopes' surface areas; traversed front to back like the kd-tree.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "rayaccel/accel/accelerator.h"
#include "rayaccel/accel/option_table.h"
#include "rayaccel/accel/registry.h"
#include "rayaccel/accel/segment_traversal.h"
#include "rayaccel/geometry/ray_box.h"

namespace rayaccel {

/// max_depth, leaf_size and the two SAH costs are KdTreeOptions' too (registered once: add_split_tree_options()); each
/// tree keeps its own struct for its own defaults (leaf_size 1 or 2, intersection_cost 20 or 3).
struct BspTreeOptions {
  /// Deepest allowed leaf; 0 picks round(8 + 1.3 log2 n), as the kd-tree. At most kMaxSplitTreeDepth.
  int max_depth = 0;
  /// A node with at most this many references becomes a leaf without trying splits.
  int leaf_size = 1;
  /// SAH cost of one traversal step and of one primitive test.
  float traversal_cost = 15.0f;
  float intersection_cost = 20.0f;
  /// Nodes with more references than this use the cheap candidate set: 16 bins per k-DOP direction and the own
  /// planes of 8 evenly strided references; smaller nodes try every reference's extents and every own plane.
  int exact_threshold = 12;
  /// Try the primitives' own supporting planes (triangles only).
  bool own_planes = true;
};

/// One BSP node in 24 bytes. Nodes are stored depth first: an interior node's below child (dot(normal, p) <=
/// offset) is the next node, its above child sits at above_child().
struct BspNode {
  Vec3 normal;  // bytes 0-11: unit plane normal (interior nodes)
  float offset = 0.0f;  // bytes 12-15: the plane is dot(normal, p) == offset, evaluated in double
  // bytes 16-19: bit 0 = 1 for a leaf; bits 1-31 = interior: index of the above child, leaf: reference count.
  std::uint32_t bits = 1;
  // bytes 20-23: leaf: index of its first entry in the primitive-index array; 0 for interior nodes.
  std::uint32_t prim_offset = 0;

  static constexpr std::uint32_t kMaxField = (1u << 31) - 1;
  static BspNode interior(const Vec3& n, float d, std::uint32_t above) { return {n, d, above << 1, 0}; }
  static BspNode leaf(std::uint32_t offset, std::uint32_t count) { return {{}, 0.0f, (count << 1) | 1u, offset}; }
  bool is_leaf() const { return (bits & 1u) != 0; }
  std::uint32_t above_child() const { return bits >> 1; }
  std::uint32_t prim_count() const { return bits >> 1; }
};
static_assert(sizeof(BspNode) == 24, "BSP nodes are 24 bytes");

/// The 13 k-DOP directions (3 axes, 4 cube diagonals, 6 face diagonals), unit length.
const std::vector<Vec3>& kdop13_directions();

/// A convex polytope as its outward faces (vertices counter-clockwise seen from outside). Used for BSP cells.
class Polytope {
 public:
  struct Face {
    Vec3 normal;  ///< outward unit normal
    double offset = 0.0;  ///< the face lies in dot(normal, p) == offset
    std::vector<Vec3> vertices;
    double area = 0.0;                         ///< cached polygon area
    double vector_area[3] = {0.0, 0.0, 0.0};  ///< cached area times unit normal (right-hand winding)
  };
  static Polytope from_box(const AABB& box);
  const std::vector<Face>& faces() const { return faces_; }
  bool is_empty() const { return faces_.empty(); }
  double surface_area() const;
  /// Surface areas of the parts below (dot(n, p) <= d) and above the plane, without building them: the clipped
  /// faces plus the cut, whose area is the length of the summed vector areas of the clipped faces (a closed
  /// surface's vector areas sum to zero). Only faces the plane crosses are clipped, and only once: the part above
  /// is the face minus the part below.
  void split_areas(const Vec3& n, double d, double& below, double& above) const;
  /// split_areas() for many offsets along one normal: the faces' extents along `n` are computed once, so only
  /// faces an offset actually crosses are clipped.
  class Slicer {
   public:
    Slicer(const Polytope& polytope, const Vec3& n);
    void split_areas(double d, double& below, double& above) const;

   private:
    const Polytope& polytope_;
    Vec3 normal_;
    std::vector<double> lo_, hi_;  ///< per face: extent of its vertices along the normal
  };
  /// The part below (keep_below) or above the plane, closed by a new face in the plane; empty when nothing is left.
  Polytope clip(const Vec3& n, double d, bool keep_below) const;
  /// Extent of the vertices along direction n.
  void extent(const Vec3& n, double& lo, double& hi) const;

 private:
  void add_face(Face face);

  std::vector<Face> faces_;
};

/// A built BSP tree in its traversal layout.
struct BspTreeData {
  std::vector<BspNode> nodes;               ///< depth first; empty for an empty scene
  std::vector<std::uint32_t> prim_indices;  ///< leaf references, leaf by leaf
  AABB bounds;                              ///< the root cell (the scene box)
  double sah_cost = 0.0;                    ///< SAH cost of the built tree, relative to the root's area
  int max_depth = 0;                        ///< the depth limit the build used
  double tolerance = 0.0;  ///< a reference within this distance of a plane went to both sides
};

/// Builds over the scene's valid primitives. Triangles are clipped to each cell (a triangle goes to every side
/// that a part of it inside the cell reaches, with a small tolerance); other primitives use their boxes.
BspTreeData build_bsp_tree(const Scene& scene, const BspTreeOptions& options);

/// The BspTree's options: key, member, range and doc of each (the registry's options, their parsing and checks).
const OptionTable<BspTreeOptions>& bsp_tree_option_table();

class BspTree final : public AcceleratorImpl<BspTree> {
 public:
  /// Throws Error naming the first option outside its range (bsp_tree_option_table()).
  explicit BspTree(BspTreeOptions options = {});

  void build(const Scene& scene) override;
  std::size_t memory_bytes() const override {
    return data_.nodes.size() * sizeof(BspNode) + data_.prim_indices.size() * sizeof(std::uint32_t);
  }
  std::vector<BuildStatistic> build_statistics() const override;
  std::vector<std::string> validate() const override;
  const BspTreeData& data() const { return data_; }

  /// Clips the ray to the scene box, then walks the cells front to back (segment_traversal.h). The crossing
  /// distance of each plane is computed in double with an error bound, so the near and far segments overlap by
  /// at least the rounding error; a ray parallel to a plane (dot(normal, d) == 0) visits its origin's side only,
  /// both sides when its origin lies in the plane.
  template <bool AnyHit, class Stats>
  void trace(const PreparedRay& ray, Hit& hit, Stats& stats) const {
    float t0 = ray.t_min, t1 = ray.t_max;
    if (data_.nodes.empty() || !clip_ray_to_box(ray, data_.bounds, t0, t1)) return;
    t0 = std::fmax(ray.t_min, t0 * (t0 >= 0.0f ? kSlabWidenDown : kSlabWidenUp));
    traverse_segments(0, t0, t1, hit, [&](const SegmentEntry& entry, ChildSegments& children) {
      const BspNode& node = data_.nodes[entry.node];
      stats.visit_node();
      if (!node.is_leaf()) {
        const Vec3& n = node.normal;
        const double nx = double(n.x) * ray.origin.x, ny = double(n.y) * ray.origin.y,
                     nz = double(n.z) * ray.origin.z;
        const double offset = nx + ny + nz - node.offset;
        const double rate =
            double(n.x) * ray.direction.x + double(n.y) * ray.direction.y + double(n.z) * ray.direction.z;
        const int side = offset < 0.0 ? -1 : (offset > 0.0 ? 1 : 0);
        float lo = 0.0f, hi = 0.0f;
        if (rate != 0.0) {
          const double t = -offset / rate;
          // Double rounding of both sums (each relative to the sum of its terms' magnitudes) and of the
          // division, bounded generously; the float rounding is covered by stepping one ulp outward.
          const double offset_terms = std::fabs(nx) + std::fabs(ny) + std::fabs(nz) + std::fabs(node.offset);
          const double rate_terms = std::fabs(double(n.x) * ray.direction.x) +
                                    std::fabs(double(n.y) * ray.direction.y) +
                                    std::fabs(double(n.z) * ray.direction.z);
          const double error = 0x1p-48 * ((offset_terms + std::fabs(t) * rate_terms) / std::fabs(rate) + std::fabs(t));
          constexpr float kInf = std::numeric_limits<float>::infinity();
          lo = std::nextafter(static_cast<float>(t - error), -kInf);
          hi = std::nextafter(static_cast<float>(t + error), kInf);
        }
        const float rate_sign = rate > 0.0 ? 1.0f : (rate < 0.0 ? -1.0f : 0.0f);
        children = split_segment(entry.node + 1, node.above_child(), side, rate_sign, lo, hi, entry.t0, entry.t1);
        return SegmentVisit::descend;
      }
      const std::uint32_t* ids = data_.prim_indices.data() + node.prim_offset;
      for (std::uint32_t i = 0, count = node.prim_count(); i < count; ++i) {
        if (test_scene_primitive(*scene_, ids[i], ray, hit, stats) && AnyHit) return SegmentVisit::stop;
      }
      return SegmentVisit::leaf_done;
    });
  }

 private:
  BspTreeOptions options_;
  const Scene* scene_ = nullptr;
  BspTreeData data_;
  double build_ms_ = 0.0;
};

void register_bsp_tree(std::vector<AcceleratorInfo>& registry);

}  // namespace rayaccel
