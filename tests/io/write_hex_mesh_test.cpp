// SPDX-License-Identifier: MIT
// Every hex format is written, then read back by third-party readers (meshio; Python's
// XML parser for FEBio) and by the Verdict-based referee script (hexeval), and compared with
// what we wrote.
#include <dthex/hexes/mesh_sets.h>
#include <dthex/io/write_hex_mesh.h>
#include <dthex/mesh/quality.h>
#include <dthex/mesh/types.h>
#include "scratch_dir.h"
#include "subprocess_util.h"

#include <dthex/io/atomic_file.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace fs = std::filesystem;
using dthex::HexMesh;
using dthex::Vec3;
using nlohmann::json;

namespace {

//! An n x n x n block of hexes on a grid mapped through `place` (VTK corner order).
template <typename Place>
HexMesh make_block(int n, Place place) {
  HexMesh mesh;
  auto id = [n](int i, int j, int k) { return i + (n + 1) * (j + (n + 1) * k); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        mesh.nodes.push_back(place(i, j, k));
        const bool boundary = i == 0 || j == 0 || k == 0 || i == n || j == n || k == n;
        mesh.boundary_facet.push_back(boundary ? (i + j + k) % 5 : -1);
      }
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        mesh.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                              id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
  return mesh;
}

HexMesh unit_cubes() {
  return make_block(2, [](int i, int j, int k) { return Vec3(i, j, k); });
}

//! Distorted (shape < 1) but valid hexes, with coordinates that need all 17 digits.
HexMesh awkward_block() {
  return make_block(2, [](int i, int j, int k) {
    return Vec3(0.1 + 1e-13 + 0.7 * i + 0.05 * j * k, -3.3333333333333335 + 0.9 * j + 0.11 * std::sin(i + k),
                1e5 + 1.0 / 3.0 + 1.3 * k + 0.07 * i * i);
  });
}

fs::path hex_write_folder(const std::string& name) {
  return dthex_test::fresh_dir("hexwrite_" + name);
}

// Reads a hex mesh with meshio (or, for .feb, with Python's XML parser) and prints JSON.
const char* kReaderScript = R"PY(
import json, sys
import numpy as np
path = sys.argv[1]
out = {}
if len(sys.argv) > 2 and sys.argv[2] == 'vtk':
    # ParaView's readers: VTK's XML and legacy unstructured-grid readers
    import vtk
    from vtk.util import numpy_support as ns
    r = vtk.vtkXMLUnstructuredGridReader() if path.endswith('.vtu') else vtk.vtkUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    out['points'] = ns.vtk_to_numpy(g.GetPoints().GetData()).astype(float).tolist()
    out['hexes'] = [g.GetCell(c).GetPointId(k) for c in range(g.GetNumberOfCells()) for k in range(8)]
    out['other'] = [g.GetCellType(c) for c in range(g.GetNumberOfCells()) if g.GetCellType(c) != 12]
    cd, pd = g.GetCellData(), g.GetPointData()
    out['cell_data'] = {cd.GetArrayName(i): ns.vtk_to_numpy(cd.GetArray(i)).tolist() for i in range(cd.GetNumberOfArrays())}
    out['point_data'] = {pd.GetArrayName(i): ns.vtk_to_numpy(pd.GetArray(i)).tolist() for i in range(pd.GetNumberOfArrays())}
elif path.endswith('.feb'):
    import xml.etree.ElementTree as ET
    root = ET.parse(path).getroot()
    mesh = root.find('Mesh')
    nodes = mesh.find('Nodes').findall('node')
    elements = mesh.find('Elements')
    elems = elements.findall('elem')
    out['points'] = [[float(v) for v in n.text.split(',')] for n in nodes]
    out['hexes'] = [int(v) - 1 for e in elems for v in e.text.split(',')]
    out['feb'] = dict(version=root.get('version'), element_type=elements.get('type'),
                      part=elements.get('name'),
                      domain=root.find('MeshDomains').find('SolidDomain').get('name'),
                      node_ids=[int(n.get('id')) for n in nodes],
                      elem_ids=[int(e.get('id')) for e in elems])
    out['other'] = []
else:
    import meshio
    m = meshio.read(path)
    out['points'] = np.asarray(m.points, dtype=float).tolist()
    out['hexes'] = [int(v) for c in m.cells if c.type == 'hexahedron' for v in np.asarray(c.data).ravel()]
    out['other'] = [c.type for c in m.cells if c.type != 'hexahedron']
    out['cell_data'] = {k: np.concatenate([np.asarray(a).ravel() for a in v]).tolist()
                        for k, v in m.cell_data.items()}
    out['point_data'] = {k: np.asarray(v).ravel().tolist() for k, v in m.point_data.items()}
print(json.dumps(out))
)PY";

//! reader: "meshio" (meshio, or XML for .feb) or "vtk" (VTK's readers, as ParaView uses).
json read_back(const fs::path& file, const std::string& reader = "meshio") {
  const fs::path script = file.parent_path() / "read_hex.py";
  if (!fs::exists(script)) std::ofstream(script) << kReaderScript;
  const auto result = dthex_test::run_command("/usr/bin/python3 " + dthex_test::shell_quote(script.string()) + " " +
                                              dthex_test::shell_quote(file.string()) + " " + reader);
  EXPECT_EQ(result.exit_code, 0) << "reading " << file << " failed";
  if (result.exit_code != 0) return json();
  return json::parse(result.output);
}

