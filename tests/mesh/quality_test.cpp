// SPDX-License-Identifier: MIT
#include <dthex/hexes/conformity.h>
#include <dthex/hexes/dice.h>
#include <dthex/hexes/thex.h>
#include <dthex/mesh/quality.h>
#include <dthex/numerics/inverse_cube_root.h>
#include <dthex/tets/tetrahedralize.h>
#include "refine_fixtures.h"
#include "scratch_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>

using namespace dthex;

namespace {

std::array<Vec3, 8> unit_cube() {
  return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
          Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
}

//! A tiny legacy-VTK writer (ASCII, full precision) so the referee can read our mesh.
void write_legacy_vtk(const HexMesh& mesh, const std::string& path) {
  std::ofstream out(path);
  out << "# vtk DataFile Version 3.0\nquality test\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  out << "POINTS " << mesh.nodes.size() << " double\n" << std::setprecision(17);
  for (const auto& p : mesh.nodes) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  out << "CELLS " << mesh.hexes.size() << ' ' << 9 * mesh.hexes.size() << '\n';
  for (const auto& h : mesh.hexes) {
    out << 8;
    for (int v : h) out << ' ' << v;
    out << '\n';
  }
  out << "CELL_TYPES " << mesh.hexes.size() << '\n';
  for (size_t i = 0; i < mesh.hexes.size(); ++i) out << "12\n";
}

std::string run(const std::string& command) {
  std::string text;
  if (FILE* pipe = ::popen(command.c_str(), "r")) {
    char buffer[4096];
    size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) text.append(buffer, n);
    ::pclose(pipe);
  }
  return text;
}

}  // namespace

TEST(Quality, UnitCubeIsPerfect) {
  EXPECT_DOUBLE_EQ(hex_shape(unit_cube()), 1.0);
  EXPECT_DOUBLE_EQ(hex_scaled_jacobian(unit_cube()), 1.0);
  auto tiny = unit_cube();
  for (auto& p : tiny) p *= 1e-6;  // scale-free
  EXPECT_NEAR(hex_shape(tiny), 1.0, 1e-12);
}

// The scaled Jacobian takes one root of the product of a frame's squared edge lengths. At
// edges of 1e-100 that product (1e-600) underflows to 0, at 1e100 it overflows; there the
// lengths are taken one by one. A distorted hex gives the same values at every scale.
TEST(Quality, ScaleFreeFromTinyToHugeEdges) {
  auto x = unit_cube();
  x[6] = Vec3(1.3, 0.8, 1.2);
  x[4] = Vec3(0.1, -0.2, 0.9);
  const double sj = hex_scaled_jacobian(x), shape = hex_shape(x);
  ASSERT_GT(sj, 0.1);
  ASSERT_LT(sj, 0.95);
  for (double scale : {1e-100, 1e-60, 1e-20, 1e20, 1e60, 1e100}) {
    auto y = x;
    for (auto& p : y) p *= scale;
    EXPECT_NEAR(hex_scaled_jacobian(y), sj, 1e-12) << "scale " << scale;
    EXPECT_NEAR(hex_shape(y), shape, 1e-12) << "scale " << scale;
    EXPECT_NEAR(hex_scaled_jacobian_and_shape(y).scaled_jacobian, sj, 1e-12) << "scale " << scale;
  }
}

// The quality's cube root and the untangler's energy use a bit-level guess refined by Newton
// steps: within three ulps of the library's over the whole range of doubles.
TEST(Quality, InverseCubeRootIsWithinThreeUlps) {
  double worst = 0;
  for (double x = 1e-300; x < 1e300; x *= 1.37) {
    const double reference = 1.0 / std::cbrt(x);
    worst = std::max(worst, std::abs(inverse_cube_root(x) - reference) / reference);
  }
  EXPECT_LT(worst, 7e-16);
  EXPECT_GT(worst, 0.0);  // not the library's cube root under another name
  EXPECT_NEAR(inverse_cube_root(8.0), 0.5, 4e-16);
  EXPECT_EQ(inverse_cube_root(1e-310), 1.0 / std::cbrt(1e-310));  // subnormal: the library's
  EXPECT_TRUE(std::isinf(inverse_cube_root(0.0)));
}

TEST(Quality, MirroredHexIsInverted) {
  auto x = unit_cube();
  for (auto& p : x) p.z() = -p.z();
  EXPECT_EQ(hex_shape(x), 0.0);
  EXPECT_LT(hex_scaled_jacobian(x), 0.0);
  EXPECT_NEAR(hex_scaled_jacobian(x), -1.0, 1e-12);
}

