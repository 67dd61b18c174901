// SPDX-License-Identifier: MIT
#include "core/surface_distance.h"

#include <algorithm>
#include <cmath>

namespace dthex {
namespace {

// Max and sum of distances from the sample points of `from` to the surface behind `to`.
void one_sided(const TriSurface& from, const TriangleBvh& to, double& max_distance, double& sum, size_t& count) {
  auto probe = [&](const Vec3& q) {
    const double d = std::sqrt(to.closest_point(q).distance_sq);
    max_distance = std::max(max_distance, d);
    sum += d;
    ++count;
  };
  // Only the points the triangles use: a hex mesh's node array also holds interior nodes.
  std::vector<char> used(from.points.size(), 0);
  for (const auto& t : from.triangles)
    for (int v : t) used[size_t(v)] = 1;
  for (size_t i = 0; i < from.points.size(); ++i)
    if (used[i]) probe(from.points[i]);
  for (const auto& t : from.triangles) {
    const Vec3& a = from.points[size_t(t[0])];
    const Vec3& b = from.points[size_t(t[1])];
    const Vec3& c = from.points[size_t(t[2])];
    probe((a + b + c) / 3.0);
    probe(0.5 * (a + b));
    probe(0.5 * (b + c));
    probe(0.5 * (c + a));
  }
}

}  // namespace

TriSurface quads_to_triangles(const std::vector<Vec3>& nodes, const std::vector<std::array<int, 4>>& quads) {
  TriSurface s;
  s.points = nodes;
  s.triangles.reserve(2 * quads.size());
  for (const auto& q : quads) {
    s.triangles.push_back({q[0], q[1], q[2]});
    s.triangles.push_back({q[0], q[2], q[3]});
  }
  return s;
}

SurfaceDistance surface_distance(const TriSurface& a, const TriangleBvh& a_bvh, const TriSurface& b,
                                 const TriangleBvh& b_bvh) {
  SurfaceDistance d;
  double sum_ab = 0, sum_ba = 0;
  size_t count_ab = 0, count_ba = 0;
  one_sided(a, b_bvh, d.to_input_max, sum_ab, count_ab);
  one_sided(b, a_bvh, d.from_input_max, sum_ba, count_ba);
  d.hausdorff = std::max(d.to_input_max, d.from_input_max);
  d.mean = count_ab ? sum_ab / double(count_ab) : 0.0;
  return d;
}

double enclosed_volume(const TriSurface& s) {
  double six_volume = 0;
  for (const auto& t : s.triangles)
    six_volume += s.points[size_t(t[0])].dot(s.points[size_t(t[1])].cross(s.points[size_t(t[2])]));
  return six_volume / 6.0;
}

}  // namespace dthex
