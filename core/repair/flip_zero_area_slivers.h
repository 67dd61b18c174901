// SPDX-License-Identifier: MIT
// Flipping zero-area slivers away (one of the safe repairs, repair_surface.h): exporters and
// mesh booleans leave triangles whose three distinct corners lie on a line, which
// verify_surface() refuses as degenerate. Removing such a triangle would open a crack, but
// flipping its longest edge with the neighbour across it does not: the sliver's middle
// corner lies on that edge, so the two new triangles split the neighbour at that corner and
// cover exactly what it covered. The surface stays closed and manifold, the shape unchanged.
#pragma once

#include <dthex/mesh/triangle_crossing.h>  // has_zero_area, the test this repair flips away
#include <dthex/mesh/types.h>

#include <vector>

namespace dthex {

struct FlipZeroAreaSliversOptions {
  //! How many flipped slivers the report names.
  size_t examples = 5;
};

struct FlipZeroAreaSliversReport {
  size_t slivers_flipped = 0;
  std::vector<int> first_flipped;    //!< the first few, ids into the surface (unchanged by the flips)
  std::vector<Vec3> first_places;    //!< and the middle corner of each
  //! Slivers found but left in place: the flip would create an edge that exists already, or a
  //! new triangle that is itself degenerate (verify_surface() then refuses the surface).
  size_t left_in_place = 0;
};

//! Zero area is verify_surface()'s test: the cross product of two edges at most 1e-12 of the
//! longest edge squared. On a surface where every edge belongs to exactly two triangles that
//! traverse it in opposite directions (after repair_orientation()), each sliver (a, b, c)
//! with longest edge ab and the triangle (b, a, d) across it become (c, a, d) and (d, b, c),
//! in place of the two: no triangle is added or removed, and ids stay. A flip is made only
//! when the edge cd does not exist yet and neither new triangle has zero area; slivers
//! whose neighbour is a sliver too are retried once the neighbour has been flipped. Changes
//! nothing when a face index is out of range, a triangle repeats a vertex or an edge is not
//! on exactly two triangles.
FlipZeroAreaSliversReport flip_zero_area_slivers(TriSurface& surface, const FlipZeroAreaSliversOptions& options = {});

}  // namespace dthex
