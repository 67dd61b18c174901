// SPDX-License-Identifier: MIT
// Removing collapsed and duplicate triangles (one of the safe repairs, repair_surface.h):
// merging coincident vertices turns a soup's slivers into triangles that repeat a vertex,
// and exporters write some faces twice. Neither encloses anything, so where the surface
// without them is closed and manifold they are removed; elsewhere they are left for
// verify_surface() to refuse, since removing them there would open the surface.
#pragma once

#include <dthex/mesh/types.h>

#include <vector>

namespace dthex {

struct RemoveRedundantTrianglesOptions {
  //! How many removed triangles the report names.
  size_t examples = 5;
};

struct RemoveRedundantTrianglesReport {
  size_t collapsed_removed = 0;   //!< triangles that repeat a vertex index
  size_t duplicates_removed = 0;  //!< triangles on the same three vertices as a lower-id one
  std::vector<int> first_removed; //!< the first few removed, ids into the surface as given
  //! Redundant triangles found but kept, because the surface without them would not be
  //! closed and manifold (every edge of exactly two triangles, one fan at every vertex).
  size_t left_in_place = 0;
};

//! Finds the triangles that repeat a vertex index and, of triangles on the same three
//! vertices (in any order or orientation), all but the lowest-id one. Removes them all when
//! the surface that remains is closed and manifold; otherwise changes nothing. Triangles
//! keep their order (ids after the first removed one shift down). Zero-area triangles on
//! three distinct vertices are not touched (removing one opens a crack;
//! flip_zero_area_slivers.h flips them away instead); nor is anything when a face index is
//! out of range.
RemoveRedundantTrianglesReport remove_redundant_triangles(TriSurface& surface,
                                                          const RemoveRedundantTrianglesOptions& options = {});

//! Is every edge of these triangles used by exactly two of them, and do the triangles around
//! each vertex form one fan? (Indices must be below vertex_count, no triangle repeat a vertex.)
bool is_closed_manifold(const std::vector<std::array<int, 3>>& triangles, size_t vertex_count);

}  // namespace dthex