//! Same node count, coordinates bit-identical (%.17g and raw binary both round-trip) or, with
//! `exact` false (INP's 13 digits), within 1e-12 of each coordinate's own magnitude; same hex
//! count, connectivity identical; no other cells, or only quadrangles with `quads` (the face
//! sets of a .msh).
void expect_same_mesh(const HexMesh& mesh, const json& read, const std::string& what, bool exact = true,
                      bool quads = false) {
  ASSERT_TRUE(read.contains("points")) << what;
  ASSERT_EQ(read["points"].size(), mesh.nodes.size()) << what;
  double max_relative = 0;
  for (size_t n = 0; n < mesh.nodes.size(); ++n)
    for (int d = 0; d < 3; ++d) {
      const double ours = mesh.nodes[n][d], theirs = read["points"][n][size_t(d)].get<double>();
      if (ours != 0) max_relative = std::max(max_relative, std::abs(ours - theirs) / std::abs(ours));
      if (exact) EXPECT_EQ(ours, theirs) << what << ": node " << n << " coordinate " << d;
      else if (ours == 0) EXPECT_EQ(theirs, 0.0) << what << ": node " << n << " coordinate " << d;
    }
  EXPECT_LE(max_relative, 1e-12) << what;
  ASSERT_EQ(read["hexes"].size(), 8 * mesh.hexes.size()) << what;
  for (size_t h = 0; h < mesh.hexes.size(); ++h)
    for (size_t c = 0; c < 8; ++c)
      ASSERT_EQ(read["hexes"][8 * h + c].get<int>(), mesh.hexes[h][c]) << what << ": hex " << h << " corner " << c;
  if (quads) {
    EXPECT_FALSE(read["other"].empty()) << what << ": no face-set quadrangles";
    for (const auto& type : read["other"]) EXPECT_EQ(type, "quad") << what;
  } else {
    EXPECT_TRUE(read["other"].empty()) << what << ": unexpected cells " << read["other"].dump();
  }
}

json run_hexeval(const fs::path& file) {
  const std::string script = DTHEX_SHARED_DIR "/tools/hexeval.py";
  const auto result = dthex_test::run_command("/usr/bin/python3 " + dthex_test::shell_quote(script) + " " +
                                              dthex_test::shell_quote(file.string()) + " --json --no-probe 2>&1");
  EXPECT_EQ(result.exit_code, 0) << "hexeval rejected " << file << ":\n" << result.output;
  const size_t last_line = result.output.find_last_of('\n', result.output.size() - 2);
  return json::parse(result.output.substr(last_line == std::string::npos ? 0 : last_line + 1));
}

}  // namespace

TEST(WriteHexMesh, FormatFromExtension) {
  using dthex::HexFormat;
  EXPECT_EQ(dthex::hex_format_from_path("a/b.vtu"), HexFormat::Vtu);
  EXPECT_EQ(dthex::hex_format_from_path("b.VTK"), HexFormat::Vtk);
  EXPECT_EQ(dthex::hex_format_from_path("b.Msh"), HexFormat::GmshMsh41);
  EXPECT_EQ(dthex::hex_format_from_path("b.inp"), HexFormat::AbaqusInp);
  EXPECT_EQ(dthex::hex_format_from_path("b.feb"), HexFormat::FebioFeb);
  EXPECT_EQ(dthex::hex_format_from_path("b.exo"), HexFormat::ExodusII);
  EXPECT_EQ(dthex::hex_format_from_path("b.E"), HexFormat::ExodusII);
  EXPECT_EQ(dthex::hex_format_from_path("x.y/b.ex2"), HexFormat::ExodusII);
  EXPECT_EQ(dthex::supported_hex_extensions().size(), 8u);
  try {
    dthex::hex_format_from_path("mesh.stl");
    FAIL() << "no InputError";
  } catch (const dthex::InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("'.stl'"), std::string::npos) << message;
    EXPECT_NE(message.find(".vtu"), std::string::npos) << message;
    EXPECT_NE(message.find(".ex2"), std::string::npos) << message;
  }
  EXPECT_THROW(dthex::hex_format_from_path("mesh"), dthex::InputError);
}

class HexRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(HexRoundTrip, ThirdPartyReadersGetTheSameMesh) {
  if (!dthex_test::meshio_available()) GTEST_SKIP() << "/usr/bin/python3 cannot import meshio";
  const std::string ext = GetParam();
  const fs::path dir = hex_write_folder(ext.substr(1));
  for (const auto& [mesh, name] : {std::pair{unit_cubes(), "cubes"}, std::pair{awkward_block(), "awkward"}}) {
    const dthex::HexQuality quality = dthex::measure_hex_quality(mesh);
    const fs::path file = dir / (std::string(name) + ext);
    dthex::write_hex_mesh(mesh, file.string(), {quality.shape, quality.scaled_jacobian});
    const json read = read_back(file);
    expect_same_mesh(mesh, read, file.string(), ext != ".inp", ext == ".msh");
    if (ext == ".vtu" || ext == ".vtk") for (const std::string reader : {"meshio", "vtk"}) {
      const json via = reader == "meshio" ? read : read_back(file, reader);
      if (reader != "meshio") expect_same_mesh(mesh, via, file.string() + " read by " + reader);
      ASSERT_TRUE(via["cell_data"].contains("shape")) << reader;
      ASSERT_TRUE(via["cell_data"].contains("scaled_jacobian")) << reader;
      ASSERT_TRUE(via["cell_data"].contains("part")) << reader;
      for (size_t h = 0; h < mesh.hexes.size(); ++h) {
        EXPECT_EQ(via["cell_data"]["part"][h].get<int>(), 1) << reader << ": one body, one part";
        EXPECT_EQ(via["cell_data"]["shape"][h].get<double>(), quality.shape[h]) << reader;
        EXPECT_EQ(via["cell_data"]["scaled_jacobian"][h].get<double>(), quality.scaled_jacobian[h]) << reader;
      }
      ASSERT_TRUE(via["point_data"].contains("boundary")) << reader;
      for (size_t n = 0; n < mesh.nodes.size(); ++n)
        EXPECT_EQ(via["point_data"]["boundary"][n].get<int>(), mesh.is_boundary_node(int(n)) ? 1 : 0) << reader;
    }
    if (ext == ".msh") {  // the hexes first, all in physical volume 1; then the face sets' quadrangles
      ASSERT_TRUE(read["cell_data"].contains("gmsh:physical"));
      const json& tags = read["cell_data"]["gmsh:physical"];
      ASSERT_GT(tags.size(), mesh.hexes.size());
      for (size_t c = 0; c < mesh.hexes.size(); ++c) EXPECT_EQ(tags[c].get<int>(), 1);
    }
    if (ext == ".feb") {
      const json& feb = read["feb"];
      EXPECT_EQ(feb["version"], "4.0");
      EXPECT_EQ(feb["element_type"], "hex8");
      EXPECT_EQ(feb["part"], "body1");
      EXPECT_EQ(feb["part"], feb["domain"]);
      for (size_t n = 0; n < feb["node_ids"].size(); ++n) EXPECT_EQ(feb["node_ids"][n].get<size_t>(), n + 1);
      for (size_t e = 0; e < feb["elem_ids"].size(); ++e) EXPECT_EQ(feb["elem_ids"][e].get<size_t>(), e + 1);
    }
    if (std::string(name) == "awkward") {
      EXPECT_LT(quality.shape_stats.avg, 0.99);  // the comparison below must mean something
      EXPECT_GT(quality.shape_stats.min, 0.0);
    }
    const bool refereed = ext == ".vtu" || ext == ".msh" || ext == ".inp" || ext == ".exo";
    if (refereed && fs::exists(DTHEX_SHARED_DIR "/tools/hexeval.py")) {
      const json report = run_hexeval(file);
      EXPECT_EQ(report["nodes"].get<size_t>(), mesh.nodes.size());
      EXPECT_EQ(report["hexes"].get<size_t>(), mesh.hexes.size());
      EXPECT_TRUE(report["valid"].get<bool>()) << file;
      EXPECT_NEAR(report["shape"]["avg"].get<double>(), quality.shape_stats.avg, 1e-9) << file;
      EXPECT_NEAR(report["shape"]["min"].get<double>(), quality.shape_stats.min, 1e-9) << file;
    }
  }
  EXPECT_EQ(dthex_test::count_files(dir), 3u) << "temporaries left behind";  // two meshes + the reader script
}

INSTANTIATE_TEST_SUITE_P(AllFormats, HexRoundTrip,
                         ::testing::Values(".vtu", ".vtk", ".msh", ".inp", ".feb", ".exo", ".e", ".ex2"),
                         [](const auto& info) { return info.param.substr(1); });

