// SPDX-License-Identifier: MIT
#include <dthex/io/write_hex_mesh.h>

#include <dthex/hexes/mesh_sets.h>
#include <dthex/io/atomic_file.h>
#include <dthex/io/output_file.h>

#include <exodusII.h>

#include <algorithm>
#include <array>
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

//! Refuses sets that do not belong to the mesh: every hex must be in exactly one part (the
//! formats with element blocks need that), every face and node in range.
void check_sets(const HexMesh& mesh, const MeshSets& sets, const std::string& path) {
  const std::string prefix = "cannot write '" + path + "': ";
  std::vector<int> part_count(mesh.hexes.size(), 0);
  for (const HexSet& part : sets.parts)
    for (int h : part.hexes) {
      if (h < 0 || h >= int(mesh.hexes.size()))
        throw InputError(prefix + "part '" + part.name + "' refers to hex " + std::to_string(h));
      ++part_count[size_t(h)];
    }
  for (size_t h = 0; h < part_count.size(); ++h)
    if (part_count[h] != 1)
      throw InputError(prefix + "hex " + std::to_string(h) + " is in " + std::to_string(part_count[h]) +
                       " parts, not one");
  for (const FaceSet& surface : sets.surfaces)
    for (const HexFace& f : surface.faces)
      if (f.hex < 0 || f.hex >= int(mesh.hexes.size()) || f.side < 0 || f.side > 5)
        throw InputError(prefix + "surface '" + surface.name + "' has a face (" + std::to_string(f.hex) + ", " +
                         std::to_string(f.side) + ") outside the mesh");
  for (const NodeSet& set : sets.node_sets)
    for (int n : set.nodes)
      if (n < 0 || n >= int(mesh.nodes.size()))
        throw InputError(prefix + "node set '" + set.name + "' refers to node " + std::to_string(n));
}

//! Each hex's part (0-based index into sets.parts).
std::vector<int> part_of_hexes(const MeshSets& sets, size_t hex_count) {
  std::vector<int> part_of(hex_count, 0);
  for (size_t p = 0; p < sets.parts.size(); ++p)
    for (int h : sets.parts[p].hexes) part_of[size_t(h)] = int(p);
  return part_of;
}

