// SPDX-License-Identifier: MIT
#include <dthex/tet_edits/split_crowded_vertices.h>

#include <dthex/boundary/local_smooth.h>
#include <dthex/hexes/dice.h>
#include <dthex/hexes/thex.h>
#include <dthex/mesh/quality.h>
#include <dthex/mesh/triangle_bvh.h>
#include "boundary_fixtures.h"
#include "refine_fixtures.h"
#include "tet_edit_fixtures.h"

#include <dthex/io/read_surface.h>
#include <gtest/gtest.h>

#include <map>

#include <algorithm>
#include <cmath>

using namespace dthex;
using namespace dthex::tet_fixtures;

namespace {

// The sphere's faces coned to its centre (boundary_fixtures.h's star_tets): one interior point in
// as many tets as the sphere has triangles (64 for 8 x 5 bands), the crowding THex cannot make
// good.

// Splits down to 28 tets a vertex, a new star's worst tet allowed to fall to 0.7 of the old:
// the even cone cannot be split at all without that.
SplitCrowdedVerticesOptions down_to_28() {
  SplitCrowdedVerticesOptions options;
  options.max_tets = 28;
  options.min_quality_ratio = 0.7;
  options.very_crowded_quality_ratio = 0.7;
  return options;
}

double worst_tet_scaled_jacobian(const TetMesh& m) {
  double worst = 1;
  for (const auto& t : m.tets)
    worst = std::min(worst, tet_scaled_jacobian(m.points[size_t(t[0])], m.points[size_t(t[1])], m.points[size_t(t[2])],
                                                m.points[size_t(t[3])]));
  return worst;
}

int most_tets_at_interior_vertex(const TetMesh& m) {
  std::vector<int> count(m.points.size(), 0);
  std::vector<char> on_boundary(m.points.size(), 0);
  for (const auto& f : m.boundary_faces)
    for (int v : f) on_boundary[size_t(v)] = 1;
  for (const auto& t : m.tets)
    for (int v : t) ++count[size_t(v)];
  int most = 0;
  for (size_t v = 0; v < count.size(); ++v)
    if (!on_boundary[v]) most = std::max(most, count[v]);
  return most;
}

// THex, dice 2, then the smoother raising every hex towards 0.6 with the boundary sliding on
// the sphere's surface: the smallest scaled Jacobian it reaches.
double smoothed_min_scaled_jacobian(const TetMesh& tets, const TriSurface& surface) {
  HexMesh hexes = dice(thex(tets), 2);
  LocalSmoothOptions options;
  options.target_scaled_jacobian = 0.6;
  options.max_attempts_per_hex = 60;
  options.lift_step = 0;
  const TriangleBvh bvh(surface);
  smooth_worst_hexes(hexes, bvh, options);
  return measure_hex_quality(hexes).scaled_jacobian_stats.min;
}

}  // namespace

// The centre of the coned sphere (64 tets) is split until no interior vertex is in more than
// 28 tets; the mesh stays a valid, conforming triangulation of the same ball with the same
// boundary, the boundary points do not move, and no split lowered a star's worst tet below
// 0.7 of what it was.
TEST(SplitCrowdedVertices, SplitsTheCentreOfAConedSphereUntilNoneIsCrowded) {
  const TriSurface sphere = dthex::testing::staggered_sphere(8, 5);
  TetMesh m = dthex::testing::star_tets(sphere, Vec3::Zero());
  ASSERT_EQ(most_tets_at_interior_vertex(m), 64);
  const double volume = total_volume(m);
  const double worst_before = worst_tet_scaled_jacobian(m);
  const auto boundary_faces = m.boundary_faces;
  const SplitCrowdedVerticesReport report = split_crowded_vertices(m, down_to_28());
  EXPECT_EQ(report.most_tets_before, 64);
  EXPECT_EQ(report.crowded_before, 1u);
  EXPECT_GE(report.split, 3u);  // 64 tets cannot go below 29 in fewer than three splits
  EXPECT_EQ(report.crowded_after, 0u);
  EXPECT_LE(report.most_tets_after, 28);
  EXPECT_EQ(report.most_tets_after, most_tets_at_interior_vertex(m));
  EXPECT_EQ(m.points.size(), sphere.points.size() + 1 + report.split);
  EXPECT_EQ(report.tets_after, m.tets.size());
  expect_valid(m, volume);
  EXPECT_EQ(m.boundary_faces, boundary_faces);
  for (size_t v = 0; v < sphere.points.size(); ++v) EXPECT_EQ(m.points[v], sphere.points[v]);
  EXPECT_GE(worst_tet_scaled_jacobian(m), std::pow(0.7, double(report.split)) * worst_before);
}

