// SPDX-License-Identifier: MIT
#include <dthex/tets/split_surface_tets.h>

#include <dthex/hexes/conformity.h>
#include <dthex/hexes/node_count.h>
#include <dthex/hexes/thex.h>
#include <dthex/io/read_surface.h>
#include <dthex/mesh/quality.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/verify_surface.h>
#include <dthex/tets/tetrahedralize.h>
#include "tet_edit_fixtures.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <cmath>
#include <map>
#include <set>

using namespace dthex;
using dthex::tet_fixtures::expect_conforming;
using dthex::tet_fixtures::expect_valid;
using dthex::tet_fixtures::total_volume;
using dthex::tet_fixtures::signed_volume;
using dthex::tet_fixtures::sorted_face;

namespace {

//! A bundled mesh tet-meshed without Steiner points: every tet has all its vertices on the
//! boundary, the hardest case for the split.
TetMesh tets_without_steiner_points(const std::string& mesh) {
  TetgenOptions options;
  options.switches = "pY";
  return tetrahedralize(read_surface(std::string(DTHEX_SOURCE_DIR "/meshes/") + mesh), options);
}

// Interior faces (not boundary faces) whose three vertices are all boundary vertices.
size_t interior_faces_between_boundary_vertices(const TetMesh& m) {
  std::vector<char> on_boundary(m.points.size(), 0);
  std::set<std::array<int, 3>> boundary;
  for (const auto& f : m.boundary_faces) {
    for (int v : f) on_boundary[size_t(v)] = 1;
    std::array<int, 3> key = f;
    std::sort(key.begin(), key.end());
    boundary.insert(key);
  }
  std::set<std::array<int, 3>> bad;
  for (const auto& t : m.tets)
    for (int skip = 0; skip < 4; ++skip) {
      const std::array<int, 3> key = sorted_face(t, skip);
      if (on_boundary[size_t(key[0])] && on_boundary[size_t(key[1])] && on_boundary[size_t(key[2])] &&
          !boundary.count(key))
        bad.insert(key);
    }
  return bad.size();
}

// Hex faces that are not on the boundary but have two edges of the boundary quad surface
// meeting at one of their corners. Once the boundary lies on a smooth surface those two
// edges span its tangent plane at that corner, and the hexes on both sides of the face have
// their third edge there going inside: one of the two is flat or inverted.
size_t hex_faces_bent_along_the_boundary(const HexMesh& hexes) {
  std::vector<std::array<int, 4>> quads;
  check_conformity(hexes, &quads);
  std::set<std::pair<int, int>> boundary_edges;
  std::set<std::array<int, 4>> boundary_quads;
  for (auto q : quads) {
    for (int k = 0; k < 4; ++k) boundary_edges.insert(std::minmax(q[size_t(k)], q[size_t((k + 1) % 4)]));
    std::sort(q.begin(), q.end());
    boundary_quads.insert(q);
  }
  constexpr int kFaces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  size_t bent = 0;
  for (const auto& h : hexes.hexes)
    for (const auto& f : kFaces) {
      std::array<int, 4> ring{h[size_t(f[0])], h[size_t(f[1])], h[size_t(f[2])], h[size_t(f[3])]};
      std::array<int, 4> key = ring;
      std::sort(key.begin(), key.end());
      if (boundary_quads.count(key)) continue;
      for (int k = 0; k < 4; ++k)
        if (boundary_edges.count(std::minmax(ring[size_t((k + 3) % 4)], ring[size_t(k)])) &&
            boundary_edges.count(std::minmax(ring[size_t(k)], ring[size_t((k + 1) % 4)]))) {
          ++bent;
          break;
        }
    }
  return bent;
}

}  // namespace

