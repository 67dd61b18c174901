// SPDX-License-Identifier: MIT
#include <dthex/hexes/dice.h>
#include <dthex/hexes/thex.h>
#include <dthex/mesh/quality.h>
#include "refine_fixtures.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

using namespace dthex;

namespace {

//! The 24 rotations of the parameter cube as permutations of VTK hex corners: relabel a
//! hex with any of them and it is the same positive hex with another node 0.
std::vector<std::array<int, 8>> cube_rotations() {
  const std::array<int, 8> about_z = {1, 2, 3, 0, 5, 6, 7, 4};  // corner i -> new label
  const std::array<int, 8> about_x = {3, 2, 6, 7, 0, 1, 5, 4};
  std::vector<std::array<int, 8>> all = {{0, 1, 2, 3, 4, 5, 6, 7}};
  for (size_t i = 0; i < all.size(); ++i)
    for (const auto& g : {about_z, about_x}) {
      std::array<int, 8> p;
      for (size_t c = 0; c < 8; ++c) p[c] = all[i][size_t(g[c])];
      if (std::find(all.begin(), all.end(), p) == all.end()) all.push_back(p);
    }
  return all;
}

size_t expected_nodes(const HexMesh& mesh, size_t n) {
  const auto [edges, faces] = fixtures::hex_edges_faces(mesh);
  return mesh.nodes.size() + (n - 1) * edges + (n - 1) * (n - 1) * faces + (n - 1) * (n - 1) * (n - 1) * mesh.hexes.size();
}

}  // namespace

TEST(Dice, UnitCubeByTwoGivesEightUnitShapeCubes) {
  const HexMesh cubes = dice(fixtures::hex_block(1, 1, 1), 2);
  ASSERT_EQ(cubes.hexes.size(), 8u);
  EXPECT_EQ(cubes.nodes.size(), 27u);
  double volume = 0;
  for (size_t h = 0; h < 8; ++h) {
    EXPECT_NEAR(hex_shape(hex_corners(cubes, h)), 1.0, 1e-12);
    const auto x = hex_corners(cubes, h);
    volume += (x[1] - x[0]).cross(x[3] - x[0]).dot(x[4] - x[0]);
  }
  EXPECT_NEAR(volume, 1.0, 1e-12);
}

TEST(Dice, OneDivisionIsIdentityAndBelowOneThrows) {
  const HexMesh block = fixtures::hex_block(2, 1, 1);
  const HexMesh same = dice(block, 1);
  EXPECT_EQ(same.nodes, block.nodes);
  EXPECT_EQ(same.hexes, block.hexes);
  EXPECT_THROW(dice(block, 0), std::invalid_argument);
  EXPECT_THROW(dice(block, -2), std::invalid_argument);
}

TEST(Dice, SharedEdgesAndFacesAgreeWhateverTheNeighboursLocalOrder) {
  // Each hex of a 3x2x2 block relabelled by a random cube rotation: shared faces are
  // then seen in different local frames from each side.
  HexMesh block = fixtures::hex_block(3, 2, 2);
  const auto rotations = cube_rotations();
  ASSERT_EQ(rotations.size(), 24u);
  std::mt19937 rng(7);
  for (auto& h : block.hexes) {
    const auto& r = rotations[rng() % 24];
    std::array<int, 8> relabelled;
    for (size_t c = 0; c < 8; ++c) relabelled[size_t(r[c])] = h[c];
    h = relabelled;
  }
  for (int n : {2, 3, 4}) {
    const HexMesh diced = dice(block, n);
    EXPECT_EQ(diced.hexes.size(), block.hexes.size() * size_t(n * n * n));
    EXPECT_EQ(diced.nodes.size(), expected_nodes(block, size_t(n)));
    EXPECT_EQ(diced.nodes.size(), size_t((3 * n + 1) * (2 * n + 1) * (2 * n + 1)));
    EXPECT_EQ(fixtures::duplicate_coordinates(diced), 0u);
    for (size_t h = 0; h < diced.hexes.size(); ++h) ASSERT_NEAR(hex_shape(hex_corners(diced, h)), 1.0, 1e-9);
  }
}

TEST(Dice, IcosahedronThexDicedByThreeMatchesTheReferee) {
  const TriSurface ico = fixtures::read_off(DTHEX_SOURCE_DIR "/meshes/icosahedron.off");
  const HexMesh thexed = thex(fixtures::cone_to_centre(ico));
  const HexMesh diced = dice(thexed, 3);
  EXPECT_EQ(diced.hexes.size(), 2160u);
  EXPECT_EQ(diced.nodes.size(), 2473u);
  EXPECT_EQ(diced.nodes.size(), expected_nodes(thexed, 3));
  const HexQuality q = measure_hex_quality(diced);
  EXPECT_NEAR(q.shape_stats.avg, 0.8749, 1e-4);
  EXPECT_NEAR(q.shape_stats.min, 0.7786, 1e-4);
  EXPECT_EQ(q.inverted, 0u);
}

TEST(Dice, BoundaryFacetFollowsTheBoundaryFaces) {
  const TriSurface ico = fixtures::read_off(DTHEX_SOURCE_DIR "/meshes/icosahedron.off");
  for (int n : {2, 3}) {
    const HexMesh diced = dice(dice(thex(fixtures::cone_to_centre(ico)), n), 2);
    ASSERT_EQ(diced.boundary_facet.size(), diced.nodes.size());
    // A closed quad surface of Q quads has Q + 2 vertices; THex gives 60 quads.
    const size_t quads = 60u * size_t(n * n) * 4u;
    size_t boundary = 0;
    for (size_t v = 0; v < diced.nodes.size(); ++v) {
      const int f = diced.boundary_facet[v];
      if (f < 0) continue;
      ++boundary;
      const auto& t = ico.triangles[size_t(f)];
      const Vec3 &a = ico.points[size_t(t[0])], &b = ico.points[size_t(t[1])], &c = ico.points[size_t(t[2])];
      const Vec3 normal = (b - a).cross(c - a);
      const Vec3 p = diced.nodes[v];
      const double area = normal.squaredNorm();
      EXPECT_NEAR(normal.normalized().dot(p - a), 0.0, 1e-12) << "node " << v << " off its facet's plane";
      EXPECT_GT((b - p).cross(c - p).dot(normal) / area, -1e-12) << "node " << v << " outside its facet";
      EXPECT_GT((c - p).cross(a - p).dot(normal) / area, -1e-12) << "node " << v << " outside its facet";
      EXPECT_GT((a - p).cross(b - p).dot(normal) / area, -1e-12) << "node " << v << " outside its facet";
    }
    EXPECT_EQ(boundary, quads + 2);
  }
}

TEST(Dice, KeepsHexesPositiveOnThexOfATetBlock) {
  const HexMesh thexed = thex(fixtures::kuhn_block(2, 2, 1));
  const HexMesh diced = dice(thexed, 2);
  EXPECT_EQ(diced.nodes.size(), expected_nodes(thexed, 2));
  EXPECT_EQ(fixtures::duplicate_coordinates(diced), 0u);
  EXPECT_EQ(measure_hex_quality(diced).inverted, 0u);
}