// A mesh whose interior vertices are in 24 tets each (the Kuhn block's) is left as it was.
TEST(SplitCrowdedVertices, LeavesAMeshWithoutCrowdedVerticesAlone) {
  TetMesh m = fixtures::kuhn_block(3, 3, 3);
  const TetMesh before = m;
  SplitCrowdedVerticesOptions options;
  options.max_tets = 24;
  const SplitCrowdedVerticesReport report = split_crowded_vertices(m, options);
  EXPECT_EQ(report.split, 0u);
  EXPECT_EQ(report.crowded_before, 0u);
  EXPECT_EQ(report.most_tets_before, 24);
  EXPECT_EQ(m.tets, before.tets);
  EXPECT_EQ(m.points, before.points);
}

// The gain on the hexes: with 64 hex corners at the centre no smoothing lifts the worst hex to
// 0.5 (an even split of the sphere into 64 bounds it at 0.33); with the centre split the same
// smoothing does.
TEST(SplitCrowdedVertices, LiftsTheWorstHexOfTheConedSphereAboveOneHalf) {
  const TriSurface sphere = dthex::testing::staggered_sphere(8, 5);
  const TetMesh crowded = dthex::testing::star_tets(sphere, Vec3::Zero());
  TetMesh split = crowded;
  split_crowded_vertices(split, down_to_28());
  const double without = smoothed_min_scaled_jacobian(crowded, sphere);
  const double with = smoothed_min_scaled_jacobian(split, sphere);
  EXPECT_LT(without, 0.5);
  EXPECT_GT(with, 0.5);
  EXPECT_GT(with, without + 0.1);
}

// The most crowded vertices take a worse split. The bundled icosahedron, its faces split in
// four onto its sphere and coned to its centre, makes a star of 80 even tets whose best split
// keeps 0.95-0.99 of its worst tet: it is not split where every split must keep 0.99, and is
// where a vertex in more than 51 tets need keep only 0.9; not when 80 tets is not "more than"
// the bound.
TEST(SplitCrowdedVertices, TheMostCrowdedTakeAWorseSplit) {
  const TriSurface ico = read_surface(std::string(DTHEX_SOURCE_DIR) + "/meshes/icosahedron.off");
  TriSurface finer;
  finer.points = ico.points;
  std::map<std::pair<int, int>, int> middle;
  auto midpoint = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    const auto it = middle.find(key);
    if (it != middle.end()) return it->second;
    finer.points.push_back((ico.points[size_t(a)] + ico.points[size_t(b)]).normalized() * ico.points[size_t(a)].norm());
    return middle[key] = int(finer.points.size()) - 1;
  };
  for (const auto& t : ico.triangles) {
    const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
    finer.triangles.push_back({t[0], ab, ca});
    finer.triangles.push_back({ab, t[1], bc});
    finer.triangles.push_back({ca, bc, t[2]});
    finer.triangles.push_back({ab, bc, ca});
  }
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : finer.points) centre += p / double(finer.points.size());
  const TetMesh coned = dthex::testing::star_tets(finer, centre);
  ASSERT_EQ(most_tets_at_interior_vertex(coned), 80);
  SplitCrowdedVerticesOptions strict;
  strict.max_tets = 28;
  strict.max_passes = 1;
  strict.min_quality_ratio = 0.99;
  strict.very_crowded_quality_ratio = 0.99;
  SplitCrowdedVerticesOptions lenient = strict;
  lenient.very_crowded_tets = 51;
  lenient.very_crowded_quality_ratio = 0.9;
  SplitCrowdedVerticesOptions at_the_bound = lenient;
  at_the_bound.very_crowded_tets = 80;

  TetMesh a = coned, b = coned, c = coned;
  const double volume = total_volume(coned);
  EXPECT_EQ(split_crowded_vertices(a, strict).split, 0u);
  const SplitCrowdedVerticesReport split = split_crowded_vertices(b, lenient);
  EXPECT_EQ(split.split, 1u);
  EXPECT_LT(split.most_tets_after, 80);
  expect_valid(b, volume);
  EXPECT_EQ(split_crowded_vertices(c, at_the_bound).split, 0u);
}
