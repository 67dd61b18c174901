// SPDX-License-Identifier: MIT
// A tet mesh of several material regions (TetMesh::tet_region, a closed surface inside another
// meshed as a second material) taken apart into one closed tet mesh per region and put back
// together. The tet clean-up before THex (split_surface_tets and the flips and moves around it)
// keeps a mesh's boundary faces and boundary vertices where they are, and treats every face
// with two tets as interior; an interface between two regions has two tets per face, so the
// clean-up runs on each region alone, where the interface is boundary, and the regions are then
// joined again at their interface vertices, which it did not move.
#pragma once

#include <dthex/mesh/types.h>

#include <vector>

namespace dthex {

//! One tet mesh per region of `mesh` (mesh.tet_region; the whole mesh when it is empty), in
//! region order. Each holds its region's tets and the points they use, in the order of `mesh`,
//! and as boundary faces the faces of `mesh.boundary_faces` (the outer boundary and the
//! interfaces) that one of its tets has, oriented outward of that tet, with their sources. Its
//! tet_region is empty. Preconditions: tet_region empty or one entry per tet, every face of
//! boundary_faces a face of some tet. Pure.
std::vector<TetMesh> split_tet_regions(const TetMesh& mesh);

//! The regions joined into one tet mesh: points shared by two regions' boundary faces (the
//! interface vertices) are one point, found by their exact coordinates; every other point is
//! its region's own. tet_region numbers the tets by the region they came from (empty for one
//! region); a face on two regions' boundaries (an interface face) is one boundary face,
//! oriented outward of the lower-numbered region. Preconditions: the regions were made by
//! split_tet_regions() and changed only where they keep their boundary faces and the points
//! on them (the tet clean-up's stages do). Pure.
TetMesh merge_tet_regions(const std::vector<TetMesh>& regions);

}  // namespace dthex
