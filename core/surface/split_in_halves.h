// SPDX-License-Identifier: MIT
// Cuts a closed surface mesh into two open halves that can be decimated at the same time,
// each on its own core, and joins the decimated halves back into one closed mesh. The
// vertices on the cut are locked in the halves, so the halves still meet along it; a last,
// short decimation of the joined mesh then removes the cut.
#pragma once

#include <dthex/mesh/surface_mesh.h>

#include <array>
#include <vector>

namespace dthex {

struct SurfaceHalves {
  std::array<SurfaceMesh, 2> halves;
  //! Per half, the index in the whole mesh of each of its vertices.
  std::array<std::vector<int>, 2> whole_vertex;
  //! Per vertex of the whole mesh: 1 on the cut (in both halves).
  std::vector<char> cut;
  size_t cut_vertices = 0;
};

//! What a split carries over besides `whole`'s own status bits and sizes: per vertex of
//! `whole`, sizes that replace its "v:dthex_size" property, and extra locks. With them the
//! caller need not copy a big `whole` to set them (the coarsening's repair rounds do).
struct SplitExtras {
  const std::vector<double>* sizes = nullptr;
  const std::vector<char>* locked = nullptr;
};

//! Splits `whole` by the plane across its longest extent through the median triangle
//! centroid. Where a vertex's triangles on one side would form two separate fans (a
//! mesh OpenMesh cannot hold), all its triangles go to the side that has most of them.
//! Status bits (feature, locked) and the "v:dthex_size" property, if `whole` has it (or
//! `extras`' sizes), are copied; the vertices on the cut are locked in both halves. False,
//! with `halves` left unspecified, if no such split exists (e.g. a side ends up empty).
bool split_in_halves(const SurfaceMesh& whole, SurfaceHalves& halves, const SplitExtras& extras = {});

//! split_in_halves in two steps. The first makes the halves' triangles and vertices (no status
//! bits, no sizes) and reads only `whole`'s connectivity and points, so it can run while
//! another thread reads `whole` too: the coarsening measures its sizes meanwhile. It also
//! works on both cores when called outside a parallel region.
bool split_connectivity(const SurfaceMesh& whole, SurfaceHalves& halves);
//! The second: status bits (features, locks, and the cut's locks) and sizes from `whole` and
//! `extras`, as split_in_halves gives them, on halves that split_connectivity made of `whole`
//! and that have not been changed since.
void mark_halves(const SurfaceMesh& whole, SurfaceHalves& halves, const SplitExtras& extras = {});

//! The live triangles of both halves as one mesh, vertices in the order of `whole` (the
//! deleted ones left out). Vertex status comes from `whole` and `extras`' locks (the cut's
//! locks are dropped), edge status and sizes from the halves. Throws MeshingError if the
//! halves no longer fit together (they do whenever no cut vertex moved or was removed).
SurfaceMesh join_halves(const SurfaceHalves& halves, const SurfaceMesh& whole, const SplitExtras& extras = {});

}  // namespace dthex
