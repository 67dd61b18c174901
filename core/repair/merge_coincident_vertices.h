// SPDX-License-Identifier: MIT
// Merging vertices at exactly the same position (one of the safe repairs, repair_surface.h).
// OBJ, PLY and OFF exporters often give each triangle or each patch its own copies of the
// corners it shares, so that a closed surface looks open to verify_surface(). Coordinates
// equal to the last bit cannot be two places, so merging them cannot change the shape.
#pragma once

#include <dthex/mesh/types.h>

#include <vector>

namespace dthex {

struct MergeCoincidentVerticesOptions {
  //! How many merged vertices the report names (id, the vertex kept, the position).
  size_t examples = 5;
};

struct MergeCoincidentVerticesReport {
  size_t vertices_merged = 0;     //!< vertices whose triangles now use an earlier vertex at the same position
  std::vector<int> first_merged;  //!< the first few of them, ids into the surface as given
  std::vector<int> first_kept;    //!< for each, the vertex it was merged onto
  std::vector<Vec3> first_places; //!< and their position
};

//! Makes every triangle corner use the lowest-id vertex at exactly its position (-0 and +0
//! equal; non-finite positions are never merged, and corners whose index is out of range are
//! left as they are, for verification to refuse). No vertex is removed or renumbered: the
//! merged ones are left unused, so ids in later messages stay those of the file, and
//! verify_surface() drops them. Triangles whose corners become one vertex are left to
//! remove_redundant_triangles().
MergeCoincidentVerticesReport merge_coincident_vertices(TriSurface& surface,
                                                        const MergeCoincidentVerticesOptions& options = {});

}  // namespace dthex
