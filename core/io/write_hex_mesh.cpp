// SPDX-License-Identifier: MIT
#include <dthex/io/write_hex_mesh.h>

#include <dthex/hexes/mesh_sets.h>
#include <dthex/io/atomic_file.h>
#include <dthex/io/output_file.h>

#include <exodusII.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>

namespace dthex {
namespace {

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

//! Refuses meshes that would produce a file a solver cannot read, before any file exists.
void check_mesh(const HexMesh& mesh, const HexFields& fields, const std::string& path) {
  const std::string prefix = "cannot write '" + path + "': ";
  if (mesh.hexes.empty()) throw InputError(prefix + "the mesh has no hexahedra");
  if (mesh.nodes.size() >= size_t(INT_MAX)) throw InputError(prefix + "too many nodes for 32-bit ids");
  const int node_count = int(mesh.nodes.size());
  for (size_t h = 0; h < mesh.hexes.size(); ++h)
    for (int n : mesh.hexes[h])
      if (n < 0 || n >= node_count)
        throw InputError(prefix + "hex " + std::to_string(h) + " refers to node " + std::to_string(n) +
                         " but the mesh has " + std::to_string(node_count) + " nodes");
  if (!mesh.boundary_facet.empty() && mesh.boundary_facet.size() != mesh.nodes.size())
    throw InputError(prefix + "boundary_facet has " + std::to_string(mesh.boundary_facet.size()) +
                     " entries for " + std::to_string(mesh.nodes.size()) + " nodes");
  auto check_field = [&](const std::vector<double>& values, const char* name) {
    if (!values.empty() && values.size() != mesh.hexes.size())
      throw InputError(prefix + "field '" + name + "' has " + std::to_string(values.size()) + " values for " +
                       std::to_string(mesh.hexes.size()) + " hexes");
  };
  check_field(fields.shape, "shape");
  check_field(fields.scaled_jacobian, "scaled_jacobian");
}

bool host_is_little_endian() {
  const uint16_t probe = 1;
  unsigned char first = 0;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

// ---------------------------------------------------------------------------------------
// VTU: XML UnstructuredGrid with all arrays raw in one AppendedData block, each preceded
// by its UInt64 byte count. ParaView and meshio read this layout; exact doubles, compact.

struct AppendedArray {
  std::string xml_open;  // "<DataArray type=... " without the offset attribute
  uint64_t bytes = 0;
  std::function<void(OutputFile&)> write_data;
};

template <typename Out, typename Fill>
void write_converted(OutputFile& file, size_t count, Fill fill) {
  constexpr size_t kChunk = 1 << 16;
  std::vector<Out> chunk;
  chunk.reserve(kChunk);
  for (size_t begin = 0; begin < count; begin += kChunk) {
    chunk.clear();
    const size_t end = std::min(count, begin + kChunk);
    for (size_t i = begin; i < end; ++i) fill(i, chunk);
    file.write(chunk.data(), chunk.size() * sizeof(Out));
  }
}

void write_vtu(const HexMesh& mesh, const HexFields& fields, OutputFile& file) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
  const size_t n_nodes = mesh.nodes.size(), n_hexes = mesh.hexes.size();

  std::vector<AppendedArray> point_data, cell_data, points, cells;
  if (!mesh.boundary_facet.empty())
    point_data.push_back({R"(<DataArray type="UInt8" Name="boundary" format="appended")", n_nodes, [&](OutputFile& f) {
                            write_converted<uint8_t>(f, n_nodes, [&](size_t i, std::vector<uint8_t>& out) {
                              out.push_back(mesh.is_boundary_node(int(i)) ? 1 : 0);
                            });
                          }});
  auto add_field = [&](const std::vector<double>& values, const char* name) {
    if (values.empty()) return;
    cell_data.push_back({std::string(R"(<DataArray type="Float64" Name=")") + name + R"(" format="appended")",
                         n_hexes * sizeof(double),
                         [&values](OutputFile& f) { f.write(values.data(), values.size() * sizeof(double)); }});
  };
  add_field(fields.shape, "shape");
  add_field(fields.scaled_jacobian, "scaled_jacobian");
  points.push_back({R"(<DataArray type="Float64" Name="Points" NumberOfComponents="3" format="appended")",
                    n_nodes * 3 * sizeof(double),
                    [&](OutputFile& f) { f.write(mesh.nodes.data(), n_nodes * sizeof(Vec3)); }});
  cells.push_back({R"(<DataArray type="Int64" Name="connectivity" format="appended")", n_hexes * 8 * sizeof(int64_t),
                   [&](OutputFile& f) {
                     write_converted<int64_t>(f, n_hexes, [&](size_t h, std::vector<int64_t>& out) {
                       for (int n : mesh.hexes[h]) out.push_back(n);
                     });
                   }});
  cells.push_back({R"(<DataArray type="Int64" Name="offsets" format="appended")", n_hexes * sizeof(int64_t),
                   [&](OutputFile& f) {
                     write_converted<int64_t>(
                         f, n_hexes, [](size_t h, std::vector<int64_t>& out) { out.push_back(int64_t(8 * (h + 1))); });
                   }});
  cells.push_back({R"(<DataArray type="UInt8" Name="types" format="appended")", n_hexes, [&](OutputFile& f) {
                     write_converted<uint8_t>(f, n_hexes,
                                              [](size_t, std::vector<uint8_t>& out) { out.push_back(12); });
                   }});

  file.print("<?xml version=\"1.0\"?>\n"
             "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"%s\" header_type=\"UInt64\">\n"
             "  <UnstructuredGrid>\n"
             "    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n",
             host_is_little_endian() ? "LittleEndian" : "BigEndian", n_nodes, n_hexes);
  uint64_t offset = 0;
  auto declare = [&](const char* section, const std::vector<AppendedArray>& arrays) {
    if (arrays.empty()) return;
    file.print("      <%s>\n", section);
    for (const AppendedArray& a : arrays) {
      file.print("        %s offset=\"%llu\"/>\n", a.xml_open.c_str(), static_cast<unsigned long long>(offset));
      offset += sizeof(uint64_t) + a.bytes;
    }
    file.print("      </%s>\n", section);
  };
  declare("PointData", point_data);
  declare("CellData", cell_data);
  declare("Points", points);
  declare("Cells", cells);
  file.print("    </Piece>\n"
             "  </UnstructuredGrid>\n"
             "  <AppendedData encoding=\"raw\">\n"
             "   _");
  for (const auto* group : {&point_data, &cell_data, &points, &cells})
    for (const AppendedArray& a : *group) {
      file.write(&a.bytes, sizeof(a.bytes));
      a.write_data(file);
    }
  // The newline before the closing tag is where readers (meshio) expect the raw data to end.
  file.print("\n  </AppendedData>\n</VTKFile>\n");
}

// ---------------------------------------------------------------------------------------
// Legacy VTK, ASCII: readable by every VTK-based tool ever released.

void write_legacy_vtk(const HexMesh& mesh, const HexFields& fields, OutputFile& file) {
  const size_t n_nodes = mesh.nodes.size(), n_hexes = mesh.hexes.size();
  file.print("# vtk DataFile Version 3.0\nom_dthex hex mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n");
  file.print("POINTS %zu double\n", n_nodes);
  for (const Vec3& p : mesh.nodes) file.print("%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  file.print("CELLS %zu %zu\n", n_hexes, 9 * n_hexes);
  for (const auto& h : mesh.hexes)
    file.print("8 %d %d %d %d %d %d %d %d\n", h[0], h[1], h[2], h[3], h[4], h[5], h[6], h[7]);
  file.print("CELL_TYPES %zu\n", n_hexes);
  for (size_t h = 0; h < n_hexes; ++h) file.print("12\n");
  // FIELD rather than SCALARS: VTK's legacy reader loads only the first SCALARS array
  // unless told otherwise, but every array of a FIELD.
  std::vector<std::pair<const std::vector<double>*, const char*>> arrays;
  if (!fields.shape.empty()) arrays.emplace_back(&fields.shape, "shape");
  if (!fields.scaled_jacobian.empty()) arrays.emplace_back(&fields.scaled_jacobian, "scaled_jacobian");
  if (!arrays.empty()) {
    file.print("CELL_DATA %zu\nFIELD FieldData %zu\n", n_hexes, arrays.size());
    for (const auto& [values, name] : arrays) {
      file.print("%s 1 %zu double\n", name, n_hexes);
      for (double v : *values) file.print("%.17g\n", v);
    }
  }
  if (!mesh.boundary_facet.empty()) {
    file.print("POINT_DATA %zu\nSCALARS boundary int 1\nLOOKUP_TABLE default\n", n_nodes);
    for (size_t n = 0; n < n_nodes; ++n) file.print("%d\n", mesh.is_boundary_node(int(n)) ? 1 : 0);
  }
}

// ---------------------------------------------------------------------------------------
// Gmsh MSH 4.1 ASCII: one volume entity (tag 1) in physical group 1 "solid"; element type 5
// is the 8-node hexahedron, whose corner numbering is VTK's.

void write_gmsh(const HexMesh& mesh, OutputFile& file) {
  const size_t n_nodes = mesh.nodes.size(), n_hexes = mesh.hexes.size();
  Vec3 lo = mesh.nodes.front(), hi = mesh.nodes.front();
  for (const Vec3& p : mesh.nodes) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  file.print("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
  file.print("$PhysicalNames\n1\n3 1 \"solid\"\n$EndPhysicalNames\n");
  file.print("$Entities\n0 0 0 1\n1 %.17g %.17g %.17g %.17g %.17g %.17g 1 1 0\n$EndEntities\n", lo.x(), lo.y(),
             lo.z(), hi.x(), hi.y(), hi.z());
  file.print("$Nodes\n1 %zu 1 %zu\n3 1 0 %zu\n", n_nodes, n_nodes, n_nodes);
  for (size_t n = 0; n < n_nodes; ++n) file.print("%zu\n", n + 1);
  for (const Vec3& p : mesh.nodes) file.print("%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  file.print("$EndNodes\n");
  file.print("$Elements\n1 %zu 1 %zu\n3 1 5 %zu\n", n_hexes, n_hexes, n_hexes);
  for (size_t e = 0; e < n_hexes; ++e) {
    const auto& h = mesh.hexes[e];
    file.print("%zu %d %d %d %d %d %d %d %d\n", e + 1, h[0] + 1, h[1] + 1, h[2] + 1, h[3] + 1, h[4] + 1, h[5] + 1,
               h[6] + 1, h[7] + 1);
  }
  file.print("$EndElements\n");
}

// ---------------------------------------------------------------------------------------
// Abaqus INP, a file a deck includes (*INCLUDE, INPUT=...): nodes and C3D8 elements in element
// set SOLID, an element set per part, and for each part's boundary and each patch a node set
// and an element-based surface of the same name. No *HEADING (a deck has one of its own, and
// CalculiX refuses a second), no section or material: those belong to the analysis.

// Integers in lines of 16, the most an Abaqus data line of 256 characters surely holds.
void write_id_lines(OutputFile& file, const std::vector<int>& zero_based_ids) {
  for (size_t i = 0; i < zero_based_ids.size(); ++i)
    file.print(i % 16 == 15 || i + 1 == zero_based_ids.size() ? "%d\n" : "%d,", zero_based_ids[i] + 1);
}

void write_abaqus(const HexMesh& mesh, const MeshSets& sets, OutputFile& file) {
  file.print("** om_dthex hex mesh: %zu nodes, %zu C3D8 elements, %zu parts. Include it in a deck with\n"
             "** *INCLUDE, INPUT=<this file>. Element sets: SOLID (all) and one per part; node sets and\n"
             "** element surfaces of the same name: each part's boundary and each boundary patch.\n",
             mesh.nodes.size(), mesh.hexes.size(), sets.parts.size());
  // 13 significant digits: at most 20 characters a field (CalculiX reads no more), within
  // 5e-14 relative of the double.
  file.print("*NODE\n");
  for (size_t n = 0; n < mesh.nodes.size(); ++n) {
    const Vec3& p = mesh.nodes[n];
    file.print("%zu,%.13g,%.13g,%.13g\n", n + 1, p.x(), p.y(), p.z());
  }
  file.print("*ELEMENT, TYPE=C3D8, ELSET=SOLID\n");
  for (size_t e = 0; e < mesh.hexes.size(); ++e) {
    const auto& h = mesh.hexes[e];
    file.print("%zu,%d,%d,%d,%d,%d,%d,%d,%d\n", e + 1, h[0] + 1, h[1] + 1, h[2] + 1, h[3] + 1, h[4] + 1, h[5] + 1,
               h[6] + 1, h[7] + 1);
  }
  for (const HexSet& part : sets.parts) {
    file.print("*ELSET, ELSET=%s\n", part.name.c_str());
    write_id_lines(file, part.hexes);
  }
  for (const NodeSet& set : sets.node_sets) {
    file.print("*NSET, NSET=%s\n", set.name.c_str());
    write_id_lines(file, set.nodes);
  }
  for (const FaceSet& surface : sets.surfaces) {
    file.print("*SURFACE, NAME=%s, TYPE=ELEMENT\n", surface.name.c_str());
    for (const HexFace& f : surface.faces) file.print("%d,S%d\n", f.hex + 1, f.side + 1);
  }
}

// ---------------------------------------------------------------------------------------
// FEBio 4.0: Mesh/Nodes + Elements type hex8 (VTK corner order), and a SolidDomain for the
// part whose material the user assigns in FEBio Studio.

void write_febio(const HexMesh& mesh, OutputFile& file) {
  file.print("<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n"
             "<febio_spec version=\"4.0\">\n"
             "  <Module type=\"solid\"/>\n"
             "  <Mesh>\n"
             "    <Nodes name=\"Object1\">\n");
  for (size_t n = 0; n < mesh.nodes.size(); ++n) {
    const Vec3& p = mesh.nodes[n];
    file.print("      <node id=\"%zu\">%.17g,%.17g,%.17g</node>\n", n + 1, p.x(), p.y(), p.z());
  }
  file.print("    </Nodes>\n    <Elements type=\"hex8\" name=\"Part1\">\n");
  for (size_t e = 0; e < mesh.hexes.size(); ++e) {
    const auto& h = mesh.hexes[e];
    file.print("      <elem id=\"%zu\">%d,%d,%d,%d,%d,%d,%d,%d</elem>\n", e + 1, h[0] + 1, h[1] + 1, h[2] + 1,
               h[3] + 1, h[4] + 1, h[5] + 1, h[6] + 1, h[7] + 1);
  }
  file.print("    </Elements>\n"
             "  </Mesh>\n"
             "  <MeshDomains>\n"
             "    <SolidDomain name=\"Part1\" mat=\"\"/>\n"
             "  </MeshDomains>\n"
             "</febio_spec>\n");
}

// ---------------------------------------------------------------------------------------
// Exodus II through libexoIIv2c (netCDF classic): one element block "HEX8".

[[noreturn]] void exodus_fail(const std::string& target, const char* call, int status) {
  const char* message = nullptr;
  const char* function = nullptr;
  int error_code = 0;
  ex_get_err(&message, &function, &error_code);
  std::string detail = message && *message ? message : "";
  if (error_code != 0) detail += (detail.empty() ? "" : " ") + std::string("(error code ") + std::to_string(error_code) + ")";
  throw std::runtime_error("writing '" + target + "' failed: Exodus " + call + " returned " + std::to_string(status) +
                           (detail.empty() ? "" : ": " + detail));
}

void write_exodus(const HexMesh& mesh, const std::string& temporary, const std::string& target) {
  ex_opts(0);  // no printing, and never EX_ABORT: library code must not exit the process
  int cpu_word_size = int(sizeof(double)), io_word_size = int(sizeof(double));
  const int exoid = ex_create(temporary.c_str(), EX_CLOBBER, &cpu_word_size, &io_word_size);
  if (exoid < 0) exodus_fail(target, "ex_create", exoid);
  auto check = [&](int status, const char* call) {
    if (status < 0) {  // positive values are warnings
      ex_close(exoid);
      exodus_fail(target, call, status);
    }
  };
  const size_t n_nodes = mesh.nodes.size(), n_hexes = mesh.hexes.size();
  check(ex_put_init(exoid, "om_dthex hex mesh", 3, int64_t(n_nodes), int64_t(n_hexes), 1, 0, 0), "ex_put_init");
  std::vector<double> x(n_nodes), y(n_nodes), z(n_nodes);
  for (size_t n = 0; n < n_nodes; ++n) {
    x[n] = mesh.nodes[n].x();
    y[n] = mesh.nodes[n].y();
    z[n] = mesh.nodes[n].z();
  }
  check(ex_put_coord(exoid, x.data(), y.data(), z.data()), "ex_put_coord");
  char coordinate_names[3][2] = {"x", "y", "z"};
  char* names[3] = {coordinate_names[0], coordinate_names[1], coordinate_names[2]};
  check(ex_put_coord_names(exoid, names), "ex_put_coord_names");
  check(ex_put_elem_block(exoid, 1, "HEX8", int64_t(n_hexes), 8, 0), "ex_put_elem_block");
  std::vector<int> connectivity;
  connectivity.reserve(8 * n_hexes);
  for (const auto& h : mesh.hexes)
    for (int n : h) connectivity.push_back(n + 1);
  check(ex_put_elem_conn(exoid, 1, connectivity.data()), "ex_put_elem_conn");
  const int status = ex_close(exoid);  // netCDF flushes here: a full disk shows up now
  if (status < 0) exodus_fail(target, "ex_close", status);
}

const std::vector<std::pair<std::string, HexFormat>>& extension_table() {
  static const std::vector<std::pair<std::string, HexFormat>> table = {
      {".vtu", HexFormat::Vtu},       {".vtk", HexFormat::Vtk},      {".msh", HexFormat::GmshMsh41},
      {".inp", HexFormat::AbaqusInp}, {".feb", HexFormat::FebioFeb}, {".exo", HexFormat::ExodusII},
      {".e", HexFormat::ExodusII},    {".ex2", HexFormat::ExodusII}};
  return table;
}

}  // namespace

std::vector<std::string> supported_hex_extensions() {
  std::vector<std::string> extensions;
  for (const auto& entry : extension_table()) extensions.push_back(entry.first);
  return extensions;
}

HexFormat hex_format_from_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  for (const auto& [known, format] : extension_table())
    if (ext == known) return format;
  std::string supported;
  for (const auto& known : supported_hex_extensions()) supported += " " + known;
  throw InputError("cannot write hex mesh '" + path + "': unknown extension '" + (ext.empty() ? "(none)" : ext) +
                   "' (supported:" + supported + ")");
}

void write_hex_mesh(const HexMesh& mesh, const std::string& path, const HexFields& fields, const MeshSets* sets) {
  const HexFormat format = hex_format_from_path(path);
  check_mesh(mesh, fields, path);
  write_atomically(path, [&](const std::string& temporary) {
    if (format == HexFormat::ExodusII) {
      write_exodus(mesh, temporary, path);
      return;
    }
    OutputFile file(temporary, path);
    switch (format) {
      case HexFormat::Vtu: write_vtu(mesh, fields, file); break;
      case HexFormat::Vtk: write_legacy_vtk(mesh, fields, file); break;
      case HexFormat::GmshMsh41: write_gmsh(mesh, file); break;
      case HexFormat::AbaqusInp: write_abaqus(mesh, sets ? *sets : find_mesh_sets(mesh), file); break;
      case HexFormat::FebioFeb: write_febio(mesh, file); break;
      case HexFormat::ExodusII: break;
    }
    file.close();
  });
}

}  // namespace dthex
