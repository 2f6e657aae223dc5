// Principal component analysis of a point set for the volume fitters (OBB frames, capsule axes): the eigenvectors
// of the points' covariance, found by cyclic Jacobi rotations (Golub & Van Loan, "Matrix Computations", section 8.5).
#pragma once

#include <span>

#include "fit_support.h"

namespace rayaccel::bv_detail {

/// The unit eigenvectors of the points' covariance matrix, largest variance first, into axes[0..2] (orthonormal up
/// to rounding). False, leaving axes untouched, when the points are empty or all equal.
bool principal_axes(std::span<const Vec3> points, Vec3d axes[3]);

}  // namespace rayaccel::bv_detail
