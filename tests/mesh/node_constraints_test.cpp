// SPDX-License-Identifier: MIT
#include <dthex/mesh/node_constraints.h>

#include "boundary_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace dthex;
using namespace dthex::testing;

// A block of 4 x 4 x 4 hexes in the unit cube, its boundary labelled with the cube's two
// triangles per side: the boundary quads are its 6 * 16 outer faces, the boundary nodes the
// 5^3 - 3^3 = 98 on the cube's sides, and the feature nodes those on its 12 edges (the
// diagonals of the cube's sides are flat, no feature), 8 corners + 12 * 3 = 44.
TEST(NodeConstraints, BoundaryQuadsBoundaryNodesAndFeatureNodesOfABlock) {
  const TriSurface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 1);
  HexMesh mesh = hex_block(Vec3(0, 0, 0), Vec3(1, 1, 1), 4, 4, 4);
  label_boundary(mesh, cube);
  const NodeConstraints c = node_constraints(mesh, cube);
  EXPECT_EQ(c.boundary_quads.size(), 96u);
  ASSERT_EQ(c.on_boundary.size(), mesh.nodes.size());
  ASSERT_EQ(c.on_feature.size(), mesh.nodes.size());
  size_t boundary = 0, feature = 0;
  for (size_t v = 0; v < mesh.nodes.size(); ++v) {
    const Vec3& p = mesh.nodes[v];
    int sides = 0;
    for (int i = 0; i < 3; ++i) sides += std::abs(p[i]) < 1e-12 || std::abs(p[i] - 1) < 1e-12;
    EXPECT_EQ(bool(c.on_boundary[v]), sides >= 1) << v;
    EXPECT_EQ(c.is_feature(v), sides >= 2) << v;
    boundary += c.on_boundary[v] != 0;
    feature += c.is_feature(v);
  }
  EXPECT_EQ(boundary, 98u);
  EXPECT_EQ(feature, 44u);
  // Not known: no node is a feature node, and none out of range.
  EXPECT_FALSE(NodeConstraints().is_feature(0));
  EXPECT_FALSE(c.is_feature(mesh.nodes.size()));
}