TEST(WriteHexMesh, VtuIsRawAppendedWithExactDoubles) {
  const fs::path dir = hex_write_folder("vturaw");
  const HexMesh mesh = awkward_block();
  const std::string file = (dir / "m.vtu").string();
  dthex::write_hex_mesh(mesh, file);
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(bytes.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_NE(bytes.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  EXPECT_EQ(bytes.find("Name=\"shape\""), std::string::npos) << "no fields given, no shape";
  EXPECT_NE(bytes.find("<DataArray type=\"Int32\" Name=\"part\""), std::string::npos) << "the part array is always written";
  // The first node's x must appear as its 8 raw bytes somewhere in the appended block.
  const double x = mesh.nodes[0].x();
  EXPECT_NE(bytes.find(std::string(reinterpret_cast<const char*>(&x), sizeof x)), std::string::npos);
}

TEST(WriteHexMesh, UnknownExtensionAndBadFolderAreInputErrors) {
  const fs::path dir = hex_write_folder("bad");
  const HexMesh mesh = unit_cubes();
  EXPECT_THROW(dthex::write_hex_mesh(mesh, (dir / "m.stl").string()), dthex::InputError);
  EXPECT_THROW(dthex::write_hex_mesh(mesh, (dir / "missing" / "m.vtu").string()), dthex::InputError);
  std::ofstream(dir / "plain_file") << "x";
  EXPECT_THROW(dthex::write_hex_mesh(mesh, (dir / "plain_file" / "m.msh").string()), dthex::InputError);
  HexMesh broken = mesh;
  broken.hexes[3][5] = int(mesh.nodes.size());
  EXPECT_THROW(dthex::write_hex_mesh(broken, (dir / "m.inp").string()), dthex::InputError);
  EXPECT_THROW(dthex::write_hex_mesh(mesh, (dir / "m.vtu").string(), {{0.5}, {}}), dthex::InputError);
  EXPECT_EQ(dthex_test::count_files(dir), 1u);  // only plain_file
  if (::geteuid() != 0) {  // root may write into a read-only folder
    const fs::path locked = hex_write_folder("locked");
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_THROW(dthex::write_hex_mesh(mesh, (locked / "m.vtu").string()), dthex::InputError);
    fs::permissions(locked, fs::perms::owner_all);
    EXPECT_EQ(dthex_test::count_files(locked), 0u);
  }
}

TEST(WriteHexMesh, FailedWriteLeavesNoFile) {
  // A file-size limit makes writes fail with EFBIG, as a full disk would with ENOSPC.
  const HexMesh big = make_block(10, [](int i, int j, int k) { return Vec3(0.1 * i, 0.1 * j, 0.1 * k); });
  for (const std::string ext : {".vtu", ".vtk", ".msh", ".inp", ".feb", ".exo"}) {
    const fs::path dir = hex_write_folder("full" + ext.substr(1));
    const std::string file = (dir / ("m" + ext)).string();
    const int code = dthex_test::write_failure_under_file_size_limit(4096, [&] { dthex::write_hex_mesh(big, file); });
    EXPECT_EQ(code, 0) << ext << ": " << dthex_test::kWriteFailureCodes;
    EXPECT_EQ(dthex_test::count_files(dir), 0u) << ext;
    // Without the limit the same write succeeds (so the failure above came from the limit).
    dthex::write_hex_mesh(big, file);
    EXPECT_GT(fs::file_size(file), 4096u) << ext;
  }
}

TEST(WriteHexMesh, InpFieldsFitCalculixAndReadBackWithinTheirDigits) {
  // A model in metres (the coordinates of a vertebra) and one with extreme exponents: every
  // field of a *NODE line is at most 20 characters (CalculiX reads no more, and silently
  // misreads what is longer), and parses back within 1e-12 of the double written.
  const fs::path dir = hex_write_folder("inpwidth");
  for (const double scale : {1e-5, 1e-95, 1e95}) {
    HexMesh mesh = awkward_block();
    for (Vec3& p : mesh.nodes) p = -scale * p * 0.9769344902824719;
    const fs::path file = dir / "m.inp";
    dthex::write_hex_mesh(mesh, file.string());
    std::ifstream in(file);
    std::string line;
    bool in_nodes = false;
    size_t node = 0;
    while (std::getline(in, line)) {
      EXPECT_EQ(line.rfind("*HEADING", 0), std::string::npos) << "an included mesh file must not have *HEADING";
      if (line.rfind("*", 0) == 0) {
        in_nodes = line == "*NODE";
        continue;
      }
      if (!in_nodes) continue;
      std::stringstream fields(line);
      std::string field;
      std::getline(fields, field, ',');
      ASSERT_EQ(std::stoul(field), node + 1);
      for (int d = 0; d < 3; ++d) {
        ASSERT_TRUE(std::getline(fields, field, ','));
        EXPECT_LE(field.size(), 20u) << field;
        const double ours = mesh.nodes[node][d];
        EXPECT_LE(std::abs(std::stod(field) - ours), 1e-12 * std::abs(ours)) << field;
      }
      ++node;
    }
    EXPECT_EQ(node, mesh.nodes.size()) << scale;
  }
}

TEST(WriteHexMesh, InpSetsReadBackByMeshio) {
  if (!dthex_test::meshio_available()) GTEST_SKIP() << "/usr/bin/python3 cannot import meshio";
  // Two bodies: their parts, boundaries and patches are element and node sets meshio reads
  // with the counts find_mesh_sets() gives.
  HexMesh mesh = unit_cubes();
  const HexMesh other = make_block(1, [](int i, int j, int k) { return Vec3(5 + i, j, k); });
  const int offset = int(mesh.nodes.size());
  mesh.nodes.insert(mesh.nodes.end(), other.nodes.begin(), other.nodes.end());
  mesh.boundary_facet.insert(mesh.boundary_facet.end(), other.boundary_facet.begin(), other.boundary_facet.end());
  for (auto h : other.hexes) {
    for (int& n : h) n += offset;
    mesh.hexes.push_back(h);
  }
  const dthex::MeshSets sets = dthex::find_mesh_sets(mesh);
  ASSERT_EQ(sets.parts.size(), 2u);
  const fs::path dir = hex_write_folder("inpsets");
  const fs::path file = dir / "two.inp";
  dthex::write_hex_mesh(mesh, file.string());
  const fs::path script = dir / "sets.py";
  std::ofstream(script) << "import json, sys, meshio\n"
                           "m = meshio.read(sys.argv[1])\n"
                           "print(json.dumps({'cells': {k: sum(len(a) for a in v) for k, v in m.cell_sets.items()},\n"
                           "                  'points': {k: len(v) for k, v in m.point_sets.items()}}))\n";
  const auto result = dthex_test::run_command("/usr/bin/python3 " + dthex_test::shell_quote(script.string()) + " " +
                                              dthex_test::shell_quote(file.string()));
  ASSERT_EQ(result.exit_code, 0);
  const json read = json::parse(result.output);
  EXPECT_EQ(read["cells"]["SOLID"].get<size_t>(), mesh.hexes.size());
  EXPECT_EQ(read["cells"]["body1"].get<size_t>(), 8u);
  EXPECT_EQ(read["cells"]["body2"].get<size_t>(), 1u);
  ASSERT_EQ(read["points"].size(), sets.node_sets.size());
  for (const dthex::NodeSet& set : sets.node_sets)
    EXPECT_EQ(read["points"][set.name].get<size_t>(), set.nodes.size()) << set.name;
  EXPECT_EQ(sets.node_sets.size(), 2u + 12u);  // two boundaries, six sides each
}

namespace {

// Reads the sets of a hex mesh back with each format's own reader and prints JSON: element
// lists per physical group (gmsh's Python API, and meshio's counts), per FEBio Elements, NodeSet
// and Surface (Python's XML parser, with each facet checked to be an outward face of a hex by
// geometry alone), per Exodus block, node set and side set (netCDF4, each side turned into its
// nodes with the Exodus HEX8 side table), and the "part" cell array of VTU/VTK (VTK's readers).
const char* kSetsScript = R"PY(
import json, sys
import numpy as np
path = sys.argv[1]
out = {}
if path.endswith('.msh'):
    import gmsh, meshio
    gmsh.initialize()
    gmsh.option.setNumber('General.Terminal', 0)
    gmsh.open(path)
    groups = []
    for dim, tag in gmsh.model.getPhysicalGroups():
        elements = []
        for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
            types, tags, nodes = gmsh.model.mesh.getElements(dim, entity)
            for t, ts, ns in zip(types, tags, nodes):
                per = len(ns) // len(ts)
                elements += [[int(v) for v in ns[per * i: per * (i + 1)]] for i in range(len(ts))]
        groups.append(dict(dim=dim, name=gmsh.model.getPhysicalName(dim, tag), elements=elements))
    gmsh.finalize()
    out['groups'] = groups
    m = meshio.read(path)
    tag_name = {(int(v[1]), int(v[0])): k for k, v in m.field_data.items()}
    dims = {'hexahedron': 3, 'quad': 2}
    counts = {}
    for block, tags in zip(m.cells, m.cell_data['gmsh:physical']):
        for t in tags:
            name = tag_name[(dims[block.type], int(t))]
            counts[name] = counts.get(name, 0) + 1
    out['meshio_counts'] = counts
elif path.endswith('.feb'):
    import xml.etree.ElementTree as ET
    mesh = ET.parse(path).getroot().find('Mesh')
    points = {int(n.get('id')): np.array([float(v) for v in n.text.split(',')]) for n in mesh.find('Nodes')}
    hexes = {}
    out['parts'] = []
    for block in mesh.findall('Elements'):
        elems = [(int(e.get('id')), [int(v) for v in e.text.split(',')]) for e in block.findall('elem')]
        hexes.update(dict(elems))
        out['parts'].append(dict(name=block.get('name'), type=block.get('type'), ids=[i for i, _ in elems],
                                 elements=[c for _, c in elems]))
    root = ET.parse(path).getroot()
    out['domains'] = [d.get('name') for d in root.find('MeshDomains').findall('SolidDomain')]
    out['node_sets'] = {n.get('name'): [int(v) for v in n.text.split(',')] for n in mesh.findall('NodeSet')}
    # Sides of a hex8 as corner quadruples in either orientation; outwardness is checked by geometry.
    sides = [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    by_nodes = {}
    for hid, c in hexes.items():
        for s in sides:
            by_nodes.setdefault(frozenset(c[k] for k in s), []).append((hid, s))
    def cyclic(seq, ref):
        n = len(ref)
        return any(list(seq) == [ref[(i + k) % n] for k in range(n)] for i in range(n)) or \
               any(list(seq) == [ref[(i - k) % n] for k in range(n)] for i in range(n))
    out['surfaces'] = {}
    for surface in mesh.findall('Surface'):
        facets = [[int(v) for v in q.text.split(',')] for q in surface.findall('quad4')]
        bad = 0
        # A facet is good when it is an outward face of a hex that has it (one hex on the
        # boundary; either of two on an interface between material regions).
        def outward_of(f, hid, s):
            c = hexes[hid]
            if not cyclic(f, [c[k] for k in s]): return False
            p = [points[v] for v in f]
            normal = np.cross(p[2] - p[0], p[3] - p[1])
            centre = np.mean([points[v] for v in c], axis=0)
            return np.dot(normal, np.mean(p, axis=0) - centre) > 0
        for f in facets:
            owners = by_nodes.get(frozenset(f), [])
            if len(owners) not in (1, 2) or not any(outward_of(f, hid, s) for hid, s in owners): bad += 1
        out['surfaces'][surface.get('name')] = dict(facets=facets, bad=bad,
                                                    ids=[int(q.get('id')) for q in surface.findall('quad4')])
elif path.endswith('.exo'):
    import netCDF4
    d = netCDF4.Dataset(path)
    d.set_auto_mask(False)
    names = lambda var: [str(n) for n in netCDF4.chartostring(d.variables[var][:])]
    blocks = [np.asarray(d.variables['connect%d' % (b + 1)][:]).tolist() for b in range(len(d.dimensions['num_el_blk']))]
    out['blocks'] = dict(names=names('eb_names'), elements=blocks,
                         types=[d.variables['connect%d' % (b + 1)].getncattr('elem_type') for b in range(len(blocks))])
    out['elem_num_map'] = np.asarray(d.variables['elem_num_map'][:]).tolist() if 'elem_num_map' in d.variables else None
    out['node_sets'] = {n: np.asarray(d.variables['node_ns%d' % (i + 1)][:]).tolist() for i, n in enumerate(names('ns_names'))}
    element = [c for b in blocks for c in b]
    table = [(0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (0, 4, 7, 3), (0, 3, 2, 1), (4, 5, 6, 7)]  # Exodus HEX8 sides 1-6
    out['side_sets'] = {}
    for i, n in enumerate(names('ss_names')):
        elems = np.asarray(d.variables['elem_ss%d' % (i + 1)][:]).tolist()
        sides = np.asarray(d.variables['side_ss%d' % (i + 1)][:]).tolist()
        out['side_sets'][n] = [[element[e - 1][k] for k in table[s - 1]] for e, s in zip(elems, sides)]
else:
    import vtk
    from vtk.util import numpy_support as ns
    r = vtk.vtkXMLUnstructuredGridReader() if path.endswith('.vtu') else vtk.vtkUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    cd = g.GetCellData()
    for name in ('part', 'face_set', 'shape'):
        if cd.GetArray(name) is not None: out[name] = ns.vtk_to_numpy(cd.GetArray(name)).tolist()
    out['types'] = [g.GetCellType(c) for c in range(g.GetNumberOfCells())]
    out['cells'] = [[g.GetCell(c).GetPointId(k) for k in range(g.GetCell(c).GetNumberOfPoints())]
                    for c in range(g.GetNumberOfCells())]
print(json.dumps(out))
)PY";

json read_sets_back(const fs::path& file) {
  const fs::path script = file.parent_path() / "read_sets.py";
  if (!fs::exists(script)) std::ofstream(script) << kSetsScript;
  const auto result = dthex_test::run_command("/usr/bin/python3 " + dthex_test::shell_quote(script.string()) + " " +
                                              dthex_test::shell_quote(file.string()));
  EXPECT_EQ(result.exit_code, 0) << "reading the sets of " << file << " failed:\n" << result.output;
  if (result.exit_code != 0) return json();
  return json::parse(result.output);
}

std::vector<int> one_based(const std::array<int, 8>& hex) {
  std::vector<int> ids;
  for (int n : hex) ids.push_back(n + 1);
  return ids;
}

std::vector<int> outward_nodes_one_based(const HexMesh& mesh, const dthex::HexFace& f) {
  std::vector<int> ids;
  for (int c : dthex::kHexFaces[size_t(f.side)]) ids.push_back(mesh.hexes[size_t(f.hex)][size_t(c)] + 1);
  return ids;
}

//! True when b is a rotation of a (same cyclic order, any first corner).
bool same_cycle(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size()) return false;
  for (size_t r = 0; r < a.size(); ++r) {
    bool equal = true;
    for (size_t k = 0; k < a.size() && equal; ++k) equal = a[(r + k) % a.size()] == b[k];
    if (equal) return true;
  }
  return false;
}

//! Two bodies, the smaller one's hex first, so that grouping the hexes by part reorders them.
HexMesh two_bodies_small_first() {
  HexMesh mesh = make_block(1, [](int i, int j, int k) { return Vec3(5 + i, j, k); });
  const HexMesh big = unit_cubes();
  const int offset = int(mesh.nodes.size());
  mesh.nodes.insert(mesh.nodes.end(), big.nodes.begin(), big.nodes.end());
  mesh.boundary_facet.insert(mesh.boundary_facet.end(), big.boundary_facet.begin(), big.boundary_facet.end());
  for (auto h : big.hexes) {
    for (int& n : h) n += offset;
    mesh.hexes.push_back(h);
  }
  return mesh;
}

}  // namespace

TEST(WriteHexMesh, EveryFormatCarriesTheSetsItsReaderReadsBack) {
  if (!dthex_test::meshio_available()) GTEST_SKIP() << "/usr/bin/python3 cannot import meshio";
  const HexMesh mesh = two_bodies_small_first();
  dthex::MeshSets sets = dthex::find_mesh_sets(mesh);
  dthex::add_user_sets(sets, mesh, {dthex::parse_user_set("floor_of_the_big_block_longer_than_32=box:-0.1,-0.1,-0.1,2.1,2.1,0.1")});
  ASSERT_EQ(sets.parts.size(), 2u);
  ASSERT_EQ(sets.parts[0].hexes.size(), 8u);  // body1, the big block, is hexes 1-8
  ASSERT_EQ(sets.parts[1].hexes, std::vector<int>{0});
  ASSERT_EQ(sets.surfaces.size(), 2u + 12u + 1u);
  ASSERT_EQ(sets.surfaces.back().faces.size(), 4u);  // its name is longer than Exodus's default 32
  const fs::path dir = hex_write_folder("sets");

  for (const bool v22 : {false, true}) {  // Gmsh: physical groups of dimension 3 and 2
    const fs::path file = dir / (v22 ? "m22.msh" : "m41.msh");
    dthex::HexWriteOptions options;
    if (v22) options.msh_version = dthex::HexWriteOptions::MshVersion::V22;
    dthex::write_hex_mesh(mesh, file.string(), {}, &sets, options);
    const json read = read_sets_back(file);
    ASSERT_EQ(read["groups"].size(), sets.parts.size() + sets.surfaces.size()) << file;
    std::map<std::string, json> volume, surface;
    for (const json& g : read["groups"]) (g["dim"] == 3 ? volume : surface)[g["name"].get<std::string>()] = g;
    for (const dthex::HexSet& part : sets.parts) {
      ASSERT_TRUE(volume.count(part.name)) << file << " " << part.name;
      const json& elements = volume[part.name]["elements"];
      ASSERT_EQ(elements.size(), part.hexes.size()) << file << " " << part.name;
      for (size_t i = 0; i < part.hexes.size(); ++i)
        EXPECT_EQ(elements[i].get<std::vector<int>>(), one_based(mesh.hexes[size_t(part.hexes[i])])) << file;
      EXPECT_EQ(read["meshio_counts"][part.name].get<size_t>(), part.hexes.size()) << file << " " << part.name;
    }
    for (const dthex::FaceSet& set : sets.surfaces) {
      ASSERT_TRUE(surface.count(set.name)) << file << " " << set.name;
      const json& elements = surface[set.name]["elements"];
      ASSERT_EQ(elements.size(), set.faces.size()) << file << " " << set.name;
      for (size_t i = 0; i < set.faces.size(); ++i)
        EXPECT_EQ(elements[i].get<std::vector<int>>(), outward_nodes_one_based(mesh, set.faces[i])) << file;
      EXPECT_EQ(read["meshio_counts"][set.name].get<size_t>(), set.faces.size()) << file << " " << set.name;
    }
    std::ifstream in(file);
    std::string first_lines[2];
    std::getline(in, first_lines[0]);
    std::getline(in, first_lines[1]);
    EXPECT_EQ(first_lines[1], v22 ? "2.2 0 8" : "4.1 0 8");
  }

  {  // FEBio: Elements and SolidDomain per part, NodeSet, Surface of outward quad4 facets
    const fs::path file = dir / "m.feb";
    dthex::write_hex_mesh(mesh, file.string(), {}, &sets);
    const json read = read_sets_back(file);
    ASSERT_EQ(read["parts"].size(), sets.parts.size());
    ASSERT_EQ(read["domains"].size(), sets.parts.size());
    for (size_t p = 0; p < sets.parts.size(); ++p) {
      const json& block = read["parts"][p];
      EXPECT_EQ(block["name"], sets.parts[p].name);
      EXPECT_EQ(block["type"], "hex8");
      EXPECT_EQ(read["domains"][p], sets.parts[p].name);
      ASSERT_EQ(block["ids"].size(), sets.parts[p].hexes.size());
      for (size_t i = 0; i < sets.parts[p].hexes.size(); ++i) {
        const int h = sets.parts[p].hexes[i];
        EXPECT_EQ(block["ids"][i].get<int>(), h + 1) << "element ids are the hex's index + 1, as in the INP";
        EXPECT_EQ(block["elements"][i].get<std::vector<int>>(), one_based(mesh.hexes[size_t(h)]));
      }
    }
    ASSERT_EQ(read["node_sets"].size(), sets.node_sets.size());
    for (const dthex::NodeSet& set : sets.node_sets) {
      std::vector<int> expected;
      for (int n : set.nodes) expected.push_back(n + 1);
      EXPECT_EQ(read["node_sets"][set.name].get<std::vector<int>>(), expected) << set.name;
    }
    ASSERT_EQ(read["surfaces"].size(), sets.surfaces.size());
    for (const dthex::FaceSet& set : sets.surfaces) {
      const json& surface = read["surfaces"][set.name];
      ASSERT_EQ(surface["facets"].size(), set.faces.size()) << set.name;
      EXPECT_EQ(surface["bad"].get<int>(), 0) << set.name << ": facets that are not outward faces of a hex";
      for (size_t i = 0; i < set.faces.size(); ++i) {
        EXPECT_EQ(surface["ids"][i].get<size_t>(), i + 1);
        EXPECT_EQ(surface["facets"][i].get<std::vector<int>>(), outward_nodes_one_based(mesh, set.faces[i]));
      }
    }
  }

  {  // Exodus: a named block per part, named node sets, named side sets with Exodus side numbers
    const fs::path file = dir / "m.exo";
    dthex::write_hex_mesh(mesh, file.string(), {}, &sets);
    const json read = read_sets_back(file);
    ASSERT_EQ(read["blocks"]["names"].size(), sets.parts.size());
    std::vector<int> ids;
    for (size_t p = 0; p < sets.parts.size(); ++p) {
      EXPECT_EQ(read["blocks"]["names"][p], sets.parts[p].name);
      EXPECT_EQ(read["blocks"]["types"][p], "HEX8");
      const json& elements = read["blocks"]["elements"][p];
      ASSERT_EQ(elements.size(), sets.parts[p].hexes.size());
      for (size_t i = 0; i < elements.size(); ++i) {
        EXPECT_EQ(elements[i].get<std::vector<int>>(), one_based(mesh.hexes[size_t(sets.parts[p].hexes[i])]));
        ids.push_back(sets.parts[p].hexes[i] + 1);
      }
    }
    ASSERT_FALSE(read["elem_num_map"].is_null()) << "the hexes were reordered, so the map gives their ids";
    EXPECT_EQ(read["elem_num_map"].get<std::vector<int>>(), ids);
    ASSERT_EQ(read["node_sets"].size(), sets.node_sets.size());
    for (const dthex::NodeSet& set : sets.node_sets) {
      std::vector<int> expected;
      for (int n : set.nodes) expected.push_back(n + 1);
      EXPECT_EQ(read["node_sets"][set.name].get<std::vector<int>>(), expected) << set.name;
    }
    ASSERT_EQ(read["side_sets"].size(), sets.surfaces.size());
    for (const dthex::FaceSet& set : sets.surfaces) {
      const json& sides = read["side_sets"][set.name];
      ASSERT_EQ(sides.size(), set.faces.size()) << set.name;
      for (size_t i = 0; i < set.faces.size(); ++i)
        EXPECT_TRUE(same_cycle(sides[i].get<std::vector<int>>(), outward_nodes_one_based(mesh, set.faces[i])))
            << set.name << " face " << i << ": Exodus side of Abaqus S" << set.faces[i].side + 1;
    }
    // One part: no reordering, no map.
    const fs::path single = dir / "one.exo";
    dthex::write_hex_mesh(unit_cubes(), single.string());
    EXPECT_TRUE(read_sets_back(single)["elem_num_map"].is_null());
  }

  std::vector<double> shape(mesh.hexes.size());
  for (size_t h = 0; h < shape.size(); ++h) shape[h] = 0.5 + 0.01 * double(h);
  for (const std::string ext : {".vtu", ".vtk"}) {
    {  // by default the part array on the hexes, in their own order, and no other cells
      const fs::path file = dir / ("m" + ext);
      dthex::write_hex_mesh(mesh, file.string(), {}, &sets);
      const json read = read_sets_back(file);
      ASSERT_EQ(read["part"].size(), mesh.hexes.size()) << ext;
      EXPECT_EQ(read["part"][0].get<int>(), 2) << ext;
      for (size_t h = 1; h < mesh.hexes.size(); ++h) EXPECT_EQ(read["part"][h].get<int>(), 1) << ext;
      EXPECT_FALSE(read.contains("face_set")) << ext;
      for (const auto& type : read["types"]) EXPECT_EQ(type.get<int>(), 12) << ext;
    }
    // With vtk_face_set_cells: each face set's faces as outward quads after the hexes.
    const fs::path file = dir / ("faces" + ext);
    dthex::HexWriteOptions options;
    options.vtk_face_set_cells = true;
    dthex::write_hex_mesh(mesh, file.string(), {shape, {}}, &sets, options);
    const json read = read_sets_back(file);
    size_t quads = 0;
    for (const dthex::FaceSet& set : sets.surfaces) quads += set.faces.size();
    ASSERT_EQ(read["types"].size(), mesh.hexes.size() + quads) << ext;
    ASSERT_EQ(read["face_set"].size(), mesh.hexes.size() + quads) << ext;
    ASSERT_EQ(read["shape"].size(), mesh.hexes.size() + quads) << ext;
    for (size_t h = 0; h < mesh.hexes.size(); ++h) {
      EXPECT_EQ(read["types"][h].get<int>(), 12);
      EXPECT_EQ(read["face_set"][h].get<int>(), 0);
      EXPECT_EQ(read["part"][h].get<int>(), h == 0 ? 2 : 1);
      EXPECT_EQ(read["shape"][h].get<double>(), shape[h]);
    }
    size_t c = mesh.hexes.size();
    for (size_t s = 0; s < sets.surfaces.size(); ++s)
      for (const dthex::HexFace& f : sets.surfaces[s].faces) {
        EXPECT_EQ(read["types"][c].get<int>(), 9) << ext;
        EXPECT_EQ(read["face_set"][c].get<int>(), int(s + 1)) << ext;
        EXPECT_EQ(read["part"][c].get<int>(), 0) << ext;
        EXPECT_EQ(read["shape"][c].get<double>(), shape[size_t(f.hex)]) << ext;
        std::vector<int> expected = outward_nodes_one_based(mesh, f);
        for (int& n : expected) --n;
        EXPECT_EQ(read["cells"][c].get<std::vector<int>>(), expected) << ext;
        ++c;
      }
  }
}

//! Two material regions (HexMesh::region) that share nodes: gmsh, meshio and the FEBio and Exodus
//! readers see two parts, each part's boundary with the interface, and the interface surface,
//! with the counts find_mesh_sets() gives; the interface's FEBio facets are faces of its hexes.
TEST(WriteHexMesh, MaterialRegionsAndTheirInterfaceReadBackInEveryFormat) {
  if (!dthex_test::meshio_available()) GTEST_SKIP() << "/usr/bin/python3 cannot import meshio";
  HexMesh mesh = unit_cubes();
  mesh.region.resize(mesh.hexes.size());
  for (size_t h = 0; h < mesh.hexes.size(); ++h) mesh.region[h] = mesh.nodes[size_t(mesh.hexes[h][0])].x() < 1 ? 0 : 1;
  const dthex::MeshSets sets = dthex::find_mesh_sets(mesh);
  ASSERT_EQ(sets.parts.size(), 2u);
  const auto interface = std::find_if(sets.surfaces.begin(), sets.surfaces.end(),
                                      [](const dthex::FaceSet& f) { return f.name == "body1_body2_interface"; });
  ASSERT_NE(interface, sets.surfaces.end());
  ASSERT_EQ(interface->faces.size(), 4u);
  const fs::path dir = hex_write_folder("regions");

  const fs::path msh = dir / "m.msh";
  dthex::write_hex_mesh(mesh, msh.string(), {}, &sets);
  const json groups = read_sets_back(msh);
  ASSERT_EQ(groups["groups"].size(), sets.parts.size() + sets.surfaces.size());
  for (const dthex::HexSet& part : sets.parts)
    EXPECT_EQ(groups["meshio_counts"][part.name].get<size_t>(), part.hexes.size()) << part.name;
  for (const dthex::FaceSet& set : sets.surfaces)
    EXPECT_EQ(groups["meshio_counts"][set.name].get<size_t>(), set.faces.size()) << set.name;

  const fs::path feb = dir / "m.feb";
  dthex::write_hex_mesh(mesh, feb.string(), {}, &sets);
  const json febio = read_sets_back(feb);
  ASSERT_EQ(febio["parts"].size(), 2u);
  EXPECT_EQ(febio["surfaces"]["body1_body2_interface"]["facets"].size(), 4u);
  for (const dthex::FaceSet& set : sets.surfaces)
    EXPECT_EQ(febio["surfaces"][set.name]["bad"].get<int>(), 0) << set.name << ": facets that are not faces of a hex";

  const fs::path exo = dir / "m.exo";
  dthex::write_hex_mesh(mesh, exo.string(), {}, &sets);
  const json exodus = read_sets_back(exo);
  ASSERT_EQ(exodus["blocks"]["names"].size(), 2u);
  for (const dthex::FaceSet& set : sets.surfaces)
    EXPECT_EQ(exodus["side_sets"][set.name].size(), set.faces.size()) << set.name;
  for (const dthex::NodeSet& set : sets.node_sets)
    EXPECT_EQ(exodus["node_sets"][set.name].size(), set.nodes.size()) << set.name;
}

TEST(WriteHexMesh, SetsThatDoNotMatchTheMeshAreRefused) {
  const fs::path dir = hex_write_folder("badsets");
  const HexMesh mesh = two_bodies_small_first();
  const dthex::MeshSets good = dthex::find_mesh_sets(mesh);
  dthex::MeshSets missing = good, bad_face = good;
  missing.parts.pop_back();  // hex 0 in no part
  bad_face.surfaces[0].faces[0].side = 6;
  for (const std::string ext : {".msh", ".feb", ".exo", ".vtu"}) {
    EXPECT_THROW(dthex::write_hex_mesh(mesh, (dir / ("a" + ext)).string(), {}, &missing), dthex::InputError) << ext;
    EXPECT_THROW(dthex::write_hex_mesh(mesh, (dir / ("b" + ext)).string(), {}, &bad_face), dthex::InputError) << ext;
  }
  EXPECT_EQ(dthex_test::count_files(dir), 0u);
}

TEST(WriteHexMesh, MshVersionOptionOfTheCommandLine) {
  // --msh-version 2.2 writes MSH 2.2 that gmsh reads with its physical groups; a version the
  // writer does not have is a usage error (exit 2) before any meshing.
  const fs::path dir = hex_write_folder("mshversion");
  const std::string input = std::string(DTHEX_SOURCE_DIR) + "/meshes/sphere728.off";
  const fs::path file = dir / "s.msh";
  const auto run = dthex_test::run_om_dthex(input + " -q --no-project --msh-version 2.2 -o " + file.string(), dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::getline(in, line);
  EXPECT_EQ(line, "2.2 0 8");
  in.close();
  if (dthex_test::meshio_available()) {
    const json read = read_sets_back(file);
    size_t volumes = 0, surfaces = 0;
    for (const json& g : read["groups"]) ++(g["dim"] == 3 ? volumes : surfaces);
    EXPECT_EQ(volumes, 1u);
    EXPECT_GE(surfaces, 2u);  // body1_boundary and at least one patch
  }
  const auto bad = dthex_test::run_om_dthex(input + " -q --msh-version 3 -o " + (dir / "t.msh").string(), dir);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("msh-version"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "t.msh"));
}
