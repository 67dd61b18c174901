// SPDX-License-Identifier: MIT
// Consistent orientation within each component (one of the safe repairs, repair_surface.h):
// a triangle wound the other way looks fine in any viewer, but TetGen and the volume
// measures need every triangle of a component to agree with its neighbours. Turning a
// triangle (reversing its corners) does not move it, so the shape is unchanged.
#pragma once

#include <dthex/mesh/types.h>

#include <vector>

namespace dthex {

struct RepairOrientationOptions {
  //! How many turned triangles the report names.
  size_t examples = 5;
};

struct RepairOrientationReport {
  size_t triangles_turned = 0;
  size_t components_repaired = 0;  //!< components in which a triangle was turned
  std::vector<int> first_turned;   //!< the first few turned, ids into the surface as given
  //! Components that no choice of orientation makes consistent (a Moebius strip or Klein
  //! bottle), left as they were for verify_surface() to refuse.
  size_t non_orientable_components = 0;
  //! Nothing was done: an edge is not shared by exactly two triangles, a triangle repeats
  //! a vertex or an index is out of range (verify_surface() then refuses the surface).
  bool skipped_not_manifold = false;
};

//! On a surface where every edge belongs to exactly two triangles, splits each component
//! (triangles joined across edges) into the two classes whose members agree with their
//! neighbours, and turns the class with fewer triangles (ties: smaller area, then the class
//! without the component's lowest-id triangle) by swapping its second and third corners.
//! A single reversed triangle is thus turned back. Which way the component faces (outward or
//! into a cavity) is left to verify_surface(). Changes nothing otherwise.
RepairOrientationReport repair_orientation(TriSurface& surface, const RepairOrientationOptions& options = {});

}  // namespace dthex
