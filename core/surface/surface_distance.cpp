// SPDX-License-Identifier: MIT
#include <dthex/surface/surface_distance.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace dthex {
namespace {

// For each vertex of `from`, the first triangle that uses it (-1: none): the triangle it is
// sampled with.
std::vector<int> first_uses(const TriSurface& from) {
  std::vector<int> first_use(from.points.size(), -1);
  for (size_t f = 0; f < from.triangles.size(); ++f)
    for (int v : from.triangles[f])
      if (first_use[size_t(v)] < 0) first_use[size_t(v)] = int(f);
  return first_use;
}

// The sample points of triangle f of `from`, in order: its vertices sampled with it
// (first_use), its centroid and its edge midpoints; with `each_edge_once`, only the midpoints
// of the edges it runs along from the lower vertex id to the higher, which on a closed,
// consistently oriented surface is one of an edge's two triangles.
template <class Visit>
void visit_samples(const TriSurface& from, const std::vector<int>& first_use, size_t f, bool each_edge_once,
                   Visit&& visit) {
  const auto& t = from.triangles[f];
  for (int v : t)
    if (first_use[size_t(v)] == int(f)) visit(from.points[size_t(v)]);
  const Vec3& a = from.points[size_t(t[0])];
  const Vec3& b = from.points[size_t(t[1])];
  const Vec3& c = from.points[size_t(t[2])];
  visit((a + b + c) / 3.0);
  for (size_t i = 0; i < 3; ++i) {
    const int u = t[i], w = t[(i + 1) % 3];
    if (!each_edge_once || u < w) visit(0.5 * (from.points[size_t(u)] + from.points[size_t(w)]));
  }
}

// Max and sum of distances from the sample points of `from` (visit_samples: the vertices the
// triangles use, as a hex mesh's node array also holds interior nodes, the centroids and the
// edge midpoints) to the surface behind `to`, listed triangle by triangle so that consecutive
// samples are close: each query starts from the previous answer's triangle, which prunes most
// of the tree. The samples are split over the cores.
void one_sided(const TriSurface& from, const TriangleBvh& to, double& max_distance, double& sum, size_t& count) {
  const std::vector<int> first_use = first_uses(from);
  std::vector<Vec3> samples;
  samples.reserve(5 * from.triangles.size());
  for (size_t f = 0; f < from.triangles.size(); ++f)
    visit_samples(from, first_use, f, false, [&](const Vec3& q) { samples.push_back(q); });
  const long n = long(samples.size());
  double local_max = 0, local_sum = 0;
#pragma omp parallel reduction(max : local_max) reduction(+ : local_sum)
  {
    int hint = -1;
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) {
      const TriangleBvh::ClosestPoint cp = to.closest_point_near(samples[size_t(i)], hint);
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

// The largest distance from the sample points of `from` to the surface behind `to`, where
// `from` is closed and consistently oriented, so each edge midpoint is measured once
// (visit_samples with each_edge_once). A sample whose distance to the previous answer's
// triangle is no more than the largest distance found so far cannot raise it and is not
// searched; most samples of a close surface are settled by that one triangle. The samples are
// made where they are measured, triangle by triangle on each core (a maximum does not depend on
// the order): a list of them, five per triangle of a fine input, took longer to fill on one
// core than most of them take to settle.
double one_sided_max(const TriSurface& from, const TriangleBvh& to) {
  const std::vector<int> first_use = first_uses(from);
  const long n = long(from.triangles.size());
  double local_max = 0;
#pragma omp parallel reduction(max : local_max)
  {
    int hint = -1;
    auto measure = [&](const Vec3& q) {
      if (hint >= 0) {
        const auto& t = to.triangles()[size_t(hint)];
        const Vec3 p = closest_point_on_triangle(q, to.points()[size_t(t[0])], to.points()[size_t(t[1])],
                                                 to.points()[size_t(t[2])]);
        if ((p - q).squaredNorm() <= local_max * local_max) return;
      }
      const TriangleBvh::ClosestPoint cp = to.closest_point_near(q, hint);
      hint = cp.triangle;
      local_max = std::max(local_max, std::sqrt(cp.distance_sq));
    };
#pragma omp for schedule(static)
    for (long f = 0; f < n; ++f) visit_samples(from, first_use, size_t(f), true, measure);
  }
  return local_max;
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
  double sum_ab = 0;
  size_t count_ab = 0;
  one_sided(a, b_bvh, d.to_input_max, sum_ab, count_ab);  // its mean is reported too
  d.from_input_max = one_sided_max(b, a_bvh);
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
