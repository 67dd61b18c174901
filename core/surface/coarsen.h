// SPDX-License-Identifier: MIT
// Curvature-driven coarsening of a closed triangle surface (docs/METHOD.md section 3,
// Coarsening): the DTHex Decimater modules driven by RevalidatingDecimaterT, with edge swaps,
// local smoothing pulled back onto the input, and a self-intersection repair loop.
#pragma once

#include <dthex/mesh/surface_mesh.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>
#include <dthex/surface/features.h>
#include <dthex/surface/split_in_halves.h>

#include <cmath>
#include <functional>
#include <memory>

namespace dthex {

struct CoarsenOptions {
  double eps = 0.1;                  //!< coarsening factor (sagitta / radius), (0, 1]
  double h_min = 0, h_max = 0;       //!< size bounds; 0 = automatic (see CurvatureSizingOptions)
  double gradation = 0.5;            //!< |h(A) - h(B)| <= gradation |AB|
  double max_normalized_length = std::sqrt(2.0);  //!< bound for every new edge
  double max_normal_deviation_deg = 45.0;         //!< per collapse / smoothing move
  double min_shape = 0.2;            //!< shape floor for new triangles (Verdict)
  double swap_max_dihedral_deg = 10.0;            //!< swaps only between near-coplanar triangles
  double smoothing_c1 = 0.5;         //!< area weight of local smoothing (c2 = 1 - c1)
  double feature_angle_deg = kDefaultFeatureAngleDeg;
  bool edge_swap = true, local_smoothing = true, global_smoothing = false;
  //! Judge a collapse that fails the bounds with the kept vertex in place again with it where
  //! the post-collapse local smoothing puts it (ModNormalizedLengthT::set_placement; needs
  //! local_smoothing). Reaches the sizes with fewer coarse triangles; off, the bounds are
  //! judged on the intermediate mesh, as the paper prints them (docs/METHOD.md section 9).
  bool judge_after_smoothing = true;
  //! No collapse may leave a triangle facing more than this (degrees) away from the input
  //! surface under its centroid, and further than before (180: no such check). Without it,
  //! judged after smoothing, a coarse surface can fold where the shape narrows, and the hexes
  //! there stay inverted after projection.
  double max_surface_deviation_deg = 60.0;
  //! If > 0, the size is at most this many times the wall thickness (never below h_min; see
  //! core/surface/wall_thickness.h). Curvature sizes a thin wall by its large radius, so its
  //! hexes come out flat; off by default, because capping can fold the hex boundary of a
  //! flap thinner than a hex (docs/METHOD.md section 7, Thin walls).
  double max_size_per_thickness = 0;
  //! Self-intersections found in the result are repaired by re-running with the sizing
  //! halved around them (the last extra run keeps the input vertices there instead); at
  //! most this many extra runs.
  int max_repair_rounds = 4;
  //! Inputs with at least this many vertices are decimated in two halves at once, one per
  //! core (core/surface/split_in_halves.h), then joined and decimated once more to remove the
  //! cut; 0 never splits. The result differs from one run over the whole (another greedy
  //! order) but not in kind; smaller inputs gain too little time to be worth the cut.
  size_t split_from_vertices = 4000;
  //! Inputs with at least this many vertices are first decimated roughly (SweepDecimaterT):
  //! only edges shorter than rough_pass_fraction of their size collapse, with swaps and the
  //! per-collapse bounds but without smoothing, placement or the surface-normal test, so no
  //! vertex leaves the input and no closest-point query is made; the full decimation, with
  //! every test, then starts from far fewer vertices. 0 never; below it the full decimation
  //! alone is cheap enough.
  size_t rough_pass_from_vertices = 100000;
  //! See rough_pass_from_vertices: in (0, 1]. Smaller leaves more to the full decimation
  //! (slower, closer to its result alone).
  double rough_pass_fraction = 0.25;
  //! Called with a rough completed fraction in [0, 1].
  std::function<void(double)> progress;
};

struct CoarsenResult {
  TriSurface surface;             //!< closed, oriented like the input, vertices on the input
  std::vector<double> sizes;      //!< sizing field at each coarse vertex
  size_t input_vertices = 0;
  size_t collapses = 0, swaps = 0, smoothing_moves = 0;
  size_t rough_collapses = 0;     //!< of the collapses, those of the rough pass
  //! 0 when global smoothing was off, or undone because it made the surface self-intersect.
  size_t global_smoothing_iterations = 0;
  size_t feature_edges = 0, feature_corners = 0;  //!< on the input
  int repair_rounds = 0;          //!< extra runs needed to remove self-intersections
  //! Input vertices on the cut when it was decimated in two halves (0: in one run, or split
  //! between separate bodies, which leaves no cut).
  size_t cut_vertices = 0;
  size_t thin_wall_vertices = 0;  //!< input vertices whose size the wall thickness lowered
  double h_min = 0, h_max = 0;    //!< bounds actually used
  double seconds = 0;             //!< wall time of coarsen()
};

//! What every coarsening of one input shares whatever its eps, size bounds and thickness cap:
//! the input as an OpenMesh mesh with its feature marks, its osculating radii and automatic
//! size bounds, a tree over it, and the sizing field of the options it was made for. Made
//! once, it serves the thin-wall count and the coarsenings of a run, which would otherwise
//! each make it again: on a million triangles that costs about as much as reading them.
//! With `cut_ahead`, an input that will be coarsened in two halves (options'
//! split_from_vertices) is also cut into them, on the second core while the first measures
//! the sizes; the first coarsening takes them (see take_halves).
//! Holds references to the input (and the given tree), which must outlive it; not copyable.
class CoarseningInput {
 public:
  //! `options`: its feature angle is the one every use must have; its eps and size bounds
  //! those whose sizing field is made here (others are made from the radii when asked for).
  //! `bvh`, when given, is a tree over `input` the caller already has; else one is built.
  explicit CoarseningInput(const TriSurface& input, const CoarsenOptions& options = {},
                           const TriangleBvh* bvh = nullptr, bool cut_ahead = true);
  CoarseningInput(const CoarseningInput&) = delete;
  CoarseningInput& operator=(const CoarseningInput&) = delete;

