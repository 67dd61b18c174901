// SPDX-License-Identifier: MIT
#include <dthex/surface/features.h>

#include "boundary_fixtures.h"

#include <gtest/gtest.h>

using namespace dthex;
using dthex::testing::box_surface;

// The unit cube, each face two triangles: its 12 edges are features (90 degrees), the 6 face
// diagonals are not. Hex nodes named on a triangle: on a cube edge or corner (feature), on a
// diagonal or inside a face (not), a hair off an edge (not), interior (not).
TEST(Features, NodesOnTheCoarseSurfacesFeatureEdgesAreFound) {
  const TriSurface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 1);
  ASSERT_EQ(cube.triangles.size(), 12u);
  ASSERT_EQ(feature_edges(cube).size(), 12u);
  // Every node on triangle 0's plane: find that triangle's three corners.
  const auto& t = cube.triangles[0];
  const Vec3 a = cube.points[size_t(t[0])], b = cube.points[size_t(t[1])], c = cube.points[size_t(t[2])];
  // Which of the triangle's edges is the face diagonal (not a feature): the longest one.
  const std::array<std::pair<Vec3, Vec3>, 3> edges = {{{a, b}, {b, c}, {c, a}}};
  int diagonal = 0;
  for (int k = 1; k < 3; ++k)
    if ((edges[size_t(k)].second - edges[size_t(k)].first).norm() >
        (edges[size_t(diagonal)].second - edges[size_t(diagonal)].first).norm())
      diagonal = k;
  const auto& side = edges[size_t((diagonal + 1) % 3)];
  const auto& diag = edges[size_t(diagonal)];
  const Vec3 inward = (a + b + c) / 3 - (side.first + side.second) / 2;

  HexMesh mesh;
  mesh.nodes = {
      0.3 * side.first + 0.7 * side.second,                    // on a cube edge: feature
      side.first,                                              // a cube corner: feature
      0.5 * (diag.first + diag.second),                        // mid-diagonal: not
      (a + b + c) / 3,                                         // inside the face: not
      0.5 * (side.first + side.second) + 1e-3 * inward,        // a hair off the edge: not
      0.5 * (side.first + side.second),                        // on the edge, but interior: not
  };
  mesh.boundary_facet = {0, 0, 0, 0, 0, -1};
  const std::vector<char> on = nodes_on_feature_edges(mesh, cube);
  EXPECT_EQ(on, (std::vector<char>{1, 1, 0, 0, 0, 0}));
}

namespace {

// A flat patch (z = 0) around the triangle A B C, whose apex C is lifted to `apex`: with C
// just beside AB and lifted a little, A B C is a needle turned away from all three of its
// neighbours (a fin); lifted far, the same three edges are ordinary sharp creases.
TriSurface patch_with_apex(const Vec3& apex) {
  TriSurface s;
  s.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), apex, Vec3(0.5, 0.5, 0), Vec3(0.5, -0.5, 0)};
  s.triangles = {{0, 1, 2}, {1, 0, 4}, {2, 1, 3}, {0, 2, 3}};
  return s;
}

int features_among_the_first_triangles_edges(const std::vector<std::array<int, 2>>& edges) {
  int count = 0;
  for (const std::array<int, 2>& e : {std::array<int, 2>{0, 1}, {1, 2}, {0, 2}})
    count += std::binary_search(edges.begin(), edges.end(), e);
  return count;
}

}  // namespace

