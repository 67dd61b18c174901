// SPDX-License-Identifier: MIT
#include <dthex/hexes/mesh_sets.h>
#include <dthex/io/write_surface.h>
#include <dthex/pipeline/pipeline.h>
#include "boundary_fixtures.h"
#include "scratch_dir.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>

using namespace dthex;
using dthex::testing::hex_block;

namespace {

Vec3 face_area_vector(const HexMesh& m, const HexFace& f) {
  const auto& c = kHexFaces[size_t(f.side)];
  const auto& h = m.hexes[size_t(f.hex)];
  const Vec3 d0 = m.nodes[size_t(h[size_t(c[2])])] - m.nodes[size_t(h[size_t(c[0])])];
  const Vec3 d1 = m.nodes[size_t(h[size_t(c[3])])] - m.nodes[size_t(h[size_t(c[1])])];
  return 0.5 * d0.cross(d1);
}

Vec3 hex_centre(const HexMesh& m, int hex) {
  Vec3 c(0, 0, 0);
  for (int n : m.hexes[size_t(hex)]) c += m.nodes[size_t(n)] / 8.0;
  return c;
}

const FaceSet& surface(const MeshSets& s, const std::string& name) {
  for (const FaceSet& f : s.surfaces)
    if (f.name == name) return f;
  throw std::runtime_error("no surface " + name);
}

// A closed surface of revolution about the z axis: the profile (r, z) from the bottom pole to
// the top pole, turned in `segments` steps.
TriSurface revolve(const std::vector<std::pair<double, double>>& profile, int segments) {
  TriSurface s;
  s.points.push_back(Vec3(0, 0, profile.front().second));
  for (size_t i = 1; i + 1 < profile.size(); ++i)
    for (int k = 0; k < segments; ++k) {
      const double a = 2 * M_PI * k / segments;
      s.points.push_back(Vec3(profile[i].first * std::cos(a), profile[i].first * std::sin(a), profile[i].second));
    }
  s.points.push_back(Vec3(0, 0, profile.back().second));
  const int rings = int(profile.size()) - 2, top = int(s.points.size()) - 1;
  auto at = [&](int ring, int k) { return 1 + ring * segments + (k % segments); };
  for (int k = 0; k < segments; ++k) {
    s.triangles.push_back({0, at(0, k + 1), at(0, k)});
    for (int r = 0; r + 1 < rings; ++r) {
      s.triangles.push_back({at(r, k), at(r, k + 1), at(r + 1, k + 1)});
      s.triangles.push_back({at(r, k), at(r + 1, k + 1), at(r + 1, k)});
    }
    s.triangles.push_back({top, at(rings - 1, k), at(rings - 1, k + 1)});
  }
  return s;
}

// The largest distance of the patch's face corners from the plane through `point` with unit
// normal `normal`.
double largest_distance_from_plane(const HexMesh& m, const FaceSet& patch, const Vec3& point, const Vec3& normal) {
  double largest = 0;
  for (const HexFace& f : patch.faces)
    for (int c : kHexFaces[size_t(f.side)])
      largest = std::max(largest, std::abs((m.nodes[size_t(m.hexes[size_t(f.hex)][size_t(c)])] - point).dot(normal)));
  return largest;
}

// The patch whose faces' mean outward normal is closest to `normal`.
const FaceSet& patch_facing(const HexMesh& m, const MeshSets& s, const Vec3& normal) {
  const FaceSet* best = nullptr;
  double best_dot = -2;
  for (const FaceSet& f : s.surfaces) {
    if (f.name.rfind("patch", 0) != 0) continue;
    Vec3 sum = Vec3::Zero();
    for (const HexFace& face : f.faces) sum += face_area_vector(m, face);
    const double d = sum.normalized().dot(normal);
    if (d > best_dot) {
      best_dot = d;
      best = &f;
    }
  }
  if (!best) throw std::runtime_error("no patch");
  return *best;
}

}  // namespace

