// Beam construction and the conservative beam/box, beam/ball and beam/triangle tests (separating planes tried both
// ways), and the proof that one triangle lies in front of another set over a whole beam.
#include "rayaccel/generalized/beam.h"

#include <algorithm>

#include "rayaccel/core/float_rounding.h"

namespace rayaccel::generalized {

namespace {

using detail::dcross;
using detail::ddot;
using detail::dsub;

/// Value of a linear form n . v, and the bound it must clear for its sign to be trusted.
struct Signed {
  double value;
  double bound;
  bool surely_positive() const { return value > bound; }
  bool surely_negative() const { return value < -bound; }
};

Signed signed_dot(const DVec3& n, const DVec3& v) { return {ddot(n, v), kBeamMargin * dabs_dot(n, v)}; }

/// p - apex for float p, in double (the difference of two floats; rounding far below kBeamMargin).
DVec3 from_apex(const Vec3& apex, const Vec3& p) { return dsub(to_d(p), to_d(apex)); }

bool finite(const DVec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

Beam Beam::through(const Vec3& apex, const DVec3* edges, int count) {
  Beam beam;
  beam.apex = apex;
  if (count < 3 || count > kMaxSides || !is_finite(apex)) return beam;
  DVec3 mean{0, 0, 0};
  for (int i = 0; i < count; ++i) {
    if (!finite(edges[i]) || dnorm(edges[i]) == 0.0) return beam;
    const double len = dnorm(edges[i]);
    mean = {mean.x + edges[i].x / len, mean.y + edges[i].y / len, mean.z + edges[i].z / len};
  }
  for (int i = 0; i < count; ++i) {
    const DVec3& e0 = edges[i];
    const DVec3& e1 = edges[(i + 1) % count];
    DVec3 n = dcross(e0, e1);
    if (dnorm(n) <= 1e-7 * dnorm(e0) * dnorm(e1)) return beam;  // neighbours (nearly) parallel
    if (ddot(n, mean) < 0.0) n = {-n.x, -n.y, -n.z};
    beam.edge[i] = e0;
    beam.normal[i] = n;
  }
  // Convex and less than a half-space: every edge ray strictly inside (or on) every other side, and the mean inside.
  for (int i = 0; i < count; ++i) {
    if (!signed_dot(beam.normal[i], mean).surely_positive()) return beam;
    for (int j = 0; j < count; ++j) {
      if (j == i || j == (i + 1) % count) continue;
      if (!signed_dot(beam.normal[i], edges[j]).surely_positive()) return beam;
    }
  }
  beam.side_count = count;
  return beam;
}

bool Beam::contains(const Vec3& d) const {
  if (!valid()) return false;
  for (int i = 0; i < side_count; ++i) {
    if (!signed_dot(normal[i], to_d(d)).surely_positive()) return false;
  }
  return true;
}

bool Beam::box_outside(const AABB& box, float slack) const {
  if (box.is_empty()) return true;
  if (!valid()) return false;
  const DVec3 lo{double(box.lo.x) - slack, double(box.lo.y) - slack, double(box.lo.z) - slack};
  const DVec3 hi{double(box.hi.x) + slack, double(box.hi.y) + slack, double(box.hi.z) + slack};
  const DVec3 a = to_d(apex);
  // The beam's sides: the box corner farthest along the inward normal is still outside.
  for (int i = 0; i < side_count; ++i) {
    const DVec3& n = normal[i];
    const DVec3 corner{(n.x >= 0 ? hi.x : lo.x) - a.x, (n.y >= 0 ? hi.y : lo.y) - a.y, (n.z >= 0 ? hi.z : lo.z) - a.z};
    if (signed_dot(n, corner).surely_negative()) return true;
  }
  // The box's faces: the apex beyond a face and every edge ray moving away from it.
  for (int axis = 0; axis < 3; ++axis) {
    bool above = a[axis] > hi[axis], below = a[axis] < lo[axis];
    for (int i = 0; i < side_count && (above || below); ++i) {
      const double e = edge[i][axis], scale = kBeamMargin * dnorm(edge[i]);
      above = above && e > scale;
      below = below && e < -scale;
    }
    if (above || below) return true;
  }
  return false;
}

bool Beam::sphere_outside(const Vec3& center, float radius) const {
  if (!(radius >= 0.0f)) return true;  // the empty ball
  if (!valid() || !std::isfinite(radius)) return false;
  const DVec3 c = from_apex(apex, center);
  for (int i = 0; i < side_count; ++i) {
    const Signed s = signed_dot(normal[i], c);
    const double reach = double(radius) * dnorm(normal[i]);
    if (s.value + s.bound + reach * (1.0 + kBeamMargin) < 0.0) return true;
  }
  return false;
}

bool Beam::triangle_outside(const Vec3& a, const Vec3& b, const Vec3& c) const {
  if (!valid()) return false;
  const DVec3 v[3] = {from_apex(apex, a), from_apex(apex, b), from_apex(apex, c)};
  if (!finite(v[0]) || !finite(v[1]) || !finite(v[2])) return false;
  // The beam's sides against the vertices.
  for (int i = 0; i < side_count; ++i) {
    if (signed_dot(normal[i], v[0]).surely_negative() && signed_dot(normal[i], v[1]).surely_negative() &&
        signed_dot(normal[i], v[2]).surely_negative()) {
      return true;
    }
  }
  const auto all_edges = [&](const DVec3& n, bool positive) {
    for (int i = 0; i < side_count; ++i) {
      const Signed s = signed_dot(n, edge[i]);
      if (positive ? !s.surely_positive() : !s.surely_negative()) return false;
    }
    return true;
  };
  // The triangle's plane: the apex strictly on one side and every edge ray moving away from the plane.
  const DVec3 m = dcross(dsub(v[1], v[0]), dsub(v[2], v[0]));
  if (dnorm(m) > 1e-6 * dnorm(dsub(v[1], v[0])) * dnorm(dsub(v[2], v[0]))) {
    const Signed apex_side = signed_dot(m, {-v[0].x, -v[0].y, -v[0].z});
    if (apex_side.surely_positive() && all_edges(m, true)) return true;
    if (apex_side.surely_negative() && all_edges(m, false)) return true;
  }
  // The wedge of each triangle edge seen from the apex: every edge ray on the side away from the third vertex.
  for (int k = 0; k < 3; ++k) {
    const DVec3& p = v[k];
    const DVec3& q = v[(k + 1) % 3];
    const DVec3& r = v[(k + 2) % 3];
    const DVec3 w = dcross(p, q);
    if (!(dnorm(w) > 1e-6 * dnorm(p) * dnorm(q))) continue;  // apex (nearly) on the edge's line: no wedge
    const Signed third = signed_dot(w, r);
    if (third.surely_positive() && all_edges(w, false)) return true;
    if (third.surely_negative() && all_edges(w, true)) return true;
  }
  return false;
}

bool beam_front_of(const Beam& beam, const Vec3& a, const Vec3& b, const Vec3& c, const AABB& back) {
  if (!beam.valid() || back.is_empty() || !back.is_finite()) return false;
  const DVec3 v0 = from_apex(beam.apex, a), v1 = from_apex(beam.apex, b), v2 = from_apex(beam.apex, c);
  DVec3 n = dcross(dsub(v1, v0), dsub(v2, v0));
  const double n_len = dnorm(n);
  if (!(n_len > 1e-6 * dnorm(dsub(v1, v0)) * dnorm(dsub(v2, v0)))) return false;  // (nearly) degenerate
  n = {n.x / n_len, n.y / n_len, n.z / n_len};
  // Orient n away from the apex: the apex must lie strictly on the near side.
  const Signed apex_side = signed_dot(n, {-v0.x, -v0.y, -v0.z});
  if (apex_side.surely_positive()) {
    n = {-n.x, -n.y, -n.z};
  } else if (!apex_side.surely_negative()) {
    return false;
  }
  // The two t error bounds in world units, doubled: depth ranges (at most box diagonals) over 64 and gamma(12) of
  // the farthest vertex distances, each times sqrt(3) (t is measured along the dominant axis of the ray).
  const auto diagonal = [](const DVec3& lo, const DVec3& hi) { return dnorm(dsub(hi, lo)); };
  const DVec3 front_lo{std::min({v0.x, v1.x, v2.x}), std::min({v0.y, v1.y, v2.y}), std::min({v0.z, v1.z, v2.z})};
  const DVec3 front_hi{std::max({v0.x, v1.x, v2.x}), std::max({v0.y, v1.y, v2.y}), std::max({v0.z, v1.z, v2.z})};
  const DVec3 back_lo = from_apex(beam.apex, back.lo), back_hi = from_apex(beam.apex, back.hi);
  const auto farthest = [](const DVec3& lo, const DVec3& hi) {
    return std::max({std::fabs(lo.x), std::fabs(hi.x), std::fabs(lo.y), std::fabs(hi.y), std::fabs(lo.z),
                     std::fabs(hi.z)});
  };
  const double gamma12 = double(float_gamma(12));
  const double margin = 2.0 * std::sqrt(3.0) *
                        ((diagonal(front_lo, front_hi) + diagonal(back_lo, back_hi)) / 64.0 +
                         gamma12 * (farthest(front_lo, front_hi) + farthest(back_lo, back_hi)));
  // The box corner nearest the plane (least along n) must clear the margin beyond it.
  const DVec3 corner{n.x >= 0 ? back_lo.x : back_hi.x, n.y >= 0 ? back_lo.y : back_hi.y,
                     n.z >= 0 ? back_lo.z : back_hi.z};
  const Signed depth = signed_dot(n, dsub(corner, v0));
  return depth.value - depth.bound > margin;
}

}  // namespace rayaccel::generalized
