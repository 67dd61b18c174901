// SPDX-License-Identifier: MIT
#include <dthex/tets/tetrahedralize.h>

#include <dthex/hexes/conformity.h>
#include <dthex/hexes/dice.h>
#include <dthex/hexes/thex.h>
#include <dthex/tets/tet_regions.h>
#include "refine_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>

using namespace dthex;

namespace {

//! A closed axis-aligned box surface, outward triangles.
TriSurface box(const Vec3& lo, const Vec3& hi) {
  TriSurface s;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) s.points.push_back(Vec3(i ? hi.x() : lo.x(), j ? hi.y() : lo.y(), k ? hi.z() : lo.z()));
  // Quads (outward) as corner ids i + 2j + 4k.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    s.triangles.push_back({q[0], q[1], q[2]});
    s.triangles.push_back({q[0], q[2], q[3]});
  }
  return s;
}

TriSurface merge(const TriSurface& a, const TriSurface& b) {
  TriSurface s = a;
  const int offset = int(a.points.size());
  s.points.insert(s.points.end(), b.points.begin(), b.points.end());
  for (auto t : b.triangles) s.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return s;
}

double volume6(const TetMesh& m, const std::array<int, 4>& t) {
  const Vec3& a = m.points[size_t(t[0])];
  return (m.points[size_t(t[1])] - a).cross(m.points[size_t(t[2])] - a).dot(m.points[size_t(t[3])] - a);
}

}  // namespace

TEST(Tetrahedralize, SphereKeepsItsSurfaceWithY) {
  const TriSurface sphere = fixtures::read_off(DTHEX_SOURCE_DIR "/meshes/sphere728.off");
  ASSERT_EQ(sphere.triangles.size(), 728u);
  const TetMesh mesh = tetrahedralize(sphere);
  ASSERT_GT(mesh.tets.size(), 728u / 3);
  for (const auto& t : mesh.tets) ASSERT_GT(volume6(mesh, t), 0.0);
  ASSERT_EQ(mesh.boundary_faces.size(), 728u);
  ASSERT_EQ(mesh.boundary_face_source.size(), 728u);
  std::vector<int> seen(728, 0);
  Vec3 centre = Vec3::Zero();
  for (const auto& p : sphere.points) centre += p;
  centre /= double(sphere.points.size());
  for (size_t i = 0; i < mesh.boundary_faces.size(); ++i) {
    const int source = mesh.boundary_face_source[i];
    ASSERT_GE(source, 0);
    ASSERT_LT(source, 728);
    ++seen[size_t(source)];
    // Same three points as the input triangle it came from (Y: the surface is kept).
    std::array<Vec3, 3> in, out;
    for (int k = 0; k < 3; ++k) {
      in[size_t(k)] = sphere.points[size_t(sphere.triangles[size_t(source)][size_t(k)])];
      out[size_t(k)] = mesh.points[size_t(mesh.boundary_faces[i][size_t(k)])];
    }
    for (const auto& p : out)
      EXPECT_TRUE(p == in[0] || p == in[1] || p == in[2]) << "boundary face " << i << " is not its source triangle";
    const auto& f = mesh.boundary_faces[i];
    const Vec3 normal = (mesh.points[size_t(f[1])] - mesh.points[size_t(f[0])]).cross(mesh.points[size_t(f[2])] - mesh.points[size_t(f[0])]);
    EXPECT_GT(normal.dot(mesh.points[size_t(f[0])] - centre), 0.0) << "boundary face " << i << " points inward";
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
}

TEST(Tetrahedralize, SelfIntersectingSurfaceIsAnErrorNotACrash) {
  const TriSurface crossing = merge(box(Vec3(0, 0, 0), Vec3(1, 1, 1)), box(Vec3(0.5, 0.3, 0.2), Vec3(1.5, 1.3, 1.2)));
  try {
    tetrahedralize(crossing);
    FAIL() << "TetGen accepted two interpenetrating boxes";
  } catch (const MeshingError& e) {
    EXPECT_NE(std::string(e.what()).find("self-intersect"), std::string::npos) << e.what();
  }
}

TEST(Tetrahedralize, BoxesCloserThanItsToleranceFailNamingTheClosestPair) {
  // Two boxes 1e-12 apart (verification refuses these first; here TetGen gets them): its
  // failure names two triangles of the facing sides, the gap and the place.
  const TriSurface close = merge(box(Vec3(0, 0, 0), Vec3(1, 1, 1)), box(Vec3(1 + 1e-12, 0, 0), Vec3(2, 1, 1)));
  try {
    tetrahedralize(close);
    GTEST_SKIP() << "TetGen told the boxes apart";
  } catch (const MeshingError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("the closest triangles sharing no corner are "), std::string::npos) << message;
    EXPECT_NE(message.find(" apart at (1, "), std::string::npos) << message;
    EXPECT_NE(message.find("move the parts there apart, or merge them"), std::string::npos) << message;
  }
}

