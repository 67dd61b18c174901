// SPDX-License-Identifier: MIT
// Triangle-surface writers (.off .obj .ply .stl) with full double precision, written atomically.
#pragma once

#include <dthex/mesh/types.h>

#include <string>
#include <vector>

namespace dthex {

//! Writes the surface in the format its extension names (case-insensitive):
//! .off, .obj, .ply (ASCII, "property double"), .stl (ASCII, per-facet unit normals).
//! Coordinates are printed with %.17g so a double-reading parser gets the exact values back.
//! Why not OpenMesh::IO::write_mesh: OpenMesh 9.0's exporter hands every writer
//! single-precision points (ExporterT::point returns Vec3f), whatever the precision argument.
//! Throws InputError for an unknown extension, an unwritable folder, no triangles or an
//! index out of range; std::runtime_error when writing fails. No file is left on error.
void write_surface(const TriSurface& surface, const std::string& path);

//! The extensions write_surface accepts, with the dot (".off", ...).
std::vector<std::string> supported_surface_extensions();

}  // namespace dthex
