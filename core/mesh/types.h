// SPDX-License-Identifier: MIT
// The plain value types every stage of om_dthex shares.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace dthex {

using Vec3 = Eigen::Vector3d;

//! An indexed triangle surface: what readers return, what verification checks,
//! what TetGen gets. Triangles are counter-clockwise seen from outside once verified.
struct TriSurface {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
};

//! An all-hex mesh: node coordinates and 8-node connectivity in VTK order
//! (bottom 0-1-2-3 counter-clockwise seen from the top, top 4-5-6-7 above).
struct HexMesh {
  std::vector<Vec3> nodes;
  std::vector<std::array<int, 8>> hexes;
  //! Per node: -1 for an interior node, otherwise the index of a triangle of the
  //! surface the volume was built from (the coarse surface) that the node lies on.
  //! Empty when the producer does not track it.
  std::vector<int> boundary_facet;
  //! Per hex: its material region (0, 1, ...: a closed surface inside another, meshed as a
  //! second material); the faces between two regions are an interface whose nodes, like the
  //! boundary's, carry a boundary_facet. Empty: one region.
  std::vector<int> region;

  bool is_boundary_node(int n) const {
    return !boundary_facet.empty() && boundary_facet[size_t(n)] >= 0;
  }
};

//! A tetrahedral mesh as TetGen returns it: positively oriented tets.
struct TetMesh {
  std::vector<Vec3> points;
  std::vector<std::array<int, 4>> tets;
  //! Boundary triangles (indices into points), outward oriented, and for each the
  //! index of the input surface triangle it came from.
  std::vector<std::array<int, 3>> boundary_faces;
  std::vector<int> boundary_face_source;
  //! Per tet: its material region, as HexMesh::region (TetgenOptions::keep_nested_regions);
  //! region 0 is the shallowest. Empty: one region.
  std::vector<int> tet_region;
};

//! Bad input or usage: the command exits with code 2.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

//! A meshing stage failed on valid input (TetGen refused, untangling failed in
//! strict mode, a time limit): the command exits with code 3.
struct MeshingError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace dthex
