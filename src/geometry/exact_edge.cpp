// Exact edge functions, adaptively (Shewchuk 1997): double with a static error bound first, then expansion
// arithmetic (Dekker's two-product over Veltkamp's split, Knuth's two-sum) without any rounding.
#include "rayaccel/geometry/exact_edge.h"

#include <cassert>
#include <cmath>
#include <type_traits>

#include "rayaccel/core/dvec3.h"

namespace rayaccel {

namespace {

/// hi + lo == the exact result of one operation, |lo| at most half an ulp of hi.
struct TwoDoubles {
  double hi, lo;
};

TwoDoubles two_sum(double a, double b) {
  const double s = a + b;
  const double b_virtual = s - a;
  const double a_virtual = s - b_virtual;
  return {s, (a - a_virtual) + (b - b_virtual)};
}

/// a == hi + lo with hi and lo of at most 26 significant bits each (Veltkamp's split).
TwoDoubles split(double a) {
  const double c = 134217729.0 * a;  // 2^27 + 1
  const double hi = c - (c - a);
  return {hi, a - hi};
}

TwoDoubles two_product(double a, double b) {
  const double p = a * b;
  const TwoDoubles as = split(a), bs = split(b);
  const double err = as.lo * bs.lo - (((p - as.hi * bs.hi) - as.lo * bs.hi) - as.hi * bs.lo);
  return {p, err};
}

/// A sum of doubles held exactly: nonoverlapping components in increasing magnitude, zeros eliminated.
class Expansion {
 public:
  void add(double b) {
    if (b == 0.0) return;
    int out = 0;
    double q = b;
    for (int i = 0; i < size_; ++i) {
      const TwoDoubles s = two_sum(q, components_[i]);
      q = s.hi;
      if (s.lo != 0.0) components_[out++] = s.lo;
    }
    if (q != 0.0) components_[out++] = q;
    assert(out <= kCapacity);
    size_ = out;
  }
  int sign() const {
    if (size_ == 0) return 0;
    return components_[size_ - 1] > 0.0 ? 1 : -1;
  }
  /// The sum rounded: the components added from the smallest up (relative error below 2^-51).
  double estimate() const {
    double sum = 0.0;
    for (int i = 0; i < size_; ++i) sum += components_[i];
    return sum;
  }

