// SPDX-License-Identifier: MIT
// The whole DTHex pipeline as one call: read and verify, coarsen, tet-mesh, THex,
// dice, project onto the input surface, untangle, measure. The om_dthex command and
// the benchmark harness both run it; writing files is left to the caller, and turning
// the stage reports into prose or JSON to core/report/report.h.
#pragma once

#include <dthex/boundary/local_smooth.h>
#include <dthex/hexes/mesh_sets.h>
#include <dthex/mesh/quality.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/types.h>
#include <dthex/pipeline/progress.h>
#include <dthex/pipeline/stage_reports.h>
#include <dthex/repair/repair_surface.h>

#include <memory>
#include <string>

namespace dthex {

struct PipelineOptions {
  //! What is done to the input before verification: safe = the repairs that cannot change
  //! the shape (repair_surface.h: coincident vertices merged, collapsed and duplicate
  //! triangles removed, orientation made consistent); none = every defect is refused.
  enum class Repair { safe, none };
  Repair repair = Repair::safe;
  //! With Repair::safe, islands (triangles joined through shared vertices) of fewer triangles
  //! than this are dropped, the largest always kept (remove_small_islands.h); 0 = none. Off by
  //! default: unlike the safe repairs it removes geometry, such as a segmentation's noise voxels.
  size_t min_island_triangles = 0;
  //! With Repair::safe, closed islands enclosing less than this fraction of the largest one's
  //! volume are dropped too (RemoveSmallIslandsOptions::min_volume_fraction); 0 = none.
  double min_island_volume_fraction = 0;
  double eps = 0.1;                 //!< coarsening factor (sagitta / radius), in (0, 1)
  //! Each hex into dice^3. With target_nodes and choose_dice, the preferred dicing.
  int dice = 2;
  //! With target_nodes: when `dice` cannot reach the target (the node range it gives from eps
  //! 0.9 down to 0.001 misses it), the nearest dicing that can is used instead (1 for a budget
  //! below it, 3, 4, ... above). Off, such a target is an InputError. The command line turns
  //! it off when --dice is given. Also lets a predicted membrane be diced once
  //! (predict_thin_walls).
  bool choose_dice = true;
  double h_min = 0;                 //!< smallest coarse edge size, input units; 0 = automatic
  double h_max = 0;                 //!< largest coarse edge, input units; 0 = automatic
  double max_edge_ratio = 1.4142135623730951;  //!< no collapse makes an edge longer than this x its size
  //! Size at most this x the wall thickness; 0 = curvature alone (see
  //! CoarsenOptions::max_size_per_thickness for what each gives).
  double thickness_ratio = 0;
  //! With thickness_ratio 0: when the curvature-sized mesh ends with poor hexes (inverted or
  //! scaled Jacobian below 0.2) and at least 5% of the input vertices lie on walls thinner
  //! than their size, mesh again with thickness_ratio 1 and keep the better of the two
  //! (conforming first, then fewer inverted hexes, then the higher minimum scaled Jacobian).
  //! Not with target_nodes (the second mesh would miss the budget).
  bool thickness_retry = true;
  //! When the mesh ends unsound (an inverted hex, or a boundary not closed or folded into the
  //! mesh: the coarse surface was too coarse for the boundary to be put back on the input
  //! cleanly), mesh again at 0.7 x the eps, up to twice while it stays unsound, and keep the
  //! better mesh (as thickness_retry does). Costs time only where the mesh is unsound. Not with
  //! target_nodes (a finer mesh would miss the budget).
  bool finer_retry = true;
  //! With thickness_retry: before the first mesh, predict thin walls from the wall thickness
  //! (stage "predict thin walls"). Where they are likely to be the cause of poor hexes the
  //! first mesh is sized by thickness and no curvature-sized mesh is made; a membrane (most of
  //! the input on walls several times thinner than their curvature size) is also diced once
  //! and gets no edge shorter than its wall is thick (docs/METHOD.md, Thin walls). Off, the
  //! curvature-sized mesh always comes first.
  bool predict_thin_walls = true;
  //! With projection, the tets between boundary vertices are edited before THex (stages "flip
  //! boundary edges" and "split surface tets"): their hexes could not all be valid once
  //! projected. Turned off for a membrane (thickness_retry's prediction), where every tet
  //! spans the wall and the edits only make them flatter and more numerous.
  bool edit_boundary_tets = true;
  bool thex_only = false;           //!< classic THex of the input: no coarsening, dicing, projection
  bool project = true;              //!< put the boundary back on the input surface
  bool strict = false;              //!< fail (MeshingError) if a hex is inverted at a corner or a Gauss point
  //! Where the smoother and the regions leave a hex inverted, the hexes below scaled Jacobian
  //! 0.2 get a region repair (repair_worst_hexes.h); off only to measure what it brings.
  bool repair_worst_hexes = true;
  //! How far (a fraction of the input's bounding-box diagonal) the nodes of a knife edge (a
  //! convex crease under 30 degrees) may slide off it; 0 keeps knife edges sharp. See
  //! LocalSmoothOptions::knife_edge_slide.
  double knife_edge_slide = LocalSmoothOptions().knife_edge_slide;
  //! Where the worst hexes' regions gain nothing more with the boundary on the input, their
  //! boundary nodes where it curves (off creases) may end up to this fraction of their mean hex
  //! edge off it (OptimizeWorstRegionsOptions::surface_slack); 0 keeps every node on the input.
  //! 0.2 lifted Spot's worst hex from 0.346 to 0.400, Hausdorff distance unchanged (docs/METHOD.md
  //! section 6).
  double boundary_slack = 0.2;
  //! The same distance's cap, a fraction of the input's bounding-box diagonal: on a coarse mesh
  //! a fifth of a hex edge is far (the peer bunny's Hausdorff distance 0.41% -> 0.77% without
  //! it, 0.41% with it, for the same worst hex).
  double boundary_slack_cap = 0.002;
  //! Smallest dihedral angle of DTHex's coarse tets, in degrees (TetGen's q bound, pq1.5/DEG Y);
  //! 0 = none (pq1.5Y). With it TetGen adds points inside to remove slivers, and the local
  //! smoother then raises hexes towards scaled Jacobian kLiftedTargetScaledJacobian instead of
  //! its default: the worst hexes rise (0.27-0.29 -> 0.36-0.40 at 18 on the bundled meshes) for
  //! 10-40% more nodes (60% on the armadillo), docs/CASE_STUDIES.md, "Bounded dihedral angles".
  double min_dihedral_deg = 0;
  //! A closed surface inside another: a cavity (its inside is not meshed), or a second
  //! material, meshed conformingly with the outer one (the interface nodes shared and held on
  //! the inner surface; each region its own part in the output files).
  enum class Nested { cavity, material };
  Nested nested = Nested::cavity;
  //! TetGen switches; empty = tetgen_switches_for's default for the method (overrides
  //! min_dihedral_deg's switches, not its smoothing target).
  std::string tetgen_switches;
  double time_limit_seconds = 600;  //!< bound for TetGen and the optimizer each
  bool global_smoothing = false;    //!< smooth the coarse surface globally (the paper's comparison)
  bool judge_after_smoothing = true;  //!< CoarsenOptions::judge_after_smoothing
  //! If > 0, eps (and with choose_dice the dicing) is chosen so the final mesh has about this
  //! many nodes (within 10%); InputError, with the nearest reachable count, when no eps gets
  //! there. An eps whose coarsening fails is taken as too coarse by the search.
  size_t target_nodes = 0;
  //! Remesh the input with even triangles before coarsening (remesh_isotropic.h): automatic
  //! when needles are kRemeshNeedleShare or more of its triangles (CAD exports), always, or never.
  enum class Remesh { automatic, always, never };
  Remesh remesh = Remesh::automatic;
};

//! One material region of the mesh (PipelineOptions::Nested::material), judged alone.
struct RegionMeasure {
  size_t hexes = 0;
  size_t inverted = 0;
  double min_scaled_jacobian = 0;
  //! check_conformity() of the region's hexes alone (region_submesh()): its boundary, the
  //! interfaces included, closed and not folded into its own volume.
  bool conforming = false;
  size_t boundary_faces_inside = 0;
};

struct PipelineResult {
  std::string input_path;
  //! The coarsening factor used: chosen by --target-nodes or given, and smaller than that when
  //! the coarsening failed there (the "coarsen" stage report says so).
  double eps = 0;
  int dice = 0;                       //!< the dicing used (PipelineOptions::dice, or chosen for target_nodes)
  TriSurface input;                   //!< as read, repaired (PipelineOptions::repair) and verified
  //! A search tree over `input` (projection and the distance measurement used it; the writer's
  //! patches can, MeshSetsOptions::input_tree). Unset by read_and_verify alone.
  std::shared_ptr<const TriangleBvh> input_tree;
  SurfaceRepairReport repairs;        //!< what the safe repairs did (`ran` false with --repair none)
  SurfaceSummary input_summary;
  //! The input remeshed with even triangles (PipelineOptions::remesh), which the coarsening
  //! starts from; empty when it starts from the input itself. Projection and the distance
  //! measurement always use the input.
  TriSurface remeshed;
  const TriSurface& coarsening_input() const { return remeshed.triangles.empty() ? input : remeshed; }
  TriSurface coarse;                  //!< the surface TetGen meshed (the input itself for --thex-only)
  SurfaceSummary coarse_summary;
  size_t tets = 0;
  QualityStats tet_shape;             //!< of the tets THex gets (after the edits that precede it)
  HexMesh hexes;
  HexQuality quality;
  bool conforming = false;
  //! Boundary faces lying inside the mesh (the boundary folded into the volume), and the
  //! probe point of the first: part of `conforming`, named apart because it is geometric.
  size_t boundary_faces_inside = 0;
  Vec3 first_inside_point = Vec3::Zero();
  double hausdorff = 0, mean_distance = 0;  //!< hex boundary vs input, input units
  //! Enclosed by the boundary, and with material regions by their interfaces too, faced as the
  //! input's inner surfaces are (so it is outer minus inner volume, as the input's summary is);
  //! hausdorff and mean_distance likewise measure the interfaces against the inner surfaces.
  double hex_volume = 0;
  //! Per material region (HexMesh::region), when there are several; `conforming` above then
  //! also needs every region to conform on its own.
  std::vector<RegionMeasure> regions;
  size_t inverted_before_untangle = 0;
  //! Input vertices sized by wall thickness (--thickness-ratio) or, with that off and poor
  //! hexes left, on walls thinner than their size (what the summary's hint counts).
  size_t thin_wall_vertices = 0;
  //! The thickness ratio the kept mesh was sized with, and what the automatic retry did
  //! (PipelineOptions::thickness_retry; `ran` false when it did not run).
  double thickness_ratio_used = 0;
  ThicknessRetryReport thickness_retry;
  //! What the retry at a finer eps did (PipelineOptions::finer_retry; `ran` false when it did
  //! not run). `eps` above is the kept mesh's.
  FinerRetryReport finer_retry;
  std::vector<size_t> worst_hexes;          //!< ids of the worst hexes by scaled Jacobian
  //! Every stage run, in order, with its time and typed report (stage_reports.h).
  std::vector<StageRecord> stages;
  double total_seconds = 0;