  const TriSurface& surface() const { return input_; }
  const TriangleBvh& bvh() const { return bvh_ ? *bvh_ : *own_bvh_; }
  //! The input with edge and vertex feature marks (mark_features at the feature angle).
  const SurfaceMesh& mesh() const { return mesh_; }
  const Features& features() const { return features_; }
  double feature_angle_deg() const { return feature_angle_deg_; }
  //! h_min and h_max for these options, their automatic (0) values resolved on the input.
  std::pair<double, double> size_bounds(const CoarsenOptions& options) const;
  //! The curvature sizing field (per input vertex, before any thickness cap) at these
  //! options' eps, size bounds and gradation: the one made at construction when they match.
  std::vector<double> sizes(const CoarsenOptions& options) const;
  //! The halves cut ahead (split_connectivity of mesh()), once; null if none were, or they
  //! were taken.
  std::unique_ptr<SurfaceHalves> take_halves() { return std::move(halves_); }

 private:
  const TriSurface& input_;
  const TriangleBvh* bvh_;
  std::unique_ptr<TriangleBvh> own_bvh_;
  SurfaceMesh mesh_;
  Features features_;
  double feature_angle_deg_;
  std::vector<double> radii_;
  double mean_edge_ = 0, half_diagonal_ = 0;
  double made_eps_, made_h_min_, made_h_max_, made_gradation_;  //!< what sizes_ were made at
  std::vector<double> sizes_;
  std::unique_ptr<SurfaceHalves> halves_;
};

//! Coarsens a verified closed surface. Throws MeshingError if the result still
//! self-intersects after max_repair_rounds (it never returns an intersecting surface).
//! `input_bvh`, when given, is a tree over `input` the caller already has, so that it is not
//! built again.
CoarsenResult coarsen(const TriSurface& input, const CoarsenOptions& options = {},
                      const TriangleBvh* input_bvh = nullptr);
//! The same from a prepared input (whose feature angle must be options'; std::invalid_argument
//! otherwise). Takes the halves it was cut into ahead, if any.
CoarsenResult coarsen(CoarseningInput& input, const CoarsenOptions& options);

struct GlobalSmoothingOptions {
  size_t max_iterations = 100;
  //! Stop when no vertex moved more than tolerance x the input's bounding-box diagonal.
  double tolerance = 1e-4;
  double max_normal_deviation_deg = 45.0;
  double feature_angle_deg = kDefaultFeatureAngleDeg;
};

//! Area-weighted centroid pull over the whole coarse surface, each move re-projected onto
//! the input and rejected if it flips a normal or lowers the worst incident shape; feature
//! vertices stay. Iterates to the tolerance. If sizes (per coarse vertex) is non-empty it
//! is updated from input_sizes (per input vertex) at the projected points. Returns the
//! number of iterations run.
size_t global_smoothing(TriSurface& coarse, const TriSurface& input, const GlobalSmoothingOptions& options = {},
                        std::vector<double>* sizes = nullptr, const std::vector<double>* input_sizes = nullptr);

//! The input vertices on a wall thinner than their curvature size (at `options`' eps and
//! size bounds) over options.max_size_per_thickness, or over 1 when that is off: what the
//! option would change. Measured apart from coarsen(), which only measures when the option
//! is on: it costs a large share of the coarsening, so a run measures it only to explain
//! poor hexes.
size_t count_thin_wall_vertices(const TriSurface& input, const CoarsenOptions& options);
//! The same from a prepared input (whose feature angle must be options').
size_t count_thin_wall_vertices(const CoarseningInput& input, const CoarsenOptions& options);

//! Pairs (a < b) of triangles that intersect other than in shared vertices/edges
//! (non-coplanar crossings, and folded triangles on a shared edge).
std::vector<std::array<int, 2>> self_intersections(const TriSurface& surface);

}  // namespace dthex
