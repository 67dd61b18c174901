// SPDX-License-Identifier: MIT
#include <dthex/mesh/incidence.h>

#include "boundary_fixtures.h"

#include <gtest/gtest.h>

#include <vector>

using namespace dthex;
using namespace dthex::testing;

namespace {

std::vector<int> cells_at(const NodeCellIncidence& incidence, size_t v) {
  const NodeCellIncidence::Range r = incidence[v];
  return std::vector<int>(r.begin(), r.end());
}

}  // namespace

// A 2x1x1 block: 12 nodes, hex 0 = {0,1,4,3,6,7,10,9}, hex 1 = {1,2,5,4,7,8,11,10}. The four
// nodes of the shared face are in both hexes, the others in one.
TEST(NodeCellIncidence, HexBlockCountsAndMembers) {
  const HexMesh mesh = hex_block(Vec3(0, 0, 0), Vec3(2, 1, 1), 2, 1, 1);
  ASSERT_EQ(mesh.nodes.size(), 12u);
  ASSERT_EQ(mesh.hexes.size(), 2u);
  const NodeCellIncidence incidence(mesh.nodes.size(), mesh.hexes);
  EXPECT_EQ(incidence.node_count(), 12u);
  size_t total = 0;
  for (size_t v = 0; v < 12; ++v) total += incidence[v].size();
  EXPECT_EQ(total, 16u);
  for (size_t v : {1, 4, 7, 10}) EXPECT_EQ(cells_at(incidence, v), (std::vector<int>{0, 1})) << "node " << v;
  for (size_t v : {0, 3, 6, 9}) EXPECT_EQ(cells_at(incidence, v), (std::vector<int>{0})) << "node " << v;
  for (size_t v : {2, 5, 8, 11}) EXPECT_EQ(cells_at(incidence, v), (std::vector<int>{1})) << "node " << v;
}

// With corners, each entry names the node's position in the cell: for every entry the
// cell's node at that corner is the node itself, and the shared nodes sit at the corners
// the hexes' node lists give them.
TEST(NodeCellIncidence, CornersNameTheNodeInItsCell) {
  const HexMesh mesh = hex_block(Vec3(0, 0, 0), Vec3(2, 1, 1), 2, 1, 1);
  const NodeCellIncidence incidence(mesh.nodes.size(), mesh.hexes, true);
  for (size_t v = 0; v < mesh.nodes.size(); ++v) {
    const NodeCellIncidence::Entries entries = incidence.entries(v);
    ASSERT_EQ(entries.size(), incidence[v].size());
    size_t k = 0;
    for (const NodeCellIncidence::Entry e : entries) {
      EXPECT_EQ(e.cell, incidence[v][k++]);
      EXPECT_EQ(mesh.hexes[size_t(e.cell)][size_t(e.corner)], int(v));
    }
  }
  // Node 1 is corner 1 of hex 0 and corner 0 of hex 1; node 10 corner 6 of hex 0, 7 of hex 1.
  EXPECT_EQ(incidence.entries(1)[0].corner, 1);
  EXPECT_EQ(incidence.entries(1)[1].corner, 0);
  EXPECT_EQ(incidence.entries(10)[0].corner, 6);
  EXPECT_EQ(incidence.entries(10)[1].corner, 7);
}

// Cells come in ascending index at every node, whatever order the nodes have in the
// cells; a node listed twice in one cell appears twice; a node in no cell has none.
TEST(NodeCellIncidence, AscendingCellsRepeatsAndIsolatedNodes) {
  const std::vector<std::array<int, 3>> triangles = {{2, 0, 1}, {1, 3, 0}, {0, 0, 3}};
  const NodeCellIncidence incidence(5, triangles, true);
  EXPECT_EQ(cells_at(incidence, 0), (std::vector<int>{0, 1, 2, 2}));
  EXPECT_EQ(incidence.entries(0)[2].corner, 0);
  EXPECT_EQ(incidence.entries(0)[3].corner, 1);
  EXPECT_EQ(cells_at(incidence, 1), (std::vector<int>{0, 1}));
  EXPECT_EQ(cells_at(incidence, 3), (std::vector<int>{1, 2}));
  EXPECT_TRUE(incidence[4].empty());
  EXPECT_TRUE(incidence.entries(4).empty());
}