  //! The report of the last stage named `name` if it is an R, else nullptr.
  template <class R>
  const R* stage_report(const std::string& name) const {
    for (auto s = stages.rbegin(); s != stages.rend(); ++s)
      if (s->name == name) return std::get_if<R>(&s->report);
    return nullptr;
  }
};

//! THex's tets keep TetGen's radius-edge bound 1.2, as the paper's baseline runs it.
//! DTHex's coarse tets are diced, untangled and smoothed afterwards, and 1.5 lets TetGen put
//! fewer points inside, so fewer hex nodes (docs/METHOD.md section 4, Tetrahedralization and
//! the tet clean-up).
constexpr const char* kThexTetgenSwitches = "pq1.2Y";
constexpr const char* kDTHexTetgenSwitches = "pq1.5Y";
//! The scaled Jacobian the local smoother and the worst-hex repair raise hexes towards when
//! PipelineOptions::min_dihedral_deg > 0 (without it, raising the target above the smoother's
//! default costs average shape and lifts the minimum little: sliver tets bound it).
constexpr double kLiftedTargetScaledJacobian = 0.4;
//! The separate lift ("lift worst") runs only where at most this share of the hexes lies below
//! its first step: above it they are a thin wall's hexes at the target, and lifting them all
//! reshapes much of the mesh for a few hundredths on the worst.
constexpr double kMostHexesToLift = 0.05;
//! The stage "slide on creases" raises the hexes within this much of the minimum (scaled
//! Jacobian) after the lift and the regions. Wider bands reshape a thin wall's many hexes near
//! the minimum for little: at 0.05 the ear drum's worst rose 0.293 -> 0.303 for average shape
//! 0.613 -> 0.604; up to the lift's top (0.4) skull_hollow's average shape fell 0.684 -> 0.654.
constexpr double kCreaseSlideBand = 0.02;
//! ... at most this many times (each a slide and the regions after it), while a round raises
//! the minimum by more than 0.001. Spot and the fandisk stop gaining after 2; the ear drum,
//! with the boundary let off the input in the regions, gains about 0.013 a round: 3 rounds
//! take it to 0.347, 4 to 0.360 (average shape 0.603 -> 0.600), 5 to 0.373 (0.596).
constexpr int kCreaseSlideRounds = 4;
//! The switches a run uses: the given ones, else the method's default above (with
//! min_dihedral_deg, DTHex's as pq1.5/DEG Y).
std::string tetgen_switches_for(const PipelineOptions& options);

//! Reads, repairs (with Repair::safe) and verifies only (InputError on a bad surface; when a
//! repair changed the surface, the message says so, since its ids are then of the repaired
//! surface). `search_tree`, if given, receives the verification's search tree over
//! result.input when it still fits (VerifyOptions).
//! Only options.repair and options.min_island_* are read.
PipelineResult read_and_verify(const std::string& input_path, Progress& progress,
                               std::unique_ptr<TriangleBvh>* search_tree = nullptr,
                               const PipelineOptions& options = PipelineOptions());

//! Runs every stage. Throws InputError (bad input) or MeshingError (a stage failed).
PipelineResult run_pipeline(const std::string& input_path, const PipelineOptions& options, Progress& progress);

//! The parts and boundary sets om_dthex writes with a result: find_mesh_sets() against the
//! input surface (with the pipeline's search tree over it, not built again), the parts named by
//! the input file's OBJ `o`/`g` names where it has them (read again from `input_path`), then
//! the user's sets. Throws InputError when a user set selects no face or repeats a name.
//! Written once for om_dthex and the benchmark harness, so both time the same write.
MeshSets find_result_sets(const PipelineResult& result, const std::string& input_path,
                          const std::vector<UserSetSpec>& user_sets = {});

}  // namespace dthex
