// SPDX-License-Identifier: MIT
#include <dthex/surface/surface_distance.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace dthex {
namespace {

// Max and sum of distances from the sample points of `from` to the surface behind `to`.
// Samples are the vertices the triangles use (a hex mesh's node array also holds interior
// nodes), the centroids and the edge midpoints, listed triangle by triangle so that
// consecutive samples are close: each query starts from the previous answer's triangle,
// which prunes most of the tree. The samples are split over the cores.
// With `each_edge_once`, an edge's midpoint is taken only from the triangle that runs along
// it from the lower vertex id to the higher: on a closed, consistently oriented surface that
// is one of its two triangles, so the same points are measured with a third fewer queries
// (for a maximum; a mean would weigh the edges differently).
// With `max_only` (no sum wanted), a sample whose distance to the previous answer's triangle
// is no more than the largest distance found so far cannot raise it and is not searched: the
// maximum is the same, and most samples of a close surface are settled by that one triangle.
void one_sided(const TriSurface& from, const TriangleBvh& to, bool each_edge_once, bool max_only,
               double& max_distance, double& sum, size_t& count) {
  std::vector<Vec3> samples;
  samples.reserve(5 * from.triangles.size());
  std::vector<char> sampled(from.points.size(), 0);
  for (const auto& t : from.triangles) {
    for (int v : t)
      if (!sampled[size_t(v)]) {
        sampled[size_t(v)] = 1;
        samples.push_back(from.points[size_t(v)]);
      }
    const Vec3& a = from.points[size_t(t[0])];
    const Vec3& b = from.points[size_t(t[1])];
    const Vec3& c = from.points[size_t(t[2])];
    samples.push_back((a + b + c) / 3.0);
    for (size_t i = 0; i < 3; ++i) {
      const int u = t[i], w = t[(i + 1) % 3];
      if (!each_edge_once || u < w) samples.push_back(0.5 * (from.points[size_t(u)] + from.points[size_t(w)]));
    }
  }
  const long n = long(samples.size());
  double local_max = 0, local_sum = 0;
#pragma omp parallel reduction(max : local_max) reduction(+ : local_sum)
  {
    int hint = -1;
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) {
      const Vec3& q = samples[size_t(i)];
      if (max_only && hint >= 0) {
        const auto& t = to.triangles()[size_t(hint)];
        const Vec3 p = closest_point_on_triangle(q, to.points()[size_t(t[0])], to.points()[size_t(t[1])],
                                                 to.points()[size_t(t[2])]);
        if ((p - q).squaredNorm() <= local_max * local_max) continue;
      }
      const TriangleBvh::ClosestPoint cp = to.closest_point_near(q, hint);
      hint = cp.triangle;
      const double d = std::sqrt(cp.distance_sq);
      local_max = std::max(local_max, d);
      local_sum += d;
    }
  }
  max_distance = std::max(max_distance, local_max);
  sum += local_sum;
  count += samples.size();
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
  one_sided(a, b_bvh, false, false, d.to_input_max, sum_ab, count_ab);  // its mean is reported too
  one_sided(b, a_bvh, true, true, d.from_input_max, sum_ba, count_ba);
  d.hausdorff = std::max(d.to_input_max, d.from_input_max);
  d.mean = count_ab ? sum_ab / double(count_ab) : 0.0;
  return d;
}

double enclosed_volume(const TriSurface& s) {
  // Tets from the bounding box's centre, not from the origin: far from the origin (scanner
  // coordinates) the sum about the origin cancels catastrophically.
  Eigen::AlignedBox3d bounds;
  for (const Vec3& p : s.points) bounds.extend(p);
  const Vec3 origin = s.points.empty() ? Vec3::Zero() : Vec3(bounds.center());
  double six_volume = 0;
  for (const auto& t : s.triangles) {
    const Vec3 a = s.points[size_t(t[0])] - origin, b = s.points[size_t(t[1])] - origin, c = s.points[size_t(t[2])] - origin;
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6.0;
}

}  // namespace dthex
