// SPDX-License-Identifier: MIT
// Surfaces written in every format are read back by OpenMesh (what the pipeline's tools
// use) and by meshio (an independent double-precision parser).
#include <dthex/io/write_surface.h>
#include <dthex/mesh/surface_mesh.h>
#include <dthex/mesh/types.h>
#include "scratch_dir.h"
#include "subprocess_util.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <dthex/io/atomic_file.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;
using dthex::TriSurface;
using dthex::Vec3;
using nlohmann::json;

namespace {

//! A closed icosahedron, outward oriented, with coordinates that need all 17 digits.
TriSurface awkward_icosahedron() {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  TriSurface s;
  const Vec3 offset(0.1 + 1e-13, -3.3333333333333335, 1e5 + 1.0 / 3.0);
  for (const Vec3& p : {Vec3(-1, phi, 0), Vec3(1, phi, 0), Vec3(-1, -phi, 0), Vec3(1, -phi, 0), Vec3(0, -1, phi),
                        Vec3(0, 1, phi), Vec3(0, -1, -phi), Vec3(0, 1, -phi), Vec3(phi, 0, -1), Vec3(phi, 0, 1),
                        Vec3(-phi, 0, -1), Vec3(-phi, 0, 1)})
    s.points.push_back(offset + (0.1 + 1e-13) * p);
  s.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  return s;
}

fs::path surface_write_folder(const std::string& name) {
  return dthex_test::fresh_dir("surfwrite_" + name);
}

//! Index r with read[(k + r) % 3] == written[k], i.e. the same oriented triangle; -1 if none.
template <typename Same>
int cyclic_match(const std::array<Vec3, 3>& written, const std::array<Vec3, 3>& read, Same same) {
  for (int r = 0; r < 3; ++r)
    if (same(written[0], read[size_t(r)]) && same(written[1], read[size_t((r + 1) % 3)]) &&
        same(written[2], read[size_t((r + 2) % 3)]))
      return r;
  return -1;
}

std::array<Vec3, 3> corners(const TriSurface& s, size_t t) {
  return {s.points[size_t(s.triangles[t][0])], s.points[size_t(s.triangles[t][1])], s.points[size_t(s.triangles[t][2])]};
}

}  // namespace

class SurfaceRoundTrip : public ::testing::TestWithParam<std::string> {};

// OpenMesh 9.0 reads every one of these formats through single-precision points
// (BaseImporter::add_vertex(Vec3d) converts to Vec3f), so float precision is what it can
// give back; the exact check is the meshio one below.
TEST_P(SurfaceRoundTrip, OpenMeshReadsTheSameSurface) {
  const std::string ext = GetParam();
  const fs::path dir = surface_write_folder("om" + ext.substr(1));
  const TriSurface surface = awkward_icosahedron();
  const std::string file = (dir / ("ico" + ext)).string();
  dthex::write_surface(surface, file);
  EXPECT_EQ(dthex_test::count_files(dir), 1u);

  dthex::SurfaceMesh mesh;
  ASSERT_TRUE(OpenMesh::IO::read_mesh(mesh, file)) << file;
  ASSERT_EQ(mesh.n_vertices(), surface.points.size());
  ASSERT_EQ(mesh.n_faces(), surface.triangles.size());
  const TriSurface read = dthex::from_openmesh(mesh);
  auto float_close = [](const Vec3& a, const Vec3& b) {
    return ((a - b).array().abs() <= 1.2e-7 * a.array().abs().max(1.0)).all();
  };
  for (size_t t = 0; t < surface.triangles.size(); ++t)
    EXPECT_GE(cyclic_match(corners(surface, t), corners(read, t), float_close), 0) << ext << ": triangle " << t;
}

