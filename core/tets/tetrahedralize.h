// SPDX-License-Identifier: MIT
// TetGen behind a process wall: TetGen 1.5.0 crashes the whole process on bad input.
#pragma once

#include <dthex/mesh/types.h>

#include <string>

namespace dthex {

struct TetgenOptions {
  //! TetGen switches. Allowed: p q a A Y M T O S D c X J e n and numbers (digits . / - +);
  //! 'Q' and 'z' are always added. Anything that makes TetGen write files, read files
  //! or change the output layout (g k v N E F B f o r i m w h d V ...) is refused.
  std::string switches = "pq1.2Y";
  //! Wall-clock limit; TetGen is killed past it. Must be positive.
  double time_limit_seconds = 300;
  //! A closed surface inside another encloses a second material (TetMesh::tet_region numbers
  //! the regions) instead of a cavity, whose tets are dropped (the default).
  bool keep_nested_regions = false;
};

//! Tetrahedralizes the inside of a closed triangle surface with TetGen 1.5.0.
//!
//! TetGen runs in a fork()ed child process, which sends the mesh back through a pipe,
//! because on a self-intersecting surface or a failed internal assert the library
//! segfaults or aborts instead of throwing (see notes section 2); its stdout and stderr
//! are sent to /dev/null. The surface's triangles are the input facets and each carries
//! its own index as facet marker, so boundary_face_source is the input triangle a
//! boundary face lies on. Output tets are positively oriented and boundary faces oriented
//! outward (both are checked and fixed, not assumed). The region inside an odd number of the
//! surface's components is a cavity and dropped, unless options.keep_nested_regions; then
//! every region is kept and tet_region set, and the faces between two regions (each once,
//! in boundary_faces) are oriented outward of one of their two tets.
//! \throw InputError for invalid switches, a non-positive time limit, or a surface with
//!        out-of-range or repeated triangle indices.
//! \throw MeshingError when TetGen crashes, aborts, reports an error, exceeds the time
//!        limit, or returns no tetrahedra; the message says which and the probable cause,
//!        and for a crash, a self-intersection or close facets names the closest two
//!        triangles sharing no corner (closest_triangle_pair.h), the gap and the place.
TetMesh tetrahedralize(const TriSurface& surface, const TetgenOptions& options = {});

}  // namespace dthex
