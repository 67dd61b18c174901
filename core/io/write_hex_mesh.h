// SPDX-License-Identifier: MIT
// Hex-mesh writers for viewers (VTU, legacy VTK) and solvers (Gmsh MSH 4.1, Abaqus INP,
// FEBio 4.0, Exodus II). Every file is written atomically: whole, or not at all.
#pragma once

#include <dthex/hexes/mesh_sets.h>
#include <dthex/mesh/types.h>

#include <string>
#include <vector>

namespace dthex {

//! Optional per-hex values written as cell data where the format has a place for them
//! (VTU, legacy VTK). Each vector is either empty (not written) or has one value per hex.
struct HexFields {
  std::vector<double> shape, scaled_jacobian;
};

enum class HexFormat { Vtu, Vtk, GmshMsh41, AbaqusInp, FebioFeb, ExodusII };

//! The format for a file name, from its extension, case-insensitive:
//! .vtu .vtk .msh .inp .feb .exo/.e/.ex2. Throws InputError naming the extension and
//! listing the supported ones.
HexFormat hex_format_from_path(const std::string& path);

//! The extensions hex_format_from_path accepts, with the dot (".vtu", ...).
std::vector<std::string> supported_hex_extensions();

//! Writes the mesh in the format its extension names. Node order is VTK's everywhere:
//! Gmsh's 8-node hexahedron, Abaqus C3D8, FEBio hex8 and Exodus HEX8 all number their
//! corners the same way, so connectivity is written unpermuted (1-based except VTU/VTK).
//! Coordinates keep full double precision (raw binary or %.17g), except in INP: 13 significant
//! digits, so that no field is longer than the 20 characters CalculiX reads.
//! INP also carries the sets of find_mesh_sets() (parts as element sets, boundaries and patches
//! as node sets and element surfaces) and has no *HEADING, so any deck can include it.
//! VTU also gets the cell data in `fields` and, when mesh.boundary_facet is filled, a
//! point array "boundary" (1 on boundary nodes); legacy VTK gets the same arrays.
//! Throws InputError for an unknown extension, an unwritable folder, or a mesh whose
//! indices or field sizes do not match; std::runtime_error (naming path) when writing
//! fails (disk full, Exodus error). On any error no file is left at path.
//! `sets` (parts, boundaries, patches) are written where the format has sets (INP); when none
//! are given they are found from the mesh alone (find_mesh_sets without the input surface).
void write_hex_mesh(const HexMesh& mesh, const std::string& path, const HexFields& fields = {},
                    const MeshSets* sets = nullptr);

}  // namespace dthex
