// Exact edge functions of the watertight triangle test for the rare rays whose float edge function lies inside its
// error bound (ray_triangle.h): double with a static error bound, else expansion arithmetic (Shewchuk 1997).
#pragma once

#include "rayaccel/core/vec3.h"

namespace rayaccel {

struct DVec3;  // core/dvec3.h: declared only, so the float code that includes this header does not see double types

/// An edge function with its exact sign and its value to within `error`.
struct ExactEdge {
  int sign = 0;        ///< -1, 0 or +1: the sign of the exact value
  double value = 0.0;  ///< of that sign (0 exactly when sign is 0)
  double error = 0.0;  ///< bound on |value - exact value|: at most 2^-30 |value| (2^-45 for double inputs)
};

/// The edge function E of vertices p, q (E = X_p Y_q - Y_p X_q) for the ray from `origin` along `direction`, in the
/// frame of axes kx, ky, kz (kz: the direction's dominant axis, d[kz] != 0), from the float inputs: in double when
/// its error bound decides the sign, else exactly. Inputs must be finite.
ExactEdge exact_edge_function(const Vec3& origin, const Vec3& direction, int kx, int ky, int kz, const Vec3& p,
                              const Vec3& q);
/// The same for the double path's inputs, which must lie in the double domain (core/ray_d.h); outside it the
/// expansion may overflow or underflow and the sign is not guaranteed.
ExactEdge exact_edge_function(const DVec3& origin, const DVec3& direction, int kx, int ky, int kz, const DVec3& p,
                              const DVec3& q);

}  // namespace rayaccel
