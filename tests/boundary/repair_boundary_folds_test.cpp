// SPDX-License-Identifier: MIT
#include <dthex/boundary/repair_boundary_folds.h>

#include <dthex/hexes/conformity.h>
#include <dthex/mesh/quality.h>

#include "boundary_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace dthex;

namespace {

constexpr double kRadius = 1.0;
constexpr int kLevels = 20;  //!< node levels along y, one unit apart

double radians(double degrees) { return degrees * M_PI / 180; }
Vec3 on_circle(double degrees, double y) { return {kRadius * std::cos(radians(degrees)), y, kRadius * std::sin(radians(degrees))}; }

//! Four hexes around the y axis at every level, fanned out like the slices of a cake: each
//! spans `span` degrees from the axis to a circle of radius 1 (corners: the axis, the circle
//! at its two sides and in its middle). At 90 degrees they leave a 0-degree slit along the
//! axis; wider, the first and the last overlap there although every hex is valid and the
//! mesh is combinatorially sound: the fold Spot's concave valleys get from projection. The
//! slices of the levels within `fold_reach` of the middle span `folded_span`, the others 80.
HexMesh cake(double folded_span, int fold_reach) {
  HexMesh m;
  auto id = [](int level, int k) { return level * 10 + k; };  // k 0: axis, 1..5: sides, 6..9: middles
  for (int level = 0; level <= kLevels; ++level) {
    const double y = level;
    const bool folded = std::abs(level - kLevels / 2) <= fold_reach;
    const double span = folded ? folded_span : 80.0;
    m.nodes.push_back(Vec3(0, y, 0));
    for (int k = 0; k < 5; ++k) m.nodes.push_back(on_circle(k * span, y));
    for (int k = 0; k < 4; ++k) m.nodes.push_back(on_circle((k + 0.5) * span, y));
  }
  for (int level = 0; level < kLevels; ++level)
    for (int k = 0; k < 4; ++k) {
      std::array<int, 8> h = {id(level, 0), id(level, 1 + k), id(level, 6 + k), id(level, 2 + k),
                              id(level + 1, 0), id(level + 1, 1 + k), id(level + 1, 6 + k), id(level + 1, 2 + k)};
      // The bottom ring runs clockwise seen from +y: reversed for VTK's positive orientation.
      std::swap(h[1], h[3]);
      std::swap(h[5], h[7]);
      m.hexes.push_back(h);
    }
  return m;
}

//! The surface the cake's outer nodes lie on: the cylinder of radius 1 (fine triangles) and
//! the two end planes.
TriangleBvh cylinder_with_ends() {
  std::vector<Vec3> p;
  std::vector<std::array<int, 3>> t;
  const int around = 360, along = kLevels;
  for (int j = 0; j <= along; ++j)
    for (int i = 0; i < around; ++i) p.push_back(on_circle(i * 360.0 / around, j));
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      const int a = j * around + i, b = j * around + (i + 1) % around;
      t.push_back({a, b, b + around});
      t.push_back({a, b + around, a + around});
    }
  for (double y : {0.0, double(kLevels)}) {
    const int base = int(p.size());
    for (double x : {-2.0, 2.0})
      for (double z : {-2.0, 2.0}) p.push_back(Vec3(x, y, z));
    t.push_back({base, base + 1, base + 3});
    t.push_back({base, base + 3, base + 2});
  }
  return TriangleBvh(p, t);
}

size_t faces_inside(const HexMesh& m) {
  std::vector<int> owners;
  const auto quads = boundary_quads(m, &owners);
  return find_boundary_faces_inside(m, quads, owners).faces_inside;
}

RepairBoundaryFoldsReport repair(HexMesh& m, const TriangleBvh& surface) {
  std::vector<int> owners;
  const auto quads = boundary_quads(m, &owners);
  return repair_boundary_folds(m, surface, quads, owners);
}

}  // namespace

