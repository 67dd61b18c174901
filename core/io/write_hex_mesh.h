// SPDX-License-Identifier: MIT
// Hex-mesh writers for viewers (VTU, legacy VTK) and solvers (Gmsh MSH 4.1 or 2.2, Abaqus INP,
// FEBio 4.0, Exodus II), each carrying the named sets of find_mesh_sets() in the format's own
// way. Every file is written atomically: whole, or not at all.
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

//! Choices that only some formats have.
struct HexWriteOptions {
  enum class MshVersion { V41, V22 };
  //! .msh: MSH 4.1 (Gmsh's own, the default) or MSH 2.2 ASCII, the only version some readers
  //! take (code_aster). Both carry the same physical groups.
  MshVersion msh_version = MshVersion::V41;
  //! VTU and legacy VTK: also write each face set's faces as quad cells after the hexes, with a
  //! cell array "face_set" (the set's 1-based index in MeshSets::surfaces, 0 on hexes; quads
  //! have part 0 and their hex's field values). Off by default: viewers would then show the
  //! faces with the volume, and tools that expect only hexes would see other cells.
  bool vtk_face_set_cells = false;
};

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
//! The sets (parts, each part's boundary, patches, user sets) go where each format has them:
//! - INP: an element set per part, a *NSET per node set, a *SURFACE, TYPE=ELEMENT per face set
//!   (element, S-label); no *HEADING, so any deck can include it.
//! - MSH: a physical volume per part (its hexes in a volume entity of their own) and a physical
//!   surface per face set (its faces as 4-node quadrangles, corners in outward order, in a
//!   surface entity of their own, so a face in several sets is written once per set).
//! - FEBio: an <Elements> and a <SolidDomain> per part, a <NodeSet> per node set, a <Surface>
//!   of outward quad4 facets per face set.
//! - Exodus: an element block per part, a named node set per node set and a named side set per
//!   face set (element, Exodus side number).
//! - VTU and legacy VTK: a cell array "part" (1-based part index, in the order of `sets.parts`),
//!   beside the cell data in `fields` and, when mesh.boundary_facet is filled, a point array
//!   "boundary" (1 on boundary nodes); with HexWriteOptions::vtk_face_set_cells also the faces of
//!   each face set as quad cells.
//! Element numbers: INP, MSH and FEBio give hex h the id h + 1 in every case; MSH and FEBio list
//! the hexes part by part (each part's in ascending order). Exodus numbers elements by their
//! place in the blocks, so with more than one part its element numbers are the hexes grouped by
//! part and an element number map (elem_num_map) gives each one its id h + 1; with one part the
//! two agree and no map is written.
//! Throws InputError for an unknown extension, an unwritable folder, or a mesh whose
//! indices, field sizes or sets do not match it; std::runtime_error (naming path) when writing
//! fails (disk full, Exodus error). On any error no file is left at path.
//! When `sets` is null they are found from the mesh alone (find_mesh_sets without the input
//! surface).
void write_hex_mesh(const HexMesh& mesh, const std::string& path, const HexFields& fields = {},
                    const MeshSets* sets = nullptr, const HexWriteOptions& options = {});

}  // namespace dthex
