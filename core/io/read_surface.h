// SPDX-License-Identifier: MIT
// Reading triangle surfaces from OFF, OBJ, STL (ASCII and binary) and PLY (ASCII and
// binary, either byte order). Own readers rather than OpenMesh's: counts announced by a
// header are checked against the file size before anything is allocated, and every
// problem is reported with the file, the rule and the line or element.
#pragma once

#include <dthex/mesh/types.h>

#include <string>
#include <string_view>
#include <vector>

namespace dthex {

//! Reads the surface at path; the format is chosen by the extension (.off, .obj, .stl,
//! .ply, case-insensitive).
//!
//! What the reader guarantees (and refuses with an InputError whose message is one
//! sentence "<path>: <problem> (line N ...)"): the file exists, is a regular non-empty
//! file, parses completely, has at least one triangle, every coordinate is finite and
//! every face index is in range. Everything geometric or topological (degenerate,
//! duplicate, open, non-manifold, self-intersecting) is left to verify_surface().
//!
//! Format notes:
//! - Polygons with more than three corners (OFF, OBJ, PLY) are fan-triangulated from
//!   their first corner; a non-convex polygon may then overlap itself, which
//!   verification reports as a self-intersection.
//! - OFF: '#' starts a comment; COFF/NOFF/CNOFF headers are accepted (extra values on a
//!   vertex or face line, such as colours, are ignored); counts may follow the keyword
//!   on the same line.
//! - OBJ: only 'v' and 'f' lines matter for the surface ('o' and 'g' name parts, see
//!   read_surface_names()); corners may be v, v/vt, v/vt/vn or v//vn;
//!   negative indices count back from the last vertex read so far.
//! - STL: binary exactly when the size is 84 + 50 n for the count n stored at byte 80,
//!   even if the header starts with "solid". Exactly equal vertex positions are merged
//!   (hashing the coordinates), so a triangle soup becomes an indexed surface. The other
//!   formats keep every vertex as written; the pipeline's safe repairs merge them
//!   (merge_coincident_vertices.h).
//! - PLY: element "vertex" with x, y, z of any scalar type, element "face" with a list
//!   property vertex_indices (or vertex_index); other properties and elements are skipped.
TriSurface read_surface(const std::string& path);

//! The names a surface file gives its parts: an OBJ file's `o NAME` lines (the rest of the
//! line) and `g NAME` lines (a group line's first name), each face in the latest one before it. `surface` is the file as
//! read_surface() reads it, before any repair, and `triangle_name` gives per triangle of it the
//! index into `names`, -1 for faces before the first name. All empty for other formats and for an
//! OBJ file with no names. Throws as read_surface() does.
struct SurfaceNames {
  std::vector<std::string> names;
  TriSurface surface;
  std::vector<int> triangle_name;
};
SurfaceNames read_surface_names(const std::string& path);

//! Parses bytes already in memory as the format of extension (".off", ".obj", ".stl",
//! ".ply", case-insensitive), with the same checks and messages as read_surface();
//! name stands for the file in messages. Used by the fuzzers and for non-file sources.
TriSurface read_surface_from_memory(std::string_view bytes, const std::string& extension,
                                    const std::string& name = "<memory>");

}  // namespace dthex
