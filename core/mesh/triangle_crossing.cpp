// SPDX-License-Identifier: MIT
#include <dthex/mesh/triangle_crossing.h>

#include <dthex/numerics/signed_volume.h>

#include <algorithm>
#include <cmath>

namespace dthex {

bool segment_crosses_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                              double on_plane) {
  double dp = signed_volume6(a, b, c, p), dq = signed_volume6(a, b, c, q);
  // dp is |n| times p's distance from the plane (n = (b - a) x (c - a)).
  if (on_plane > 0) {
    const double largest = std::max({a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff(), c.cwiseAbs().maxCoeff(),
                                   p.cwiseAbs().maxCoeff(), q.cwiseAbs().maxCoeff()});
    const double within = on_plane * largest * (b - a).cross(c - a).norm();
    if (std::abs(dp) <= within) dp = 0;
    if (std::abs(dq) <= within) dq = 0;
  }
  if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0) || (dp == 0 && dq == 0)) return false;
  const double s0 = signed_volume6(p, q, a, b), s1 = signed_volume6(p, q, b, c), s2 = signed_volume6(p, q, c, a);
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

bool triangles_cross(const std::array<Vec3, 3>& A, const std::array<Vec3, 3>& B, double on_plane) {
  for (size_t k = 0; k < 3; ++k) {
    if (segment_crosses_triangle(A[k], A[(k + 1) % 3], B[0], B[1], B[2], on_plane)) return true;
    if (segment_crosses_triangle(B[k], B[(k + 1) % 3], A[0], A[1], A[2], on_plane)) return true;
  }
  return false;
}

namespace {
Vec3 normal_of(const std::array<Vec3, 3>& t) { return (t[1] - t[0]).cross(t[2] - t[0]); }
}  // namespace

bool triangles_fold_onto_each_other(const std::array<Vec3, 3>& A, const std::array<Vec3, 3>& B) {
  const Vec3 na = normal_of(A), nb = normal_of(B);
  return na.dot(nb) < -(1.0 - kFoldedCosineMargin) * na.norm() * nb.norm();
}

double angle_between_sides_deg(const std::array<Vec3, 3>& A, const std::array<Vec3, 3>& B) {
  const Vec3 na = normal_of(A), nb = normal_of(B);
  // atan2 of |na x nb| and -na.nb keeps its precision near 0, where acos would not.
  return std::atan2(na.cross(nb).norm(), -na.dot(nb)) * 180.0 / M_PI;
}

bool has_zero_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double longest_sq = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return a == b || b == c || c == a || (b - a).cross(c - a).norm() <= 1e-12 * longest_sq;
}

}  // namespace dthex