TEST(MeshSets, ABlockIsOnePartWithSixPatchesByArea) {
  const HexMesh m = hex_block(Vec3(0, 0, 0), Vec3(3, 2, 1), 3, 2, 1);
  const MeshSets s = find_mesh_sets(m);
  ASSERT_EQ(s.parts.size(), 1u);
  EXPECT_EQ(s.parts[0].name, "body1");
  EXPECT_EQ(s.parts[0].hexes.size(), 6u);
  const FaceSet& boundary = surface(s, "body1_boundary");
  EXPECT_EQ(boundary.faces.size(), 22u);  // 2 (3x2 + 3x1 + 2x1)
  EXPECT_NEAR(boundary.area, 22.0, 1e-12);
  // Each face's side is an outward face of its hex: on the boundary, its area vector points away
  // from its hex's centre, and no face is listed twice.
  std::set<std::pair<int, int>> seen;
  for (const HexFace& f : boundary.faces) {
    const auto& c = kHexFaces[size_t(f.side)];
    Vec3 centre(0, 0, 0);
    for (int i : c) centre += m.nodes[size_t(m.hexes[size_t(f.hex)][size_t(i)])] / 4.0;
    EXPECT_GT(face_area_vector(m, f).dot(centre - hex_centre(m, f.hex)), 0) << f.hex << " S" << f.side + 1;
    EXPECT_NEAR(face_area_vector(m, f).norm(), 1.0, 1e-12);
    EXPECT_TRUE(seen.insert({f.hex, f.side}).second);
  }
  // Patches are the six sides of the box, largest first: 3x2 twice, 3x1 twice, 2x1 twice.
  std::vector<double> areas;
  for (const FaceSet& f : s.surfaces)
    if (f.name.rfind("patch", 0) == 0) areas.push_back(f.area);
  ASSERT_EQ(areas.size(), 6u);
  const std::vector<double> expected = {6, 6, 3, 3, 2, 2};
  for (size_t i = 0; i < 6; ++i) EXPECT_NEAR(areas[i], expected[i], 1e-12) << "patch" << i + 1;
  EXPECT_EQ(surface(s, "patch1").name, "patch1");
  // Each face set has a node set of its faces' nodes, of the same name.
  ASSERT_EQ(s.node_sets.size(), s.surfaces.size());
  EXPECT_EQ(s.node_sets[0].name, "body1_boundary");
  EXPECT_EQ(s.node_sets[0].nodes.size(), 4u * 3u * 2u);  // every node of a 3x2x1 block is on its boundary
  for (size_t i = 1; i < s.node_sets.size(); ++i) {
    EXPECT_EQ(s.node_sets[i].name, s.surfaces[i].name);
    const size_t faces = s.surfaces[i].faces.size();
    // A 3x2 side has 12 nodes, a 3x1 side 8, a 2x1 side 6.
    EXPECT_EQ(s.node_sets[i].nodes.size(), faces == 6 ? 12u : faces == 3 ? 8u : 6u) << s.node_sets[i].name;
  }
}

TEST(MeshSets, AWideCreaseAngleJoinsTheBoxIntoOnePatch) {
  const HexMesh m = hex_block(Vec3(0, 0, 0), Vec3(3, 2, 1), 3, 2, 1);
  MeshSetsOptions options;
  options.crease_angle_degrees = 100;  // the box's 90-degree edges are no longer creases
  const MeshSets s = find_mesh_sets(m, options);
  ASSERT_EQ(s.surfaces.size(), 2u);
  EXPECT_EQ(s.surfaces[1].name, "patch1");
  EXPECT_EQ(s.surfaces[1].faces.size(), 22u);
}

