// SPDX-License-Identifier: MIT
// Feature lines of a triangle surface (docs/METHOD.md section 3, Coarsening: Features): edges
// whose two triangles' normals differ by more than an angle, and the corners where feature
// lines end or meet.
#pragma once

#include <dthex/mesh/surface_mesh.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>

#include <array>
#include <vector>

namespace dthex {

//! Default feature angle (degrees between the two triangle normals of an edge, 0 for a flat
//! edge). 60: organ and bone scans are smooth, and their staircase/noise creases mostly
//! stay below it, while machined or cut edges (cube 90, cut faces) are caught.
constexpr double kDefaultFeatureAngleDeg = 60.0;

struct Features {
  //! Feature edges as vertex pairs (a < b), sorted.
  std::vector<std::array<int, 2>> edges;
  //! Per vertex: number of incident feature edges.
  std::vector<int> feature_valence;
  //! Vertices with 1 or more than 2 feature edges (line ends and junctions), sorted.
  std::vector<int> corners;
};

//! A needle is a triangle with an angle below this (degrees).
constexpr double kFinNeedleAngleDeg = 10.0;

//! A fin: a needle whose normal turns by more than `angle_deg` from each of its three edge
//! neighbours. Segmentation leaves them, and a needle's normal rests on its tiny width.
//! Taken as a feature, a fin's tip is a corner the mesh must hold and its few-degree angle
//! goes into a boundary quad: a hex there reaches at most the sine of that angle. Fins are
//! therefore no features, and crease tests ignore them.
bool is_fin(const std::array<Vec3, 3>& corners, const Vec3& unit_normal, const std::array<Vec3, 3>& neighbour_normals,
            double angle_deg = kDefaultFeatureAngleDeg);

//! Per triangle of the surface: is it a fin? (Edges with other than two triangles count as
//! turning: a fin needs three neighbours that all turn away.)
std::vector<char> fin_triangles(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles,
                                double angle_deg = kDefaultFeatureAngleDeg);

//! The test detect_features makes on an edge of exactly two triangles: the angle between their
//! unit normals ((b - a) x (c - a) normalized, zero for a degenerate triangle) exceeds
//! angle_deg, and neither is a fin. Made once per surface, then asked per pair, by callers that
//! walk the edges themselves.
class CreaseTest {
 public:
  explicit CreaseTest(const TriSurface& surface, double angle_deg = kDefaultFeatureAngleDeg);
  //! Is the edge that triangles a and b share (its only two) a feature edge?
  bool operator()(int a, int b) const {
    return !fins_[size_t(a)] && !fins_[size_t(b)] && normals_[size_t(a)].dot(normals_[size_t(b)]) < cos_limit_;
  }

 private:
  std::vector<Vec3> normals_;
  std::vector<char> fins_;
  double cos_limit_ = 0;
};

//! Features of a surface. An edge is a feature when the angle between its two triangles'
//! normals exceeds angle_deg, or when it does not have exactly two triangles (border); an
//! edge of a fin is not.
Features detect_features(const TriSurface& surface, double angle_deg = kDefaultFeatureAngleDeg);

//! Just the feature edges of detect_features (for projection onto the fine surface).
std::vector<std::array<int, 2>> feature_edges(const TriSurface& surface, double angle_deg = kDefaultFeatureAngleDeg);

//! Per node of a hex mesh whose boundary nodes still lie on the coarse surface they were
//! made from (before projection; boundary_facet names each one's coarse triangle): whether
//! the node lies on a feature edge of `coarse`. Those nodes belong on the input's feature
//! lines; any other node that projection puts on a crease got there by accident.
std::vector<char> nodes_on_feature_edges(const HexMesh& mesh, const TriSurface& coarse,
                                         double angle_deg = kDefaultFeatureAngleDeg);

//! The unit normal of every triangle (zero for a degenerate one and for a fin): what the
//! crease tests below take as `normals`; they ignore triangles with a zero normal.
std::vector<Vec3> unit_triangle_normals(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles);

//! True if a triangle of `surface` within `radius` of x faces away from `normal` by more
//! than acos(min_cos): x is on a crease or corner, which a slide on the surface would round
//! off. With `convex_only`, a triangle rising above x's tangent plane (the far wall of a
//! concave crease) does not count. `normals` are the unit normals of surface's triangles.
bool on_surface_crease(const TriangleBvh& surface, const std::vector<Vec3>& normals, const Vec3& x, const Vec3& normal,
                       double radius, double min_cos, bool convex_only);

//! True if the triangles of `surface` within `radius` of x on its own face (those whose normal
//! turns less than acos(face_cos) from `normal`, so not across a crease) turn more than
//! acos(flat_cos) from it: x is on a curved part of the surface, not on a plane. A node may
//! leave a curved surface by a little for a sounder hex (optimize_worst_regions); off a plane
//! it would only bend a face a solver takes as flat.
bool surface_curves_near(const TriangleBvh& surface, const std::vector<Vec3>& normals, const Vec3& x, const Vec3& normal,
                         double radius, double flat_cos, double face_cos);

//! What the triangles of `surface` within `radius` of x make there, their normals grouped
//! by `min_cos`: one face (none), two faces meeting on a line, convex or concave as seen from
//! `normal` (the line's unit direction into `direction`), or three and more (a corner).
enum class CreaseKind { none, convex_line, concave_line, corner };
//! With `faces_cos`, a line's two face normals' dot product goes there (-1: a knife edge).
CreaseKind crease_at(const TriangleBvh& surface, const std::vector<Vec3>& normals, const Vec3& x, const Vec3& normal,
                     double radius, double min_cos, Vec3& direction, double* faces_cos = nullptr);

//! A knife edge: a convex crease whose two faces meet at less than this inside (degrees),
//! as where a cut plane grazes the outer surface.
constexpr double kKnifeEdgeAngleDeg = 30.0;

//! Does the surface have a knife edge: two neighbouring triangles whose normals (from
//! unit_triangle_normals: fins have none) turn by more than 180 - knife_angle_deg degrees?
bool has_knife_edge(const std::vector<std::array<int, 3>>& triangles, const std::vector<Vec3>& normals,
                    double knife_angle_deg = kKnifeEdgeAngleDeg);

//! True if x is within `radius` of a knife edge: an edge of `surface` whose two triangles'
//! normals (unit, zero ones ignored) turn by more than 180 - knife_angle_deg degrees.
bool near_knife_edge(const TriangleBvh& surface, const std::vector<Vec3>& normals, const Vec3& x, double radius,
                     double knife_angle_deg = kKnifeEdgeAngleDeg);

//! Marks features on an OpenMesh mesh for the Decimater: edge and vertex status feature()
//! on feature edges (as detect_features) and their vertices, and locked() on corners (never
//! removed). Clears the bits elsewhere. Returns what it marked, indexed like the mesh's vertices.
Features mark_features(SurfaceMesh& mesh, double angle_deg = kDefaultFeatureAngleDeg);

}  // namespace dthex
