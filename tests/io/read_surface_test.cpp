// SPDX-License-Identifier: MIT
#include <dthex/io/read_surface.h>
#include <dthex/surface/verify_surface.h>
#include "scratch_dir.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;
using dthex::InputError;
using dthex::TriSurface;
using dthex::Vec3;

namespace {

fs::path folder() {
  static const fs::path dir = dthex_test::fresh_dir("read");
  return dir;
}

std::string write_file(const std::string& name, const std::string& bytes) {
  const std::string path = (folder() / name).string();
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

//! A unit-ish cube with coordinates exact in float, vertices in order of first use by the
//! triangles (so a triangle soup read back and merged gives the same indices).
TriSurface reference_cube() {
  TriSurface s;
  const Vec3 corner[8] = {Vec3(0, 0, 0),     Vec3(0, 1.5, 0),  Vec3(1.25, 1.5, 0), Vec3(1.25, 0, 0),
                          Vec3(0, 0, -2),    Vec3(1.25, 0, -2), Vec3(1.25, 1.5, -2), Vec3(0, 1.5, -2)};
  s.points.assign(corner, corner + 8);
  s.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}, {0, 3, 5}, {0, 5, 4},
                 {1, 7, 6}, {1, 6, 2}, {0, 4, 7}, {0, 7, 1}, {3, 2, 6}, {3, 6, 5}};
  return s;
}

std::string off_text(const TriSurface& s) {
  std::ostringstream out;
  out.precision(17);
  out << "OFF\n# a comment line\n" << s.points.size() << " " << s.triangles.size() << " 0\n";
  for (const Vec3& p : s.points) out << p.x() << " " << p.y() << " " << p.z() << "  # trailing comment\n";
  for (const auto& t : s.triangles) out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return out.str();
}

std::string obj_text(const TriSurface& s) {
  std::ostringstream out;
  out.precision(17);
  out << "# obj\nmtllib none.mtl\no cube\n";
  for (const Vec3& p : s.points) out << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
  out << "vt 0 0\nvn 0 0 1\n";
  const int n = int(s.points.size());
  for (size_t k = 0; k < s.triangles.size(); ++k) {
    const auto& t = s.triangles[k];
    out << "f";
    for (int v : t) {
      switch (k % 4) {  // every corner syntax, and negative indices
        case 0: out << " " << v + 1; break;
        case 1: out << " " << v + 1 << "/1"; break;
        case 2: out << " " << v + 1 << "/1/1"; break;
        case 3: out << " " << v - n << "//1"; break;
      }
    }
    out << "\n";
  }
  return out.str();
}

std::string ascii_stl_text(const TriSurface& s) {
  std::ostringstream out;
  out.precision(9);
  out << "solid cube\n";
  for (const auto& t : s.triangles) {
    out << "  facet normal 0 0 0\n    outer loop\n";
    for (int v : t) out << "      vertex " << s.points[size_t(v)].x() << " " << s.points[size_t(v)].y() << " "
                        << s.points[size_t(v)].z() << "\n";
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid cube\n";
  return out.str();
}

template <class T>
void put(std::string& bytes, T value, bool big_endian = false) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));
  bytes.append(b, sizeof(T));
}

std::string binary_stl(const TriSurface& s, const std::string& header_start = "binary header") {
  std::string bytes = header_start;
  bytes.resize(80, ' ');
  put<uint32_t>(bytes, uint32_t(s.triangles.size()));
  for (const auto& t : s.triangles) {
    for (int k = 0; k < 3; ++k) put<float>(bytes, 0.0f);
    for (int v : t)
      for (int k = 0; k < 3; ++k) put<float>(bytes, float(s.points[size_t(v)][k]));
    put<uint16_t>(bytes, 0);
  }
  return bytes;
}

std::string ply_text(const TriSurface& s) {
  std::ostringstream out;
  out.precision(17);
  out << "ply\nformat ascii 1.0\ncomment made by a test\nelement vertex " << s.points.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\nelement face "
      << s.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& p : s.points) out << p.x() << " " << p.y() << " " << p.z() << " 255\n";
  for (const auto& t : s.triangles) out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return out.str();
}

std::string ply_binary(const TriSurface& s, bool big_endian) {
  std::string bytes = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                      " 1.0\nelement vertex " + std::to_string(s.points.size()) +
                      "\nproperty float x\nproperty float y\nproperty double z\nelement face " +
                      std::to_string(s.triangles.size()) +
                      "\nproperty list uchar uint vertex_indices\nproperty int flags\nend_header\n";
  for (const Vec3& p : s.points) {
    put<float>(bytes, float(p.x()), big_endian);
    put<float>(bytes, float(p.y()), big_endian);
    put<double>(bytes, p.z(), big_endian);
  }
  for (const auto& t : s.triangles) {
    put<uint8_t>(bytes, 3);
    for (int v : t) put<uint32_t>(bytes, uint32_t(v), big_endian);
    put<int32_t>(bytes, 7, big_endian);
  }
  return bytes;
}

