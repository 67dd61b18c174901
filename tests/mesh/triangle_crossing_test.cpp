// SPDX-License-Identifier: MIT
#include <dthex/mesh/triangle_crossing.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

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

// Two triangles side by side on one plane, the plane turned and moved off the axes: the points
// lie on it only to within rounding, and no edge of one may cross the other by that noise,
// while a segment through the plane still crosses.
TEST(TriangleCrossing, TrianglesSideBySideOnATurnedPlaneDoNotCross) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  int through = 0, noise = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(M_PI * unit(random), Vec3(unit(random), unit(random), unit(random)).normalized())
            .toRotationMatrix();
    const Vec3 offset = 100 * Vec3(unit(random), unit(random), unit(random));
    auto place = [&](double x, double y, double z = 0) { return Vec3(turn * Vec3(x, y, z) + offset); };
    // abc and the triangle b, d, c beside it across edge bc (d = (1, 1)).
    const Vec3 A = place(0, 0), B = place(1, 0), C = place(0, 1), D = place(1.3, 0.9);
    const double on_plane = dthex::kWithinRoundingOfPlane;
    ASSERT_FALSE(segment_crosses_triangle(B, D, A, B, C, on_plane)) << trial;
    ASSERT_FALSE(segment_crosses_triangle(D, C, A, B, C, on_plane)) << trial;
    ASSERT_FALSE(triangles_cross({A, B, C}, {B, D, C}, on_plane)) << trial;
    through += segment_crosses_triangle(place(0.2, 0.2, -1), place(0.2, 0.2, 1), A, B, C, on_plane);
    // Without the tolerance (the remeshing's stricter guard) the noise may read as a crossing.
    noise += triangles_cross({A, B, C}, {B, D, C});
  }
  EXPECT_EQ(through, 2000);
  EXPECT_GT(noise, 0);
}

// The zero-area test counts corners within rounding of one line, not only an exactly zero
// cross product. The remeshing made such a triangle of the flattened heart (its corners two
// ends of a split edge, at about these coordinates, and the split's point, as a flip can make
// it): its cross product was not zero in floating point, so a test for exactly zero let it
// through, and the verification, which uses this test, then refused the remeshed surface. A
// triangle of a hair's height stays one with area.
TEST(TriangleCrossing, ZeroAreaMeansWithinRoundingOfOneLine) {
  const Vec3 a(27.29937064, -35.70330127, 19.81772699), b(27.25888167, -35.80870983, 19.81905495);
  const Vec3 m = a + 0.3 * (b - a);
  EXPECT_GT((b - a).cross(m - a).norm(), 0.0);
  EXPECT_TRUE(has_zero_area(a, b, m));
  EXPECT_TRUE(has_zero_area(a, a, b));
  const Vec3 off = m + 1e-6 * (b - a).norm() * (b - a).cross(Vec3::UnitZ()).normalized();
  EXPECT_FALSE(has_zero_area(a, b, off));
  EXPECT_FALSE(has_zero_area(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)));
}
