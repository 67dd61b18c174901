// SPDX-License-Identifier: MIT
#include <dthex/mesh/closest_triangle_pair.h>

#include <algorithm>
#include <exception>
#include <tuple>

namespace dthex {

namespace {

//! Closest points of segments p1q1 and p2q2 (Ericson, Real-Time Collision Detection 5.1.9).
std::pair<Vec3, Vec3> closest_points_of_segments(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 0 && e <= 0) return {p1, p2};
  if (a <= 0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return {p1 + s * d1, p2 + t * d2};
}

bool closer(const TrianglePairDistance& x, const TrianglePairDistance& y) {
  return std::tie(x.distance, x.a, x.b) < std::tie(y.distance, y.a, y.b);
}

}  // namespace

TrianglePairDistance triangle_distance(const std::array<Vec3, 3>& A, const std::array<Vec3, 3>& B) {
  TrianglePairDistance best;
  auto consider = [&](const Vec3& on_a, const Vec3& on_b) {
    const double d = (on_a - on_b).norm();
    if (d < best.distance) {
      best.distance = d;
      best.point_a = on_a;
      best.point_b = on_b;
    }
  };
  for (const Vec3& p : A) consider(p, closest_point_on_triangle(p, B[0], B[1], B[2]));
  for (const Vec3& p : B) consider(closest_point_on_triangle(p, A[0], A[1], A[2]), p);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const auto [on_a, on_b] =
          closest_points_of_segments(A[size_t(i)], A[size_t((i + 1) % 3)], B[size_t(j)], B[size_t((j + 1) % 3)]);
      consider(on_a, on_b);
    }
  return best;
}

TrianglePairDistance closest_separate_pair(const TriangleBvh& tree, double max_distance,
                                           const std::function<bool(int, int)>& separate) {
  const auto& P = tree.points();
  const auto& T = tree.triangles();
  const long nt = long(T.size());
  auto corners = [&](int t) {
    const auto& tri = T[size_t(t)];
    return std::array<Vec3, 3>{P[size_t(tri[0])], P[size_t(tri[1])], P[size_t(tri[2])]};
  };
  // Chunks of triangles, each keeping its own best: the minimum over them does not depend
  // on how the chunks were shared out.
  const long chunk = 4096, chunks = (nt + chunk - 1) / chunk;
  std::vector<TrianglePairDistance> best_in(static_cast<size_t>(chunks));
  std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, 1) if (nt > 20000)
  for (long c = 0; c < chunks; ++c) {
    try {
      TrianglePairDistance& best = best_in[size_t(c)];
      for (long a = c * chunk; a < std::min(nt, (c + 1) * chunk); ++a) {
        const std::array<Vec3, 3> A = corners(int(a));
        Eigen::AlignedBox3d box;
        for (const Vec3& p : A) box.extend(p);
        box.min().array() -= max_distance;
        box.max().array() += max_distance;
        tree.for_each_in_box(box, [&](int b) {
          if (b <= a || !separate(int(a), b)) return;
          TrianglePairDistance d = triangle_distance(A, corners(b));
          if (!(d.distance <= max_distance)) return;
          d.a = int(a);
          d.b = b;
          if (best.a < 0 || closer(d, best)) best = d;
        });
      }
    } catch (...) {
#pragma omp critical(dthex_closest_pair_failure)
      failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
  TrianglePairDistance best;
  for (const TrianglePairDistance& d : best_in)
    if (d.a >= 0 && (best.a < 0 || closer(d, best))) best = d;
  return best;
}

}  // namespace dthex