//! Expects read_surface(path) to throw an InputError starting with "<path>: " and containing text.
void expect_read_error(const std::string& path, const std::string& text) {
  try {
    dthex::read_surface(path);
    ADD_FAILURE() << path << " was accepted, expected '" << text << "'";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(text), std::string::npos) << "missing '" << text << "' in: " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace

TEST(ReadSurface, EveryFormatGivesTheSameSurface) {
  const TriSurface cube = reference_cube();
  const std::vector<std::string> paths = {
      write_file("cube.off", off_text(cube)),
      write_file("cube.OBJ", obj_text(cube)),
      write_file("cube_ascii.stl", ascii_stl_text(cube)),
      write_file("cube_binary.stl", binary_stl(cube)),
      write_file("cube_solid.Stl", binary_stl(cube, "solid but binary")),
      write_file("cube.ply", ply_text(cube)),
      write_file("cube_le.ply", ply_binary(cube, false)),
      write_file("cube_be.ply", ply_binary(cube, true)),
  };
  for (const std::string& path : paths) {
    SCOPED_TRACE(path);
    TriSurface s;
    ASSERT_NO_THROW(s = dthex::read_surface(path));
    EXPECT_EQ(s.points, cube.points);  // STL: exactly equal corners merged back to 8 vertices
    EXPECT_EQ(s.triangles, cube.triangles);
    const auto stats = dthex::verify_surface(s, path);
    EXPECT_NEAR(stats.volume, 1.25 * 1.5 * 2, 1e-12);
  }
}

TEST(ReadSurface, PolygonsAreFanTriangulated) {
  const std::string off = write_file("quad.off", "OFF 5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n4 0 1 2 3\n3 0 4 1\n");
  const TriSurface s = dthex::read_surface(off);
  EXPECT_EQ(s.triangles, (std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 2, 3}, {0, 4, 1}}));
  const std::string obj = write_file("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  EXPECT_EQ(dthex::read_surface(obj).triangles, (std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 2, 3}}));
}

