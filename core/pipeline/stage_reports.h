// SPDX-License-Identifier: MIT
// The typed report of each pipeline stage, as PipelineResult keeps them (one StageRecord
// per stage run, in order). Stages whose algorithm has a report of its own keep it; the
// others (reading, counting, the pipeline's own decisions) have a small struct here. They
// are turned into prose and JSON in one place, core/report/report.cpp.
#pragma once

#include <dthex/boundary/local_smooth.h>
#include <dthex/boundary/optimize_worst_regions.h>
#include <dthex/boundary/project_boundary.h>
#include <dthex/boundary/repair_boundary_folds.h>
#include <dthex/boundary/repair_worst_hexes.h>
#include <dthex/boundary/untangle.h>
#include <dthex/mesh/quality.h>
#include <dthex/surface/coarsen.h>
#include <dthex/surface/remesh_isotropic.h>
#include <dthex/tet_edits/collapse_interior_vertices.h>
#include <dthex/tet_edits/flip_three_tet_edges.h>
#include <dthex/tet_edits/flip_worst_tets.h>
#include <dthex/tet_edits/remove_boundary_edges.h>
#include <dthex/tet_edits/split_crowded_vertices.h>
#include <dthex/tet_edits/thin_crowded_boundary_stars.h>
#include <dthex/tets/refine_flat_needles.h>
#include <dthex/tets/relax_interior_points.h>
#include <dthex/tets/split_surface_tets.h>

#include <string>
#include <variant>
#include <vector>