// A box of edges 1, 1 and 0.2: the scaled Jacobian sees a perfect hex, the edge ratio 0.2.
TEST(Quality, EdgeRatioSeesWhatTheScaledJacobianDoesNot) {
  std::array<Vec3, 8> box;
  for (int i = 0; i < 8; ++i) box[size_t(i)] = Vec3((i == 1 || i == 2 || i == 5 || i == 6) ? 1 : 0, (i % 4) >= 2 ? 1 : 0, i >= 4 ? 0.2 : 0);
  EXPECT_NEAR(hex_scaled_jacobian(box), 1.0, 1e-12);
  EXPECT_NEAR(hex_edge_ratio_squared(box), 0.04, 1e-12);
  HexWithMovingCorner moving(box, 6);
  // The top corner pulled down to 0.05: its vertical edge 0.05, the longest (6-7, 6-5) 1.0112.
  EXPECT_NEAR(moving.edge_ratio_squared_at(Vec3(1, 1, 0.05)), 0.0025 / 1.0225, 1e-12);
  EXPECT_NEAR(hex_edge_ratio_squared(box), 0.04, 1e-12);
  std::array<Vec3, 8> point;
  point.fill(Vec3::Zero());
  EXPECT_EQ(hex_edge_ratio_squared(point), 0.0);
}

TEST(Quality, CollapsedEdgeHasZeroScaledJacobian) {
  auto x = unit_cube();
  x[1] = x[0];
  EXPECT_EQ(hex_scaled_jacobian(x), 0.0);
  EXPECT_EQ(hex_shape(x), 0.0);
}

TEST(Quality, TetShapes) {
  const TetMesh regular = fixtures::regular_tet();
  const auto& t = regular.tets[0];
  EXPECT_NEAR(tet_shape(regular.points[size_t(t[0])], regular.points[size_t(t[1])], regular.points[size_t(t[2])],
                        regular.points[size_t(t[3])]),
              1.0, 1e-12);
  EXPECT_NEAR(tet_shape(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)), 0.839947, 1e-6);
  EXPECT_EQ(tet_shape(Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)), 0.0);  // inverted
  const HexMesh hexes = thex(regular);
  const HexQuality q = measure_hex_quality(hexes);
  EXPECT_NEAR(q.shape_stats.min, std::pow(2.0, -1.0 / 3.0), 1e-12);  // 0.7937
  EXPECT_NEAR(q.shape_stats.max, std::pow(2.0, -1.0 / 3.0), 1e-12);
  EXPECT_NEAR(q.scaled_jacobian_stats.min, std::sqrt(0.5), 1e-12);
}

TEST(Quality, TetScaledJacobians) {
  // Verdict's values: regular 1, the right-corner tet 1/sqrt 2 (its worst corner is not the
  // right angle), mirrored -1 and -1/sqrt 2, flat 0.
  const TetMesh regular = fixtures::regular_tet();
  const auto& t = regular.tets[0];
  const auto p = [&](int i) { return regular.points[size_t(t[size_t(i)])]; };
  EXPECT_NEAR(tet_scaled_jacobian(p(0), p(1), p(2), p(3)), 1.0, 1e-12);
  EXPECT_NEAR(tet_scaled_jacobian(p(0), p(2), p(1), p(3)), -1.0, 1e-12);
  EXPECT_NEAR(tet_scaled_jacobian(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(tet_scaled_jacobian(Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)), -std::sqrt(0.5), 1e-12);
  EXPECT_EQ(tet_scaled_jacobian(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)), 0.0);
  // Scale-free.
  EXPECT_NEAR(tet_scaled_jacobian(Vec3(0, 0, 0), Vec3(1e-6, 0, 0), Vec3(0, 1e-6, 0), Vec3(0, 0, 1e-6)), std::sqrt(0.5),
              1e-12);
}

