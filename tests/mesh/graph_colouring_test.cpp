// SPDX-License-Identifier: MIT
#include <dthex/mesh/graph_colouring.h>
#include <dthex/mesh/incidence.h>

#include "boundary_fixtures.h"

#include <gtest/gtest.h>

#include <set>
#include <vector>

using namespace dthex;
using namespace dthex::testing;

namespace {

//! The nodes of `mesh` coloured in ascending order, each by the hexes around it.
std::vector<size_t> colour_nodes(const HexMesh& mesh, size_t max_colours = GreedyCellColouring::kNoLimit) {
  const NodeCellIncidence incidence(mesh.nodes.size(), mesh.hexes);
  GreedyCellColouring colouring(mesh.hexes.size(), max_colours);
  std::vector<size_t> colour(mesh.nodes.size());
  for (size_t v = 0; v < mesh.nodes.size(); ++v) colour[v] = colouring.add(incidence[v].begin(), incidence[v].end());
  return colour;
}

}  // namespace

// On a 3x3x3 block no two nodes of a hex share a colour, and greedy colouring in the
// block's node order gives the 8 parity classes (i, j, k mod 2): 8 colours, the fewest
// possible since a hex's 8 nodes pairwise conflict.
TEST(GreedyCellColouring, HexBlockNodesByParity) {
  const int n = 3;
  const HexMesh mesh = hex_block(Vec3(0, 0, 0), Vec3(1, 1, 1), n, n, n);
  const std::vector<size_t> colour = colour_nodes(mesh);
  for (const auto& hex : mesh.hexes) {
    std::set<size_t> seen;
    for (int v : hex) seen.insert(colour[size_t(v)]);
    EXPECT_EQ(seen.size(), 8u);
  }
  EXPECT_EQ(std::set<size_t>(colour.begin(), colour.end()).size(), 8u);
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        EXPECT_EQ(colour[size_t((k * (n + 1) + j) * (n + 1) + i)], size_t(i % 2 + 2 * (j % 2) + 4 * (k % 2)));
}

// Items sharing no cell all take colour 0; an item takes the lowest colour free on its
// cells, not one past the highest in use.
TEST(GreedyCellColouring, LowestFreeColour) {
  GreedyCellColouring colouring(4);
  const int a[] = {0, 1}, b[] = {1, 2}, c[] = {3}, d[] = {0, 2};
  EXPECT_EQ(colouring.add(a, a + 2), 0u);
  EXPECT_EQ(colouring.add(b, b + 2), 1u);  // shares cell 1 with a
  EXPECT_EQ(colouring.add(c, c + 1), 0u);  // shares nothing
  EXPECT_EQ(colouring.add(d, d + 2), 2u);  // cell 0 has 0, cell 2 has 1
  EXPECT_EQ(colouring.colour_count(), 3u);
}

// With a limit, an item that finds every colour taken gets the overflow class (the limit)
// and marks nothing: the next item can still take the colours it finds free.
TEST(GreedyCellColouring, OverflowClassAtTheLimit) {
  GreedyCellColouring colouring(3, 2);
  const int shared[] = {0}, other[] = {1};
  EXPECT_EQ(colouring.add(shared, shared + 1), 0u);
  EXPECT_EQ(colouring.add(shared, shared + 1), 1u);
  EXPECT_EQ(colouring.add(shared, shared + 1), 2u);  // overflow
  EXPECT_EQ(colouring.add(shared, shared + 1), 2u);
  EXPECT_EQ(colouring.add(other, other + 1), 0u);
  EXPECT_EQ(colouring.colour_count(), 2u);
}

// Without a limit colours go past 64 (one cell held by 150 items needs 150 colours), and
// the colours recorded before the cells grew a second and third word still count.
TEST(GreedyCellColouring, MoreThan64Colours) {
  GreedyCellColouring colouring(2);
  const int shared[] = {0}, both[] = {0, 1};
  for (size_t k = 0; k < 150; ++k) ASSERT_EQ(colouring.add(shared, shared + 1), k);
  EXPECT_EQ(colouring.add(both, both + 2), 150u);
  EXPECT_EQ(colouring.colour_count(), 151u);
}
