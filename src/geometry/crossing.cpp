// Simulation of simplicity for the watertight test (see crossing.h): the signs of the edge functions, then, for each
// edge the ray passes exactly through, the sign of that edge function's derivative along the perturbation.
#include "rayaccel/geometry/crossing.h"

#include "rayaccel/geometry/exact_edge.h"

namespace rayaccel {
namespace {

/// Sign of a + b + c + d for doubles, exactly: the terms are summed into a nonoverlapping expansion (Knuth's two-sum,
/// as Shewchuk 1997 grows one), whose largest nonzero component has the sign of the exact sum.
int exact_sign_of_sum(const double (&terms)[4]) {
  double components[4];
  int size = 0;
  for (double q : terms) {
    for (int i = 0; i < size; ++i) {
      const double s = q + components[i];
      const double b_virtual = s - q;
      const double a_virtual = s - b_virtual;
      components[i] = (q - a_virtual) + (components[i] - b_virtual);
      q = s;
    }
    components[size++] = q;
  }
  for (int i = size - 1; i >= 0; --i) {
    if (components[i] != 0.0) return components[i] > 0.0 ? 1 : -1;
  }
  return 0;
}

int sign_of(float x) { return (x > 0.0f) - (x < 0.0f); }

/// Sign of A_p[a] - A_q[a] in the sheared frame, for a = kx or ky (A: vertex relative to the origin, after the shear
/// A[a] - (d[a] / d[kz]) A[kz]): the sign of d[kz] (p[a] - q[a]) - d[a] (p[kz] - q[kz]) times that of d[kz]. Each
/// product of two floats is exact in double, and the sum is signed exactly.
int sheared_difference_sign(const Vec3& d, int a, int kz, const Vec3& p, const Vec3& q) {
  const double dz = d[kz], da = d[a];
  const double terms[4] = {dz * p[a], -(dz * q[a]), -(da * p[kz]), da * q[kz]};
  return exact_sign_of_sum(terms) * sign_of(d[kz]);
}

/// The sign of the edge function E(p, q) = X_p Y_q - Y_p X_q once the ray moves by (eps, eps^2): its value shifts by
/// eps (Y_p - Y_q) + eps^2 (X_q - X_p) (the eps^2 terms of the product cancel), so for E = 0 the first nonzero of
/// the two coefficients decides. Both are zero only when p and q project to one point, a triangle no ray hits.
int perturbed_edge_sign(const PreparedRay& r, const Vec3& p, const Vec3& q) {
  const int first = sheared_difference_sign(r.direction, r.ky, r.kz, p, q);
  if (first != 0) return first;
  return sheared_difference_sign(r.direction, r.kx, r.kz, q, p);
}

}  // namespace

bool counts_as_crossing(const PreparedRay& r, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
  // Edge functions as the watertight test names them: u of edge (v2, v1), v of (v0, v2), w of (v1, v0).
  const Vec3* edges[3][2] = {{&v2, &v1}, {&v0, &v2}, {&v1, &v0}};
  int sign[3];
  int side = 0;  // the sign shared by the nonzero edge functions: the side of the triangle's interior
  for (int e = 0; e < 3; ++e) {
    sign[e] = exact_edge_function(r.origin, r.direction, r.kx, r.ky, r.kz, *edges[e][0], *edges[e][1]).sign;
    if (sign[e] != 0) side = sign[e];
  }
  if (side == 0) return false;  // every edge function zero: a triangle seen edge-on, which the test never hits
  for (int e = 0; e < 3; ++e) {
    if (sign[e] == 0 && perturbed_edge_sign(r, *edges[e][0], *edges[e][1]) != side) return false;
  }
  return true;
}

}  // namespace rayaccel