TEST(Quality, AgreesWithTheReferee) {
  const std::string script = DTHEX_SHARED_DIR "/tools/hexeval.py";
  if (!std::filesystem::exists(script)) GTEST_SKIP() << script << " is absent";
  if (std::system("/usr/bin/python3 -c 'import vtk, meshio' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 cannot import vtk and meshio";
  // A TetGen sphere has slivers, so the minima are far from trivial.
  const TriSurface sphere = fixtures::read_off(DTHEX_SOURCE_DIR "/meshes/sphere728.off");
  const HexMesh mesh = dice(thex(tetrahedralize(sphere)), 2);
  const std::string path = (dthex_test::fresh_dir("quality") / "sphere_hexes.vtk").string();
  write_legacy_vtk(mesh, path);
  const std::string output = run("/usr/bin/python3 '" + script + "' '" + path + "' --json 2>/dev/null");
  std::filesystem::remove(path);
  // --json prints the report as the last line.
  std::string trimmed = output.substr(0, output.find_last_not_of("\n") + 1);
  const auto last_line = trimmed.substr(trimmed.rfind('\n') == std::string::npos ? 0 : trimmed.rfind('\n') + 1);
  ASSERT_FALSE(last_line.empty()) << "the referee printed nothing";
  const auto referee = nlohmann::json::parse(last_line);
  const HexQuality ours = measure_hex_quality(mesh);
  ASSERT_EQ(referee["hexes"].get<size_t>(), mesh.hexes.size());
  EXPECT_NEAR(referee["shape"]["avg"].get<double>(), ours.shape_stats.avg, 1e-9);
  EXPECT_NEAR(referee["shape"]["min"].get<double>(), ours.shape_stats.min, 1e-9);
  EXPECT_NEAR(referee["shape"]["max"].get<double>(), ours.shape_stats.max, 1e-9);
  EXPECT_NEAR(referee["scaled_jacobian"]["avg"].get<double>(), ours.scaled_jacobian_stats.avg, 1e-9);
  EXPECT_NEAR(referee["scaled_jacobian"]["min"].get<double>(), ours.scaled_jacobian_stats.min, 1e-9);
  EXPECT_NEAR(referee["scaled_jacobian"]["max"].get<double>(), ours.scaled_jacobian_stats.max, 1e-9);
  EXPECT_LT(ours.shape_stats.min, 0.5);  // not a trivially uniform mesh
  // The referee's conformity verdict matches ours.
  const ConformityReport conformity = check_conformity(mesh);
  EXPECT_TRUE(referee["conforming"].get<bool>());
  EXPECT_TRUE(referee["boundary"]["closed"].get<bool>());
  EXPECT_TRUE(conformity.conforming());
  EXPECT_EQ(referee["faces_boundary"].get<size_t>(), conformity.boundary_faces);
}

// The one-pass pair is what the smoother ranks positions by: it must give exactly what the
// two referee-checked functions give, on good, distorted, inverted and degenerate hexes.
TEST(Quality, OnePassPairEqualsSeparateFunctions) {
  const TriSurface sphere = fixtures::read_off(DTHEX_SOURCE_DIR "/meshes/sphere728.off");
  HexMesh mesh = dice(thex(tetrahedralize(sphere)), 2);
  std::vector<std::array<Vec3, 8>> hexes;
  for (size_t h = 0; h < mesh.hexes.size(); ++h) hexes.push_back(hex_corners(mesh, h));
  auto folded = unit_cube();
  folded[6] = Vec3(0.2, 0.2, 0.2);  // some corners inverted, others not
  hexes.push_back(folded);
  auto collapsed = unit_cube();
  collapsed[1] = collapsed[0];
  hexes.push_back(collapsed);
  auto mirrored = unit_cube();
  for (auto& p : mirrored) p.z() = -p.z();
  hexes.push_back(mirrored);
  size_t inverted = 0;
  for (const auto& x : hexes) {
    const HexScaledJacobianAndShape q = hex_scaled_jacobian_and_shape(x);
    EXPECT_EQ(q.scaled_jacobian, hex_scaled_jacobian(x));
    EXPECT_EQ(q.shape, hex_shape(x));
    inverted += q.scaled_jacobian <= 0;
  }
  EXPECT_GE(inverted, 3u);
}

// The smoother's incremental evaluation of a hex with one moving corner equals the full
// evaluation for every corner and many positions, valid or not.
TEST(Quality, MovingCornerEqualsFullEvaluation) {
  const TriSurface sphere = fixtures::read_off(DTHEX_SOURCE_DIR "/meshes/sphere728.off");
  const HexMesh mesh = dice(thex(tetrahedralize(sphere)), 2);
  size_t checked = 0, inverted = 0;
  for (size_t h = 0; h < mesh.hexes.size(); h += 37) {
    const auto x = hex_corners(mesh, h);
    for (int c = 0; c < 8; ++c) {
      HexWithMovingCorner moving(x, c);
      for (int trial = 0; trial < 6; ++trial) {
        auto y = x;
        // Steps from small to past the opposite corner (which inverts).
        y[size_t(c)] += 0.4 * trial * (x[size_t(7 - c)] - x[size_t(c)]) + Vec3(0.01 * trial, -0.02, 0.005 * c);
        const HexScaledJacobianAndShape full = hex_scaled_jacobian_and_shape(y);
        const HexScaledJacobianAndShape fast = moving.at(y[size_t(c)]);
        EXPECT_EQ(fast.scaled_jacobian, full.scaled_jacobian);
        EXPECT_EQ(fast.shape, full.shape);
        EXPECT_EQ(moving.at(y[size_t(c)], false).scaled_jacobian, hex_scaled_jacobian(y));
        EXPECT_EQ(moving.edge_ratio_squared_at(y[size_t(c)]), hex_edge_ratio_squared(y));
        inverted += full.scaled_jacobian <= 0;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 1000u);
  EXPECT_GT(inverted, 100u);
}

namespace {

// VTK's corner signs: corner i of the cube [-1, 1]^3.
std::array<Vec3, 8> cube_corners() {
  return {Vec3(-1, -1, -1), Vec3(1, -1, -1), Vec3(1, 1, -1), Vec3(-1, 1, -1),
          Vec3(-1, -1, 1),  Vec3(1, -1, 1),  Vec3(1, 1, 1),  Vec3(-1, 1, 1)};
}

}  // namespace

TEST(HexGaussPoints, CubeAndAffineHexesHaveTheirCornerValue) {
  EXPECT_NEAR(dthex::hex_gauss_scaled_jacobian(cube_corners()), 1.0, 1e-15);
  // An affine map has one Jacobian everywhere: the Gauss points see what the corners see.
  Eigen::Matrix3d a;
  a << 2.0, 0.7, -0.3, 0.1, 1.5, 0.4, 0.2, -0.5, 0.8;
  std::array<Vec3, 8> sheared = cube_corners();
  for (Vec3& p : sheared) p = a * p + Vec3(3, -1, 7);
  EXPECT_NEAR(dthex::hex_gauss_scaled_jacobian(sheared), dthex::hex_scaled_jacobian(sheared), 1e-12);
  // Mirrored: inverted everywhere.
  std::array<Vec3, 8> mirrored = cube_corners();
  for (Vec3& p : mirrored) p.x() = -p.x();
  EXPECT_NEAR(dthex::hex_gauss_scaled_jacobian(mirrored), -1.0, 1e-15);
}

TEST(HexGaussPoints, FrustumHasTheClosedFormValue) {
  // Top face shrunk by s about the axis: x = xi f, y = eta f, z = zeta with f = 1 + (s - 1)(1 + zeta)/2.
  // The scaled Jacobian is 1 / sqrt(1 + ((s - 1)/2)^2 (xi^2 + eta^2)): at the Gauss points
  // xi^2 + eta^2 = 2/3, at the corners 2, so the two differ and each is known.
  const double s = 0.5;
  std::array<Vec3, 8> frustum = cube_corners();
  for (Vec3& p : frustum) {
    const double f = p.z() > 0 ? s : 1.0;
    p.x() *= f;
    p.y() *= f;
  }
  EXPECT_NEAR(dthex::hex_gauss_scaled_jacobian(frustum), 1.0 / std::sqrt(1.0 + 0.0625 * 2.0 / 3.0), 1e-14);
  EXPECT_NEAR(dthex::hex_scaled_jacobian(frustum), 1.0 / std::sqrt(1.0 + 0.0625 * 2.0), 1e-14);
}

TEST(HexGaussPoints, MeasureCountsHexesInvertedAtAGaussPoint) {
  // Two hexes, the second with its corners in mirrored order (inverted everywhere).
  dthex::HexMesh mesh;
  const auto c = cube_corners();
  for (const Vec3& p : c) mesh.nodes.push_back(p);
  for (const Vec3& p : c) mesh.nodes.push_back(p + Vec3(5, 0, 0));
  mesh.hexes.push_back({0, 1, 2, 3, 4, 5, 6, 7});
  mesh.hexes.push_back({9, 8, 11, 10, 13, 12, 15, 14});  // x mirrored
  const dthex::HexQuality q = dthex::measure_hex_quality(mesh);
  EXPECT_EQ(q.gauss_inverted, 1u);
  EXPECT_NEAR(q.gauss_scaled_jacobian_min, -1.0, 1e-15);
  EXPECT_NEAR(dthex::hex_gauss_scaled_jacobian(dthex::hex_corners(mesh, 0)), 1.0, 1e-15);
}