//! The four nodes of a face, in the order whose normal points out of its hex.
std::array<int, 4> outward_face_nodes(const HexMesh& mesh, const HexFace& f) {
  const auto& hex = mesh.hexes[size_t(f.hex)];
  const auto& corners = kHexFaces[size_t(f.side)];
  return {hex[size_t(corners[0])], hex[size_t(corners[1])], hex[size_t(corners[2])], hex[size_t(corners[3])]};
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

//! The cells of a VTU or legacy VTK file: the hexes, then (HexWriteOptions::vtk_face_set_cells)
//! each face set's faces as quads, corners in outward order. A quad carries the cell data of the
//! hex it is a face of, part 0, and its face set's 1-based index in the array "face_set" (0 on the
//! hexes), so that thresholding "part" >= 1 or "face_set" >= 1 separates the two.
struct VtkCells {
  std::vector<int> part_of;              //!< each hex's 0-based part
  bool face_set_cells = false;           //!< the quads and "face_set" are written
  std::vector<std::array<int, 4>> quads;
  std::vector<int> quad_hex, quad_set;   //!< each quad's hex and 0-based face set
};

VtkCells vtk_cells(const HexMesh& mesh, const MeshSets& sets, bool face_set_cells) {
  VtkCells cells;
  cells.part_of = part_of_hexes(sets, mesh.hexes.size());
  cells.face_set_cells = face_set_cells;
  if (face_set_cells)
    for (size_t s = 0; s < sets.surfaces.size(); ++s)
      for (const HexFace& f : sets.surfaces[s].faces) {
        cells.quads.push_back(outward_face_nodes(mesh, f));
        cells.quad_hex.push_back(f.hex);
        cells.quad_set.push_back(int(s));
      }
  return cells;
}

void write_vtu(const HexMesh& mesh, const HexFields& fields, const VtkCells& vc, OutputFile& file) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 must be three packed doubles");
  const size_t n_nodes = mesh.nodes.size(), n_hexes = mesh.hexes.size(), n_quads = vc.quads.size();
  const size_t n_cells = n_hexes + n_quads;

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
                         n_cells * sizeof(double), [&values, &vc, n_quads](OutputFile& f) {
                           f.write(values.data(), values.size() * sizeof(double));
                           write_converted<double>(f, n_quads, [&](size_t q, std::vector<double>& out) {
                             out.push_back(values[size_t(vc.quad_hex[q])]);
                           });
                         }});
  };
  add_field(fields.shape, "shape");
  add_field(fields.scaled_jacobian, "scaled_jacobian");
  cell_data.push_back({R"(<DataArray type="Int32" Name="part" format="appended")", n_cells * sizeof(int32_t),
                       [&](OutputFile& f) {
                         write_converted<int32_t>(f, n_cells, [&](size_t c, std::vector<int32_t>& out) {
                           out.push_back(c < n_hexes ? int32_t(vc.part_of[c] + 1) : 0);
                         });
                       }});
  if (vc.face_set_cells)
    cell_data.push_back({R"(<DataArray type="Int32" Name="face_set" format="appended")", n_cells * sizeof(int32_t),
                         [&](OutputFile& f) {
                           write_converted<int32_t>(f, n_cells, [&](size_t c, std::vector<int32_t>& out) {
                             out.push_back(c < n_hexes ? 0 : int32_t(vc.quad_set[c - n_hexes] + 1));
                           });
                         }});
  points.push_back({R"(<DataArray type="Float64" Name="Points" NumberOfComponents="3" format="appended")",
                    n_nodes * 3 * sizeof(double),
                    [&](OutputFile& f) { f.write(mesh.nodes.data(), n_nodes * sizeof(Vec3)); }});
  cells.push_back({R"(<DataArray type="Int64" Name="connectivity" format="appended")",
                   (n_hexes * 8 + n_quads * 4) * sizeof(int64_t), [&](OutputFile& f) {
                     write_converted<int64_t>(f, n_hexes, [&](size_t h, std::vector<int64_t>& out) {
                       for (int n : mesh.hexes[h]) out.push_back(n);
                     });
                     write_converted<int64_t>(f, n_quads, [&](size_t q, std::vector<int64_t>& out) {
                       for (int n : vc.quads[q]) out.push_back(n);
                     });
                   }});
  cells.push_back({R"(<DataArray type="Int64" Name="offsets" format="appended")", n_cells * sizeof(int64_t),
                   [&](OutputFile& f) {
                     write_converted<int64_t>(f, n_cells, [n_hexes](size_t c, std::vector<int64_t>& out) {
                       out.push_back(c < n_hexes ? int64_t(8 * (c + 1)) : int64_t(8 * n_hexes + 4 * (c + 1 - n_hexes)));
                     });
                   }});
  cells.push_back({R"(<DataArray type="UInt8" Name="types" format="appended")", n_cells, [&](OutputFile& f) {
                     write_converted<uint8_t>(f, n_cells, [n_hexes](size_t c, std::vector<uint8_t>& out) {
                       out.push_back(c < n_hexes ? 12 : 9);  // VTK_HEXAHEDRON, VTK_QUAD
                     });
                   }});

  file.print("<?xml version=\"1.0\"?>\n"
             "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"%s\" header_type=\"UInt64\">\n"
             "  <UnstructuredGrid>\n"
             "    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n",
             host_is_little_endian() ? "LittleEndian" : "BigEndian", n_nodes, n_cells);
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

