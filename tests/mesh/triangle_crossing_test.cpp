// SPDX-License-Identifier: MIT
#include <dthex/mesh/triangle_crossing.h>

#include <gtest/gtest.h>

using dthex::segment_crosses_triangle;
using dthex::triangles_cross;
using dthex::Vec3;

namespace {
const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
}  // namespace

TEST(TriangleCrossing, SegmentThroughTheInsideCrossesAndOneBesideItDoesNot) {
  EXPECT_TRUE(segment_crosses_triangle(Vec3(0.2, 0.2, -1), Vec3(0.2, 0.2, 1), a, b, c));
  EXPECT_TRUE(segment_crosses_triangle(Vec3(0.2, 0.2, 1), Vec3(0.2, 0.2, -1), c, b, a));  // either orientation
  EXPECT_FALSE(segment_crosses_triangle(Vec3(0.8, 0.8, -1), Vec3(0.8, 0.8, 1), a, b, c));  // past the hypotenuse
  EXPECT_FALSE(segment_crosses_triangle(Vec3(0.2, 0.2, 0.1), Vec3(0.2, 0.2, 1), a, b, c));  // stops above it
}

TEST(TriangleCrossing, TouchingCountsButLyingInThePlaneDoesNot) {
  EXPECT_TRUE(segment_crosses_triangle(Vec3(0.2, 0.2, 0), Vec3(0.2, 0.2, 1), a, b, c));  // an end on it
  EXPECT_TRUE(segment_crosses_triangle(Vec3(0.5, 0, -1), Vec3(0.5, 0, 1), a, b, c));    // through an edge
  EXPECT_FALSE(segment_crosses_triangle(Vec3(-1, 0.2, 0), Vec3(2, 0.2, 0), a, b, c));   // coplanar
}

TEST(TriangleCrossing, TrianglesCrossWhenAnEdgeOfEitherPassesThroughTheOther) {
  // A triangle standing through the middle of abc, one whose edge abc pierces (none of its
  // edges meets abc), and one lifted clear of it.
  EXPECT_TRUE(triangles_cross({a, b, c}, {Vec3(0.2, 0.2, -1), Vec3(0.3, 0.2, 1), Vec3(0.2, 0.3, 1)}));
  EXPECT_TRUE(triangles_cross({a, b, c}, {Vec3(0.5, -1, -1), Vec3(0.5, -1, 1), Vec3(0.5, 2, 0)}));
  EXPECT_FALSE(triangles_cross({a, b, c}, {Vec3(0, 0, 0.1), Vec3(1, 0, 0.1), Vec3(0, 1, 0.1)}));
}
