// SPDX-License-Identifier: MIT
#include <dthex/hexes/conformity.h>
#include <dthex/hexes/dice.h>
#include <dthex/hexes/thex.h>
#include <dthex/tets/tetrahedralize.h>
#include "refine_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

using namespace dthex;

namespace {

//! Splits hex h of the mesh into 8 (new nodes appended), leaving its neighbours alone.
HexMesh split_one_hex(HexMesh mesh, size_t h) {
  HexMesh single;
  single.nodes = mesh.nodes;
  single.hexes = {mesh.hexes[h]};
  const HexMesh split = dice(single, 2);
  // dice() keeps the input nodes' indices and appends the new ones.
  for (size_t i = mesh.nodes.size(); i < split.nodes.size(); ++i) mesh.nodes.push_back(split.nodes[i]);
  mesh.hexes.erase(mesh.hexes.begin() + long(h));
  mesh.hexes.insert(mesh.hexes.end(), split.hexes.begin(), split.hexes.end());
  return mesh;
}

}  // namespace

TEST(Conformity, BlockIsConformingWithClosedOutwardBoundary) {
  const HexMesh block = fixtures::hex_block(2, 2, 1);
  const ConformityReport r = check_conformity(block);
  EXPECT_TRUE(r.conforming());
  EXPECT_EQ(r.boundary_faces, 2u * 4 + 2u * 2 + 2u * 2);
  const auto quads = boundary_quads(block);
  ASSERT_EQ(quads.size(), r.boundary_faces);
  std::vector<std::array<int, 4>> found_on_the_way;
  check_conformity(block, &found_on_the_way);
  EXPECT_EQ(found_on_the_way, quads);
  // Outward: each quad's normal points away from the block's centre.
  const Vec3 centre(1, 1, 0.5);
  for (const auto& q : quads) {
    const Vec3 n = (block.nodes[size_t(q[2])] - block.nodes[size_t(q[0])]).cross(block.nodes[size_t(q[3])] - block.nodes[size_t(q[1])]);
    const Vec3 mid = 0.25 * (block.nodes[size_t(q[0])] + block.nodes[size_t(q[1])] + block.nodes[size_t(q[2])] + block.nodes[size_t(q[3])]);
    EXPECT_GT(n.dot(mid - centre), 0.0);
  }
}

// A 4 x 3 x 2 block of hexes has 5 * 4 * 3 = 60 nodes, of which 3 * 2 * 1 = 6 are inside;
// a node labelled with a facet counts as boundary wherever it is (projection holds it).
TEST(Conformity, BoundaryNodesAreTheQuadNodesAndTheLabelledOnes) {
  HexMesh block = fixtures::hex_block(4, 3, 2);
  ASSERT_EQ(block.nodes.size(), 60u);
  std::vector<char> on_boundary = boundary_nodes(block);
  EXPECT_EQ(std::count(on_boundary.begin(), on_boundary.end(), 1), 54);
  int inner = -1;
  for (size_t v = 0; v < block.nodes.size(); ++v)
    if (!on_boundary[v]) {
      const Vec3& p = block.nodes[v];
      EXPECT_TRUE(p.x() > 0 && p.x() < 4 && p.y() > 0 && p.y() < 3 && p.z() > 0 && p.z() < 2) << p.transpose();
      inner = int(v);
    }
  ASSERT_GE(inner, 0);
  block.boundary_facet.assign(block.nodes.size(), -1);
  block.boundary_facet[size_t(inner)] = 0;
  on_boundary = boundary_nodes(block);
  EXPECT_EQ(std::count(on_boundary.begin(), on_boundary.end(), 1), 55);
  EXPECT_EQ(on_boundary[size_t(inner)], 1);
  // Known flags are taken as they are; flags of another size are not.
  const std::vector<char> all(block.nodes.size(), 1), short_list(3, 1);
  EXPECT_EQ(boundary_nodes(block, &all), all);
  EXPECT_EQ(boundary_nodes(block, &short_list), on_boundary);
}

