// SPDX-License-Identifier: MIT
// Verifies a surface and also changes it: turns whole components to face outward and drops
// unused vertices. TetGen and the projection stage need a closed, manifold, consistently
// oriented, non-self-intersecting surface, and they fail late and obscurely otherwise. Here
// the first broken rule is reported with ids and coordinates. The repairs of defects within
// a component (coincident vertices, duplicate triangles, reversed triangles) come before it,
// in repair_surface.h.
#pragma once

#include <dthex/mesh/quality.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

namespace dthex {

struct VerifyOptions {
  bool check_self_intersections = true;
  //! Two components (bodies, or a body and its cavity) closer than this fraction of the
  //! bounding-box diagonal are refused; 0 = not checked. TetGen tells facets apart only down
  //! to its relative tolerance (-T, 1e-8) and reports closer ones as a self-intersection
  //! without saying where; 1e-6 leaves a margin of 100 for the coarsening and rounding that
  //! come before it, and is far below any real gap (0.2 micrometres across a 200 mm bone).
  double near_contact_tolerance = 1e-6;
  //! Optional: receives the self-intersection check's search tree when it still fits the
  //! verified surface (no component flipped, no vertex removed), so that a caller who needs
  //! one does not build it again; left empty otherwise.
  std::unique_ptr<TriangleBvh>* search_tree = nullptr;
};

struct SurfaceStats {
  size_t vertices = 0, edges = 0, triangles = 0, components = 0, cavities = 0;
  std::vector<int> component_genus;  //!< per component, from V - E + F = 2 - 2g
  int genus = 0;                     //!< sum over components
  double area = 0, volume = 0, bbox_diagonal = 0;  //!< volume = outer bodies minus cavities
  Eigen::AlignedBox3d bounds;
  size_t flipped_components = 0;      //!< components whose orientation was reversed
  size_t unreferenced_vertices = 0;   //!< vertices used by no triangle, removed
  QualityStats triangle_shape;        //!< Verdict triangle shape
};

//! Checks the surface and refuses it with an InputError "<name>: <rule>: <first offending
//! elements with ids and coordinates>" for the first broken rule, in this order:
//! empty; non-finite coordinates; coordinates beyond +-1e100 (they would overflow later
//! geometry); face index out of range; degenerate triangle (repeated
//! index, coincident corners, or area below 1e-12 of its longest edge squared); duplicate
//! triangles (same vertex set); open surface (an edge of one triangle only) / non-manifold edge (on
//! three or more; open edges are refused first); non-manifold vertex (its triangles form more than one fan);
//! inconsistent orientation within a component; folded edge (the two triangles on an edge
//! whose sides lie under 0.0008 degrees apart, triangle_crossing.h; optional, with the next);
//! self-intersection (optional); zero volume
//! (a component enclosing less than 1e-9 of its bounding-box diagonal cubed); bodies too
//! close (two components nearer than near_contact_tolerance, closest_triangle_pair.h).
//! Each refusal also says how to get past it: an open surface names its holes (count, edges,
//! length and a vertex of each of the first few), a self-intersection the first few pairs
//! and a point of each, bodies too close both components, the gap and where, and the tools.
//! Ids are 0-based indices into the surface as given.
//!
//! Then it repairs, never refuses: vertices used by no triangle are removed (indices
//! compacted, counted in unreferenced_vertices); each component is oriented so that outer
//! boundaries enclose positive volume and cavities (components nested inside an odd
//! number of others, found by the winding number, which unlike ray casting has no
//! degenerate hits) face into the cavity (negative volume).
SurfaceStats verify_surface(TriSurface& surface, const std::string& name, const VerifyOptions& options = {});

}  // namespace dthex