TEST(MeshSets, DisjointBodiesArePartsNamedBySize) {
  // The small body comes first in the mesh; body1 must still be the larger one.
  HexMesh small = hex_block(Vec3(10, 0, 0), Vec3(11, 1, 1), 1, 1, 1);
  const HexMesh large = hex_block(Vec3(0, 0, 0), Vec3(2, 2, 2), 2, 2, 2);
  const int offset = int(small.nodes.size());
  small.nodes.insert(small.nodes.end(), large.nodes.begin(), large.nodes.end());
  for (auto h : large.hexes) {
    for (int& n : h) n += offset;
    small.hexes.push_back(h);
  }
  const MeshSets s = find_mesh_sets(small);
  ASSERT_EQ(s.parts.size(), 2u);
  EXPECT_EQ(s.parts[0].name, "body1");
  EXPECT_EQ(s.parts[0].hexes, (std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(s.parts[1].name, "body2");
  EXPECT_EQ(s.parts[1].hexes, (std::vector<int>{0}));
  EXPECT_EQ(surface(s, "body1_boundary").faces.size(), 24u);
  EXPECT_EQ(surface(s, "body2_boundary").faces.size(), 6u);
  for (const HexFace& f : surface(s, "body2_boundary").faces) EXPECT_EQ(f.hex, 0);
  // 6 sides of each box: 12 patches, the large box's (area 4) first.
  size_t patches = 0;
  for (const FaceSet& f : s.surfaces)
    if (f.name.rfind("patch", 0) == 0) {
      ++patches;
      EXPECT_NEAR(f.area, patches <= 6 ? 4.0 : 1.0, 1e-12) << f.name;
    }
  EXPECT_EQ(patches, 12u);
}

//! Two material regions sharing nodes (HexMesh::region): the block's left column (x < 1) and the
//! rest. Each region is a part, each part's boundary holds the interface as faces of its own hexes,
//! and the interface is a surface faced from region 0 into region 1; user sets and patches see
//! only the outer boundary.
TEST(MeshSets, MaterialRegionsArePartsWithTheirInterfaceBetween) {
  HexMesh m = hex_block(Vec3(0, 0, 0), Vec3(3, 2, 1), 3, 2, 1);
  m.region.resize(m.hexes.size());
  for (size_t h = 0; h < m.hexes.size(); ++h) m.region[h] = hex_centre(m, int(h)).x() < 1 ? 1 : 0;
  MeshSets s = find_mesh_sets(m);
  ASSERT_EQ(s.parts.size(), 2u);
  EXPECT_EQ(s.parts[0].hexes.size(), 4u);  // region 0, the larger, is body1
  EXPECT_EQ(s.parts[1].hexes.size(), 2u);
  for (int h : s.parts[1].hexes) EXPECT_EQ(m.region[size_t(h)], 1);
  const FaceSet& interface = surface(s, "body1_body2_interface");
  ASSERT_EQ(interface.faces.size(), 2u);  // the x = 1 plane, 2 faces of area 1
  EXPECT_NEAR(interface.area, 2.0, 1e-12);
  for (const HexFace& f : interface.faces) {
    EXPECT_EQ(m.region[size_t(f.hex)], 0);
    EXPECT_LT(face_area_vector(m, f).x(), 0) << "faces from region 0 into region 1 (towards -x)";
  }
  // 14 outer faces + 2 for body1, 8 outer + 2 for body2; the two sides of the interface are
  // faces of different hexes.
  EXPECT_EQ(surface(s, "body1_boundary").faces.size(), 16u);
  EXPECT_EQ(surface(s, "body2_boundary").faces.size(), 10u);
  for (const HexFace& f : surface(s, "body2_boundary").faces) EXPECT_EQ(m.region[size_t(f.hex)], 1);
  double patch_area = 0;
  for (const FaceSet& f : s.surfaces)
    if (f.name.rfind("patch", 0) == 0) patch_area += f.area;
  EXPECT_NEAR(patch_area, 22.0, 1e-12) << "patches cover the outer boundary only";
  EXPECT_THROW(add_user_sets(s, m, {parse_user_set("cut=plane:1,0,0,1,0,0,1e-9")}), InputError)
      << "the interface is not a boundary a user set can select";
  add_user_sets(s, m, {parse_user_set("floor=plane:0,0,0,0,0,1,1e-9")});
  EXPECT_EQ(surface(s, "floor").faces.size(), 6u);
}

//! Parts named by the input: three blocks, the large one near triangles named "Left bone", the two
//! small ones near "2nd" and none; the names become valid set names, the largest part keeps a
//! shared one, and the boundary sets follow their part's name.
TEST(MeshSets, PartsTakeTheNamesOfTheInputTrianglesNearestThem) {
  HexMesh m = hex_block(Vec3(0, 0, 0), Vec3(2, 2, 2), 2, 2, 2);
  for (const Vec3& corner : {Vec3(10, 0, 0), Vec3(20, 0, 0), Vec3(30, 0, 0)}) {
    const HexMesh small = hex_block(corner, corner + Vec3(1, 1, 1), 1, 1, 1);
    const int offset = int(m.nodes.size());
    m.nodes.insert(m.nodes.end(), small.nodes.begin(), small.nodes.end());
    for (auto h : small.hexes) {
      for (int& n : h) n += offset;
      m.hexes.push_back(h);
    }
  }
  MeshSets s = find_mesh_sets(m);
  ASSERT_EQ(s.parts.size(), 4u);
  // One named triangle at each block's centre height: nearest to all of that block's faces.
  TriSurface named;
  std::vector<int> triangle_name;
  for (const auto& [x, name] : {std::pair{1.0, 0}, std::pair{10.5, 1}, std::pair{20.5, 1}, std::pair{30.5, -1}}) {
    const int base = int(named.points.size());
    named.points.push_back(Vec3(x - 0.1, 0.5, 0.5));
    named.points.push_back(Vec3(x + 0.1, 0.5, 0.5));
    named.points.push_back(Vec3(x, 0.6, 0.5));
    named.triangles.push_back({base, base + 1, base + 2});
    triangle_name.push_back(name);
  }
  EXPECT_EQ(name_parts_by_input(s, m, named, triangle_name, {"Left bone", "2nd"}), 3u);
  EXPECT_EQ(s.parts[0].name, "Left_bone");
  EXPECT_EQ(s.parts[1].name, "part_2nd");
  EXPECT_EQ(s.parts[2].name, "part_2nd_2");
  EXPECT_EQ(s.parts[3].name, "body4");
  EXPECT_EQ(surface(s, "Left_bone_boundary").faces.size(), 24u);
  EXPECT_EQ(surface(s, "part_2nd_2_boundary").faces.size(), 6u);
  EXPECT_EQ(surface(s, "body4_boundary").faces.size(), 6u);
  for (size_t i = 0; i < s.surfaces.size(); ++i) EXPECT_EQ(s.node_sets[i].name, s.surfaces[i].name);
}

TEST(MeshSets, UserSetsByBoxAndPlaneSelectWholeBoundaryFaces) {
  const HexMesh m = hex_block(Vec3(0, 0, 0), Vec3(3, 2, 1), 3, 2, 1);
  MeshSets s = find_mesh_sets(m);
  const size_t before = s.surfaces.size();
  // The x = 0 side (2 faces, area 2) by a thin box; the x = 3 side by its plane. The box holds
  // the corner nodes of the faces next to the side but no whole face of theirs.
  add_user_sets(s, m, {parse_user_set("fixed=box:0.1,-1,-1,-0.1,3,2"),
                       parse_user_set("loaded=plane:3,0,0,2,0,0,1e-9")});
  ASSERT_EQ(s.surfaces.size(), before + 2);
  const FaceSet& fixed = surface(s, "fixed");
  EXPECT_EQ(fixed.faces.size(), 2u);
  EXPECT_NEAR(fixed.area, 2.0, 1e-12);
  for (const HexFace& f : fixed.faces) EXPECT_EQ(f.side, 5) << "S6 is the x = 0 side of a VTK-ordered hex";
  EXPECT_EQ(s.node_sets.back().name, "loaded");
  EXPECT_EQ(s.node_sets.back().nodes.size(), 6u);
  for (int n : s.node_sets.back().nodes) EXPECT_EQ(m.nodes[size_t(n)].x(), 3.0);
}

TEST(MeshSets, UserSetsRefuseBadTextGeneratedNamesAndEmptySelections) {
  auto message_of = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no InputError");
  };
  EXPECT_NE(message_of([] { parse_user_set("a=box:1,2,3"); }).find("3 numbers where 6"), std::string::npos);
  EXPECT_NE(message_of([] { parse_user_set("a=box:1,2,x,4,5,6"); }).find("'x' is not a number"), std::string::npos);
  EXPECT_NE(message_of([] { parse_user_set("a=sphere:1,2,3,4"); }).find("expected NAME=box:"), std::string::npos);
  EXPECT_NE(message_of([] { parse_user_set("patch2=box:0,0,0,1,1,1"); }).find("'patch2'"), std::string::npos);
  EXPECT_NE(message_of([] { parse_user_set("p=plane:0,0,0,0,0,0,1"); }).find("normal is zero"), std::string::npos);
  const HexMesh m = hex_block(Vec3(0, 0, 0), Vec3(1, 1, 1), 1, 1, 1);
  MeshSets s = find_mesh_sets(m);
  const std::string empty = message_of([&] { add_user_sets(s, m, {parse_user_set("far=box:5,5,5,6,6,6")}); });
  EXPECT_NE(empty.find("--set far: no boundary face"), std::string::npos) << empty;
  const std::string twice = message_of([&] {
    add_user_sets(s, m, {parse_user_set("top=plane:0,0,1,0,0,1,0"), parse_user_set("top=plane:0,0,1,0,0,1,0")});
  });
  EXPECT_NE(twice.find("given twice"), std::string::npos) << twice;
}

TEST(MeshSets, ACylindersFlatEndsArePatchesThoughItsRimIsRounded) {
  // Radius 1, height 1, the rims rounded with radius 0.2 in 8 steps of 11.25 degrees: no edge is
  // a crease, so only the planar regions separate the flat ends (radius 0.8) from the rest.
  std::vector<std::pair<double, double>> profile = {{0, 0}, {0.4, 0}, {0.8, 0}};
  for (int i = 1; i <= 8; ++i) {
    const double a = M_PI / 2 * i / 8;
    profile.push_back({0.8 + 0.2 * std::sin(a), 0.2 - 0.2 * std::cos(a)});
  }
  for (int i = 1; i <= 8; ++i) {
    const double a = M_PI / 2 * i / 8;
    profile.push_back({1.0 - 0.2 * (1 - std::cos(a)), 0.8 + 0.2 * std::sin(a)});
  }
  profile.push_back({0.4, 1});
  profile.push_back({0, 1});
  const TriSurface cylinder = revolve(profile, 64);
  const std::string path = (dthex_test::fresh_dir("mesh_sets_cylinder") / "cylinder.off").string();
  write_surface(cylinder, path);
  Progress quiet;
  const PipelineResult r = run_pipeline(path, PipelineOptions(), quiet);
  const MeshSets s = find_mesh_sets(r.hexes, r.input);
  const double flat_area = M_PI * 0.8 * 0.8;
  for (const double z : {0.0, 1.0}) {
    SCOPED_TRACE(z);
    const Vec3 outward(0, 0, z == 0 ? -1 : 1);
    const FaceSet& end = patch_facing(r.hexes, s, outward);
    EXPECT_LT(largest_distance_from_plane(r.hexes, end, Vec3(0, 0, z), outward), 0.01);
    EXPECT_NEAR(end.area, flat_area, 0.15 * flat_area);
  }
  // Without planar regions the rounded rims separate nothing: the whole boundary is one patch.
  MeshSetsOptions creases_only;
  creases_only.planar_min_area_fraction = 0;
  const MeshSets one = find_mesh_sets(r.hexes, r.input, creases_only);
  ASSERT_EQ(one.surfaces.size(), 2u);
  EXPECT_EQ(one.surfaces[1].name, "patch1");
}

TEST(MeshSets, TheFemursDistalCutIsOnePatch) {
  // The bundled femur is cut by the plane z = const at its lowest point, and the scan rounds the
  // cut's rim: no input edge there bends by more than 30 degrees.
  Progress quiet;
  PipelineOptions once;  // diced once: the patches follow the boundary, in half the time
  once.dice = 1;
  const PipelineResult r = run_pipeline(DTHEX_SOURCE_DIR "/meshes/femur_proximal_ct.off", once, quiet);
  double lowest = INFINITY;
  for (const Vec3& p : r.input.points) lowest = std::min(lowest, p.z());
  // The cut's area from the input alone: the triangles facing down within 10 degrees whose
  // corners are within 0.5 mm of the lowest point's height.
  double cut_area = 0;
  for (const auto& t : r.input.triangles) {
    const Vec3 &a = r.input.points[size_t(t[0])], &b = r.input.points[size_t(t[1])], &c = r.input.points[size_t(t[2])];
    const Vec3 n = (b - a).cross(c - a);
    const bool low = std::max({a.z(), b.z(), c.z()}) <= lowest + 0.5;
    if (low && -n.z() >= std::cos(10 * M_PI / 180) * n.norm()) cut_area += 0.5 * n.norm();
  }
  ASSERT_GT(cut_area, 300.0);  // mm^2: the cut is there
  const MeshSets s = find_mesh_sets(r.hexes, r.input);
  const FaceSet& cut = patch_facing(r.hexes, s, Vec3(0, 0, -1));
  EXPECT_LT(largest_distance_from_plane(r.hexes, cut, Vec3(0, 0, lowest), Vec3(0, 0, -1)), 1.0);
  EXPECT_NEAR(cut.area, cut_area, 0.15 * cut_area);
  // The pipeline's search tree over the input, handed in, finds the same patches face for face.
  ASSERT_TRUE(r.input_tree);
  MeshSetsOptions with_tree;
  with_tree.input_tree = r.input_tree.get();
  const MeshSets same = find_mesh_sets(r.hexes, r.input, with_tree);
  ASSERT_EQ(same.surfaces.size(), s.surfaces.size());
  for (size_t i = 0; i < s.surfaces.size(); ++i) {
    EXPECT_EQ(same.surfaces[i].name, s.surfaces[i].name);
    ASSERT_EQ(same.surfaces[i].faces.size(), s.surfaces[i].faces.size());
    for (size_t f = 0; f < s.surfaces[i].faces.size(); ++f) {
      EXPECT_EQ(same.surfaces[i].faces[f].hex, s.surfaces[i].faces[f].hex);
      EXPECT_EQ(same.surfaces[i].faces[f].side, s.surfaces[i].faces[f].side);
    }
  }
  // Without planar regions the cut is no patch of its own.
  MeshSetsOptions creases_only;
  creases_only.planar_min_area_fraction = 0;
  const MeshSets without = find_mesh_sets(r.hexes, r.input, creases_only);
  for (const FaceSet& f : without.surfaces)
    if (f.name.rfind("patch", 0) == 0)
      EXPECT_GT(largest_distance_from_plane(r.hexes, f, Vec3(0, 0, lowest), Vec3(0, 0, -1)), 1.0) << f.name;
}
