// SPDX-License-Identifier: MIT
// Dropping small islands (--min-island, off unless asked for): segmentations leave noise
// voxels beside the body, closed surfaces of a few triangles each that would otherwise be
// meshed as bodies of their own. Unlike the safe repairs this removes geometry, so it runs
// only with a threshold the user gives.
#pragma once

#include <dthex/mesh/types.h>

#include <vector>

namespace dthex {

struct RemoveSmallIslandsOptions {
  //! Islands (triangles joined through shared vertices) with fewer triangles than this are
  //! dropped; 0 drops nothing. The largest island is always kept.
  size_t min_triangles = 0;
  //! How many dropped islands the report names.
  size_t examples = 5;
};

struct RemoveSmallIslandsReport {
  size_t islands_dropped = 0;
  size_t triangles_dropped = 0;
  std::vector<int> first_triangles;  //!< the lowest triangle id of each of the first few dropped
  std::vector<Vec3> first_places;    //!< and the centre of that triangle
};

//! Removes the triangles of every island below options.min_triangles (triangles keep their
//! order; vertices are left in place, unused, for verify_surface() to drop). Does nothing
//! when a face index is out of range.
RemoveSmallIslandsReport remove_small_islands(TriSurface& surface, const RemoveSmallIslandsOptions& options);

}  // namespace dthex
