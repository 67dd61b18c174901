// SPDX-License-Identifier: MIT
#include <dthex/surface/coarsen.h>

#include <dthex/mesh/surface_mesh.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/triangle_crossing.h>
#include <dthex/surface/split_in_halves.h>
#include <dthex/surface/wall_thickness.h>

#include <dthex/modules/ModCurvatureSizingT.hh>
#include <dthex/modules/ModEdgeSwapT.hh>
#include <dthex/modules/ModLocalSmoothingT.hh>
#include <dthex/modules/ModNormalizedLengthT.hh>
#include <dthex/modules/RevalidatingDecimaterT.hh>
#include <dthex/modules/SweepDecimaterT.hh>

#include <OpenMesh/Tools/Decimater/Observer.hh>

#include <algorithm>
#include <chrono>
#include <exception>
#include <stdexcept>

#include <Eigen/Geometry>

namespace dthex {
namespace {

using Point = SurfaceMesh::Point;

//! Closest point on the input and the sizing field interpolated there (barycentric in the
//! closest input triangle): the size of a moved coarse vertex is the input's at its position.
class InputSurface {
 public:
  InputSurface(const TriSurface& input, const TriangleBvh& bvh, const std::vector<double>* sizes)
      : input_(input), bvh_(bvh), sizes_(sizes) {}

  Point project(const Point& p, double& size) const {
    const auto cp = bvh_.closest_point(to_eigen(p));
    if (cp.triangle < 0) return p;
    if (sizes_) size = interpolate(cp.triangle, cp.point);
    return to_openmesh(cp.point);
  }

  //! As project(), but only onto input triangles facing the same side as normal: the
  //! closest point across a thin wall (or a cavity close under the surface) is the wrong one.
  bool project_facing(const Point& p, const Point& normal, Point& out, double& size) const {
    const Vec3 towards = to_eigen(normal);
    const auto cp = bvh_.closest_point(to_eigen(p), [&](int triangle) {
      const auto& t = input_.triangles[size_t(triangle)];
      const Vec3 a = input_.points[size_t(t[0])];
      return (input_.points[size_t(t[1])] - a).cross(input_.points[size_t(t[2])] - a).dot(towards) > 0;
    });
    if (cp.triangle < 0) return false;
    if (sizes_) size = interpolate(cp.triangle, cp.point);
    out = to_openmesh(cp.point);
    return true;
  }

  //! The unit normal of the input triangle closest to p.
  bool normal_at(const Point& p, Point& normal) const {
    const auto cp = bvh_.closest_point(to_eigen(p));
    if (cp.triangle < 0) return false;
    const auto& t = input_.triangles[size_t(cp.triangle)];
    const Vec3 a = input_.points[size_t(t[0])];
    const Vec3 n = (input_.points[size_t(t[1])] - a).cross(input_.points[size_t(t[2])] - a);
    if (!(n.norm() > 0)) return false;
    normal = to_openmesh(n.normalized());
    return true;
  }

  double interpolate(int triangle, const Vec3& q) const {
    const auto& t = input_.triangles[size_t(triangle)];
    const Vec3 a = input_.points[size_t(t[0])], b = input_.points[size_t(t[1])], c = input_.points[size_t(t[2])];
    const Vec3 n = (b - a).cross(c - a);
    const double nn = n.squaredNorm();
    double wa = 1.0 / 3, wb = 1.0 / 3, wc = 1.0 / 3;
    if (nn > 0) {
      wa = std::clamp((c - b).cross(q - b).dot(n) / nn, 0.0, 1.0);
      wb = std::clamp((a - c).cross(q - c).dot(n) / nn, 0.0, 1.0);
      wc = std::clamp(1.0 - wa - wb, 0.0, 1.0);
      const double s = wa + wb + wc;
      wa /= s, wb /= s, wc /= s;
    }
    const auto& h = *sizes_;
    return wa * h[size_t(t[0])] + wb * h[size_t(t[1])] + wc * h[size_t(t[2])];
  }

