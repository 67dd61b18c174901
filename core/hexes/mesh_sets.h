// SPDX-License-Identifier: MIT
// The named sets an analyst needs to load and fix a hex mesh without picking nodes by hand:
// its parts (each connected body), each part's boundary as faces and nodes, and the boundary
// split into patches at its sharp creases (a cut with sharp edges is a patch: it is where a
// bone is fixed). The INP writer carries them as element sets, node sets and element
// surfaces (docs/METHOD.md section 8, Sets for the solver).
#pragma once

#include <dthex/mesh/hex_topology.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>

#include <array>
#include <string>
#include <vector>

namespace dthex {

//! A face of a hex: the hex's index and its side, numbered as Abaqus/CalculiX number the faces
//! of a C3D8 (0-based here: side s is the label S(s+1)). With VTK's corner order the sides are
//! {0,1,2,3}, {4,7,6,5}, {0,4,5,1}, {1,5,6,2}, {2,6,7,3}, {3,7,4,0}.
struct HexFace {
  int hex = -1;
  int side = -1;
  bool operator==(const HexFace& o) const { return hex == o.hex && side == o.side; }
};


struct HexSet {
  std::string name;
  std::vector<int> hexes;  //!< ascending
};
struct FaceSet {
  std::string name;
  std::vector<HexFace> faces;  //!< in the order boundary_quads() finds them (by hex)
  double area = 0;             //!< sum of the faces' areas (each quad as two triangles)
};
struct NodeSet {
  std::string name;
  std::vector<int> nodes;  //!< ascending
};

//! Everything find_mesh_sets() names. Names are unique within each kind, and a face set and
//! the node set of its faces' nodes share a name.
struct MeshSets {
  std::vector<HexSet> parts;         //!< body1, body2, ... by hex count, largest first
  //! body1_boundary, ..., then bodyM_bodyN_interface for each two material regions that touch
  //! (the faces of bodyM's hexes, M < N), then patch1, patch2, ... by area. A part's boundary
  //! holds its interfaces too, each face as a face of the part's own hex.
  std::vector<FaceSet> surfaces;
  std::vector<NodeSet> node_sets;    //!< one per surface, same name, its faces' nodes
};

struct MeshSetsOptions {
  //! A crease separates patches where the two faces beside an edge differ in normal by more
  //! than this angle, in degrees (the feature angle of the coarsening by default). Smaller
  //! splits curved regions into many patches; larger merges a cut with the surface around it.
  double crease_angle_degrees = 60;
  //! Planar regions of the input surface become patches of their own, whether or not a crease
  //! bounds them (a cut whose rim is rounded): a triangle joins a region when its normal is
  //! within this angle of the region's plane, in degrees. Larger finds noisier planes but also
  //! flat-looking strips of curved surfaces.
  double planar_angle_degrees = 5;
  //! ... and its corners lie within this distance of the plane, as a fraction of the input's
  //! bounding-box diagonal.
  double planar_distance_fraction = 0.002;
  //! A planar region is a patch only when its area is at least this fraction of the input's
  //! area; 0 turns planar regions off.
  double planar_min_area_fraction = 0.01;
  //! Optional: a search tree over the same input surface, if the caller has one (om_dthex keeps
  //! the pipeline's, PipelineResult::input_tree). Without it the overload with the input builds
  //! its own, which at a million triangles takes about half a second.
  const TriangleBvh* input_tree = nullptr;
};

//! Finds the parts (hexes connected through shared nodes, and of one region when mesh.region is
//! set), each part's boundary (faces used by one hex, and its faces on another region), the
//! interfaces between regions, and the boundary's patches. Here the patches come from the hex boundary itself:
//! faces joined across boundary edges whose dihedral angle is below the crease angle (an edge of
//! more than two boundary faces always separates). That finds the sharp edges of a mesh whose
//! boundary keeps them, not a crease that the boundary rounds over a few faces: use the overload
//! below when the input surface is at hand. Preconditions: node indices in range. Pure.
//! O(n log n) in the number of hexes.
MeshSets find_mesh_sets(const HexMesh& mesh, const MeshSetsOptions& options = {});

//! The same, with the patches taken from the surface the mesh was made from: its large planar
//! regions (grown from seeds, see the options), and its other triangles joined across every edge
//! that is not a feature edge (dihedral above the crease angle); each boundary face is given the
//! region of the input triangle closest to its centre. The planar cut of a scanned bone is then
//! one patch even where the scan rounds its rim and no input edge is a crease. Preconditions:
//! `input` closed and manifold (as om_dthex verified it). O(n log n) in the triangles and faces,
//! times the few regions that may try each triangle.
MeshSets find_mesh_sets(const HexMesh& mesh, const TriSurface& input, const MeshSetsOptions& options = {});

//! Gives each part the name its input gives it (read_surface_names(): an OBJ file's `o` and `g`
//! names) in place of bodyN, renaming its boundary and interface sets with it. A part takes the
//! name most of its boundary faces are nearest to (each face's centre against `named`'s
//! triangles, `triangle_name` per triangle, -1 for none); a name is made a valid set name
//! (characters other than letters, digits and underscores become underscores, and one that does
//! not start with a letter gets "part_" before it), and when several parts take one name the
//! largest keeps it and the others get _2, _3, ... A part that takes no name, or a name of the
//! kind find_mesh_sets() makes (bodyN, patchN, ...), keeps its bodyN. Returns how many parts
//! were renamed. Preconditions: `sets` made by find_mesh_sets() for `mesh`.
size_t name_parts_by_input(MeshSets& sets, const HexMesh& mesh, const TriSurface& named,
                           const std::vector<int>& triangle_name, const std::vector<std::string>& names);

//! A set the user names on the command line (--set NAME=box:... or NAME=plane:...): the boundary
//! faces all of whose corners lie in an axis-aligned box, or within a distance of a plane.
struct UserSetSpec {
  enum class Kind { Box, Plane };
  std::string name;
  Kind kind = Kind::Box;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();          //!< Box: opposite corners, any order
  Vec3 point = Vec3::Zero(), normal = Vec3::UnitZ();  //!< Plane: a point on it and its normal
  double distance = 0;                                //!< Plane: how far a corner may lie from it
};

//! Parses "NAME=box:X0,Y0,Z0,X1,Y1,Z1" or "NAME=plane:PX,PY,PZ,NX,NY,NZ,DISTANCE" (a point on
//! the plane, its normal, and the distance, in the input's units). NAME is letters, digits and
//! underscores, starting with a letter, and not one of the names find_mesh_sets() makes
//! (bodyN, bodyN_boundary, patchN, bodyM_bodyN_interface). Throws InputError quoting the text and the expected form.
UserSetSpec parse_user_set(const std::string& text);

//! Adds each user set to `sets` as a face set and a node set of its name: the boundary faces
//! (of the mesh's boundary, part by part; not the faces between material regions) whose four
//! corners are all inside it. Throws InputError
//! naming the set when it selects no face, or when its name is already used.
void add_user_sets(MeshSets& sets, const HexMesh& mesh, const std::vector<UserSetSpec>& specs);

}  // namespace dthex
