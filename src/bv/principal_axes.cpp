// Principal axes by cyclic Jacobi rotations on the 3x3 covariance matrix (Golub & Van Loan, section 8.5).
#include "principal_axes.h"

#include <algorithm>
#include <cmath>

namespace rayaccel::bv_detail {
namespace {

/// Diagonalizes the symmetric matrix m in place by cyclic Jacobi rotations; column i of v becomes the eigenvector of
/// the eigenvalue left in m[i][i].
void jacobi_eigenvectors(double m[3][3], double v[3][3]) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) v[r][c] = r == c ? 1.0 : 0.0;
  for (int sweep = 0; sweep < 32; ++sweep) {
    const double off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
    const double diag = m[0][0] * m[0][0] + m[1][1] * m[1][1] + m[2][2] * m[2][2];
    if (off <= 1e-24 * diag) break;  // off-diagonal below 1e-12 of the diagonal: converged for fitting
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        if (std::fabs(m[p][q]) <= 1e-15 * (std::fabs(m[p][p]) + std::fabs(m[q][q]))) continue;
        // The rotation angle that zeroes m[p][q], in the stable form t = sign(theta) / (|theta| + sqrt(theta^2+1)).
        const double theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
        const double t = std::copysign(1.0, theta) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) {  // m <- m * J
          const double mkp = m[k][p], mkq = m[k][q];
          m[k][p] = c * mkp - s * mkq;
          m[k][q] = s * mkp + c * mkq;
        }
        for (int k = 0; k < 3; ++k) {  // m <- J^T * m
          const double mpk = m[p][k], mqk = m[q][k];
          m[p][k] = c * mpk - s * mqk;
          m[q][k] = s * mpk + c * mqk;
        }
        for (int k = 0; k < 3; ++k) {  // v <- v * J
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
    }
  }
}

}  // namespace

bool principal_axes(std::span<const Vec3> points, Vec3d axes[3]) {
  if (points.empty()) return false;
  Vec3d mean;
  for (const Vec3& p : points) mean = mean + Vec3d(p);
  mean = mean * (1.0 / double(points.size()));
  double m[3][3] = {};
  for (const Vec3& pf : points) {
    const Vec3d d = Vec3d(pf) - mean;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m[r][c] += d[r] * d[c];
  }
  if (m[0][0] + m[1][1] + m[2][2] == 0.0) return false;
  double v[3][3];
  jacobi_eigenvectors(m, v);
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int a, int b) { return m[a][a] > m[b][b]; });
  for (int i = 0; i < 3; ++i) axes[i] = normalize(Vec3d{v[0][order[i]], v[1][order[i]], v[2][order[i]]});
  return true;
}

}  // namespace rayaccel::bv_detail