// The fin: angle 6.9 degrees at A and B, its normal turned 80-88 degrees from the three
// neighbours. Its edges are no features (on the input, in the Decimater's marking, and on the
// coarse surface alike), and the crease tests get a zero normal for it. The same triangle
// lifted to 50 degrees at A turns as much, and its edges are features.
TEST(Features, AFinIsNoFeatureAndAnOrdinaryCreaseIs) {
  const TriSurface fin = patch_with_apex(Vec3(0.5, 0.01, 0.06));
  const TriSurface crease = patch_with_apex(Vec3(0.5, 0.1, 0.6));
  EXPECT_EQ(fin_triangles(fin.points, fin.triangles), (std::vector<char>{1, 0, 0, 0}));
  EXPECT_EQ(fin_triangles(crease.points, crease.triangles), (std::vector<char>{0, 0, 0, 0}));

  EXPECT_EQ(features_among_the_first_triangles_edges(feature_edges(fin)), 0);
  EXPECT_EQ(features_among_the_first_triangles_edges(feature_edges(crease)), 3);

  SurfaceMesh fin_mesh = to_openmesh(fin), crease_mesh = to_openmesh(crease);
  EXPECT_EQ(features_among_the_first_triangles_edges(mark_features(fin_mesh).edges), 0);
  EXPECT_EQ(features_among_the_first_triangles_edges(mark_features(crease_mesh).edges), 3);

  const std::vector<Vec3> fin_normals = unit_triangle_normals(fin.points, fin.triangles);
  EXPECT_EQ(fin_normals[0], Vec3::Zero());
  EXPECT_NEAR(fin_normals[1].norm(), 1.0, 1e-12);
  EXPECT_NEAR(unit_triangle_normals(crease.points, crease.triangles)[0].norm(), 1.0, 1e-12);
}

// A crease test near the fin's tip: without the fin the patch there is flat, so no crease;
// with its normal counted (as before fins were recognised) the tip would be a crease.
TEST(Features, CreaseTestsIgnoreAFin) {
  const TriSurface fin = patch_with_apex(Vec3(0.5, 0.01, 0.06));
  const TriangleBvh bvh(fin);
  const std::vector<Vec3> normals = unit_triangle_normals(fin.points, fin.triangles);
  const Vec3 beside_the_tip(0.5, -0.05, 0), up(0, 0, 1);
  EXPECT_FALSE(on_surface_crease(bvh, normals, beside_the_tip, up, 0.2, std::cos(M_PI / 3), false));
  std::vector<Vec3> counted = normals;
  counted[0] = (fin.points[1] - fin.points[0]).cross(fin.points[2] - fin.points[0]).normalized();
  EXPECT_TRUE(on_surface_crease(bvh, counted, beside_the_tip, up, 0.2, std::cos(M_PI / 3), false));
}

namespace {

// A prism whose cross-section is a 16-degree wedge (apex on the z axis, 1 long), each face
// split in two: its apex edge is a knife edge, the others are not.
TriSurface wedge_prism(double degrees) {
  const double t = std::tan(degrees / 2 * M_PI / 180);
  TriSurface s;
  s.points = {Vec3(0, 0, 0), Vec3(1, t, 0), Vec3(1, -t, 0), Vec3(0, 0, 1), Vec3(1, t, 1), Vec3(1, -t, 1)};
  s.triangles = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}, {2, 0, 3}, {2, 3, 5}};
  return s;
}

}  // namespace

// The knife-edge zone is the distance to the knife edge, not to its other face: on a
// 16-degree wedge a point of one face 0.1 from the edge is only 0.028 from the other face.
TEST(Features, KnifeEdgeZoneIsTheDistanceToTheEdge) {
  const TriSurface wedge = wedge_prism(16);
  auto knife = [](const TriSurface& s) {
    return has_knife_edge(s.triangles, unit_triangle_normals(s.points, s.triangles));
  };
  EXPECT_TRUE(knife(wedge));
  EXPECT_FALSE(knife(wedge_prism(40)));
  EXPECT_FALSE(knife(box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 2)));
  const TriangleBvh bvh(wedge);
  const std::vector<Vec3> normals = unit_triangle_normals(wedge.points, wedge.triangles);
  const Vec3 along_face = (wedge.points[1] - wedge.points[0]).normalized();
  const Vec3 edge_point(0, 0, 0.5);
  EXPECT_TRUE(near_knife_edge(bvh, normals, edge_point + 0.04 * along_face, 0.05));
  EXPECT_FALSE(near_knife_edge(bvh, normals, edge_point + 0.1 * along_face, 0.05));
  // The square ends meet the faces at 82 and 90 degrees: far from the knife, no knife.
  EXPECT_FALSE(near_knife_edge(bvh, normals, Vec3(1, 0, 0.5), 0.05));
}
