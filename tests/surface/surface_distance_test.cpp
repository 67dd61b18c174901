// SPDX-License-Identifier: MIT
#include <dthex/surface/surface_distance.h>

#include "boundary_fixtures.h"
#include <dthex/io/read_surface.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace dthex;
using namespace dthex::testing;

// Scanner coordinates put a model far from the origin; the volume must not lose its digits
// to the distance (about the origin, a liver at 1e6 summed to -646 for 1.15).
TEST(SurfaceDistance, EnclosedVolumeFarFromTheOrigin) {
  TriSurface liver = read_surface(DTHEX_SOURCE_DIR "/meshes/liver.off");
  const double volume = enclosed_volume(liver);
  ASSERT_GT(volume, 1.0);
  for (Vec3& p : liver.points) p += Vec3(1e6, -2e6, 3e6);
  EXPECT_NEAR(enclosed_volume(liver), volume, 1e-6 * volume);
  const TriSurface unit = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 1);
  EXPECT_NEAR(enclosed_volume(unit), 1.0, 1e-15);
}

// A unit cube against one 10% larger from the same corner: the far corner (1.1, 1.1, 1.1)
// is sqrt(3) * 0.1 from the unit cube, and that is the Hausdorff distance.
TEST(SurfaceDistance, HausdorffOfTwoCubesIsTheirFarCorners) {
  const TriSurface a = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 2);
  const TriSurface b = box_surface(Vec3(0, 0, 0), Vec3(1.1, 1.1, 1.1), 2);
  const TriangleBvh a_bvh(a), b_bvh(b);
  const SurfaceDistance d = surface_distance(a, a_bvh, b, b_bvh);
  EXPECT_NEAR(d.hausdorff, std::sqrt(3.0) * 0.1, 1e-12);
  EXPECT_GT(d.mean, 0.0);
  EXPECT_LT(d.mean, d.hausdorff);
}

// Inside a cube the distance to its surface peaks where a point is nearest the centre. A flat
// tetrahedron whose two opposite edges pass 0.05 below and above the centre is farthest from
// the cube (0.95) at those edges' midpoints; its vertices are at 0.1 and its centroids at
// 0.7. Each of its edges is sampled once, from one of its two triangles, and both midpoints
// must still be among the samples.
TEST(SurfaceDistance, FindsTheFarthestPointAtAnEdgeMidpointOfTheInput) {
  const TriSurface cube = box_surface(Vec3(-1, -1, -1), Vec3(1, 1, 1), 1);
  TriSurface tet;
  tet.points = {Vec3(-0.9, 0, -0.05), Vec3(0.9, 0, -0.05), Vec3(0, -0.9, 0.05), Vec3(0, 0.9, 0.05)};
  tet.triangles = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  ASSERT_GT(enclosed_volume(tet), 0.0);  // outward, so every edge runs once each way
  const TriangleBvh cube_bvh(cube), tet_bvh(tet);
  const SurfaceDistance d = surface_distance(cube, cube_bvh, tet, tet_bvh);
  EXPECT_NEAR(d.from_input_max, 0.95, 1e-12);
  // And the other way: the cube's corners are farthest from the tetrahedron.
  double corner = 0;
  for (const Vec3& p : cube.points) corner = std::max(corner, std::sqrt(tet_bvh.closest_point(p).distance_sq));
  EXPECT_NEAR(d.to_input_max, corner, 1e-12);
}

// Both one-sided maxima against a brute-force pass over every sample and every triangle: the
// input-to-boundary side skips a sample that the previous answer's triangle shows cannot
// raise the maximum, and must still find the same one. A sphere against a copy of itself
// with its vertices pushed in and out.
TEST(SurfaceDistance, MaximaEqualABruteForceSearch) {
  const TriSurface sphere = read_surface(DTHEX_SOURCE_DIR "/meshes/sphere728.off");
  TriSurface bumpy = sphere;
  for (size_t v = 0; v < bumpy.points.size(); ++v)
    bumpy.points[v] *= 1.0 + 0.03 * std::sin(double(v) * 1.7) + 0.02 * std::cos(double(v) * 0.3);
  auto brute_max = [](const TriSurface& from, const TriSurface& to) {
    std::vector<Vec3> samples = from.points;
    for (const auto& t : from.triangles) {
      const Vec3 &a = from.points[size_t(t[0])], &b = from.points[size_t(t[1])], &c = from.points[size_t(t[2])];
      samples.push_back((a + b + c) / 3.0);
      samples.push_back(0.5 * (a + b));
      samples.push_back(0.5 * (b + c));
      samples.push_back(0.5 * (c + a));
    }
    double worst = 0;
    for (const Vec3& q : samples) {
      double nearest = std::numeric_limits<double>::infinity();
      for (const auto& t : to.triangles) {
        const Vec3 p = closest_point_on_triangle(q, to.points[size_t(t[0])], to.points[size_t(t[1])],
                                                 to.points[size_t(t[2])]);
        nearest = std::min(nearest, (p - q).squaredNorm());
      }
      worst = std::max(worst, std::sqrt(nearest));
    }
    return worst;
  };
  const TriangleBvh sphere_bvh(sphere), bumpy_bvh(bumpy);
  const SurfaceDistance d = surface_distance(bumpy, bumpy_bvh, sphere, sphere_bvh);
  EXPECT_DOUBLE_EQ(d.to_input_max, brute_max(bumpy, sphere));
  EXPECT_DOUBLE_EQ(d.from_input_max, brute_max(sphere, bumpy));
  EXPECT_GT(d.from_input_max, 0.01);
}
