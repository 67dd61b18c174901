// SPDX-License-Identifier: MIT
// hex_quality: the figures om_dthex reports for its own mesh, measured on any hex mesh, so a
// published mesh and ours are judged by the same code (core/mesh/quality.h, core/hexes/
// conformity.h, core/surface/surface_distance.h). tools/benchmark.sh runs it on both sides of
// its comparison with published meshes.
//
// Usage: hex_quality MESH.vtk SURFACE
//   MESH.vtk  legacy ASCII VTK unstructured grid (format 2.0-4.2: "CELLS n size" with a count
//             before each cell's ids); only its hexahedra (cell type 12) are read, other cells
//             (boundary quads) and nodes no hex uses are dropped
//   SURFACE   the input surface the mesh was made of (.off .obj .stl .ply), read and verified as
//             om_dthex does (with the safe repairs)
// Prints one JSON object: nodes, hexes, shape and scaled Jacobian statistics, inverted hexes,
// conformity, Hausdorff distance (input units and % of the surface's bounding-box diagonal),
// volumes (and the hexes' volume error in % of the surface's). Exit 0, or 2 with a message on
// a file it cannot read.
#include <dthex/hexes/conformity.h>
#include <dthex/mesh/quality.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/pipeline/pipeline.h>
#include <dthex/surface/surface_distance.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace {

// The hexes of a legacy ASCII VTK unstructured grid, their nodes renumbered densely.
dthex::HexMesh read_legacy_vtk_hexes(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open '" + path + "'");
  std::string line;
  for (int i = 0; i < 3 && std::getline(in, line); ++i)
    if (i == 2 && line.rfind("ASCII", 0) != 0) throw std::runtime_error(path + ": not an ASCII legacy VTK file");
  std::vector<dthex::Vec3> points;
  std::vector<std::vector<long>> cells;
  std::vector<int> types;
  std::string word;
  while (in >> word) {
    if (word == "POINTS") {
      size_t n;
      std::string type;
      in >> n >> type;
      points.resize(n);
      for (auto& p : points) in >> p.x() >> p.y() >> p.z();
    } else if (word == "CELLS") {
      size_t n, size;
      in >> n >> size;
      cells.resize(n);
      for (auto& c : cells) {
        size_t count;
        in >> count;
        c.resize(count);
        for (long& v : c) in >> v;
      }
    } else if (word == "CELL_TYPES") {
      size_t n;
      in >> n;
      types.resize(n);
      for (int& t : types) in >> t;
      break;  // the cell and point data that follow are not needed
    } else if (word == "OFFSETS" || word == "CONNECTIVITY") {
      throw std::runtime_error(path + ": legacy VTK 5.x cell arrays are not read; write version 4.2");
    }
    if (!in) throw std::runtime_error(path + ": truncated or malformed after " + word);
  }
  if (types.size() != cells.size()) throw std::runtime_error(path + ": CELLS and CELL_TYPES disagree");
  dthex::HexMesh mesh;
  std::vector<int> new_id(points.size(), -1);
  for (size_t c = 0; c < cells.size(); ++c) {
    if (types[c] != 12) continue;
    if (cells[c].size() != 8) throw std::runtime_error(path + ": hexahedron " + std::to_string(c) + " has not 8 nodes");
    std::array<int, 8> hex{};
    for (int k = 0; k < 8; ++k) {
      const long v = cells[c][size_t(k)];
      if (v < 0 || size_t(v) >= points.size()) throw std::runtime_error(path + ": node id out of range");
      if (new_id[size_t(v)] < 0) {
        new_id[size_t(v)] = int(mesh.nodes.size());
        mesh.nodes.push_back(points[size_t(v)]);
      }
      hex[size_t(k)] = new_id[size_t(v)];
    }
    mesh.hexes.push_back(hex);
  }
  if (mesh.hexes.empty()) throw std::runtime_error(path + ": no hexahedra");
  return mesh;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: hex_quality MESH.vtk SURFACE\n");
    return 2;
  }
  try {
    const dthex::HexMesh mesh = read_legacy_vtk_hexes(argv[1]);
    dthex::Progress quiet(dthex::Progress::Mode::Quiet);
    const dthex::PipelineResult input = dthex::read_and_verify(argv[2], quiet);
    const dthex::TriangleBvh input_bvh(input.input);

    const dthex::HexQuality quality = dthex::measure_hex_quality(mesh);
    std::vector<std::array<int, 4>> quads;
    const dthex::ConformityReport conformity = dthex::check_conformity(mesh, &quads);
    const dthex::TriSurface boundary = dthex::quads_to_triangles(mesh.nodes, quads);
    const dthex::TriangleBvh boundary_bvh(boundary);
    const dthex::SurfaceDistance distance = dthex::surface_distance(boundary, boundary_bvh, input.input, input_bvh);
    const double hex_volume = dthex::enclosed_volume(boundary);
    const double diagonal = input.input_summary.bbox_diagonal, volume = input.input_summary.volume;

    const auto stats = [](const dthex::QualityStats& s) {
      return nlohmann::json{{"avg", s.avg}, {"std", s.std_dev}, {"min", s.min}, {"max", s.max}};
    };
    const nlohmann::json j = {
        {"mesh", argv[1]},
        {"surface", argv[2]},
        {"nodes", mesh.nodes.size()},
        {"hexes", mesh.hexes.size()},
        {"shape", stats(quality.shape_stats)},
        {"scaled_jacobian", stats(quality.scaled_jacobian_stats)},
        {"inverted", quality.inverted},
        {"below_0_2", quality.below_0_2},
        {"gauss_scaled_jacobian_min", quality.gauss_scaled_jacobian_min},
        {"conforming", conformity.conforming()},
        {"hausdorff", distance.hausdorff},
        {"hausdorff_pct_diagonal", diagonal > 0 ? 100 * distance.hausdorff / diagonal : 0.0},
        {"mean_distance", distance.mean},
        {"bbox_diagonal", diagonal},
        {"volume", hex_volume},
        {"surface_volume", volume},
        {"volume_pct", volume != 0 ? 100 * (hex_volume - volume) / volume : 0.0}};
    std::cout << j.dump(2) << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hex_quality: %s\n", e.what());
    return 2;
  }
}
