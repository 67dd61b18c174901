// SPDX-License-Identifier: MIT
// The catalogue of hostile inputs (issue 7): every file a segmentation program, a scanner
// or an attacker could hand over, made here, run through the om_dthex command. Each must
// get the right exit code, a one-line message naming the file and the problem, no output
// file and no leftover temporary; the valid tricky ones must mesh. `timeout` bounds each
// run, so a hang fails as exit 124 instead of stalling the suite.
#include "hostile_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <functional>
#include <random>
#include <sys/stat.h>

using namespace dthex_test;

namespace {

struct HostileCase {
  std::string name;      //!< test name
  std::string file;      //!< input file name (its extension picks the reader)
  std::function<void(const fs::path& input)> make;  //!< creates the input
  int exit_code;
  std::string message;   //!< a phrase the error message must contain ("" for valid inputs)
  std::string options = "";  //!< extra command-line options (--repair none for the refusals safe repair fixes)
  std::string repaired = "";  //!< for a valid input the safe repairs fix: the input.repairs count that must be 1
};

void PrintTo(const HostileCase& c, std::ostream* os) { *os << c.name; }

std::function<void(const fs::path&)> bytes(std::string content) {
  return [content](const fs::path& p) { write_bytes(p, content); };
}

std::string random_bytes(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (char& c : s) c = char(rng() & 0xff);
  return s;
}

Surface with_point(Surface s, int index, std::array<double, 3> p) {
  s.points[size_t(index)] = p;
  return s;
}

std::string cube_off() { return off_text(cube()); }

std::vector<HostileCase> catalogue() {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  Surface open = cube();
  open.triangles.pop_back();
  Surface duplicate = cube();
  duplicate.triangles.push_back({duplicate.triangles[0][1], duplicate.triangles[0][2], duplicate.triangles[0][0]});
  Surface inconsistent = cube();
  std::swap(inconsistent.triangles[3][1], inconsistent.triangles[3][2]);
  // Two cubes sharing the vertical edge x = y = 1 (vertices merged): four triangles there.
  Surface edge_pair = join(cube(), cube(1, 1, 0));
  // Two cubes touching at the corner (1,1,1) only, the corner merged: two fans at one vertex.
  Surface corner_pair = join(cube(), cube(1, 1, 1));
  for (auto* s : {&edge_pair, &corner_pair}) {
    for (auto& t : s->triangles)
      for (int& v : t)
        for (int w = 0; w < 8; ++w)
          if (v >= 8 && s->points[size_t(v)] == s->points[size_t(w)]) v = w;
  }
  // Two tetrahedra glued on a face, each written whole: the shared face twice, and removing
  // either copy leaves its edges on three triangles, so no safe repair applies.
  Surface glued;
  glued.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}};
  glued.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 1, 2}, {0, 4, 1}, {1, 4, 2}, {2, 4, 0}};
  // An OBJ soup (every triangle its own corners) of the cube with a triangle missing: merged
  // by the safe repair, and still open.
  std::string open_soup;
  const Surface unit = cube();
  for (size_t t = 0; t + 1 < unit.triangles.size(); ++t)
    for (int v : unit.triangles[t]) {
      const auto& p = unit.points[size_t(v)];
      open_soup += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
    }
  for (size_t t = 0; t + 1 < unit.triangles.size(); ++t)
    open_soup += "f " + std::to_string(3 * t + 1) + " " + std::to_string(3 * t + 2) + " " + std::to_string(3 * t + 3) + "\n";
  Surface degenerate = cube();
  degenerate.points.push_back({0.5, 0, 0});  // on the edge 0-1: a zero-area sliver
  degenerate.triangles.push_back({0, 1, 8});
  degenerate.triangles.push_back({1, 0, 8});
  // The cube's triangle {0, 2, 1} split at c on the edge 0-1, the crack closed by the
  // zero-area sliver (1, 0, c): the safe repair flips it with {0, 1, 4} across the edge.
  Surface sliver = cube();
  sliver.points.push_back({0.25, 0, 0});
  sliver.triangles[0] = {0, 2, 8};
  sliver.triangles.push_back({8, 2, 1});
  sliver.triangles.push_back({1, 0, 8});
  // A square pyramid flattened until its sides lie 2e-7 radians from its base: no triangles
  // cross, but the coarsening's check refuses the folds at every eps (minutes of retries).
  Surface fin;
  fin.points = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {1, 0.5, -1e-7}};
  fin.triangles = {{0, 2, 1}, {0, 3, 2}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  const std::string binary_cube = binary_stl_bytes(cube());
  const std::string ascii_cube = ascii_stl_text(cube());
  const std::string ply_cube_header = "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
                                      "property float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n";
  std::string ply_cube_body;
  for (const auto& p : cube().points) ply_cube_body += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  for (const auto& t : cube().triangles) ply_cube_body += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";

  std::vector<HostileCase> cases = {
      {"Empty", "empty.off", bytes(""), 2, "is empty"},
      {"HeaderOnly", "header.off", bytes("OFF\n"), 2, "counts line is missing"},
      {"CountsButNoData", "counts.off", bytes("OFF\n8 12 0\n"), 2, "more than the remaining"},
      {"NaNCoordinate", "nan.off", bytes(off_text(with_point(cube(), 3, {nan, 0, 0}))), 2, "non-finite"},
      {"InfCoordinateObj", "inf.obj", bytes("v 0 0 0\nv 1 0 0\nv 0 1 0\nv inf 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n"), 2,
       "non-finite"},
      {"HugeCoordinate", "huge.off", bytes(off_text(with_point(cube(), 7, {1e200, 1, 1}))), 2, "out of range"},
      {"IndexOutOfRange", "range.off", bytes("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 9\n"), 2,
       "refers to vertex 9"},
      {"NegativeIndex", "negative.off", bytes("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 -1\n"), 2,
       "refers to vertex -1"},
      {"ObjIndexZero", "zero.obj", bytes("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), 2, "non-zero vertex index"},
      {"FaceWithTwoCorners", "two.off", bytes("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n"), 2, "at least 3"},
      {"OpenCube", "open.off", bytes(off_text(open)), 2, "open"},
      {"SingleTriangle", "single.obj", bytes("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), 2, "open"},
      {"NonManifoldEdge", "edge.off", bytes(off_text(edge_pair)), 2, "non-manifold edge"},
      {"NonManifoldVertex", "vertex.off", bytes(off_text(corner_pair)), 2, "non-manifold vertex"},
      {"DuplicateFace", "duplicate.off", bytes(off_text(duplicate)), 2, "duplicate", "--repair none"},
      {"DuplicateFaceBetweenBodies", "glued.off", bytes(off_text(glued)), 2, "duplicate triangles"},
      {"InconsistentOrientation", "orient.off", bytes(off_text(inconsistent)), 2, "orientation", "--repair none"},
      {"OpenSoupObj", "soup.obj", bytes(open_soup), 2, "open boundary edge"},
      {"OpenSoupObjSaysItsIdsAreAfterTheRepairs", "soup.obj", bytes(open_soup), 2,
       "(ids after the safe repairs; --repair none checks the file as given)"},
      {"OpenSoupObjWithoutRepairIsOpenAtOnce", "soup.obj", bytes(open_soup), 2, "open boundary edge", "--repair none"},
      {"DegenerateSliver", "sliver.off", bytes(off_text(degenerate)), 2, "degenerate"},
      {"DegenerateSliverSaysHowToRemoveIt", "sliver.off", bytes(off_text(degenerate)), 2, "MeshLab (Remove Zero Area Faces)"},
      {"ZeroAreaSliverUnrepaired", "sliver.off", bytes(off_text(sliver)), 2, "has zero area", "--repair none"},
      {"InterpenetratingCubes", "crossing.off", bytes(off_text(join(cube(), cube(0.5, 0.5, 0.5)))), 2, "self-intersection"},
      {"InterpenetratingCubesNamesThePairsAndTheTools", "crossing.off", bytes(off_text(join(cube(), cube(0.5, 0.5, 0.5)))), 2,
       "Select Self Intersecting Faces"},
      {"OpenCubeNamesTheHoleAndTheTools", "open.off", bytes(off_text(open)), 2,
       "1 hole (loops of open boundary edges, 3 edges in all): hole 1 of 3 edges"},
      {"NearlyFoldedFinAtOnce", "fin.off", bytes(off_text(fin)), 2, "fin.off: folded edge: 4 edges"},
      {"CubesTooCloseToTellApart", "close.off", bytes(off_text(join(cube(), cube(1 + 1e-9, 0, 0)))), 2,
       "bodies too close: component 0 (12 triangles"},
      {"CubesTooCloseSayHowToSeparateOrMerge", "close.off", bytes(off_text(join(cube(), cube(1 + 1e-9, 0, 0)))), 2,
       "move one away from the other, or merge them"},
      {"TruncatedBinaryStl", "truncated.stl", bytes(binary_cube.substr(0, binary_cube.size() - 20)), 2, "truncated"},
      {"BinaryStlClaiming4e9Triangles", "claims.stl", bytes(binary_stl_bytes(cube(), "binary", 4000000000LL)), 2,
       "4000000000 triangles"},
      {"AsciiStlCutMidFacet", "cut.stl", bytes(ascii_cube.substr(0, ascii_cube.find("vertex", ascii_cube.size() / 2) + 7)), 2, "file ends"},
      {"AsciiStlWithBinaryGarbage", "garbage.stl", bytes("solid x\n" + random_bytes(300, 7)), 2, "STL"},
      {"RandomBytesOff", "random.off", bytes(random_bytes(4096, 1)), 2, "OFF"},
      {"RandomBytesObj", "random.obj", bytes(random_bytes(4096, 2)), 2, "random.obj"},
      {"RandomBytesStl", "random.stl", bytes(random_bytes(4096, 3)), 2, "STL"},
      {"RandomBytesPly", "random.ply", bytes(random_bytes(4096, 4)), 2, "ply"},
      {"OffHugeCounts", "counts.off", bytes("OFF\n2000000000 2000000000 0\n0 0 0\n"), 2, "more than the remaining"},
      {"PlyHugeVertexCount", "count.ply",
       bytes("ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" + std::string(64, '\0')),
       2, "4000000000 vertices"},
      {"PlyTruncatedBody", "cut.ply", bytes(ply_cube_header + ply_cube_body.substr(0, ply_cube_body.size() / 2)), 2,
       "file ends inside"},
      {"PlyNoEndHeader", "noend.ply", bytes("ply\nformat ascii 1.0\nelement vertex 8\n"), 2, "end_header"},
      {"UnsupportedExtension", "surface.xyz", bytes(cube_off()), 2, "unknown surface format"},
      {"NoExtension", "surface", bytes(cube_off()), 2, "unknown surface format"},
      {"DirectoryAsInput", "folder.off", [](const fs::path& p) { fs::create_directory(p); }, 2, "is a directory"},
      {"MissingFile", "missing.off", [](const fs::path&) {}, 2, "no such file"},
      {"SymlinkToDevZero", "zero.off", [](const fs::path& p) { fs::create_symlink("/dev/zero", p); }, 2,
       "not a regular file"},
      {"NamedPipe", "pipe.off", [](const fs::path& p) { ::mkfifo(p.c_str(), 0600); }, 2, "not a regular file"},
      {"OnlyComments", "comments.off", bytes("# nothing\n# here\n"), 2, "only comments"},
      // Valid but tricky: each must mesh.
      {"DuplicateFaceRepaired", "duplicate.off", bytes(off_text(duplicate)), 0, "", "", "duplicate_triangles_removed"},
      {"InconsistentOrientationRepaired", "orient.off", bytes(off_text(inconsistent)), 0, "", "", "triangles_turned"},
      {"ZeroAreaSliverFlipped", "sliver.off", bytes(off_text(sliver)), 0, "", "", "slivers_flipped"},
      {"CubesAMillimetreApart", "apart.off", bytes(off_text(join(cube(), cube(1.001, 0, 0)))), 0, ""},
      {"InwardCube", "inward.off", bytes(off_text(reversed(cube()))), 0, ""},
      {"TwoDisjointCubes", "two.off", bytes(off_text(join(cube(), cube(3, 0, 0)))), 0, ""},
      {"CubeWithCavity", "cavity.off", bytes(off_text(join(cube(0, 0, 0, 3), cube(1, 1, 1, 1)))), 0, ""},
      {"BinaryStlHeaderSaysSolid", "solid.stl", bytes(binary_stl_bytes(cube(), "solid but binary")), 0, ""},
      {"AsciiStlCube", "ascii.stl", bytes(ascii_cube), 0, ""},
      {"PlyWithHugePropertylessElement", "extra.ply",
       bytes("ply\nformat ascii 1.0\nelement nothing 9000000000000000000\nelement vertex 8\nproperty float x\n"
             "property float y\nproperty float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n" +
             ply_cube_body),
       0, ""},
  };
  return cases;
}

class HostileInput : public testing::TestWithParam<HostileCase> {};

TEST_P(HostileInput, RightExitCodeMessageAndNoOutput) {
  const HostileCase& c = GetParam();
  const fs::path dir = fresh_dir("hostile_" + c.name);
  const fs::path in = dir / "in", out = dir / "out";
  fs::create_directories(in);
  fs::create_directories(out);
  const fs::path input = in / c.file;
  c.make(input);
  const CommandRun r = run_om_dthex(input.string() + " -q --time-limit 30 -o " + (out / "o.vtu").string() + " --report " +
                                 (out / "r.json").string() + " " + c.options,
                             dir);
  EXPECT_EQ(r.exit_code, c.exit_code) << r.err;
  if (c.exit_code != 0) {
    EXPECT_NE(r.err.find(c.file), std::string::npos) << "message does not name the file: " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << "expected '" << c.message << "' in: " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line expected: " << r.err;
    EXPECT_EQ(entries_in(out), 0u) << "a refused input left a file in the output folder";
  } else {
    ASSERT_TRUE(fs::exists(out / "o.vtu")) << r.err;
    EXPECT_EQ(entries_in(out), 2u) << "exactly the mesh and the report, no temporaries";
    const nlohmann::json report = nlohmann::json::parse(read_bytes(out / "r.json"));
    EXPECT_GT(report["hex"]["hexes"].get<size_t>(), 0u);
    EXPECT_TRUE(report["hex"]["conforming"].get<bool>());
    if (!c.repaired.empty()) EXPECT_EQ(report["input"]["repairs"][c.repaired].get<size_t>(), 1u);
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Catalogue, HostileInput, testing::ValuesIn(catalogue()),
                         [](const testing::TestParamInfo<HostileCase>& info) { return info.param.name; });

TEST(HostileCatalogue, HasAtLeast25RefusedInputsAndTheValidTrickyOnes) {
  size_t refused = 0, valid = 0;
  for (const HostileCase& c : catalogue()) (c.exit_code == 0 ? valid : refused)++;
  EXPECT_GE(refused, 25u);
  EXPECT_GE(valid, 4u);
}

}  // namespace