TEST(RepairBoundaryFolds, TheCakeFixtureFoldsWithEveryHexValid) {
  // The fixture is what it claims: 95-degree slices overlap by 20 degrees at the slit, so the
  // two slit faces of each folded layer lie inside the other's hex; 80-degree ones do not.
  const HexMesh folded = cake(95, 1);
  EXPECT_GT(dthex::testing::min_scaled_jacobian(folded), 0.3);
  EXPECT_TRUE([&] {
    ConformityReport c = check_conformity(folded);
    c.boundary_faces_inside = 0;
    return c.conforming();
  }());
  EXPECT_EQ(faces_inside(folded), 2u * 2);  // two folded layers (levels 9-10 and 10-11)
  EXPECT_EQ(faces_inside(cake(80, 1)), 0u);
}

TEST(RepairBoundaryFolds, RemovesTheFoldKeepingHexesValidAndFarNodesInPlace) {
  const TriangleBvh surface = cylinder_with_ends();
  const HexMesh before = cake(95, 1);
  HexMesh after = before;
  const RepairBoundaryFoldsReport r = repair(after, surface);
  EXPECT_EQ(r.faces_inside_before, 4u);
  EXPECT_EQ(r.faces_inside_after, 0u);
  EXPECT_FALSE(r.undone);
  EXPECT_GT(r.moved_nodes, 0u);
  EXPECT_EQ(r.phases_ended_without_gain, 0u);
  // The report's count is the truth, the scaled Jacobian is not below min(before, 0.2)...
  EXPECT_EQ(faces_inside(after), 0u);
  EXPECT_GE(dthex::testing::min_scaled_jacobian(after), std::min(dthex::testing::min_scaled_jacobian(before), 0.2));
  EXPECT_GE(r.region_min_scaled_jacobian_after, 0.2);
  // ...no node left the surface it was on (the axis stays the axis, the rim the cylinder)...
  for (size_t v = 0; v < after.nodes.size(); ++v) {
    const double r_before = std::hypot(before.nodes[v].x(), before.nodes[v].z());
    const double r_after = std::hypot(after.nodes[v].x(), after.nodes[v].z());
    EXPECT_NEAR(r_after, r_before, 1e-3) << "node " << v;
  }
  // ...and the levels far from the fold (more than the largest region reaches) did not move.
  for (int level = 0; level <= kLevels; ++level) {
    if (std::abs(level - kLevels / 2) <= 1 + RepairBoundaryFoldsOptions{}.max_rings + 1) continue;
    for (int k = 0; k < 10; ++k) EXPECT_EQ(after.nodes[size_t(level * 10 + k)], before.nodes[size_t(level * 10 + k)]);
  }
}

TEST(RepairBoundaryFolds, LeavesAMeshWithoutFoldsBitIdentical) {
  const TriangleBvh surface = cylinder_with_ends();
  const HexMesh before = cake(80, 1);
  HexMesh after = before;
  const RepairBoundaryFoldsReport r = repair(after, surface);
  EXPECT_EQ(r.faces_inside_before, 0u);
  EXPECT_EQ(r.faces_inside_after, 0u);
  EXPECT_EQ(r.moved_nodes, 0u);
  ASSERT_EQ(after.nodes.size(), before.nodes.size());
  for (size_t v = 0; v < after.nodes.size(); ++v) EXPECT_EQ(after.nodes[v], before.nodes[v]);
}

TEST(RepairBoundaryFolds, LeavesTheMeshAsItWasWhenNothingCanMove) {
  // The same fold with every node pinned (a surface too far away for any landing, interior
  // nodes none): nothing can move, the count stays and the mesh is unchanged.
  const HexMesh before = cake(95, 1);
  HexMesh after = before;
  const TriangleBvh far_away(std::vector<Vec3>{Vec3(100, 0, 0), Vec3(101, 0, 0), Vec3(100, 1, 0)},
                             std::vector<std::array<int, 3>>{{0, 1, 2}});
  const RepairBoundaryFoldsReport r = repair(after, far_away);
  EXPECT_EQ(r.faces_inside_before, 4u);
  EXPECT_EQ(r.faces_inside_after, 4u);
  EXPECT_EQ(r.moved_nodes, 0u);
  for (size_t v = 0; v < after.nodes.size(); ++v) EXPECT_EQ(after.nodes[v], before.nodes[v]);
  // Both phases (on the surface, off it) stop after their first ring count: it removed no fold,
  // so no wider region is tried.
  EXPECT_EQ(r.phases_ended_without_gain, 2u);
}
