// SPDX-License-Identifier: MIT
#include <dthex/mesh/closest_triangle_pair.h>

#include <gtest/gtest.h>

using dthex::TriangleBvh;
using dthex::TrianglePairDistance;
using dthex::TriSurface;
using dthex::Vec3;
using dthex::closest_separate_pair;
using dthex::triangle_distance;

TEST(TriangleDistance, CornerToFaceEdgeToEdgeAndParallel) {
  const std::array<Vec3, 3> base{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  // A corner 0.3 above the interior of the base.
  const TrianglePairDistance corner = triangle_distance(base, {Vec3(0.2, 0.2, 0.3), Vec3(0.2, 0.2, 1), Vec3(1, 1, 1)});
  EXPECT_NEAR(corner.distance, 0.3, 1e-15);
  EXPECT_TRUE(corner.point_a.isApprox(Vec3(0.2, 0.2, 0)));
  EXPECT_TRUE(corner.point_b.isApprox(Vec3(0.2, 0.2, 0.3)));
  // Crossed edges, no corner near the other triangle: only the edge-edge distance sees 0.5.
  const TrianglePairDistance edges =
      triangle_distance({Vec3(-1, 0.5, 0), Vec3(2, 0.5, 0), Vec3(0.5, 0.5, -3)},
                        {Vec3(0.5, -1, 0.5), Vec3(0.5, 2, 0.5), Vec3(0.5, 0.5, 3)});
  EXPECT_NEAR(edges.distance, 0.5, 1e-15);
  EXPECT_TRUE(edges.point_a.isApprox(Vec3(0.5, 0.5, 0)));
  EXPECT_TRUE(edges.point_b.isApprox(Vec3(0.5, 0.5, 0.5)));
  // Parallel copies 1e-9 apart.
  const TrianglePairDistance parallel =
      triangle_distance(base, {Vec3(0, 0, 1e-9), Vec3(1, 0, 1e-9), Vec3(0, 1, 1e-9)});
  EXPECT_NEAR(parallel.distance, 1e-9, 1e-20);
}

TEST(ClosestSeparatePair, FindsTheNearestPairWithinTheDistanceOnly) {
  // Three separate triangles: 0 and 1 are 0.01 apart, 1 and 2 are 0.001 apart, 0 and 2 far.
  TriSurface s;
  s.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),          Vec3(0, 0, 0.01), Vec3(1, 0, 0.01),
              Vec3(0, 1, 0.01), Vec3(0, 0, 0.011), Vec3(1, 0, 0.011), Vec3(0, 1, 0.011)};
  s.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  const TriangleBvh tree(s);
  auto all = [](int, int) { return true; };
  const TrianglePairDistance near = closest_separate_pair(tree, 0.1, all);
  EXPECT_EQ(near.a, 1);
  EXPECT_EQ(near.b, 2);
  EXPECT_NEAR(near.distance, 0.001, 1e-12);
  // Excluding that pair, the next; below both distances, none.
  const TrianglePairDistance next = closest_separate_pair(tree, 0.1, [](int a, int b) { return !(a == 1 && b == 2); });
  EXPECT_EQ(next.a, 0);
  EXPECT_EQ(next.b, 1);
  EXPECT_NEAR(next.distance, 0.01, 1e-12);
  EXPECT_EQ(closest_separate_pair(tree, 0.0009, all).a, -1);
}