 private:
  static constexpr int kCapacity = 100;  // 96 terms at most, and add() grows the size by at most one
  double components_[kCapacity];
  int size_ = 0;
};

/// a - b of two floats or two doubles, exactly (doubles of the double domain cannot overflow).
TwoDoubles difference(double a, double b) { return two_sum(a, -b); }

/// Adds coefficient * (a_i b_j - a_j b_i) to `sum`, exactly.
void add_scaled_minor(Expansion& sum, double coefficient, const TwoDoubles& a_i, const TwoDoubles& a_j,
                      const TwoDoubles& b_i, const TwoDoubles& b_j) {
  const auto add_product = [&](const TwoDoubles& x, const TwoDoubles& y, double sign) {
    for (double xs : {x.hi, x.lo}) {
      for (double ys : {y.hi, y.lo}) {
        if (xs == 0.0 || ys == 0.0) continue;
        const TwoDoubles p = two_product(xs, ys);
        for (double part : {p.hi, p.lo}) {
          if (part == 0.0) continue;
          const TwoDoubles term = two_product(part, sign * coefficient);
          sum.add(term.lo);
          sum.add(term.hi);
        }
      }
    }
  };
  if (coefficient == 0.0) return;
  add_product(a_i, b_j, 1.0);
  add_product(a_j, b_i, -1.0);
}

/// The edge function in double with a bound on its error (Shewchuk's stage with a static error bound): A's
/// components rounded once, each product and sum once more, at most 7 roundings on any term of the permanent
/// P = sum |d_k| (|a_i b_j| + |a_j b_i|), so |G - G_exact| <= 10 * 2^-53 * P (P's own rounding included).
struct DoubleEdge {
  double g, error;
};

template <class V>
DoubleEdge double_edge_times_dz(const V& origin, const V& direction, const int axes[3], const V& p, const V& q) {
  double pa[3], qa[3];
  for (int i = 0; i < 3; ++i) {
    pa[i] = double(p[axes[i]]) - double(origin[axes[i]]);
    qa[i] = double(q[axes[i]]) - double(origin[axes[i]]);
  }
  const double d[3] = {direction[axes[0]], direction[axes[1]], direction[axes[2]]};
  // (coefficient, i, j): d_z (x, y), d_x (y, z), d_y (z, x)
  const int terms[3][3] = {{2, 0, 1}, {0, 1, 2}, {1, 2, 0}};
  double g = 0.0, permanent = 0.0;
  for (const auto& term : terms) {
    const double c = d[term[0]];
    const double left = pa[term[1]] * qa[term[2]], right = pa[term[2]] * qa[term[1]];
    g += c * (left - right);
    permanent += std::fabs(c) * (std::fabs(left) + std::fabs(right));
  }
  return {g, 10.0 * 0x1p-53 * permanent};
}

/// How precise the double stage's value must be for its answer to stand: the caller computes t (and its bound)
/// from these values, so a sign that the static bound decides is not enough. A value whose error was nearly its own
/// size made t's bound near the whole depth range of the triangle, and a hit at t = 0.003 was dropped against
/// t_min = -0.5 (fuzz corpus exact-edge-value-imprecise). Float callers round the value to float, so 2^-30 is ample;
/// double callers keep 2^-45 of it (their t bounds count that). Beyond these, the expansion's estimate (2^-50).
template <class V>
constexpr double kDoubleStageRelativeError = std::is_same_v<V, Vec3> ? 0x1p-30 : 0x1p-45;

/// Both overloads: V is Vec3 or DVec3.
template <class V>
ExactEdge exact_edge(const V& origin, const V& direction, int kx, int ky, int kz, const V& p, const V& q) {
  const int axes[3] = {kx, ky, kz};
  const double dz = direction[kz];
  const int dz_sign = dz > 0.0 ? 1 : -1;
  const DoubleEdge fast = double_edge_times_dz(origin, direction, axes, p, q);
  if (std::fabs(fast.g) * kDoubleStageRelativeError<V> > fast.error) {
    return {fast.g > 0.0 ? dz_sign : -dz_sign, fast.g / dz, fast.error / std::fabs(dz)};
  }
  TwoDoubles pa[3], qa[3];
  for (int i = 0; i < 3; ++i) {
    pa[i] = difference(p[axes[i]], origin[axes[i]]);
    qa[i] = difference(q[axes[i]], origin[axes[i]]);
  }
  // G = E d_z = d_z (p_x q_y - p_y q_x) + d_x (p_y q_z - p_z q_y) + d_y (p_z q_x - p_x q_z), x, y, z = kx, ky, kz.
  Expansion g;
  add_scaled_minor(g, direction[kz], pa[0], pa[1], qa[0], qa[1]);
  add_scaled_minor(g, direction[kx], pa[1], pa[2], qa[1], qa[2]);
  add_scaled_minor(g, direction[ky], pa[2], pa[0], qa[2], qa[0]);
  ExactEdge e;
  e.sign = g.sign() * dz_sign;
  e.value = e.sign == 0 ? 0.0 : g.estimate() / dz;
  e.error = std::fabs(e.value) * 0x1p-50;
  return e;
}

}  // namespace

ExactEdge exact_edge_function(const Vec3& origin, const Vec3& direction, int kx, int ky, int kz, const Vec3& p,
                              const Vec3& q) {
  return exact_edge(origin, direction, kx, ky, kz, p, q);
}

ExactEdge exact_edge_function(const DVec3& origin, const DVec3& direction, int kx, int ky, int kz, const DVec3& p,
                              const DVec3& q) {
  return exact_edge(origin, direction, kx, ky, kz, p, q);
}

}  // namespace rayaccel
