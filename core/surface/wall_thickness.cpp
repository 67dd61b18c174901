// SPDX-License-Identifier: MIT
#include <dthex/surface/wall_thickness.h>

#include <algorithm>
#include <cmath>

namespace dthex {

std::vector<double> inner_wall_radii(const TriSurface& surface, const TriangleBvh& bvh,
                                     const std::vector<double>& start_radius, const WallThicknessOptions& options) {
  const size_t n = surface.points.size();
  std::vector<double> radius = start_radius;
  radius.resize(n, 0.0);
  // Unit triangle normals, area-weighted vertex normals, and which way is inside.
  std::vector<Vec3> triangle_normal(surface.triangles.size());
  std::vector<Vec3> vertex_normal(n, Vec3::Zero());
  double volume6 = 0;
  for (size_t t = 0; t < surface.triangles.size(); ++t) {
    const auto& f = surface.triangles[t];
    const Vec3 &a = surface.points[size_t(f[0])], &b = surface.points[size_t(f[1])], &c = surface.points[size_t(f[2])];
    const Vec3 cross = (b - a).cross(c - a);
    volume6 += a.dot(b.cross(c));
    for (int v : f) vertex_normal[size_t(v)] += cross;
    const double length = cross.norm();
    triangle_normal[t] = length > 0 ? Vec3(cross / length) : Vec3::Zero();
  }
  // Outward normals: flipped when the triangles wind inward (negative enclosed volume).
  const double outward_sign = volume6 >= 0 ? 1.0 : -1.0;
  for (Vec3& normal : triangle_normal) normal *= outward_sign;
  const double opposite_cos = std::cos(options.opposite_angle_deg * M_PI / 180.0);
  // Near the vertex every triangle faces its way: the searches skip such parts of the tree.
  const TriangleBvh::NormalBounds normal_bounds = bvh.normal_bounds();

#pragma omp parallel for schedule(dynamic, 256)
  for (long i = 0; i < long(n); ++i) {
    const size_t v = size_t(i);
    double r = radius[v];
    if (!(r > 0) || !std::isfinite(r) || !(vertex_normal[v].norm() > 0)) continue;
    const Vec3 outward = vertex_normal[v].normalized() * outward_sign;
    const Vec3 inward = -outward;
    const Vec3& p = surface.points[v];
    // A triangle of the opposite wall faces back at the vertex.
    const auto opposite = [&](int t) { return triangle_normal[size_t(t)].dot(outward) < opposite_cos; };
    const TriangleBvh::Facing facing{&normal_bounds, outward * outward_sign, opposite_cos};
    for (int step = 0; step < options.max_steps; ++step) {
      // Only a point inside the ball matters: the search stays within it (the nearest
      // opposite triangle can be across the whole model, and finding it is slow).
      const TriangleBvh::ClosestPoint cp = bvh.closest_point_within(p + r * inward, r * (1 - 1e-9), opposite, &facing);
      if (cp.triangle < 0) break;  // the ball is empty
      // The ball tangent at p through the point found: |p + s m - q| = s.
      const Vec3 d = cp.point - p;
      const double along = d.dot(inward);
      if (!(along > 0)) break;
      const double shrunk = d.squaredNorm() / (2 * along);
      if (!(shrunk < r)) break;
      r = shrunk;
    }
    radius[v] = r;
  }
  return radius;
}

double median_wall_thickness(const TriSurface& surface, const TriangleBvh& bvh, double start_radius,
                             const WallThicknessOptions& options) {
  const std::vector<double> start(surface.points.size(), start_radius);
  std::vector<double> thickness;
  for (double r : inner_wall_radii(surface, bvh, start, options))
    if (r < start_radius) thickness.push_back(2 * r);
  if (thickness.empty()) return 0;
  const auto middle = thickness.begin() + long(thickness.size() / 2);
  std::nth_element(thickness.begin(), middle, thickness.end());
  return *middle;
}

}  // namespace dthex