TEST_P(SurfaceRoundTrip, MeshioReadsExactCoordinates) {
  if (!dthex_test::meshio_available()) GTEST_SKIP() << "/usr/bin/python3 cannot import meshio";
  const std::string ext = GetParam();
  const fs::path dir = surface_write_folder("mio" + ext.substr(1));
  const TriSurface surface = awkward_icosahedron();
  const std::string file = (dir / ("ico" + ext)).string();
  dthex::write_surface(surface, file);
  const auto result = dthex_test::run_command(
      "/usr/bin/python3 -c 'import sys, json, meshio, numpy as np; m = meshio.read(sys.argv[1]); "
      "print(json.dumps(dict(points=np.asarray(m.points, float).tolist(), "
      "triangles=[t for c in m.cells if c.type == \"triangle\" for t in np.asarray(c.data).tolist()])))' " +
      dthex_test::shell_quote(file));
  ASSERT_EQ(result.exit_code, 0) << file;
  const json read = json::parse(result.output);
  ASSERT_EQ(read["triangles"].size(), surface.triangles.size());
  auto point = [&](int index) {
    const json& p = read["points"][size_t(index)];
    return Vec3(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
  };
  // STL stores each facet's corners; meshio merges equal points, so compare facet by facet.
  for (size_t t = 0; t < surface.triangles.size(); ++t) {
    const auto& tri = read["triangles"][t];
    const std::array<Vec3, 3> got = {point(tri[0].get<int>()), point(tri[1].get<int>()), point(tri[2].get<int>())};
    EXPECT_EQ(cyclic_match(corners(surface, t), got, [](const Vec3& a, const Vec3& b) { return a == b; }), 0)
        << ext << ": triangle " << t << " differs or is rotated";
  }
  if (ext != ".stl") {
    ASSERT_EQ(read["points"].size(), surface.points.size());
    for (size_t v = 0; v < surface.points.size(); ++v) EXPECT_EQ(point(int(v)), surface.points[v]) << ext << " " << v;
  }
}

INSTANTIATE_TEST_SUITE_P(AllFormats, SurfaceRoundTrip, ::testing::Values(".off", ".obj", ".ply", ".stl"),
                         [](const auto& info) { return info.param.substr(1); });

TEST(WriteSurface, ExtensionIsCaseInsensitiveAndUnknownOnesAreInputErrors) {
  const fs::path dir = surface_write_folder("ext");
  const TriSurface surface = awkward_icosahedron();
  dthex::write_surface(surface, (dir / "UPPER.OFF").string());
  std::ifstream in(dir / "UPPER.OFF");
  std::string header;
  in >> header;
  EXPECT_EQ(header, "OFF");
  try {
    dthex::write_surface(surface, (dir / "s.vtu").string());
    FAIL() << "no InputError";
  } catch (const dthex::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'.vtu'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(".stl"), std::string::npos) << e.what();
  }
  EXPECT_THROW(dthex::write_surface(surface, (dir / "no_such_dir" / "s.off").string()), dthex::InputError);
  TriSurface broken = surface;
  broken.triangles[4][1] = -1;
  EXPECT_THROW(dthex::write_surface(broken, (dir / "b.off").string()), dthex::InputError);
  EXPECT_EQ(dthex_test::count_files(dir), 1u);
  EXPECT_EQ(dthex::supported_surface_extensions().size(), 4u);
}

TEST(WriteSurface, FailedWriteLeavesNoFile) {
  const TriSurface surface = awkward_icosahedron();  // every format of it is > 1 kB
  for (const std::string ext : {".off", ".obj", ".ply", ".stl"}) {
    const fs::path dir = surface_write_folder("full" + ext.substr(1));
    const std::string file = (dir / ("s" + ext)).string();
    const int code = dthex_test::write_failure_under_file_size_limit(512, [&] { dthex::write_surface(surface, file); });
    EXPECT_EQ(code, 0) << ext << ": " << dthex_test::kWriteFailureCodes;
    EXPECT_EQ(dthex_test::count_files(dir), 0u) << ext;
    dthex::write_surface(surface, file);
    EXPECT_GT(fs::file_size(file), 512u) << ext;
  }
}