 private:
  const TriSurface& input_;
  const TriangleBvh& bvh_;
  const std::vector<double>* sizes_;
};

class ProgressObserver : public OpenMesh::Decimater::Observer {
 public:
  //! `done`: collapses made before this decimater's (by a rough pass), counted as done.
  ProgressObserver(const std::function<void(double)>& progress, double total, double done = 0)
      : Observer(64), progress_(progress), total_(std::max(total, 1.0)), done_(done) {}
  void notify(size_t step) override {
    if (progress_) progress_(std::min(1.0, (done_ + double(step)) / total_));
  }

 private:
  const std::function<void(double)>& progress_;
  double total_, done_;
};

bool triangles_intersect(const TriSurface& s, int fa, int fb) {
  const auto& ta = s.triangles[size_t(fa)];
  const auto& tb = s.triangles[size_t(fb)];
  int shared = 0;
  for (int i : ta)
    for (int j : tb) shared += (i == j);
  auto P = [&](int v) -> const Vec3& { return s.points[size_t(v)]; };
  if (shared >= 3) return true;  // duplicate triangle
  if (shared == 2) return triangles_fold_onto_each_other({P(ta[0]), P(ta[1]), P(ta[2])}, {P(tb[0]), P(tb[1]), P(tb[2])});
  if (shared == 1) {
    // Only the edges opposite the shared vertex can cross the other triangle.
    auto opposite = [&](const std::array<int, 3>& t, const std::array<int, 3>& other) {
      std::array<int, 2> e{};
      int k = 0;
      for (int v : t)
        if (v != other[0] && v != other[1] && v != other[2]) e[size_t(k++)] = v;
      return e;
    };
    const auto ea = opposite(ta, tb), eb = opposite(tb, ta);
    return segment_crosses_triangle(P(ea[0]), P(ea[1]), P(tb[0]), P(tb[1]), P(tb[2]), kWithinRoundingOfPlane) ||
           segment_crosses_triangle(P(eb[0]), P(eb[1]), P(ta[0]), P(ta[1]), P(ta[2]), kWithinRoundingOfPlane);
  }
  return triangles_cross({P(ta[0]), P(ta[1]), P(ta[2])}, {P(tb[0]), P(tb[1]), P(tb[2])}, kWithinRoundingOfPlane);
}

double bbox_diagonal(const TriSurface& s) {
  Eigen::AlignedBox3d box;
  for (const Vec3& p : s.points) box.extend(p);
  return s.points.empty() ? 0.0 : box.diagonal().norm();
}

//! One coarsening run on a fresh copy of the input with the given sizes and extra locks.
struct RunOutput {
  TriSurface surface;
  std::vector<double> sizes;
  size_t collapses = 0, swaps = 0, moves = 0, rough_collapses = 0;
  size_t cut_vertices = 0;
};

//! Counts of one decimation.
struct DecimationCounts {
  size_t collapses = 0, swaps = 0, moves = 0, rough_collapses = 0;
};

// The collapse test's bounds and the edge swap's, as both decimations (the rough pass and the
// full one) set them from the options.
NormalizedLengthLimits length_limits_for(const CoarsenOptions& options) {
  NormalizedLengthLimits limits;
  limits.max_normalized_length = options.max_normalized_length;
  limits.max_normal_deviation_deg = options.max_normal_deviation_deg;
  limits.min_shape = options.min_shape;
  return limits;
}

EdgeSwapOptions swap_options_for(const CoarsenOptions& options) {
  EdgeSwapOptions swap_options;
  swap_options.max_dihedral_deg = options.swap_max_dihedral_deg;
  swap_options.max_normalized_length = options.max_normalized_length;
  return swap_options;
}

//! The cheap first pass of CoarsenOptions::rough_pass_from_vertices on a mesh whose status and
//! sizes are set: collapses only edges shorter than `fraction` of their size (the sizes are
//! scaled by it meanwhile, so every bound of ModNormalizedLengthT holds at that scale), with
//! edge swaps but without smoothing, placement or surface-normal test. Every vertex left is an
//! input vertex where it was, with its own size, so no closest-point query is needed.
DecimationCounts rough_pass(SurfaceMesh& mesh, const CoarsenOptions& options, double fraction) {
  const auto size = size_property(mesh);
  std::vector<double> sizes(mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    sizes[size_t(v.idx())] = mesh.property(size, v);
    mesh.property(size, v) *= fraction;
  }
  // No vertex moves, and nothing reads the stored face normals: rather than keep them up to
  // date through every collapse and swap, they are computed again at the end.
  const bool face_normals = mesh.has_face_normals();
  if (face_normals) mesh.release_face_normals();
  DecimationCounts out;
  {
    SweepDecimaterT<SurfaceMesh> decimater(mesh);
    ModNormalizedLengthT<SurfaceMesh>::Handle length;
    ModEdgeSwapT<SurfaceMesh>::Handle swap;
    decimater.add(length);
    decimater.module(length).set_limits(length_limits_for(options));
    if (options.edge_swap) {
      decimater.add(swap);
      decimater.module(swap).set_options(swap_options_for(options));
    }
    decimater.set_priority_estimate([&mesh, size](const ModNormalizedLengthT<SurfaceMesh>::CollapseInfo& ci) {
      return ModNormalizedLengthT<SurfaceMesh>::priority_estimate(mesh, size, ci);
    });
    if (!decimater.initialize()) throw MeshingError("coarsening: the decimater modules failed to initialize");
    out.collapses = decimater.decimate();
    if (options.edge_swap) out.swaps = decimater.module(swap).n_swaps();
  }
  for (auto v : mesh.vertices()) mesh.property(size, v) = sizes[size_t(v.idx())];
  if (face_normals) {
    mesh.request_face_normals();
    mesh.update_face_normals();
  }
  return out;
}

//! Decimates a mesh whose status (features, locks) and sizes are set, with the DTHex modules.
//! `progress_total`: the collapses that count as done (0: no progress reports). `rough`: run
//! rough_pass first (CoarsenOptions::rough_pass_from_vertices).
DecimationCounts decimate_prepared(SurfaceMesh& mesh, const InputSurface& surface, const CoarsenOptions& options,
                                   double progress_total, bool rough) {
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  const auto size = size_property(mesh);
  DecimationCounts out;
  if (rough) {
    out = rough_pass(mesh, options, options.rough_pass_fraction);
    out.rough_collapses = out.collapses;
  }
  RevalidatingDecimaterT<SurfaceMesh> decimater(mesh);
  ModCurvatureSizingT<SurfaceMesh>::Handle sizing;
  ModNormalizedLengthT<SurfaceMesh>::Handle length;
  ModEdgeSwapT<SurfaceMesh>::Handle swap;
  ModLocalSmoothingT<SurfaceMesh>::Handle smoothing;
  decimater.add(sizing);
  decimater.module(sizing).set_compute_on_initialize(false);  // h is given
  decimater.add(length);
  decimater.module(length).set_limits(length_limits_for(options));
  if (options.max_surface_deviation_deg < 180)
    decimater.module(length).set_surface_normal(
        [&surface](const Point& p, Point& n) { return surface.normal_at(p, n); }, options.max_surface_deviation_deg);
  if (options.edge_swap) {
    decimater.add(swap);
    decimater.module(swap).set_options(swap_options_for(options));
  }
  if (options.local_smoothing) {
    decimater.add(smoothing);
    ModLocalSmoothingT<SurfaceMesh>::Options smooth_options;
    smooth_options.c1 = options.smoothing_c1;
    smooth_options.max_normal_deviation_deg = options.max_normal_deviation_deg;
    smooth_options.max_normalized_length = options.max_normalized_length;
    smooth_options.projection = [&surface](const Point& p, double& s) { return surface.project(p, s); };
    decimater.module(smoothing).set_options(smooth_options);
    // Bounds judged after the smoothing that follows each collapse (see set_placement).
    if (options.judge_after_smoothing)
      decimater.module(length).set_placement(
          [&surface, smooth_options, size](const SurfaceMesh& m,
                                           const ModNormalizedLengthT<SurfaceMesh>::CollapseInfo& ci,
                                           Point& position, double& h) {
            auto unprojected = smooth_options;
            unprojected.projection = nullptr;
            if (!smoothed_collapse_target(m, ci, unprojected, size, position, h)) return false;
            return surface.project_facing(position, vertex_normal(m, ci.v1), position, h);
          });
  }
  decimater.set_priority_estimate([&mesh, size](const ModNormalizedLengthT<SurfaceMesh>::CollapseInfo& ci) {
    return ModNormalizedLengthT<SurfaceMesh>::priority_estimate(mesh, size, ci);
  });
  static const std::function<void(double)> no_progress;
  ProgressObserver observer(progress_total > 0 ? options.progress : no_progress, progress_total, double(out.collapses));
  decimater.set_observer(&observer);
  if (!decimater.initialize()) throw MeshingError("coarsening: the decimater modules failed to initialize");
  out.collapses += decimater.decimate();
  if (options.edge_swap) out.swaps += decimater.module(swap).n_swaps();
  if (options.local_smoothing) out.moves += decimater.module(smoothing).n_moves();
  decimater.set_observer(nullptr);
  return out;
}

//! Decimates `whole` in two halves at once, one per core, then the joined mesh, which only
//! has the cut left to remove; the result goes to `joined`. False if it cannot be split.
//! `whole` itself is not copied: the run's sizes and locks travel in `extras`. `cut_ahead`:
//! `whole` already cut (split_connectivity), or null.
bool decimate_in_halves(const SurfaceMesh& whole, const SplitExtras& extras, const InputSurface& surface,
                        const CoarsenOptions& options, bool rough, SurfaceMesh& joined, DecimationCounts& counts,
                        size_t& cut_vertices, SurfaceHalves* cut_ahead) {
  SurfaceHalves own;
  SurfaceHalves& split = cut_ahead ? *cut_ahead : own;
  if (cut_ahead) mark_halves(whole, split, extras);
  else if (!split_in_halves(whole, split, extras)) return false;
  cut_vertices = split.cut_vertices;
  DecimationCounts half_counts[2];
  std::exception_ptr failure[2];
  const double total = 0.9 * double(whole.n_vertices());
#pragma omp parallel for num_threads(2) schedule(static, 1)
  for (int p = 0; p < 2; ++p) {
    try {
      // Only the first half reports progress (the callback is not made for two threads).
      half_counts[p] = decimate_prepared(split.halves[size_t(p)], surface, options, p == 0 ? 0.5 * total : 0, rough);
    } catch (...) {
      failure[p] = std::current_exception();
    }
  }
  for (const auto& f : failure)
    if (f) std::rethrow_exception(f);
  joined = join_halves(split, whole, extras);
  counts = decimate_prepared(joined, surface, options, 0, false);
  for (const auto& c : half_counts) {
    counts.collapses += c.collapses;
    counts.swaps += c.swaps;
    counts.moves += c.moves;
    counts.rough_collapses += c.rough_collapses;
  }
  return true;
}

//! `cut_ahead`: input_mesh already cut (split_connectivity), or null.
RunOutput run_once(const SurfaceMesh& input_mesh, const TriSurface& input, const TriangleBvh& input_bvh,
                   const std::vector<double>& h, const std::vector<char>& locked, const CoarsenOptions& options,
                   std::unique_ptr<SurfaceHalves> cut_ahead) {
  const InputSurface surface(input, input_bvh, &h);
  DecimationCounts counts;
  RunOutput out;
  SurfaceMesh mesh;
  const bool rough = options.rough_pass_from_vertices > 0 && input_mesh.n_vertices() >= options.rough_pass_from_vertices;
  const bool halves =
      options.split_from_vertices > 0 && input_mesh.n_vertices() >= options.split_from_vertices &&
      decimate_in_halves(input_mesh, SplitExtras{&h, &locked}, surface, options, rough, mesh, counts, out.cut_vertices,
                         cut_ahead.get());
  if (!halves) {
    // The copy keeps the input's feature and corner marks (coarsen() made them).
    mesh = input_mesh;
    // Status must be requested by the app, not only by the decimater (notes section 1).
    mesh.request_vertex_status();
    mesh.request_edge_status();
    mesh.request_face_status();
    for (auto v : mesh.vertices())
      if (locked[size_t(v.idx())]) mesh.status(v).set_locked(true);
    const auto size = size_property(mesh);
    for (auto v : mesh.vertices()) mesh.property(size, v) = h[size_t(v.idx())];
    counts = decimate_prepared(mesh, surface, options, 0.9 * double(input.points.size()), rough);
  }
  out.collapses = counts.collapses;
  out.swaps = counts.swaps;
  out.moves = counts.moves;
  out.rough_collapses = counts.rough_collapses;
  const auto final_size = size_property(mesh);
  for (auto v : mesh.vertices())
    if (!mesh.status(v).deleted()) out.sizes.push_back(mesh.property(final_size, v));
  out.surface = from_openmesh(mesh);
  return out;
}

CurvatureSizingOptions sizing_options(const CoarsenOptions& options) {
  CurvatureSizingOptions sizing;
  sizing.eps = options.eps;
  sizing.h_min = options.h_min;
  sizing.h_max = options.h_max;
  sizing.gradation = options.gradation;
  return sizing;
}

//! The input vertices on a wall thinner than h / ratio (never counting one whose size
//! would stay at h_min); with `apply`, their sizes become ratio x the thickness and the
//! gradation is restored.
size_t cap_by_wall_thickness(const TriSurface& input, const SurfaceMesh& input_mesh, const TriangleBvh& input_bvh,
                             double ratio, double gradation, double h_min, bool apply, std::vector<double>& h) {
  // Only "is the wall thinner than h / ratio here?" matters: the search starts at that
  // ball (radius half of it), and an empty one costs a single query.
  std::vector<double> start(h.size());
  for (size_t v = 0; v < h.size(); ++v) start[v] = h[v] / (2 * ratio);
  const std::vector<double> radius = inner_wall_radii(input, input_bvh, start);
  size_t thin = 0;
  for (size_t v = 0; v < h.size(); ++v) {
    // An empty starting ball is no thin wall: its radius came back unchanged, and
    // 2 x ratio x (h / (2 x ratio)) can round below h when ratio is not a power of two.
    if (!(radius[v] < start[v])) continue;
    const double cap = std::max(h_min, 2 * ratio * radius[v]);
    if (!(cap < h[v])) continue;
    ++thin;
    if (apply) h[v] = cap;
  }
  if (apply && thin) limit_gradation(input_mesh, h, gradation);
  return thin;
}

void require_feature_angle(const CoarseningInput& input, const CoarsenOptions& options) {
  if (options.feature_angle_deg != input.feature_angle_deg())
    throw std::invalid_argument("coarsening: the prepared input's feature angle is not the options' one");
}

}  // namespace

CoarseningInput::CoarseningInput(const TriSurface& input, const CoarsenOptions& options, const TriangleBvh* bvh,
                                 bool cut_ahead)
    : input_(input), bvh_(bvh), feature_angle_deg_(options.feature_angle_deg) {
  if (input.triangles.empty()) throw InputError("coarsen: the surface has no triangles");
  fill_openmesh(mesh_, input);
  // The sizing follows feature lines, not creases; every run starts from a copy with these marks.
  features_ = mark_features(mesh_, feature_angle_deg_);
  made_eps_ = options.eps, made_h_min_ = options.h_min, made_h_max_ = options.h_max;
  made_gradation_ = options.gradation;
  // Its loop runs on both cores; inside a section below it would run on one.
  radii_ = osculating_radii(mesh_);
  // The sizes and the halves only read mesh_ from here on: one core each. An exception must
  // not leave the parallel region (out of memory there ended the program).
  cut_ahead = cut_ahead && options.split_from_vertices > 0 && mesh_.n_vertices() >= options.split_from_vertices;
  std::exception_ptr failure[2];
#pragma omp parallel sections num_threads(2) if (cut_ahead)
  {
#pragma omp section
    try {
      const AutomaticSizeBounds automatic = automatic_size_bounds(mesh_);
      mean_edge_ = automatic.mean_edge;
      half_diagonal_ = automatic.half_diagonal;
      sizes_ = sizing_from_radii(mesh_, radii_, size_bounds(options), sizing_options(options));
    } catch (...) {
      failure[0] = std::current_exception();
    }
#pragma omp section
    try {
      if (cut_ahead) {
        auto halves = std::make_unique<SurfaceHalves>();
        if (split_connectivity(mesh_, *halves)) halves_ = std::move(halves);
      }
    } catch (...) {
      failure[1] = std::current_exception();
    }
  }
  for (const auto& f : failure)
    if (f) std::rethrow_exception(f);
  if (!bvh_) own_bvh_ = std::make_unique<TriangleBvh>(input);
}

std::pair<double, double> CoarseningInput::size_bounds(const CoarsenOptions& options) const {
  return sizing_bounds(AutomaticSizeBounds{mean_edge_, half_diagonal_}, sizing_options(options));
}

std::vector<double> CoarseningInput::sizes(const CoarsenOptions& options) const {
  if (options.eps == made_eps_ && options.h_min == made_h_min_ && options.h_max == made_h_max_ &&
      options.gradation == made_gradation_)
    return sizes_;
  return sizing_from_radii(mesh_, radii_, size_bounds(options), sizing_options(options));
}

size_t count_thin_wall_vertices(const TriSurface& input, const CoarsenOptions& options) {
  if (input.triangles.empty()) return 0;
  return count_thin_wall_vertices(CoarseningInput(input, options, nullptr, false), options);
}

size_t count_thin_wall_vertices(const CoarseningInput& input, const CoarsenOptions& options) {
  require_feature_angle(input, options);
  std::vector<double> h = input.sizes(options);
  const double ratio = options.max_size_per_thickness > 0 ? options.max_size_per_thickness : 1.0;
  return cap_by_wall_thickness(input.surface(), input.mesh(), input.bvh(), ratio, options.gradation,
                               input.size_bounds(options).first, false, h);
}

std::vector<std::array<int, 2>> self_intersections(const TriSurface& surface) {
  const TriangleBvh bvh(surface);
  std::vector<std::array<int, 2>> pairs;
  bvh.for_each_overlapping_pair([&](int a, int b) {
    if (triangles_intersect(surface, a, b)) pairs.push_back({std::min(a, b), std::max(a, b)});
  });
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

CoarsenResult coarsen(const TriSurface& input, const CoarsenOptions& options, const TriangleBvh* input_bvh) {
  const auto start = std::chrono::steady_clock::now();
  CoarseningInput prepared(input, options, input_bvh);
  CoarsenResult result = coarsen(prepared, options);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

CoarsenResult coarsen(CoarseningInput& prepared, const CoarsenOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  require_feature_angle(prepared, options);
  const TriSurface& input = prepared.surface();
  const SurfaceMesh& input_mesh = prepared.mesh();
  const TriangleBvh& input_bvh = prepared.bvh();
  CoarsenResult result;
  result.input_vertices = input.points.size();
  std::tie(result.h_min, result.h_max) = prepared.size_bounds(options);
  std::vector<double> h = prepared.sizes(options);
  if (options.max_size_per_thickness > 0)
    result.thin_wall_vertices = cap_by_wall_thickness(input, input_mesh, input_bvh, options.max_size_per_thickness,
                                                      options.gradation, result.h_min, true, h);
  result.feature_edges = prepared.features().edges.size();
  result.feature_corners = prepared.features().corners.size();

  std::vector<char> locked(input.points.size(), 0), halve(input.points.size(), 0);
  RunOutput run;
  for (int round = 0;; ++round) {
    run = run_once(input_mesh, input, input_bvh, h, locked, options, prepared.take_halves());
    const auto crossings = self_intersections(run.surface);
    if (crossings.empty()) break;
    if (round >= options.max_repair_rounds)
      throw MeshingError("coarsening: " + std::to_string(crossings.size()) +
                         " self-intersecting triangle pairs remain after " + std::to_string(round) +
                         " repair rounds (first: triangles " + std::to_string(crossings[0][0]) + " and " +
                         std::to_string(crossings[0][1]) + ")");
    // Around each offending triangle: halve the sizes (shorter chords dip less), and in the
    // last round keep the input vertices there (the input does not self-intersect).
    const bool lock = round + 1 >= options.max_repair_rounds;
    for (const auto& pair : crossings)
      for (int f : pair) {
        Eigen::AlignedBox3d box;
        double reach = 0;
        for (int v : run.surface.triangles[size_t(f)]) {
          box.extend(run.surface.points[size_t(v)]);
          reach = std::max(reach, run.sizes[size_t(v)]);
        }
        box.min().array() -= reach;
        box.max().array() += reach;
        input_bvh.for_each_in_box(box, [&](int t) {
          for (int v : input.triangles[size_t(t)]) {
            if (!box.contains(input.points[size_t(v)])) continue;
            if (lock) locked[size_t(v)] = 1;
            else halve[size_t(v)] = 1;
          }
        });
      }
    for (size_t v = 0; v < h.size(); ++v)
      if (halve[v]) h[v] *= 0.5;
    std::fill(halve.begin(), halve.end(), 0);
    limit_gradation(input_mesh, h, options.gradation);
    ++result.repair_rounds;
  }
  result.surface = std::move(run.surface);
  result.sizes = std::move(run.sizes);
  result.collapses = run.collapses;
  result.swaps = run.swaps;
  result.smoothing_moves = run.moves;
  result.rough_collapses = run.rough_collapses;
  result.cut_vertices = run.cut_vertices;

  if (options.global_smoothing) {
    GlobalSmoothingOptions global;
    global.max_normal_deviation_deg = options.max_normal_deviation_deg;
    global.feature_angle_deg = options.feature_angle_deg;
    TriSurface smoothed = result.surface;
    std::vector<double> sizes = result.sizes;
    const size_t iterations = global_smoothing(smoothed, input, global, &sizes, &h);
    if (self_intersections(smoothed).empty()) {  // otherwise keep the surface before smoothing
      result.surface = std::move(smoothed);
      result.sizes = std::move(sizes);
      result.global_smoothing_iterations = iterations;
    }
  }
  if (options.progress) options.progress(1.0);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

size_t global_smoothing(TriSurface& coarse, const TriSurface& input, const GlobalSmoothingOptions& options,
                        std::vector<double>* sizes, const std::vector<double>* input_sizes) {
  const bool with_sizes = sizes && input_sizes && sizes->size() == coarse.points.size();
  const TriangleBvh bvh(input);
  const InputSurface surface(input, bvh, with_sizes ? input_sizes : nullptr);
  SurfaceMesh mesh = to_openmesh(coarse);
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  mark_features(mesh, options.feature_angle_deg);
  OpenMesh::VPropHandleT<double> size;
  if (with_sizes) {
    size = size_property(mesh);
    for (auto v : mesh.vertices()) mesh.property(size, v) = (*sizes)[size_t(v.idx())];
  }
  LocalSmoothingOptions<Point> smooth;
  smooth.c1 = 1.0;  // area-weighted centroid pull
  smooth.max_normal_deviation_deg = options.max_normal_deviation_deg;
  smooth.projection = [&surface](const Point& p, double& s) { return surface.project(p, s); };
  const double limit = options.tolerance * bbox_diagonal(input);
  size_t iterations = 0;
  while (iterations < options.max_iterations) {
    ++iterations;
    double largest = 0;
    for (auto v : mesh.vertices()) {
      const Point before = mesh.point(v);
      if (smooth_vertex(mesh, v, smooth, size)) largest = std::max(largest, (mesh.point(v) - before).norm());
    }
    if (largest <= limit) break;
  }
  // Vertex and triangle order are unchanged (no deletions).
  for (auto v : mesh.vertices()) {
    coarse.points[size_t(v.idx())] = to_eigen(mesh.point(v));
    if (with_sizes) (*sizes)[size_t(v.idx())] = mesh.property(size, v);
  }
  return iterations;
}

}  // namespace dthex