TEST(Conformity, ThexAndDiceOfATetGenMeshAreConforming) {
  const TriSurface sphere = fixtures::read_off(DTHEX_SOURCE_DIR "/meshes/sphere728.off");
  const TetMesh tets = tetrahedralize(sphere);
  const HexMesh thexed = thex(tets);
  const ConformityReport r1 = check_conformity(thexed);
  EXPECT_TRUE(r1.conforming());
  EXPECT_EQ(r1.boundary_faces, 3 * tets.boundary_faces.size());
  const HexMesh diced = dice(thexed, 2);
  const ConformityReport r2 = check_conformity(diced);
  EXPECT_TRUE(r2.conforming());
  EXPECT_EQ(r2.boundary_faces, 4 * r1.boundary_faces);
  EXPECT_EQ(r2.hexes, 8 * thexed.hexes.size());
}

TEST(Conformity, CatchesAHangingNode) {
  const HexMesh mesh = split_one_hex(fixtures::hex_block(2, 1, 1), 1);
  ASSERT_EQ(mesh.hexes.size(), 9u);
  const ConformityReport r = check_conformity(mesh);
  EXPECT_FALSE(r.conforming());
  EXPECT_EQ(r.hanging_nodes, 4u);                  // the 4 edge midpoints of the shared face
  EXPECT_EQ(r.non_manifold_boundary_nodes, 4u);    // the shared face's corners
  EXPECT_EQ(r.boundary_faces, 6u + 24u);           // both sides of the interface count
  EXPECT_EQ(r.duplicate_nodes, 0u);
}

// The same hanging nodes, on edges many grid cells long and slanted: a far-away block of
// tiny hexes shrinks the search grid's cell (the mean boundary edge), and a rotation puts
// the edges off the axes, so the search walks the edge instead of scanning its box.
TEST(Conformity, CatchesAHangingNodeOnALongSlantedEdge) {
  HexMesh mesh = split_one_hex(fixtures::hex_block(2, 1, 1), 1);
  const HexMesh tiny = fixtures::hex_block(30, 30, 1);
  const int offset = int(mesh.nodes.size());
  for (const Vec3& p : tiny.nodes) mesh.nodes.push_back(0.01 * p + Vec3(10, 10, 10));
  for (auto hex : tiny.hexes) {
    for (int& v : hex) v += offset;
    mesh.hexes.push_back(hex);
  }
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()) * Eigen::AngleAxisd(0.3, Vec3::UnitX())).toRotationMatrix();
  for (Vec3& p : mesh.nodes) p = rotation * p;
  const ConformityReport r = check_conformity(mesh);
  EXPECT_FALSE(r.conforming());
  EXPECT_EQ(r.hanging_nodes, 4u);
  EXPECT_EQ(r.non_manifold_boundary_nodes, 4u);
}

TEST(Conformity, CatchesADuplicatedNode) {
  HexMesh mesh = fixtures::hex_block(2, 1, 1);
  // Hex 1 gets its own copy of node 1 (on the shared face).
  mesh.nodes.push_back(mesh.nodes[1]);
  for (int& v : mesh.hexes[1])
    if (v == 1) v = int(mesh.nodes.size()) - 1;
  const ConformityReport r = check_conformity(mesh);
  EXPECT_FALSE(r.conforming());
  EXPECT_EQ(r.duplicate_nodes, 1u);
  EXPECT_EQ(r.boundary_faces, 12u);
}

TEST(Conformity, CatchesOrientationUnusedNodesAndRepeatedHexes) {
  HexMesh mirrored = fixtures::hex_block(2, 1, 1);
  auto& h = mirrored.hexes[1];
  h = {h[4], h[5], h[6], h[7], h[0], h[1], h[2], h[3]};  // inside out
  EXPECT_GT(check_conformity(mirrored).misoriented_boundary_edges, 0u);

  HexMesh extra = fixtures::hex_block(1, 1, 1);
  extra.nodes.push_back(Vec3(5, 5, 5));
  EXPECT_EQ(check_conformity(extra).unreferenced_nodes, 1u);
  extra.hexes.push_back(extra.hexes[0]);
  const ConformityReport r = check_conformity(extra);
  EXPECT_EQ(r.duplicate_hexes, 1u);
  EXPECT_EQ(r.overshared_faces, 0u);
  EXPECT_EQ(r.boundary_faces, 0u);  // every face used twice
  EXPECT_FALSE(r.conforming());
}