// Two tets on one triangle a-b-c (a triangular bipyramid): every edge is a boundary edge and
// every tet has three boundary faces, but the face a-b-c between them is inside. Splitting
// each tet at its centroid alone keeps that face, and THex then gives hexes at a, b and c
// with two edges along the surface and the face between them inside, on both sides. The
// face split leaves no such face and no such hex face.
TEST(SplitSurfaceTets, InteriorFaceOfThreeBoundaryEdgesIsSplit) {
  TetMesh m;
  const double s = std::sqrt(3.0) / 2;
  m.points = {Vec3(1, 0, 0), Vec3(-0.5, s, 0), Vec3(-0.5, -s, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  m.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  m.boundary_faces = {{0, 1, 3}, {1, 2, 3}, {0, 3, 2}, {0, 2, 4}, {2, 1, 4}, {0, 4, 1}};
  m.boundary_face_source = {0, 1, 2, 3, 4, 5};
  ASSERT_EQ(interior_faces_between_boundary_vertices(m), 1u);
  double volume_before = 0;
  for (const auto& t : m.tets) volume_before += signed_volume(m, t);
  const auto faces_before = m.boundary_faces;

  const SplitSurfaceTetsReport report = split_surface_tets(m);
  EXPECT_EQ(report.split_faces, 1u);
  EXPECT_EQ(report.split_edges, 0u);
  EXPECT_EQ(interior_faces_between_boundary_vertices(m), 0u);
  EXPECT_EQ(m.boundary_faces, faces_before);
  double volume_after = 0;
  for (const auto& t : m.tets) {
    EXPECT_GT(signed_volume(m, t), 0);
    volume_after += signed_volume(m, t);
  }
  EXPECT_NEAR(volume_after, volume_before, 1e-12);
  expect_conforming(m);

  const HexMesh hexes = thex(m);
  EXPECT_TRUE(check_conformity(hexes).conforming());
  EXPECT_EQ(hex_faces_bent_along_the_boundary(hexes), 0u);
  EXPECT_EQ(measure_hex_quality(hexes).inverted, 0u);
}

// The icosahedron meshed without Steiner points: after the split the mesh is a
// valid conforming tet mesh of the same volume, no tet has two boundary faces, and no
// interior edge joins two boundary vertices.
TEST(SplitSurfaceTets, IcosahedronStaysConformingWithoutFlatCornerTets) {
  TetMesh tets = tets_without_steiner_points("icosahedron.off");
  double volume_before = 0;
  for (const auto& t : tets.tets) volume_before += signed_volume(tets, t);
  const auto faces_before = tets.boundary_faces;

  const SplitSurfaceTetsReport report = split_surface_tets(tets);
  EXPECT_GT(report.split_edges + report.split_tets + report.coned_clusters, 0u);
  EXPECT_EQ(tets.boundary_faces, faces_before);

  double volume_after = 0;
  for (const auto& t : tets.tets) {
    const double v = signed_volume(tets, t);
    EXPECT_GT(v, 0);
    volume_after += v;
  }
  EXPECT_NEAR(volume_after, volume_before, 1e-12 * volume_before);
  expect_conforming(tets);

  std::vector<char> on_boundary(tets.points.size(), 0);
  std::vector<std::array<int, 3>> keys;
  std::vector<std::pair<int, int>> boundary_edges;
  for (const auto& f : tets.boundary_faces) {
    for (int v : f) on_boundary[size_t(v)] = 1;
    std::array<int, 3> key = f;
    std::sort(key.begin(), key.end());
    keys.push_back(key);
    for (int i = 0; i < 3; ++i) boundary_edges.emplace_back(std::minmax(f[size_t(i)], f[size_t((i + 1) % 3)]));
  }
  std::sort(keys.begin(), keys.end());
  std::sort(boundary_edges.begin(), boundary_edges.end());
  for (const auto& t : tets.tets) {
    int boundary_faces = 0;
    for (int skip = 0; skip < 4; ++skip) {
      const std::array<int, 3> key = sorted_face(t, skip);
      boundary_faces += std::binary_search(keys.begin(), keys.end(), key);
    }
    EXPECT_LT(boundary_faces, 2);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const std::pair<int, int> e = std::minmax(t[size_t(i)], t[size_t(j)]);
        if (on_boundary[size_t(e.first)] && on_boundary[size_t(e.second)])
          EXPECT_TRUE(std::binary_search(boundary_edges.begin(), boundary_edges.end(), e))
              << "interior edge " << e.first << "-" << e.second << " joins two boundary vertices";
      }
  }
  // THex of the split mesh: conforming, nothing inverted.
  const HexMesh hexes = thex(tets);
  EXPECT_TRUE(check_conformity(hexes).conforming());
  EXPECT_EQ(measure_hex_quality(hexes).inverted, 0u);
}

// A single tet has four boundary faces: it is split at its centroid into four tets with one
// boundary face each.
TEST(SplitSurfaceTets, SingleTetSplitsIntoFour) {
  TetMesh m;
  m.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.tets = {{0, 1, 2, 3}};
  m.boundary_faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const SplitSurfaceTetsReport report = split_surface_tets(m);
  EXPECT_EQ(report.split_tets, 1u);
  EXPECT_EQ(report.split_edges, 0u);
  ASSERT_EQ(m.tets.size(), 4u);
  ASSERT_EQ(m.points.size(), 5u);
  EXPECT_LT((m.points[4] - Vec3(0.25, 0.25, 0.25)).norm(), 1e-15);
  for (const auto& t : m.tets) EXPECT_NEAR(signed_volume(m, t), 1.0 / 24.0, 1e-15);
  expect_conforming(m);
}

// TetGen meshes the icosahedron with 15 tets and no interior point; its 6 interior edges
// between boundary vertices all share tets (one cluster), so one point at the centroid
// replaces them: the paper's 20 tets around the centre (Fig. 19), whose THex diced by 3
// has the paper's 2473 nodes, not 45 tets from six midpoint splits.
TEST(SplitSurfaceTets, IcosahedronClusterBecomesTwentyTetsAroundTheCentre) {
  TetMesh tets = tets_without_steiner_points("icosahedron.off");
  ASSERT_EQ(tets.points.size(), 12u);
  const SplitSurfaceTetsReport report = split_surface_tets(tets);
  EXPECT_EQ(report.coned_clusters, 1u);
  EXPECT_EQ(report.split_edges, 0u);
  EXPECT_EQ(report.split_tets, 0u);
  ASSERT_EQ(tets.points.size(), 13u);
  EXPECT_EQ(tets.tets.size(), 20u);
  Vec3 centre = Vec3::Zero();
  for (size_t i = 0; i < 12; ++i) centre += tets.points[i] / 12.0;
  EXPECT_LT((tets.points[12] - centre).norm(), 1e-9);
  for (const auto& t : tets.tets) {
    EXPECT_GT(signed_volume(tets, t), 0);
    EXPECT_NE(std::find(t.begin(), t.end(), 12), t.end());
  }
  expect_conforming(tets);
  EXPECT_EQ(diced_thex_nodes(count_tet_entities(tets), 3), 2473u);
}

// Without the cone (option off) the same cluster is split edge by edge: more tets.
TEST(SplitSurfaceTets, WithoutConesTheIcosahedronGetsMidpointSplits) {
  TetMesh tets = tets_without_steiner_points("icosahedron.off");
  SplitSurfaceTetsOptions split;
  split.cone_edge_clusters = false;
  const SplitSurfaceTetsReport report = split_surface_tets(tets, split);
  EXPECT_EQ(report.coned_clusters, 0u);
  EXPECT_GT(report.split_edges, 0u);
  EXPECT_GT(tets.tets.size(), 20u);
  expect_conforming(tets);
}

// A real coarse-enough surface meshed without Steiner points has many interior edges between
// boundary vertices, some in clusters: after the split none is left, no tet has two
// boundary faces, the mesh is conforming with the same volume, and each such edge cost at
// most one new point (a cone apex or a midpoint), never one for an edge that was not there.
TEST(SplitSurfaceTets, LiverWithoutSteinerPointsLosesEveryInteriorBoundaryEdge) {
  TetMesh tets = tets_without_steiner_points("liver.off");
  std::vector<char> on_boundary(tets.points.size(), 0);
  std::set<std::pair<int, int>> boundary_edges;
  for (const auto& f : tets.boundary_faces)
    for (int i = 0; i < 3; ++i) {
      on_boundary[size_t(f[size_t(i)])] = 1;
      boundary_edges.insert(std::minmax(f[size_t(i)], f[size_t((i + 1) % 3)]));
    }
  auto bad_edges = [&](const TetMesh& m) {
    std::set<std::pair<int, int>> bad;
    for (const auto& t : m.tets)
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) {
          const std::pair<int, int> e = std::minmax(t[size_t(i)], t[size_t(j)]);
          if (size_t(e.second) < on_boundary.size() && on_boundary[size_t(e.first)] &&
              on_boundary[size_t(e.second)] && !boundary_edges.count(e))
            bad.insert(e);
        }
    return bad.size();
  };
  const size_t before = bad_edges(tets), points_before = tets.points.size();
  ASSERT_GT(before, 10u);
  const double volume_before = total_volume(tets);
  const SplitSurfaceTetsReport report = split_surface_tets(tets);
  EXPECT_EQ(bad_edges(tets), 0u);
  EXPECT_EQ(interior_faces_between_boundary_vertices(tets), 0u);
  EXPECT_EQ(hex_faces_bent_along_the_boundary(thex(tets)), 0u);
  EXPECT_LE(report.split_edges + report.coned_clusters, before);
  EXPECT_EQ(tets.points.size(),
            points_before + report.split_edges + report.coned_clusters + report.split_faces + report.split_tets);
  expect_valid(tets, volume_before);
}

// The shared aneurysm coarsened at the default eps and meshed with the default switches (its
// coarse boundary has a vertex whose three faces are one tet's, the case of the bipyramid
// above): after the split no interior edge or face joins only boundary vertices, and no
// hex face of its THex is bent between two boundary edges.
TEST(SplitSurfaceTets, CoarseAneurysmHasNoHexFaceBentAlongTheBoundary) {
  const std::string path = DTHEX_SHARED_DIR "/meshes/aneurysm.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no shared meshes";
  TriSurface surface = read_surface(path);
  verify_surface(surface, path);
  TriSurface coarse = coarsen(surface).surface;
  verify_surface(coarse, "coarse");
  TetMesh tets = tetrahedralize(coarse);
  split_surface_tets(tets);
  EXPECT_EQ(interior_faces_between_boundary_vertices(tets), 0u);
  for (const auto& t : tets.tets) EXPECT_GT(signed_volume(tets, t), 0);
  expect_conforming(tets);
  const HexMesh hexes = thex(tets);
  EXPECT_TRUE(check_conformity(hexes).conforming());
  EXPECT_EQ(hex_faces_bent_along_the_boundary(hexes), 0u);
}