namespace dthex {

//! A verified surface (the input, or the coarse surface): stage "verify" and "verify coarse".
struct SurfaceSummary {
  size_t vertices = 0, triangles = 0, components = 0, cavities = 0;
  int genus = 0;
  double volume = 0, bbox_diagonal = 0;
  size_t flipped_components = 0;
  QualityStats shape;
};

//! Stage "read": the surface as read.
struct ReadReport {
  size_t vertices = 0, triangles = 0;
};

//! Stage "remesh input" (PipelineOptions::remesh): the remeshing's own report, and whether
//! its surface was kept or why it was dropped (the input is then coarsened as it is).
struct RemeshStageReport {
  enum class Outcome {
    kept,                 //!< the coarsening starts from the remeshed surface
    gave_up,              //!< the remeshing only grew the mesh (RemeshIsotropicReport::gave_up)
    failed_verification,  //!< the remeshed surface failed verify_surface (see `failure`)
    no_better,            //!< no fewer needles, or a smaller smallest angle
  };
  Outcome outcome = Outcome::kept;
  double needle_share_before = 0;  //!< of the input's triangles, in [0, 1]
  double needle_share_after = 0;   //!< of the remeshed triangles (0 when not measured)
  RemeshIsotropicReport remesh;
  std::string failure;             //!< verify_surface's message, for failed_verification
};

//! Stage "thin walls": the vertices of the coarsened surface on walls thinner than their size.
struct ThinWallReport {
  size_t vertices = 0;
};

//! Stage "choose eps" (PipelineOptions::target_nodes): the eps and the dicing chosen, and why
//! that dicing.
struct ChooseEpsReport {
  double eps = 0;
  size_t target_nodes = 0;
  int dice = 0;                 //!< the dicing used
  int preferred_dice = 0;       //!< PipelineOptions::dice
  bool dice_given = false;      //!< PipelineOptions::choose_dice off: `dice` is the one given
  //! The node range the preferred dicing reaches, at the search's two ends.
  size_t preferred_least = 0, preferred_most = 0;
  //! The ends of the search: 0.001 and 0.9, or the nearest eps to them whose meshing works.
  double finest_eps = 0, coarsest_eps = 0;
  //! Eps tried whose meshing failed (at an end, the next one towards the other is tried; in
  //! the bisection, it is taken as too coarse).
  size_t failed_probes = 0;
  std::string first_failure;    //!< the first such failure's message
};

//! An eps at which the coarsening (or the coarse surface's verification) failed, so the
//! pipeline tried a smaller one.
struct FailedEps {
  double eps = 0;
  std::string failure;
};

//! Stage "coarsen": the coarsening's report (its surface and sizes are not kept here: the
//! surface is PipelineResult::coarse), then the fixes made before TetGen.
struct CoarsenStageReport {
  //! The larger eps tried first, in order, whose coarsening failed (PipelineResult::eps is the
  //! one that worked).
  std::vector<FailedEps> failed;
  double eps = 0;                      //!< the eps of this coarsening
  CoarsenResult coarsen;               //!< surface and sizes emptied
  size_t triangles = 0;                //!< of the coarsened surface, before the fixes
  size_t flat_valence3_removed = 0;    //!< remove_flat_valence3_vertices (with projection)
  RefineFlatNeedlesReport needles;
};

//! Stage "tetrahedralize".
struct TetrahedralizeReport {
  size_t tets = 0;
};

//! Stage "flip boundary edges": cone_edge_clusters, then remove_boundary_edges.
struct BoundaryEdgesReport {
  size_t clusters_coned = 0;
  RemoveBoundaryEdgesReport removed;  //!< tets_after is the count after both
};

//! Stages "thex" and "dice": the hexes made.
struct HexCountReport {
  size_t hexes = 0;
};

//! Stage "repair worst": the repair's report with the threshold it used and the mesh's hex
//! count (for the share below it).
struct RepairWorstStageReport {
  RepairWorstHexesReport repair;
  double threshold = 0;
  size_t hexes = 0;
};

//! Stage "repair folds": the fold repair's report; or, where the input is meshed again at a
//! finer eps anyway (PipelineOptions::finer_retry), the folds found and the repair left for
//! the mesh that is kept (`deferred`: then only repair.faces_inside_before/after are set).
struct RepairFoldsStageReport {
  RepairBoundaryFoldsReport repair;
  bool deferred = false;
};

//! Stage "slide on creases": the smoother's report, and whether the slide was undone because
//! it folded boundary faces into the mesh (more of them inside it than before the slide).
struct CreaseSlideStageReport {
  LocalSmoothReport smooth;
  size_t faces_inside_before = 0, faces_inside_after = 0;  //!< counted only where the slide moved nodes
  bool undone = false;
};

//! Stage "measure": what makes the mesh good or poor.
struct MeasureReport {
  size_t inverted = 0;
  size_t below_0_2 = 0;              //!< hexes with scaled Jacobian below 0.2
  double min_scaled_jacobian = 0;
  bool conforming = false;
  size_t boundary_faces_inside = 0;
};

//! One whole meshing of the input (PipelineOptions::thickness_retry and finer_retry): stage
//! "curvature-sized try", "thickness-sized try" or "eps E try", the mesh not kept.
struct MeshTryReport {
  double thickness_ratio = 0;  //!< 0 = sized by curvature alone
  double eps = 0;              //!< the coarsening factor it was meshed at
  bool failed = false;         //!< it threw (then `failure` says why; the rest is unset)
  std::string failure;
  size_t inverted = 0;
  double min_scaled_jacobian = 0;
  bool conforming = false;
  //! Its boundary folds were counted but not repaired, since a finer try followed
  //! (RepairFoldsStageReport::deferred); false once the mesh kept is repaired.
  bool fold_repair_left = false;
};

//! Is try `a` to be kept over try `b` (two meshes of one input)? A conforming mesh first, then
//! fewer inverted hexes, then the higher minimum scaled Jacobian. Where the fold repair of
//! either was left (fold_repair_left), that one is not conforming only for want of the repair,
//! which turns no hex over: then the inverted hexes count first (with none and its folds left
//! a mesh can still end sound; with inverted hexes it cannot). A failed try is never better.
bool better_try(const MeshTryReport& a, const MeshTryReport& b);

//! Stage "predict thin walls" (PipelineOptions::thickness_retry): before the first mesh, the
//! vertices of the surface the coarsening starts from on walls several times thinner than
//! their curvature size, and the sizing chosen from them.
struct ThinWallPredictionReport {
  size_t vertices = 0;           //!< of that surface
  size_t thinner_twice = 0;      //!< on walls at least 2x thinner than their curvature size
  size_t thinner_four_times = 0;  //!< at least 4x (counted only when thinner_twice makes walls thin)
  //! The sizing chosen: 0 = curvature alone (the retry may follow), else the wall thickness
  //! ratio the first mesh is sized with, and its dicing.
  double thickness_ratio = 0;
  int dice = 0;
  bool membrane = false;  //!< the walls are a membrane (thinner_four_times), meshed as one
  //! A membrane's median wall thickness, and the smallest coarse edge it is given (input units).
  double wall_thickness = 0, h_min = 0;
};

using StageReport =
    std::variant<ReadReport, SurfaceSummary, RemeshStageReport, ThinWallReport, ChooseEpsReport, CoarsenStageReport,
                 TetrahedralizeReport, BoundaryEdgesReport, FlipThreeTetEdgesReport, CollapseInteriorVerticesReport,
                 SplitSurfaceTetsReport, FlipWorstTetsReport, RelaxInteriorPointsReport, SplitCrowdedVerticesReport,
                 ThinCrowdedBoundaryStarsReport,
                 HexCountReport, ProjectReport, UntangleReport, LocalSmoothReport, OptimizeWorstRegionsReport, CreaseSlideStageReport,
                 RepairWorstStageReport,
                 RepairFoldsStageReport, MeasureReport, MeshTryReport, ThinWallPredictionReport>;

struct StageRecord {
  std::string name;
  double seconds = 0;
  StageReport report;
};

//! What the automatic thickness retry did (PipelineOptions::thickness_retry), when it ran.
struct ThicknessRetryReport {
  bool ran = false;
  size_t thin_wall_vertices = 0;    //!< of the surface the coarsening started from
  size_t coarsening_vertices = 0;   //!< that surface's vertex count
  bool remeshed_input = false;      //!< that surface was the remeshed input
  MeshTryReport curvature, thickness;  //!< the two meshes
  bool kept_thickness = false;      //!< the thickness-sized mesh was kept
};

//! What the retry at a finer eps did (PipelineOptions::finer_retry), when it ran.
struct FinerRetryReport {
  bool ran = false;
  std::vector<MeshTryReport> tries;  //!< the unsound mesh first, then each retry, in order
  size_t kept = 0;                   //!< the index in `tries` of the mesh kept
};

}  // namespace dthex