TEST(Tetrahedralize, TimeLimitStopsTetGen) {
  const std::string path = DTHEX_SOURCE_DIR "/meshes/femur_proximal_ct.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent";
  const TriSurface femur = fixtures::read_off(path);
  ASSERT_GT(femur.triangles.size(), 10000u);
  TetgenOptions options;
  options.time_limit_seconds = 0.05;
  try {
    tetrahedralize(femur, options);
    FAIL() << "TetGen finished the femur in 50 ms";
  } catch (const MeshingError& e) {
    EXPECT_NE(std::string(e.what()).find("time limit of 0.05 s"), std::string::npos) << e.what();
  }
}

TEST(Tetrahedralize, RefusesSwitchesThatTouchFilesAndBadLimits) {
  const TriSurface cube = box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  for (const char* bad : {"pq1.2Yk", "pg", "pv", "pNEF", "pr", "pi", "pm", "pV", "pq1.2 Y", "pf", "po2"}) {
    TetgenOptions options;
    options.switches = bad;
    EXPECT_THROW(tetrahedralize(cube, options), InputError) << bad;
  }
  TetgenOptions zero_limit;
  zero_limit.time_limit_seconds = 0;
  EXPECT_THROW(tetrahedralize(cube, zero_limit), InputError);
  TriSurface broken = cube;
  broken.triangles[3][1] = 99;
  EXPECT_THROW(tetrahedralize(broken), InputError);
}

TEST(Tetrahedralize, CubeWithVolumeBound) {
  TetgenOptions options;
  options.switches = "pq1.2a0.01";
  const TetMesh mesh = tetrahedralize(box(Vec3(0, 0, 0), Vec3(2, 1, 1)), options);
  double volume = 0;
  for (const auto& t : mesh.tets) {
    ASSERT_GT(volume6(mesh, t), 0.0);
    EXPECT_LE(volume6(mesh, t) / 6, 0.01 + 1e-12);
    volume += volume6(mesh, t) / 6;
  }
  EXPECT_NEAR(volume, 2.0, 1e-9);
  for (int s : mesh.boundary_face_source) EXPECT_TRUE(s >= 0 && s < 12);
}

//! TetGen fills every enclosed region; a cavity must stay empty, and a body inside the
//! cavity is material again. Box [0,5]^3, cavity [1,4]^3, island [2,3]^3: 125 - 27 + 1.
TEST(Tetrahedralize, CavitiesStayEmptyAndIslandsInThemAreMeshed) {
  const TriSurface surface =
      merge(merge(box(Vec3(0, 0, 0), Vec3(5, 5, 5)), box(Vec3(1, 1, 1), Vec3(4, 4, 4))), box(Vec3(2, 2, 2), Vec3(3, 3, 3)));
  const TetMesh mesh = tetrahedralize(surface);
  double volume = 0;
  std::vector<int> used(mesh.points.size(), 0);
  std::map<std::array<int, 3>, std::vector<size_t>> tets_of_face;
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& tet = mesh.tets[t];
    ASSERT_GT(volume6(mesh, tet), 0.0);
    volume += volume6(mesh, tet) / 6;
    for (int v : tet) used[size_t(v)] = 1;
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> key = {tet[size_t((f + 1) % 4)], tet[size_t((f + 2) % 4)], tet[size_t((f + 3) % 4)]};
      std::sort(key.begin(), key.end());
      tets_of_face[key].push_back(t);
    }
  }
  EXPECT_NEAR(volume, 99.0, 1e-9);
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "points of the dropped cavity tets remain";
  // Every facet is on the boundary of what is left: one tet, and the face points away from it.
  ASSERT_EQ(mesh.boundary_faces.size(), 36u);
  size_t faces_per_box[3] = {0, 0, 0};
  for (size_t i = 0; i < mesh.boundary_faces.size(); ++i) {
    const auto& f = mesh.boundary_faces[i];
    std::array<int, 3> key = f;
    std::sort(key.begin(), key.end());
    ASSERT_EQ(tets_of_face[key].size(), 1u) << "face " << i;
    Vec3 tet_centre = Vec3::Zero();
    for (int v : mesh.tets[tets_of_face[key][0]]) tet_centre += mesh.points[size_t(v)] / 4;
    const Vec3 a = mesh.points[size_t(f[0])], b = mesh.points[size_t(f[1])], c = mesh.points[size_t(f[2])];
    EXPECT_GT((b - a).cross(c - a).dot((a + b + c) / 3 - tet_centre), 0.0) << "face " << i << " points into its tet";
    ++faces_per_box[size_t(mesh.boundary_face_source[i] / 12)];
  }
  EXPECT_EQ(faces_per_box[0], 12u);
  EXPECT_EQ(faces_per_box[1], 12u);
  EXPECT_EQ(faces_per_box[2], 12u);
}

