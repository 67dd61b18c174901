// SPDX-License-Identifier: MIT
#include <dthex/hexes/dice.h>
#include <dthex/hexes/node_count.h>
#include <dthex/hexes/thex.h>
#include <dthex/io/read_surface.h>
#include <dthex/tets/tetrahedralize.h>

#include <gtest/gtest.h>

using namespace dthex;

TEST(NodeCount, IcosahedronAroundItsCentreGivesThePapersCounts) {
  // 12 surface vertices + 1 centre, 20 tets: THex 125 nodes, diced by 3: 2473 (paper, Figs 19-20).
  TriSurface ico = read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/icosahedron.off");
  TetMesh tets;
  tets.points = ico.points;
  tets.points.push_back(Vec3::Zero());
  for (const auto& t : ico.triangles) tets.tets.push_back({t[0], t[1], t[2], 12});
  const TetCounts c = count_tet_entities(tets);
  EXPECT_EQ(c.vertices, 13u);
  EXPECT_EQ(c.edges, 42u);
  EXPECT_EQ(c.faces, 50u);
  EXPECT_EQ(diced_thex_nodes(c, 1), 125u);
  EXPECT_EQ(diced_thex_nodes(c, 3), 2473u);
}

TEST(NodeCount, PredictionEqualsWhatThexAndDiceMake) {
  const TriSurface sphere = read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/sphere728.off");
  const TetMesh tets = tetrahedralize(sphere, {});
  const TetCounts c = count_tet_entities(tets);
  const HexMesh thexed = thex(tets);
  EXPECT_EQ(diced_thex_nodes(c, 1), thexed.nodes.size());
  for (int n : {2, 3}) EXPECT_EQ(diced_thex_nodes(c, n), dice(thexed, n).nodes.size()) << "dice " << n;
}