void write_legacy_vtk(const HexMesh& mesh, const HexFields& fields, const VtkCells& vc, OutputFile& file) {
  const size_t n_nodes = mesh.nodes.size(), n_hexes = mesh.hexes.size(), n_quads = vc.quads.size();
  const size_t n_cells = n_hexes + n_quads;
  file.print("# vtk DataFile Version 3.0\nom_dthex hex mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n");
  file.print("POINTS %zu double\n", n_nodes);
  for (const Vec3& p : mesh.nodes) file.print("%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  file.print("CELLS %zu %zu\n", n_cells, 9 * n_hexes + 5 * n_quads);
  for (const auto& h : mesh.hexes)
    file.print("8 %d %d %d %d %d %d %d %d\n", h[0], h[1], h[2], h[3], h[4], h[5], h[6], h[7]);
  for (const auto& q : vc.quads) file.print("4 %d %d %d %d\n", q[0], q[1], q[2], q[3]);
  file.print("CELL_TYPES %zu\n", n_cells);
  for (size_t h = 0; h < n_hexes; ++h) file.print("12\n");
  for (size_t q = 0; q < n_quads; ++q) file.print("9\n");
  // FIELD rather than SCALARS: VTK's legacy reader loads only the first SCALARS array
  // unless told otherwise, but every array of a FIELD.
  std::vector<std::pair<const std::vector<double>*, const char*>> arrays;
  if (!fields.shape.empty()) arrays.emplace_back(&fields.shape, "shape");
  if (!fields.scaled_jacobian.empty()) arrays.emplace_back(&fields.scaled_jacobian, "scaled_jacobian");
  file.print("CELL_DATA %zu\nFIELD FieldData %zu\n", n_cells, arrays.size() + (vc.face_set_cells ? 2 : 1));
  for (const auto& [values, name] : arrays) {
    file.print("%s 1 %zu double\n", name, n_cells);
    for (double v : *values) file.print("%.17g\n", v);
    for (int h : vc.quad_hex) file.print("%.17g\n", (*values)[size_t(h)]);
  }
  file.print("part 1 %zu int\n", n_cells);
  for (int p : vc.part_of) file.print("%d\n", p + 1);
  for (size_t q = 0; q < n_quads; ++q) file.print("0\n");
  if (vc.face_set_cells) {
    file.print("face_set 1 %zu int\n", n_cells);
    for (size_t h = 0; h < n_hexes; ++h) file.print("0\n");
    for (int set : vc.quad_set) file.print("%d\n", set + 1);
  }
  if (!mesh.boundary_facet.empty()) {
    file.print("POINT_DATA %zu\nSCALARS boundary int 1\nLOOKUP_TABLE default\n", n_nodes);
    for (size_t n = 0; n < n_nodes; ++n) file.print("%d\n", mesh.is_boundary_node(int(n)) ? 1 : 0);
  }
}

// ---------------------------------------------------------------------------------------
// Gmsh MSH 4.1 or 2.2 ASCII. Physical volume i+1 "bodyN" is part i, its hexes (type 5, VTK's
// corner numbering) in volume entity i+1; physical surface j+1 is face set j, its faces as
// quadrangles (type 3) in surface entity j+1. Physical tags are per dimension in Gmsh, so a
// volume and a surface may share a number. All nodes are listed in the block of volume 1 (each
// node is listed once; elements of any entity refer to nodes by tag). Hex h has tag h + 1, the
// quadrangles follow from hex count + 1 in set order.

void write_gmsh_physical_names(const MeshSets& sets, OutputFile& file) {
  file.print("$PhysicalNames\n%zu\n", sets.parts.size() + sets.surfaces.size());
  for (size_t p = 0; p < sets.parts.size(); ++p) file.print("3 %zu \"%s\"\n", p + 1, sets.parts[p].name.c_str());
  for (size_t s = 0; s < sets.surfaces.size(); ++s)
    file.print("2 %zu \"%s\"\n", s + 1, sets.surfaces[s].name.c_str());
  file.print("$EndPhysicalNames\n");
}

void write_gmsh41(const HexMesh& mesh, const MeshSets& sets, OutputFile& file) {
  const size_t n_nodes = mesh.nodes.size(), n_hexes = mesh.hexes.size();
  auto print_box = [&](const auto& node_lists) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& nodes : node_lists)
      for (int n : nodes) {
        lo = lo.cwiseMin(mesh.nodes[size_t(n)]);
        hi = hi.cwiseMax(mesh.nodes[size_t(n)]);
      }
    file.print("%.17g %.17g %.17g %.17g %.17g %.17g", lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
  };
  file.print("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
  write_gmsh_physical_names(sets, file);
  file.print("$Entities\n0 0 %zu %zu\n", sets.surfaces.size(), sets.parts.size());
  size_t n_quads = 0;
  for (size_t s = 0; s < sets.surfaces.size(); ++s) {
    std::vector<std::array<int, 4>> faces;
    for (const HexFace& f : sets.surfaces[s].faces) faces.push_back(outward_face_nodes(mesh, f));
    n_quads += faces.size();
    file.print("%zu ", s + 1);
    print_box(faces);
    file.print(" 1 %zu 0\n", s + 1);
  }
  for (size_t p = 0; p < sets.parts.size(); ++p) {
    std::vector<std::array<int, 8>> hexes;
    for (int h : sets.parts[p].hexes) hexes.push_back(mesh.hexes[size_t(h)]);
    file.print("%zu ", p + 1);
    print_box(hexes);
    file.print(" 1 %zu 0\n", p + 1);
  }
  file.print("$EndEntities\n");
  file.print("$Nodes\n1 %zu 1 %zu\n3 1 0 %zu\n", n_nodes, n_nodes, n_nodes);
  for (size_t n = 0; n < n_nodes; ++n) file.print("%zu\n", n + 1);
  for (const Vec3& p : mesh.nodes) file.print("%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  file.print("$EndNodes\n");
  const size_t n_elements = n_hexes + n_quads;
  file.print("$Elements\n%zu %zu 1 %zu\n", sets.parts.size() + sets.surfaces.size(), n_elements, n_elements);
  for (size_t p = 0; p < sets.parts.size(); ++p) {
    file.print("3 %zu 5 %zu\n", p + 1, sets.parts[p].hexes.size());
    for (int e : sets.parts[p].hexes) {
      const auto& h = mesh.hexes[size_t(e)];
      file.print("%d %d %d %d %d %d %d %d %d\n", e + 1, h[0] + 1, h[1] + 1, h[2] + 1, h[3] + 1, h[4] + 1, h[5] + 1,
                 h[6] + 1, h[7] + 1);
    }
  }
  size_t tag = n_hexes;
  for (size_t s = 0; s < sets.surfaces.size(); ++s) {
    file.print("2 %zu 3 %zu\n", s + 1, sets.surfaces[s].faces.size());
    for (const HexFace& f : sets.surfaces[s].faces) {
      const auto q = outward_face_nodes(mesh, f);
      file.print("%zu %d %d %d %d\n", ++tag, q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
    }
  }
  file.print("$EndElements\n");
}

// MSH 2.2: each element line carries two tags, its physical group and its elementary entity.
void write_gmsh22(const HexMesh& mesh, const MeshSets& sets, OutputFile& file) {
  const size_t n_nodes = mesh.nodes.size(), n_hexes = mesh.hexes.size();
  file.print("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
  write_gmsh_physical_names(sets, file);
  file.print("$Nodes\n%zu\n", n_nodes);
  for (size_t n = 0; n < n_nodes; ++n) {
    const Vec3& p = mesh.nodes[n];
    file.print("%zu %.17g %.17g %.17g\n", n + 1, p.x(), p.y(), p.z());
  }
  file.print("$EndNodes\n");
  size_t n_quads = 0;
  for (const FaceSet& surface : sets.surfaces) n_quads += surface.faces.size();
  file.print("$Elements\n%zu\n", n_hexes + n_quads);
  for (size_t p = 0; p < sets.parts.size(); ++p)
    for (int e : sets.parts[p].hexes) {
      const auto& h = mesh.hexes[size_t(e)];
      file.print("%d 5 2 %zu %zu %d %d %d %d %d %d %d %d\n", e + 1, p + 1, p + 1, h[0] + 1, h[1] + 1, h[2] + 1,
                 h[3] + 1, h[4] + 1, h[5] + 1, h[6] + 1, h[7] + 1);
    }
  size_t tag = n_hexes;
  for (size_t s = 0; s < sets.surfaces.size(); ++s)
    for (const HexFace& f : sets.surfaces[s].faces) {
      const auto q = outward_face_nodes(mesh, f);
      file.print("%zu 3 2 %zu %zu %d %d %d %d\n", ++tag, s + 1, s + 1, q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
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
// FEBio 4.0: Mesh/Nodes, an Elements type hex8 (VTK corner order) per part, a NodeSet per node
// set, a Surface of quad4 facets (outward, right-hand rule) per face set, and a SolidDomain per
// part whose material the user assigns in FEBio Studio.

void write_febio(const HexMesh& mesh, const MeshSets& sets, OutputFile& file) {
  file.print("<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n"
             "<febio_spec version=\"4.0\">\n"
             "  <Module type=\"solid\"/>\n"
             "  <Mesh>\n"
             "    <Nodes name=\"Object1\">\n");
  for (size_t n = 0; n < mesh.nodes.size(); ++n) {
    const Vec3& p = mesh.nodes[n];
    file.print("      <node id=\"%zu\">%.17g,%.17g,%.17g</node>\n", n + 1, p.x(), p.y(), p.z());
  }
  file.print("    </Nodes>\n");
  for (const HexSet& part : sets.parts) {
    file.print("    <Elements type=\"hex8\" name=\"%s\">\n", part.name.c_str());
    for (int e : part.hexes) {
      const auto& h = mesh.hexes[size_t(e)];
      file.print("      <elem id=\"%d\">%d,%d,%d,%d,%d,%d,%d,%d</elem>\n", e + 1, h[0] + 1, h[1] + 1, h[2] + 1,
                 h[3] + 1, h[4] + 1, h[5] + 1, h[6] + 1, h[7] + 1);
    }
    file.print("    </Elements>\n");
  }
  for (const NodeSet& set : sets.node_sets) {
    file.print("    <NodeSet name=\"%s\">", set.name.c_str());
    for (size_t i = 0; i < set.nodes.size(); ++i) file.print(i == 0 ? "%d" : ",%d", set.nodes[i] + 1);
    file.print("</NodeSet>\n");
  }
  for (const FaceSet& surface : sets.surfaces) {
    file.print("    <Surface name=\"%s\">\n", surface.name.c_str());
    for (size_t i = 0; i < surface.faces.size(); ++i) {
      const auto q = outward_face_nodes(mesh, surface.faces[i]);
      file.print("      <quad4 id=\"%zu\">%d,%d,%d,%d</quad4>\n", i + 1, q[0] + 1, q[1] + 1, q[2] + 1, q[3] + 1);
    }
    file.print("    </Surface>\n");
  }
  file.print("  </Mesh>\n  <MeshDomains>\n");
  for (const HexSet& part : sets.parts) file.print("    <SolidDomain name=\"%s\" mat=\"\"/>\n", part.name.c_str());
  file.print("  </MeshDomains>\n</febio_spec>\n");
}

// ---------------------------------------------------------------------------------------
// Exodus II through libexoIIv2c (netCDF classic): an element block "HEX8" per part, named node
// sets and side sets.

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

// Exodus numbers the sides of a HEX8 differently from Abaqus: Exodus side k is Abaqus
// S(((k + 1) mod 6) + 1), so Abaqus side s (0-based) is Exodus side kExodusSideOfAbaqusSide[s].
// Both list the same four corners for the face.
constexpr std::array<int, 6> kExodusSideOfAbaqusSide = {5, 6, 1, 2, 3, 4};

void write_exodus(const HexMesh& mesh, const MeshSets& sets, const std::string& temporary, const std::string& target) {
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
  // Names longer than Exodus's default 32 characters would be truncated (a user's --set name).
  size_t longest_name = 0;
  for (const HexSet& part : sets.parts) longest_name = std::max(longest_name, part.name.size());
  for (const FaceSet& surface : sets.surfaces) longest_name = std::max(longest_name, surface.name.size());
  for (const NodeSet& set : sets.node_sets) longest_name = std::max(longest_name, set.name.size());
  if (longest_name > 32) check(ex_set_max_name_length(exoid, int(longest_name)), "ex_set_max_name_length");
  const size_t n_nodes = mesh.nodes.size(), n_hexes = mesh.hexes.size();
  check(ex_put_init(exoid, "om_dthex hex mesh", 3, int64_t(n_nodes), int64_t(n_hexes), int64_t(sets.parts.size()),
                    int64_t(sets.node_sets.size()), int64_t(sets.surfaces.size())),
        "ex_put_init");
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
  // Block p+1 holds part p's hexes; the element number of hex h is its place in the blocks.
  std::vector<int> element_of(n_hexes, 0), id_map;
  bool identity = true;
  for (size_t p = 0; p < sets.parts.size(); ++p) {
    const std::vector<int>& hexes = sets.parts[p].hexes;
    check(ex_put_elem_block(exoid, int64_t(p + 1), "HEX8", int64_t(hexes.size()), 8, 0), "ex_put_elem_block");
    std::vector<int> connectivity;
    connectivity.reserve(8 * hexes.size());
    for (int h : hexes) {
      for (int n : mesh.hexes[size_t(h)]) connectivity.push_back(n + 1);
      id_map.push_back(h + 1);
      element_of[size_t(h)] = int(id_map.size());
      identity = identity && element_of[size_t(h)] == h + 1;
    }
    check(ex_put_elem_conn(exoid, int64_t(p + 1), connectivity.data()), "ex_put_elem_conn");
  }
  if (!identity) check(ex_put_id_map(exoid, EX_ELEM_MAP, id_map.data()), "ex_put_id_map");
  auto put_names = [&](ex_entity_type type, const auto& named) {
    if (named.empty()) return;
    std::vector<std::vector<char>> storage;
    std::vector<char*> pointers;
    for (const auto& item : named) {
      storage.emplace_back(item.name.begin(), item.name.end());
      storage.back().push_back('\0');
    }
    for (auto& name : storage) pointers.push_back(name.data());
    check(ex_put_names(exoid, type, pointers.data()), "ex_put_names");
  };
  put_names(EX_ELEM_BLOCK, sets.parts);
  for (size_t s = 0; s < sets.node_sets.size(); ++s) {
    std::vector<int> nodes;
    for (int n : sets.node_sets[s].nodes) nodes.push_back(n + 1);
    check(ex_put_set_param(exoid, EX_NODE_SET, int64_t(s + 1), int64_t(nodes.size()), 0), "ex_put_set_param");
    check(ex_put_set(exoid, EX_NODE_SET, int64_t(s + 1), nodes.data(), nullptr), "ex_put_set");
  }
  put_names(EX_NODE_SET, sets.node_sets);
  for (size_t s = 0; s < sets.surfaces.size(); ++s) {
    std::vector<int> elements, sides;
    for (const HexFace& f : sets.surfaces[s].faces) {
      elements.push_back(element_of[size_t(f.hex)]);
      sides.push_back(kExodusSideOfAbaqusSide[size_t(f.side)]);
    }
    check(ex_put_set_param(exoid, EX_SIDE_SET, int64_t(s + 1), int64_t(elements.size()), 0), "ex_put_set_param");
    check(ex_put_set(exoid, EX_SIDE_SET, int64_t(s + 1), elements.data(), sides.data()), "ex_put_set");
  }
  put_names(EX_SIDE_SET, sets.surfaces);
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

void write_hex_mesh(const HexMesh& mesh, const std::string& path, const HexFields& fields, const MeshSets* sets,
                    const HexWriteOptions& options) {
  const HexFormat format = hex_format_from_path(path);
  check_mesh(mesh, fields, path);
  MeshSets found;
  if (!sets) found = find_mesh_sets(mesh);
  const MeshSets& named = sets ? *sets : found;
  check_sets(mesh, named, path);
  write_atomically(path, [&](const std::string& temporary) {
    if (format == HexFormat::ExodusII) {
      write_exodus(mesh, named, temporary, path);
      return;
    }
    OutputFile file(temporary, path);
    switch (format) {
      case HexFormat::Vtu: write_vtu(mesh, fields, vtk_cells(mesh, named, options.vtk_face_set_cells), file); break;
      case HexFormat::Vtk:
        write_legacy_vtk(mesh, fields, vtk_cells(mesh, named, options.vtk_face_set_cells), file);
        break;
      case HexFormat::GmshMsh41:
        if (options.msh_version == HexWriteOptions::MshVersion::V22) write_gmsh22(mesh, named, file);
        else write_gmsh41(mesh, named, file);
        break;
      case HexFormat::AbaqusInp: write_abaqus(mesh, named, file); break;
      case HexFormat::FebioFeb: write_febio(mesh, named, file); break;
      case HexFormat::ExodusII: break;
    }
    file.close();
  });
}

}  // namespace dthex