//! With keep_nested_regions the same three boxes are three materials (a shell, a shell inside
//! it, a core), each closed on its own once taken apart (tet_regions.h), joined again at their
//! shared interface points, and after THex and dicing the interface nodes carry a facet as the
//! boundary's do. Volumes 125 - 64, 64 - 1, 1.
TEST(Tetrahedralize, NestedRegionsAreKeptAndTakenApartAtTheirInterfaces) {
  const TriSurface surface =
      merge(merge(box(Vec3(0, 0, 0), Vec3(5, 5, 5)), box(Vec3(1, 1, 1), Vec3(4, 4, 4))), box(Vec3(2, 2, 2), Vec3(3, 3, 3)));
  TetgenOptions options;
  options.keep_nested_regions = true;
  const TetMesh mesh = tetrahedralize(surface, options);
  ASSERT_EQ(mesh.tet_region.size(), mesh.tets.size());
  double volume[3] = {0, 0, 0};
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    ASSERT_GE(mesh.tet_region[t], 0);
    ASSERT_LT(mesh.tet_region[t], 3);
    volume[mesh.tet_region[t]] += volume6(mesh, mesh.tets[t]) / 6;
  }
  EXPECT_NEAR(volume[0], 125.0 - 27.0, 1e-9);  // region 0 is the outermost, the depth order
  EXPECT_NEAR(volume[1], 27.0 - 1.0, 1e-9);
  EXPECT_NEAR(volume[2], 1.0, 1e-9);
  ASSERT_EQ(mesh.boundary_faces.size(), 36u) << "each interface face once";

  const std::vector<TetMesh> regions = split_tet_regions(mesh);
  ASSERT_EQ(regions.size(), 3u);
  const size_t expected_faces[3] = {24, 24, 12};  // outer + inner box, both boxes, the core's
  size_t points = 0;
  for (size_t r = 0; r < 3; ++r) {
    const TetMesh& region = regions[r];
    EXPECT_TRUE(region.tet_region.empty());
    EXPECT_EQ(region.boundary_faces.size(), expected_faces[r]) << r;
    // Closed: each boundary face has one tet of the region, which lies behind it.
    std::map<std::array<int, 3>, std::vector<std::pair<size_t, int>>> tets_of_face;
    for (size_t t = 0; t < region.tets.size(); ++t)
      for (int f = 0; f < 4; ++f) {
        const auto& tet = region.tets[t];
        std::array<int, 3> key = {tet[size_t((f + 1) % 4)], tet[size_t((f + 2) % 4)], tet[size_t((f + 3) % 4)]};
        std::sort(key.begin(), key.end());
        tets_of_face[key].push_back({t, tet[size_t(f)]});
      }
    for (const auto& f : region.boundary_faces) {
      std::array<int, 3> key = f;
      std::sort(key.begin(), key.end());
      ASSERT_EQ(tets_of_face[key].size(), 1u);
      const Vec3& a = region.points[size_t(f[0])];
      const Vec3 normal = (region.points[size_t(f[1])] - a).cross(region.points[size_t(f[2])] - a);
      EXPECT_LT(normal.dot(region.points[size_t(tets_of_face[key][0].second)] - a), 0) << "outward of its region";
    }
    points += region.points.size();
  }
  // The two interfaces' 8 + 8 corners are in two regions each.
  EXPECT_EQ(points, mesh.points.size() + 16);

  const TetMesh joined = merge_tet_regions(regions);
  EXPECT_EQ(joined.points.size(), mesh.points.size());
  EXPECT_EQ(joined.tets.size(), mesh.tets.size());
  EXPECT_EQ(joined.boundary_faces.size(), 36u);
  ASSERT_EQ(joined.tet_region.size(), joined.tets.size());
  double joined_volume[3] = {0, 0, 0};
  for (size_t t = 0; t < joined.tets.size(); ++t) joined_volume[joined.tet_region[t]] += volume6(joined, joined.tets[t]) / 6;
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(joined_volume[r], volume[r], 1e-9);

  // THex and dice: hexes keep the region; the nodes on either inner box carry a facet.
  const HexMesh hexes = dice(thex(joined), 2);
  ASSERT_EQ(hexes.region.size(), hexes.hexes.size());
  EXPECT_EQ(interface_quads(hexes).size(), 2 * 12 * 3 * 4u);  // 24 triangles, 3 quads each, diced in 4
  auto on_box = [](const Vec3& p, double lo, double hi) {  // on the surface of [lo, hi]^3
    const bool inside = (p.array() >= lo - 1e-12).all() && (p.array() <= hi + 1e-12).all();
    return inside && (((p.array() - lo).abs() < 1e-12).any() || ((p.array() - hi).abs() < 1e-12).any());
  };
  size_t interface_nodes = 0;
  for (size_t v = 0; v < hexes.nodes.size(); ++v)
    if (on_box(hexes.nodes[v], 1, 4) || on_box(hexes.nodes[v], 2, 3)) {
      ++interface_nodes;
      EXPECT_GE(hexes.boundary_facet[v], 0) << "interface node " << v;
    }
  EXPECT_GT(interface_nodes, 0u);
}
