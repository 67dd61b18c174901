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
  //! Closed islands enclosing less than this fraction of the volume of the largest one (by
  //! volume) are dropped too; 0 drops nothing. Unlike a triangle count it does not depend on
  //! how finely the file was triangulated. An island that is not closed and manifold, or not
  //! orientable, has no volume and is kept (verification refuses it); a small cavity is an
  //! island too and is filled.
  double min_volume_fraction = 0;
  //! How many dropped islands the report names.
  size_t examples = 5;
};

struct RemoveSmallIslandsReport {
  size_t islands_dropped = 0;
  size_t dropped_by_volume = 0;      //!< of islands_dropped, those below min_volume_fraction
  size_t triangles_dropped = 0;
  std::vector<int> first_triangles;  //!< the lowest triangle id of each of the first few dropped
  std::vector<Vec3> first_places;    //!< and the centre of that triangle
};

//! Removes the triangles of every island below options.min_triangles or, if it is closed,
//! enclosing less than options.min_volume_fraction of the largest island's volume (measured
//! with its triangles oriented consistently, repair_orientation.h, on a copy). Triangles keep
//! their order; vertices are left in place, unused, for verify_surface() to drop. Does
//! nothing when a face index is out of range.
RemoveSmallIslandsReport remove_small_islands(TriSurface& surface, const RemoveSmallIslandsOptions& options);

}  // namespace dthex
