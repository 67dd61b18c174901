// SPDX-License-Identifier: MIT
#include <dthex/hexes/thex.h>
#include <dthex/mesh/quality.h>
#include "refine_fixtures.h"

#include <gtest/gtest.h>

using namespace dthex;

namespace {

//! Largest distance of p from triangle (a, b, c), negative barycentric weight included.
bool lies_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double tol) {
  const Vec3 n = (b - a).cross(c - a);
  if (std::abs(n.normalized().dot(p - a)) > tol) return false;
  const double area = n.squaredNorm();
  const double wa = (b - p).cross(c - p).dot(n) / area, wb = (c - p).cross(a - p).dot(n) / area,
               wc = (a - p).cross(b - p).dot(n) / area;
  return wa > -tol && wb > -tol && wc > -tol;
}

}  // namespace

TEST(Thex, RegularTetGivesFourEqualHexes) {
  const HexMesh hex = thex(fixtures::regular_tet());
  ASSERT_EQ(hex.hexes.size(), 4u);
  ASSERT_EQ(hex.nodes.size(), 4u + 6u + 4u + 1u);
  for (size_t h = 0; h < 4; ++h) {
    EXPECT_NEAR(hex_shape(hex_corners(hex, h)), 0.7937, 1e-4);  // 2^(-1/3)
    EXPECT_NEAR(hex_scaled_jacobian(hex_corners(hex, h)), 0.7071, 1e-4);
  }
}

TEST(Thex, MirroredTetStillGivesPositiveHexes) {
  TetMesh tet = fixtures::regular_tet();
  std::swap(tet.tets[0][1], tet.tets[0][2]);
  const HexMesh hex = thex(tet);
  for (size_t h = 0; h < 4; ++h) EXPECT_NEAR(hex_shape(hex_corners(hex, h)), 0.7937, 1e-4);
}

TEST(Thex, CountsAreFourHexesPerTetAndOneNodePerVertexEdgeFaceTet) {
  const TetMesh tets = fixtures::kuhn_block(3, 2, 2);
  const auto [edges, faces] = fixtures::tet_edges_faces(tets);
  const HexMesh hex = thex(tets);
  EXPECT_EQ(hex.hexes.size(), 4 * tets.tets.size());
  EXPECT_EQ(hex.nodes.size(), tets.points.size() + edges + faces + tets.tets.size());
  EXPECT_EQ(fixtures::duplicate_coordinates(hex), 0u);  // shared, never duplicated
  for (size_t h = 0; h < hex.hexes.size(); ++h) EXPECT_GT(hex_scaled_jacobian(hex_corners(hex, h)), 0.0);
  for (size_t p = 0; p < tets.points.size(); ++p) EXPECT_EQ(hex.nodes[p], tets.points[p]);  // points keep indices
}

TEST(Thex, IcosahedronAroundCentre) {
  const TriSurface ico = fixtures::read_off(DTHEX_SOURCE_DIR "/meshes/icosahedron.off");
  ASSERT_EQ(ico.triangles.size(), 20u);
  const HexMesh hex = thex(fixtures::cone_to_centre(ico));
  EXPECT_EQ(hex.hexes.size(), 80u);
  EXPECT_EQ(hex.nodes.size(), 125u);
}

TEST(Thex, BoundaryFacetMarksExactlyTheNodesOnTheSurface) {
  const TriSurface ico = fixtures::read_off(DTHEX_SOURCE_DIR "/meshes/icosahedron.off");
  const TetMesh tets = fixtures::cone_to_centre(ico);
  const HexMesh hex = thex(tets);
  ASSERT_EQ(hex.boundary_facet.size(), hex.nodes.size());
  size_t boundary = 0;
  for (size_t v = 0; v < hex.nodes.size(); ++v) {
    const int f = hex.boundary_facet[v];
    if (f < 0) continue;
    ++boundary;
    ASSERT_LT(size_t(f), ico.triangles.size());
    const auto& t = ico.triangles[size_t(f)];
    EXPECT_TRUE(lies_on_triangle(hex.nodes[v], ico.points[size_t(t[0])], ico.points[size_t(t[1])],
                                 ico.points[size_t(t[2])], 1e-12))
        << "node " << v;
  }
  EXPECT_EQ(boundary, 12u + 30u + 20u);  // surface vertices, edge midpoints, face centroids
}

TEST(Thex, RejectsBadTets) {
  TetMesh tets = fixtures::regular_tet();
  tets.tets[0][3] = 7;
  EXPECT_THROW(thex(tets), InputError);
  tets.tets[0][3] = 0;
  EXPECT_THROW(thex(tets), InputError);
}