//! An OBJ file's o and g lines name its faces' parts: each face takes the latest name (an
//! object line's whole name, a group line's first), faces before any take none (-1); a polygon's triangles share its name. Other
//! formats, and an OBJ with no names, give none.
TEST(ReadSurface, ObjNamesTheTrianglesOfEachObjectAndGroup) {
  const std::string obj = write_file("named.obj",
                                     "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                     "f 1 2 3\n"
                                     "o femur\nf 1 3 4\nf 1 2 3 4\n"
                                     "g tibia shaft\nf 2 3 4\n"
                                     "o femur\nf 1 2 4\n"
                                     "o left patella\nf 1 2 3\n");
  const dthex::SurfaceNames named = dthex::read_surface_names(obj);
  EXPECT_EQ(named.names, (std::vector<std::string>{"femur", "tibia", "left patella"}));
  EXPECT_EQ(named.triangle_name, (std::vector<int>{-1, 0, 0, 0, 1, 0, 2}));
  EXPECT_EQ(named.surface.triangles.size(), dthex::read_surface(obj).triangles.size());
  const std::string plain = write_file("plain.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
  EXPECT_TRUE(dthex::read_surface_names(plain).names.empty());
  EXPECT_TRUE(dthex::read_surface_names(plain).triangle_name.empty());
  const std::string off = write_file("named.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n");
  EXPECT_TRUE(dthex::read_surface_names(off).names.empty());
}

TEST(ReadSurface, FileLevelErrors) {
  expect_read_error((folder() / "missing.off").string(), "no such file");
  fs::create_directories(folder() / "dir.off");
  expect_read_error((folder() / "dir.off").string(), "is a directory");
  expect_read_error(write_file("empty.off", ""), "is empty");
  expect_read_error(write_file("cube.xyz", off_text(reference_cube())), "unknown surface format '.xyz'");
  expect_read_error(write_file("noext", off_text(reference_cube())), "unknown surface format");
}

TEST(ReadSurface, OffErrorsNameTheLineAndElement) {
  expect_read_error(write_file("header_only.off", "OFF\n8 12 0\n"), "header claims 8 vertices and 12 faces");
  expect_read_error(write_file("zero.off", "OFF\n0 0 0\n"), "contains no triangles");
  expect_read_error(write_file("not_off.off", "PLY\n3 1 0\n"), "does not start with the OFF keyword");
  expect_read_error(write_file("short.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n# padding padding padding padding\n"),
                    "file ends after 2 of 3 vertices (line 5)");
  expect_read_error(write_file("range.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 9\n"),
                    "face 1 refers to vertex 9 but there are only 3 vertices (valid 0..2) (line 7)");
  expect_read_error(write_file("negative.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"),
                    "face 0 refers to vertex -1");
  expect_read_error(write_file("nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"),
                    "vertex 1 has a non-finite coordinate (line 4)");
  expect_read_error(write_file("inf.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 -inf\n3 0 1 2\n"),
                    "vertex 2 has a non-finite coordinate (line 5)");
  expect_read_error(write_file("word.off", "OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n"),
                    "vertex 1 is not three numbers (line 4)");
  expect_read_error(write_file("two.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"),
                    "face 0 has 2 corners, at least 3 are needed (line 6)");
}

TEST(ReadSurface, ObjErrors) {
  expect_read_error(write_file("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), "face 0 has a corner '0'");
  expect_read_error(write_file("forward.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n"),
                    "face 0 refers to vertex 2 but there are only 2 vertices");
  expect_read_error(write_file("back.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"), "face 0 refers to vertex -1");
  expect_read_error(write_file("novertex.obj", "# nothing\nvn 0 0 1\n"), "contains no triangles");
}

TEST(ReadSurface, StlErrorsAndHugeCountsAreRefusedWithoutAllocating) {
  const TriSurface cube = reference_cube();
  std::string truncated = binary_stl(cube);
  truncated.resize(truncated.size() - 7);
  expect_read_error(write_file("truncated.stl", truncated), "truncated");
  std::string truncated_solid = binary_stl(cube, "solid looks like text");
  truncated_solid.resize(truncated_solid.size() - 50);
  expect_read_error(write_file("truncated_solid.stl", truncated_solid), "claims 12 triangles");

  // A header claiming four billion triangles on a 134-byte file: refused by the size check.
  std::string huge = binary_stl(cube);
  huge.resize(84 + 50);
  const uint32_t claim = 4000000000u;
  std::memcpy(&huge[80], &claim, 4);
  expect_read_error(write_file("huge.stl", huge), "claims 4000000000 triangles");

  expect_read_error(write_file("tiny.stl", "abc"), "neither ASCII STL");
  std::string ascii = ascii_stl_text(cube);
  expect_read_error(write_file("cut.stl", ascii.substr(0, ascii.size() / 2)), "file ends where");
  std::string bad = ascii;
  bad.replace(bad.find("outer loop"), 10, "outer lope");
  expect_read_error(write_file("bad.stl", bad), "expected 'loop' but found 'lope' (line 3)");
  std::string nan_stl = ascii;
  nan_stl.replace(nan_stl.find("vertex 0 0 0"), 12, "vertex 0 nan 0");
  expect_read_error(write_file("nan.stl", nan_stl), "triangle 0 has a non-finite vertex coordinate");
}

TEST(ReadSurface, PlyErrors) {
  const TriSurface cube = reference_cube();
  std::string huge = ply_binary(cube, false);
  huge.replace(huge.find("element vertex 8"), 16, "element vertex 1000000000");
  expect_read_error(write_file("huge.ply", huge), "header claims 1000000000 vertices");
  // Binary records have a fixed minimum size: a cut file fails the size check.
  std::string cut = ply_binary(cube, true);
  cut.resize(cut.size() - 10);
  expect_read_error(write_file("cut.ply", cut), "header claims 8 vertices and 12 faces");
  std::string cut_text = ply_text(cube);
  cut_text.resize(cut_text.rfind("3 3 6 5"));
  expect_read_error(write_file("cut_text.ply", cut_text), "file ends inside face 11");
  std::string range = ply_text(cube);
  range.replace(range.rfind("3 3 6 5"), 7, "3 3 6 8");
  expect_read_error(write_file("range.ply", range), "face 11 refers to vertex 8");
  std::string no_face = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                        "property float z\nend_header\n0 0 0\n";
  expect_read_error(write_file("noface.ply", no_face), "no 'face' element");
  expect_read_error(write_file("format.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"),
                    "unknown PLY format");
}

TEST(ReadSurface, BundledOffMatchesStlRoundTrip) {
  // A real mesh written as binary STL (float coordinates) reads back as the same topology.
  TriSurface liver = dthex::read_surface(DTHEX_SOURCE_DIR "/meshes/liver.off");
  // Round to float through a volatile: GCC 12 -O2 (SLP vectorizer) folds a vectorized
  // double(float(x)) loop into a no-op on this machine.
  for (Vec3& p : liver.points)
    for (int k = 0; k < 3; ++k) {
      volatile float rounded = float(p[k]);
      p[k] = rounded;
    }
  const TriSurface back = dthex::read_surface(write_file("liver.stl", binary_stl(liver)));
  EXPECT_EQ(back.triangles.size(), liver.triangles.size());
  EXPECT_EQ(back.points.size(), liver.points.size());
  for (size_t t = 0; t < liver.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(back.points[size_t(back.triangles[t][size_t(k)])], liver.points[size_t(liver.triangles[t][size_t(k)])]);
}
