// SPDX-License-Identifier: MIT
// Boundary faces that lie inside the mesh: a geometric defect the combinatorial checks of
// check_conformity() cannot see. A hex mesh whose boundary folds back into its own volume
// (after projection onto a thin or sharply bent surface) has every face shared by at most two
// hexes and a closed, oriented boundary, yet some of its volume is covered twice and a solver
// sees overlapping elements. The Verdict-based referee script (hexeval) probes for exactly
// this; so do we (docs/METHOD.md section 8, Measurement and output).
#pragma once

#include <dthex/mesh/types.h>

#include <array>
#include <vector>

namespace dthex {

struct BoundaryOverlapOptions {
  //! How far outside a boundary face its probe point goes, as a fraction of the square root
  //! of the face's area: far enough to leave the face's own hex, near enough to stay in the
  //! gap before any neighbour. 0.01 is the referee's choice.
  double probe_offset = 0.01;
  //! Parametric tolerance of the point-in-hex test ([-tol, 1 + tol] counts as inside). At
  //! 0 the count agrees with the referee's; VTK's own 1e-3 also counts probes just outside a
  //! hex.
  double parametric_tolerance = 0;
};

struct BoundaryOverlapReport {
  size_t faces_inside = 0;  //!< boundary quads whose probe point lies inside some hex
  int first_face = -1;      //!< the lowest such quad index, -1 when none
  int first_hex = -1;       //!< a hex that holds its probe point
  Vec3 first_point = Vec3::Zero();  //!< the probe point of first_face
  //! Every such quad (ascending) and, at the same position, the hex that holds its probe.
  std::vector<int> faces, hexes;
};

//! For each boundary quad (outward rings, as boundary_quads() returns them), pushes its centre
//! a little along its outward normal and asks whether that point lies inside any hex of the
//! mesh (trilinear map inverted by Newton's method; hexes found through a uniform grid of their
//! bounding boxes). Quads of inverted hexes point inward, so their normal is turned round:
//! inversion is counted elsewhere, this test stays purely geometric. `owner[i]` is the hex of
//! quad i; when empty, the owners are taken as unknown and every normal as outward.
BoundaryOverlapReport find_boundary_faces_inside(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads,
                                                 const std::vector<int>& owner = {},
                                                 const BoundaryOverlapOptions& options = {});

//! The probe point of boundary quad `quad` of hex `owner` (-1: unknown, the ring taken as
//! outward): its centre pushed options.probe_offset * sqrt(area) along its outward normal.
//! False for a degenerate quad, which has no probe.
bool boundary_probe_point(const HexMesh& mesh, const std::array<int, 4>& quad, int owner,
                          const BoundaryOverlapOptions& options, Vec3& probe);

//! Whether `p` lies inside the trilinear hex with corners `corner` (VTK order), with the
//! given parametric tolerance; the parametric coordinates go to `rst` when given.
bool point_in_hex(const std::array<Vec3, 8>& corner, const Vec3& p, double parametric_tolerance,
                  Vec3* rst = nullptr);

}  // namespace dthex
