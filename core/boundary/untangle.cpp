// SPDX-License-Identifier: MIT
#include <dthex/boundary/untangle.h>

#include <dthex/hexes/conformity.h>
#include <dthex/mesh/graph_colouring.h>
#include <dthex/mesh/hex_topology.h>
#include <dthex/mesh/incidence.h>
#include <dthex/numerics/inverse_cube_root.h>
#include <dthex/numerics/lbfgs.h>

#include <dthex/mesh/quality.h>
#include <dthex/numerics/tangent_basis.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>

namespace dthex {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();
//! Below this many hexes (or nodes) a loop runs on one thread: waking threads costs more.
constexpr long kParallelThreshold = 20000;
//! A hex counts as inverted at scaled Jacobian <= this: a margin over Verdict's <= 0.
constexpr double kInvertedBelow = 1e-6;
//! Garanzha's epsilon once every frame is valid: the energy is then a barrier.
constexpr double kBarrierEps = 1e-10;
//! How far (in local edge lengths) a boundary node may slide in one round.
constexpr double kMaxSlidePerRound = 0.2;

// Garanzha's regularized determinant chi(D, eps) = (D + sqrt(eps^2 + D^2)) / 2, stable for D <= 0.
inline double chi(double d, double eps) {
  const double root = std::sqrt(eps * eps + d * d);
  return d > 0 ? 0.5 * (d + root) : 0.5 * eps * eps / (root - d);
}

//! Garanzha's per-frame energy (1 - theta) |J|^2 / chi^(2/3) + theta (1 + det^2) / chi for
//! the (up to 9) frames of one hex, and its gradient with respect to each J, which is
//! jac_weight J + det_weight cof(J).
struct FrameBatch {
  int count = 0;
  int frame[9];  //!< corner frame 0-7, or 8 for the centre frame
  Eigen::Matrix3d jac[9], cof[9];
  double det[9], energy[9], jac_weight[9], det_weight[9];

  void evaluate(double eps, double theta, bool need_gradient) {
    double frob[9];
    for (int f = 0; f < count; ++f) {
      const Eigen::Matrix3d& j = jac[f];
      cof[f].col(0) = j.col(1).cross(j.col(2));
      cof[f].col(1) = j.col(2).cross(j.col(0));
      cof[f].col(2) = j.col(0).cross(j.col(1));
      det[f] = j.col(0).dot(cof[f].col(0));
      frob[f] = j.squaredNorm();
    }
    for (int f = 0; f < count; ++f) {
      const double d = det[f];
      const double root = std::sqrt(eps * eps + d * d);
      const double c = d > 0 ? 0.5 * (d + root) : 0.5 * eps * eps / (root - d);  // chi(det, eps)
      const double inv_c = 1.0 / c;
      const double inv_cube_root = inverse_cube_root(c);
      const double c23 = inv_cube_root * inv_cube_root;  // c^(-2/3)
      energy[f] = (1 - theta) * frob[f] * c23 + theta * (1 + d * d) * inv_c;
      if (!need_gradient) continue;
      const double dc = c / root;  // d chi / d det
      det_weight[f] = -(2.0 / 3.0) * (1 - theta) * frob[f] * c23 * inv_c * dc +
                      theta * (2 * d * inv_c - (1 + d * d) * dc * inv_c * inv_c);
      jac_weight[f] = 2 * (1 - theta) * c23;
    }
  }
};

//! The variables and energy terms of one repair or shape problem. Problems whose active
//! hexes are disjoint touch disjoint entries of the per-node arrays, so each thread solves
//! its own with its own Phase.
struct Phase {
  std::vector<size_t> movable_nodes, sliding_nodes;
  std::vector<size_t> active_hexes;     //!< sorted: hexes with a movable node
  std::vector<unsigned> active_frames;  //!< per active hex: bit k set if frame k can move
  std::vector<int> incidence_start, incidence;  //!< per movable node: slots a * 8 + j in hex_gradient
  std::vector<Vec3> hex_gradient;
  int rounds = 0;
  bool timed_out = false;
  //! The energy's work in this problem: hexes evaluated, summed over its evaluations; while
  //! the stall bound is watched, the problem stops once it reaches work_cap.
  long work = 0, work_cap = std::numeric_limits<long>::max();
};

class Untangler {
 public:
  Untangler(HexMesh& mesh, const TriangleBvh& bvh, const UntangleOptions& options)
      : mesh_(mesh), bvh_(bvh), options_(options) {
    deadline_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(options.time_limit_seconds));
    const size_t n_nodes = mesh.nodes.size();
    // Boundary nodes: those of the faces used by one hex only, and those with a facet.
    const std::vector<char> on_boundary = boundary_nodes(mesh, options.constraints ? &options.constraints->on_boundary : nullptr);
    is_boundary_.assign(on_boundary.begin(), on_boundary.end());
    // Per-hex reference size (mean edge length) and per-node variable scale.
    hex_size_.resize(mesh.hexes.size());
    node_scale_.assign(n_nodes, 0.0);
    std::vector<int> count(n_nodes, 0);
    constexpr int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                  {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (size_t h = 0; h < mesh.hexes.size(); ++h) {
      double sum = 0;
      for (const auto& e : edges) sum += (node(h, e[0]) - node(h, e[1])).norm();
      hex_size_[h] = std::max(sum / 12.0, 1e-300);
      for (int v : mesh.hexes[h]) node_scale_[size_t(v)] += hex_size_[h], ++count[size_t(v)];
    }
    for (size_t v = 0; v < n_nodes; ++v) node_scale_[v] = count[v] ? node_scale_[v] / count[v] : 1.0;
    node_hexes_ = NodeCellIncidence(n_nodes, mesh.hexes);
  }

  UntangleReport run() {
    const auto start = Clock::now();
    UntangleReport report;
    const size_t n_nodes = mesh_.nodes.size(), n_hexes = mesh_.hexes.size();
    scaled_jacobian_.resize(n_hexes);
    update_scaled_jacobians(n_hexes, [](size_t h) { return h; });
    report.inverted_before = size_t(
        std::count_if(scaled_jacobian_.begin(), scaled_jacobian_.end(), [](double sj) { return sj <= 0; }));
    pos_ = mesh_.nodes;
    base_ = mesh_.nodes;
    // Where the regularized energy cannot untangle, it lowers itself by flattening hexes
    // instead, and can hand on more inverted hexes than came in. A run that ends worse than
    // it began is undone.
    const std::vector<Vec3> given = mesh_.nodes;
    tangent1_.assign(n_nodes, Vec3::Zero());
    tangent2_.assign(n_nodes, Vec3::Zero());
    var_offset_.assign(n_nodes, -1);

    std::vector<char> ever_sliding(n_nodes, 0);
    // Local repair: nodes within a few hex rings of every hex below the target move; with
    // `slide` the boundary nodes among them slide on the surface too. True if it ran.
    auto repair = [&](double threshold, bool slide, int rounds) {
      std::vector<size_t> seeds;
      for (size_t h = 0; h < n_hexes; ++h)
        if (scaled_jacobian_[h] < threshold) seeds.push_back(h);
      if (seeds.empty()) return false;
      std::vector<size_t> movable;
      for (size_t v : grow_region(seeds, options_.region_rings))
        if (!is_boundary_[v] || slide) movable.push_back(v);
      for (size_t v : movable)
        if (is_boundary_[v]) ever_sliding[v] = 1;
      // Each connected part on its own: a part that is repaired stops, a hard one does not
      // hold the step length and the rounds of the others.
      solve_parts(connected_parts(movable, movable.size()), rounds, options_.max_lbfgs_iterations, report);
      return true;
    };
    auto min_scaled_jacobian = [&] { return *std::min_element(scaled_jacobian_.begin(), scaled_jacobian_.end()); };

    // 1. Inverted hexes first, interior nodes only, then with the boundary sliding.
    const int fixed_rounds = options_.slide_boundary ? options_.fixed_boundary_rounds : options_.max_rounds;
    // The interior-only repair gives up on a part whose worst frame cannot become valid in
    // the rounds left at its present pace: the sliding repair that follows undoes such a
    // fold in a few rounds, where the fixed boundary would spend all its rounds on hopeless
    // parts and still leave them inverted.
    give_up_hopeless_ = options_.slide_boundary;
    watch_stall_ = true;
    fewest_inverted_ = inverted_count();
    work_since_fall_ = 0;
    repair(kInvertedBelow, false, fixed_rounds);
    give_up_hopeless_ = false;
    // The sliding passes get their own stall window: they undo what the fixed boundary
    // cannot. A sliding pass that removes no inverted hex stalls the repair: the next would
    // start from the same folds.
    if (options_.slide_boundary) stalled_ = false, work_since_fall_ = 0;
    size_t before_pass = inverted_count();
    for (int phase = 0; phase < options_.max_boundary_phases && options_.slide_boundary && !report.time_limit_reached &&
                        !stalled_;
         ++phase) {
      if (!repair(kInvertedBelow, true, options_.max_rounds)) break;
      const size_t after_pass = inverted_count();
      if (after_pass > 0 && after_pass >= before_pass && options_.stall_work > 0) stalled_ = true;
      before_pass = after_pass;
    }
    watch_stall_ = false;
    const double stalled_after = std::chrono::duration<double>(Clock::now() - start).count();
    // 2. Shape where it is poor (a barrier once nothing is inverted). Each connected part of
    // the region is its own problem: one near-flat frame then limits the steps of its own
    // part only, not of the whole mesh, and a part stops when it has converged.
    if (options_.smoothing_iterations > 0 && !report.time_limit_reached) {
      std::vector<size_t> seeds;
      const bool everywhere = options_.smoothing_shape_threshold >= 1;
      for (size_t h = 0; h < n_hexes; ++h)
        if (everywhere || hex_shape(hex_corners(mesh_, h)) < options_.smoothing_shape_threshold) seeds.push_back(h);
      std::vector<size_t> movable;
      for (size_t v : grow_region(seeds, everywhere ? 0 : options_.smoothing_rings))
        if (!is_boundary_[v]) movable.push_back(v);
      solve_parts(connected_parts(movable, size_t(options_.smoothing_part_nodes)), options_.smoothing_rounds,
                  options_.smoothing_iterations, report);
    }
    // 3. What is still below the target, locally, the boundary sliding where it must (not
    // when that is only the inverted hexes whose repair stalled).
    const bool only_stalled = stalled_ && options_.target_scaled_jacobian <= kInvertedBelow;
    if (!report.time_limit_reached && !only_stalled) repair(options_.target_scaled_jacobian, false, fixed_rounds);
    for (int phase = 0;
         phase < options_.max_boundary_phases && options_.slide_boundary && !report.time_limit_reached && !only_stalled;
         ++phase) {
      const double before = min_scaled_jacobian();
      if (!repair(options_.target_scaled_jacobian, true, options_.max_rounds)) break;
      if (min_scaled_jacobian() <= before + 1e-3) break;  // no progress
    }
    report.sliding_boundary_nodes = size_t(std::count(ever_sliding.begin(), ever_sliding.end(), 1));

    HexQuality q = measure_hex_quality(mesh_);
    if (q.inverted > report.inverted_before) {
      mesh_.nodes = given;
      q = measure_hex_quality(mesh_);
      report.undone = true;
    }
    report.inverted_after = q.inverted;
    // Said only where the stall left inverted hexes (not where it stopped at a few frames just
    // above zero, which the smoother lifts).
    if (stalled_ && q.inverted > 0) report.stalled = true, report.stalled_after_seconds = stalled_after;
    report.min_scaled_jacobian = q.scaled_jacobian_stats.min;
    report.avg_shape = q.shape_stats.avg;
    report.min_shape = q.shape_stats.min;
    std::vector<size_t> order(mesh_.hexes.size());
    std::iota(order.begin(), order.end(), size_t(0));
    const size_t n_worst = std::min(options_.report_worst, order.size());
    std::partial_sort(order.begin(), order.begin() + long(n_worst), order.end(),
                      [&](size_t a, size_t b) { return q.scaled_jacobian[a] < q.scaled_jacobian[b]; });
    report.worst_hexes.assign(order.begin(), order.begin() + long(n_worst));
    report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return report;
  }

 private:
  const Vec3& node(size_t h, int i) const { return mesh_.nodes[size_t(mesh_.hexes[h][size_t(i)])]; }

  //! Recomputes the scaled Jacobian of `count` hexes, the i-th being hex_of(i).
  template <class HexOf>
  void update_scaled_jacobians(size_t count, HexOf&& hex_of) {
#pragma omp parallel for schedule(static) if (long(count) > kParallelThreshold)
    for (long i = 0; i < long(count); ++i) {
      const size_t h = hex_of(size_t(i));
      scaled_jacobian_[h] = hex_scaled_jacobian(hex_corners(mesh_, h));
    }
  }

  //! The nodes of `seed_hexes` and of every hex within `rings` rings of them, in
  //! increasing order: found from the seeds outwards, so the cost follows the region.
  std::vector<size_t> grow_region(const std::vector<size_t>& seed_hexes, int rings) {
    std::vector<size_t> nodes, frontier;
    in_region_.resize(mesh_.nodes.size(), 0);
    auto add_hex = [&](size_t h, std::vector<size_t>& added) {
      for (int v : mesh_.hexes[h])
        if (!in_region_[size_t(v)]) in_region_[size_t(v)] = 1, added.push_back(size_t(v));
    };
    for (size_t h : seed_hexes) add_hex(h, frontier);
    for (int ring = 0; ring < rings; ++ring) {
      std::vector<size_t> next;
      for (size_t v : frontier)
        for (int h : node_hexes_[v]) add_hex(size_t(h), next);
      nodes.insert(nodes.end(), frontier.begin(), frontier.end());
      frontier.swap(next);
    }
    nodes.insert(nodes.end(), frontier.begin(), frontier.end());
    for (size_t v : nodes) in_region_[v] = 0;
    std::sort(nodes.begin(), nodes.end());
    return nodes;
  }

  //! `nodes` (sorted) split into sets that share no hex, each sorted; a connected set of
  //! more than `max_nodes` is cut into pieces of that many grown breadth-first (solve_parts
  //! solves neighbouring pieces one after the other, so each sees where the other moved).
  std::vector<std::vector<size_t>> connected_parts(const std::vector<size_t>& nodes, size_t max_nodes) {
    std::vector<std::vector<size_t>> parts;
    in_region_.resize(mesh_.nodes.size(), 0);
    for (size_t v : nodes) in_region_[v] = 1;
    for (size_t seed : nodes) {
      if (in_region_[seed] != 1) continue;
      std::vector<size_t> part = {seed};
      in_region_[seed] = 2;
      for (size_t i = 0; i < part.size(); ++i)
        for (int h : node_hexes_[part[i]])
          for (int u : mesh_.hexes[size_t(h)])
            if (in_region_[size_t(u)] == 1 && part.size() < max_nodes) in_region_[size_t(u)] = 2, part.push_back(size_t(u));
      std::sort(part.begin(), part.end());
      parts.push_back(std::move(part));
    }
    for (size_t v : nodes) in_region_[v] = 0;
    return parts;
  }

  //! Solves every part, each with run_phase. Parts are coloured so that two of one colour
  //! share no hex; the colours run one after the other (a part sees where the parts of
  //! earlier colours moved their nodes) and the parts of one colour on all threads. The
  //! result does not depend on the number of threads.
  void solve_parts(const std::vector<std::vector<size_t>>& parts, int rounds, int iterations, UntangleReport& report) {
    if (parts.empty() || report.time_limit_reached) return;
    // Greedy colouring over the hexes the parts touch: a part takes the lowest colour no
    // part already coloured uses on any of its hexes. 64 colours; a part that finds them all
    // taken is solved alone after the others.
    constexpr int kColours = 64;
    GreedyCellColouring colouring(mesh_.hexes.size(), kColours);
    std::vector<std::vector<size_t>> by_colour(kColours + 1);
    std::vector<int> hexes;
    for (size_t p = 0; p < parts.size(); ++p) {
      hexes.clear();
      for (size_t v : parts[p])
        for (int h : node_hexes_[v]) hexes.push_back(h);
      by_colour[colouring.add(hexes.data(), hexes.data() + hexes.size())].push_back(p);
    }
    for (size_t colour = 0; colour <= kColours && !report.time_limit_reached && !stalled_; ++colour) {
      const auto& batch = by_colour[colour];
      // Each part in the last list may share hexes with any other: one at a time.
      const bool parallel = colour < kColours && batch.size() > 1;
      // While the inverted hexes are repaired, each part may do the work the stall bound
      // leaves: counted, not timed, so the parts stop at the same point in every run.
      const long work_cap = stall_watched() ? std::max(0L, options_.stall_work - work_since_fall_)
                                            : std::numeric_limits<long>::max();
      int rounds_done = 0;
      long work_done = 0;
      bool timed_out = false;
#pragma omp parallel if (parallel) reduction(+ : rounds_done, work_done) reduction(|| : timed_out)
      {
        Phase ph;
        ph.work_cap = work_cap;
#pragma omp for schedule(dynamic, 1)
        for (long i = 0; i < long(batch.size()); ++i) {
          if (Clock::now() > deadline_) {
            timed_out = true;
            continue;
          }
          run_phase(ph, parts[batch[size_t(i)]], rounds, iterations);
          timed_out = timed_out || ph.timed_out;
          work_done += ph.work;
        }
        rounds_done += ph.rounds;
      }
      report.rounds += rounds_done;
      if (timed_out) report.time_limit_reached = true;
      if (stall_watched()) {  // the stall bound's count restarts whenever the inverted count falls
        const size_t inverted = inverted_count();
        work_since_fall_ += work_done;
        if (inverted < fewest_inverted_) fewest_inverted_ = inverted, work_since_fall_ = 0;
        if (work_since_fall_ >= options_.stall_work) stalled_ = true;
      }
    }
  }

  //! Hexes counted as inverted (the repair's seeds).
  size_t inverted_count() const {
    return size_t(std::count_if(scaled_jacobian_.begin(), scaled_jacobian_.end(),
                                [](double sj) { return sj < kInvertedBelow; }));
  }

  //! Whether the stall bound is watched now: while the inverted hexes are repaired.
  bool stall_watched() const { return watch_stall_ && options_.stall_work > 0; }

  // One epsilon-continuation run over `movable` (sorted node ids): interior nodes free,
  // boundary nodes among them move in their tangent plane and go back onto the surface
  // after every round. The cost follows the size of the region, not of the mesh.
  void run_phase(Phase& ph, const std::vector<size_t>& movable, int max_rounds, int max_iterations) {
    ph.movable_nodes.clear();
    for (size_t v : movable)
      if (!(is_boundary_[v] && options_.held && options_.held(v, mesh_.nodes[v]))) ph.movable_nodes.push_back(v);
    ph.timed_out = false;
    ph.work = 0;
    ph.sliding_nodes.clear();
    int n_vars = 0;
    for (size_t v : ph.movable_nodes) {
      var_offset_[v] = n_vars;
      n_vars += is_boundary_[v] ? 2 : 3;
      if (is_boundary_[v]) ph.sliding_nodes.push_back(v);
    }
    if (n_vars == 0) {
      for (size_t v : ph.movable_nodes) var_offset_[v] = -1;
      return;
    }
    // Only frames with a movable node enter the energy: the others are constant, and their
    // determinant would pin detmin (and so epsilon) where no move can change it.
    ph.active_hexes.clear();
    for (size_t v : ph.movable_nodes)
      for (int h : node_hexes_[v]) ph.active_hexes.push_back(size_t(h));
    std::sort(ph.active_hexes.begin(), ph.active_hexes.end());
    ph.active_hexes.erase(std::unique(ph.active_hexes.begin(), ph.active_hexes.end()), ph.active_hexes.end());
    ph.active_frames.clear();
    for (size_t h : ph.active_hexes) {
      unsigned mask = 1u << 8;  // the centre frame involves all 8 nodes
      auto movable_corner = [&](int j) { return var_offset_[size_t(mesh_.hexes[h][size_t(j)])] >= 0; };
      for (int k = 0; k < 8; ++k)
        for (int j : kHexCornerFrames[k])
          if (movable_corner(j)) mask |= 1u << k;
      ph.active_frames.push_back(mask);
    }
    ph.incidence_start.assign(ph.movable_nodes.size() + 1, 0);
    for (size_t i = 0; i < ph.movable_nodes.size(); ++i)
      ph.incidence_start[i + 1] = ph.incidence_start[i] + int(node_hexes_[ph.movable_nodes[i]].size());
    ph.incidence.assign(size_t(ph.incidence_start.back()), 0);
    for (size_t i = 0; i < ph.movable_nodes.size(); ++i) {
      int slot = ph.incidence_start[i];
      const size_t v = ph.movable_nodes[i];
      for (int h : node_hexes_[v]) {
        const size_t a = size_t(std::lower_bound(ph.active_hexes.begin(), ph.active_hexes.end(), size_t(h)) -
                                ph.active_hexes.begin());
        size_t j = 0;
        while (size_t(mesh_.hexes[size_t(h)][j]) != v) ++j;
        ph.incidence[size_t(slot++)] = int(a * 8 + j);
      }
    }
    ph.hex_gradient.assign(ph.active_hexes.size() * 8, Vec3::Zero());
    rebase(ph);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n_vars), grad(n_vars);
    double detmin = 0;
    // The first evaluation is made with the gradient at the barrier's epsilon: where nothing
    // is inverted (detmin > 0, as in the shape pass) that is the first round's epsilon, and
    // this evaluation the minimizer's start, not made a second time.
    double start_energy = evaluate(ph, z, &grad, kBarrierEps, &detmin);
    bool start_known = detmin > 0;
    double eps = detmin > 0 ? kBarrierEps : std::sqrt(1e-12 + 0.04 * detmin * detmin);
    const bool any_sliding = !ph.sliding_nodes.empty();
    for (int round = 0; round < max_rounds; ++round) {
      ++ph.rounds;
      const bool keep_valid = detmin > 0;
      auto energy = [&](const Eigen::VectorXd& zz, Eigen::VectorXd& g) {
        double dm = 0;
        const double e = evaluate(ph, zz, &g, eps, &dm);
        return keep_valid && dm <= 0 ? kInf : e;
      };
      // detmin is where z stands: the energy refuses no start, and its first value is the
      // round's starting energy (the same evaluation, not repeated).
      const double detmin_before = detmin;
      LbfgsOptions lbfgs;
      lbfgs.max_iterations = max_iterations;
      lbfgs.deadline = deadline_;
      if (ph.work_cap < std::numeric_limits<long>::max()) lbfgs.stop = [&ph] { return ph.work >= ph.work_cap; };
      lbfgs.max_steepest_step = 0.1;  // a tenth of the local edge length: variables are scaled by it
      const LbfgsReport minimized =
          start_known ? minimize_lbfgs(z, energy, lbfgs, start_energy, grad) : minimize_lbfgs(z, energy, lbfgs);
      const bool timed_out = minimized.timed_out || minimized.stopped;
      double e_prev = minimized.start_energy;
      start_known = false;
      if (!std::isfinite(e_prev)) e_prev = evaluate(ph, z, nullptr, eps, &detmin);  // z did not move
      apply(ph, z);
      if (any_sliding) {
        reproject(ph);
        rebase(ph);
        z.setZero();
      }
      if (timed_out) {
        ph.timed_out = minimized.timed_out;
        break;
      }
      // What follows only steers the next round.
      if (round + 1 == max_rounds) break;
      const double e = evaluate(ph, z, nullptr, eps, &detmin);
      const double sigma = std::max(1.0 - e / e_prev, 0.1);
      const double mu = (1.0 - sigma) * chi(detmin, eps);
      // Garanzha's schedule while something is inverted; once every frame is valid the
      // regularization has done its job and the energy becomes a barrier at once.
      eps = detmin > 0 ? kBarrierEps : detmin < mu ? 2.0 * std::sqrt(mu * (mu - detmin)) : kBarrierEps;
      if (detmin > 0 && std::abs(e_prev - e) <= 1e-5 * std::abs(e)) break;
      if (give_up_hopeless_ && detmin <= 0 && round >= 2 &&
          detmin + (detmin - detmin_before) * (max_rounds - 1 - round) < 0)
        break;
    }
    apply(ph, z);
    // var_offset_ is -1 everywhere between problems: a neighbouring problem solved at the
    // same time reads it for the nodes of its own hexes.
    for (size_t v : ph.movable_nodes) pos_[v] = base_[v] = mesh_.nodes[v], var_offset_[v] = -1;
    update_scaled_jacobians(ph.active_hexes.size(), [&](size_t a) { return ph.active_hexes[a]; });
  }

  // Base positions and tangent frames of the variables: x = base + scale * (z or z0 t1 + z1 t2).
  void rebase(const Phase& ph) {
    for (size_t v : ph.movable_nodes) base_[v] = mesh_.nodes[v];
    const auto& points = bvh_.points();
    const auto& triangles = bvh_.triangles();
    for (size_t v : ph.sliding_nodes) {
      // The tangent plane of the fine surface where the node is (the hex faces around it
      // may be folded, their normal is no guide).
      const TriangleBvh::ClosestPoint cp = bvh_.closest_point(mesh_.nodes[v]);
      Vec3 n = Vec3::UnitZ();
      if (cp.triangle >= 0) {
        const auto& t = triangles[size_t(cp.triangle)];
        const Vec3 c = (points[size_t(t[1])] - points[size_t(t[0])]).cross(points[size_t(t[2])] - points[size_t(t[0])]);
        if (c.norm() > 0) n = c.normalized();
      }
      const auto [t1, t2] = tangent_basis(n);
      tangent1_[v] = t1;
      tangent2_[v] = t2;
      if (options_.held && options_.held(v, mesh_.nodes[v])) tangent1_[v] = tangent2_[v] = Vec3::Zero();
    }
  }

  Vec3 position(const Eigen::VectorXd& z, size_t v) const {
    const int o = var_offset_[v];
    if (o < 0) return base_[v];
    if (!is_boundary_[v]) return base_[v] + node_scale_[v] * Vec3(z[o], z[o + 1], z[o + 2]);
    // A sliding node moves in its tangent plane and is put straight back on the surface, so
    // the energy the optimizer sees is the energy of on-surface positions (the gradient
    // uses the tangent plane, exact while the node stays on its triangle).
    const Vec3 moved = base_[v] + node_scale_[v] * (z[o] * tangent1_[v] + z[o + 1] * tangent2_[v]);
    const TriangleBvh::ClosestPoint cp = bvh_.closest_point(moved);
    if (cp.triangle >= 0 && cp.distance_sq <= (moved - base_[v]).squaredNorm()) return cp.point;
    return moved;
  }

  void apply(const Phase& ph, const Eigen::VectorXd& z) {
    for (size_t v : ph.movable_nodes) mesh_.nodes[v] = position(z, v);
  }

  // Sliding nodes back onto the surface; a node whose closest point is further than it moved
  // in the round (it would cross to another sheet of the surface) goes back where it was.
  void reproject(const Phase& ph) {
    for (size_t v : ph.sliding_nodes) {
      // At most a fraction of the local edge length per round: the tangent plane is a
      // good guide only near where it was taken.
      const double cap = kMaxSlidePerRound * node_scale_[v];
      double moved = (mesh_.nodes[v] - base_[v]).norm();
      if (moved > cap) mesh_.nodes[v] = base_[v] + (cap / moved) * (mesh_.nodes[v] - base_[v]), moved = cap;
      const TriangleBvh::ClosestPoint cp = bvh_.closest_point(mesh_.nodes[v]);
      if (cp.triangle >= 0 && std::sqrt(cp.distance_sq) <= moved + 1e-9 * node_scale_[v] &&
          (!options_.may_land || options_.may_land(v, base_[v], cp.point)))
        mesh_.nodes[v] = cp.point;
      else
        mesh_.nodes[v] = base_[v];
    }
  }

  //! Energy over the active hexes, its gradient in z (if grad), and the smallest normalized
  //! determinant among them. Only the movable nodes are placed: every other node sits at
  //! its mesh position in pos_ for the whole phase.
  double evaluate(Phase& ph, const Eigen::VectorXd& z, Eigen::VectorXd* grad, double eps, double* detmin) {
    const double theta = options_.theta;
    const long n_movable = long(ph.movable_nodes.size());
    const long n_active = long(ph.active_hexes.size());
    double total = 0, dmin = kInf;
    ph.work += n_active;
    if (grad) grad->resize(z.size());
    // One parallel region per evaluation, and none for a small region: on a busy machine
    // every fork and barrier can cost a time slice.
#pragma omp parallel if (n_active > kParallelThreshold)
    {
#pragma omp for schedule(static)
      for (long i = 0; i < n_movable; ++i) {
        const size_t v = ph.movable_nodes[size_t(i)];
        pos_[v] = position(z, v);
      }
#pragma omp for schedule(static) reduction(+ : total) reduction(min : dmin)
      for (long a = 0; a < n_active; ++a) {
        const auto& hex = mesh_.hexes[ph.active_hexes[size_t(a)]];
        const unsigned mask = ph.active_frames[size_t(a)];
        const double inv_size = 1.0 / hex_size_[ph.active_hexes[size_t(a)]];
        std::array<Vec3, 8> x, g;
        for (size_t j = 0; j < 8; ++j) x[j] = pos_[size_t(hex[j])], g[j].setZero();
        // All frames of the hex first, then their energies: each frame's energy is a long
        // chain (determinant, root, cube root, divisions), and frames side by side let the
        // processor run the chains of several at once. Same values, same order of the sums.
        FrameBatch batch;
        for (int k = 0; k < 8; ++k) {
          if (!(mask & (1u << k))) continue;
          const int* c = kHexCornerFrames[k];
          Eigen::Matrix3d& jac = batch.jac[batch.count];
          for (int i = 0; i < 3; ++i) jac.col(i) = (x[size_t(c[i + 1])] - x[size_t(c[0])]) * inv_size;
          batch.frame[batch.count++] = k;
        }
        if (mask & (1u << 8)) {
          Eigen::Matrix3d& jac = batch.jac[batch.count];
          jac.setZero();
          for (size_t j = 0; j < 8; ++j)
            for (int i = 0; i < 3; ++i) jac.col(i) += kHexCentreAxes[i][j] * x[j];
          jac *= 0.25 * inv_size;
          batch.frame[batch.count++] = 8;
        }
        batch.evaluate(eps, theta, grad != nullptr);
        for (int f = 0; f < batch.count; ++f) {
          total += batch.energy[f];
          dmin = std::min(dmin, batch.det[f]);
        }
        if (grad) {
          for (int f = 0; f < batch.count; ++f) {
            const Eigen::Matrix3d dj = batch.jac_weight[f] * batch.jac[f] + batch.det_weight[f] * batch.cof[f];
            const int k = batch.frame[f];
            if (k < 8) {
              const int* c = kHexCornerFrames[k];
              for (int i = 0; i < 3; ++i) {
                const Vec3 gi = dj.col(i) * inv_size;
                g[size_t(c[i + 1])] += gi;
                g[size_t(c[0])] -= gi;
              }
            } else {
              for (size_t j = 0; j < 8; ++j)
                g[j] += (0.25 * inv_size) * (kHexCentreAxes[0][j] * dj.col(0) + kHexCentreAxes[1][j] * dj.col(1) +
                                             kHexCentreAxes[2][j] * dj.col(2));
            }
          }
        }
        if (grad)
          for (size_t j = 0; j < 8; ++j) ph.hex_gradient[size_t(a) * 8 + j] = g[j];
      }
      if (grad) {
#pragma omp for schedule(static)
        for (long i = 0; i < n_movable; ++i) {
          const size_t v = ph.movable_nodes[size_t(i)];
          Vec3 gv = Vec3::Zero();
          for (int slot = ph.incidence_start[size_t(i)]; slot < ph.incidence_start[size_t(i) + 1]; ++slot)
            gv += ph.hex_gradient[size_t(ph.incidence[size_t(slot)])];
          gv *= node_scale_[v];
          const int o = var_offset_[v];
          if (!is_boundary_[v]) {
            (*grad)[o] = gv.x(), (*grad)[o + 1] = gv.y(), (*grad)[o + 2] = gv.z();
          } else {
            (*grad)[o] = gv.dot(tangent1_[v]), (*grad)[o + 1] = gv.dot(tangent2_[v]);
          }
        }
      }
    }
    if (detmin) *detmin = dmin;
    return total;
  }

  HexMesh& mesh_;
  const TriangleBvh& bvh_;
  UntangleOptions options_;
  Clock::time_point deadline_;
  std::vector<bool> is_boundary_;
  std::vector<double> hex_size_, node_scale_;
  NodeCellIncidence node_hexes_;
  std::vector<double> scaled_jacobian_;  //!< per hex, kept up to date after every phase
  std::vector<char> in_region_;          //!< scratch of grow_region, all zero between calls
  std::vector<int> var_offset_;          //!< per node: first variable, -1 if it does not move
  std::vector<Vec3> pos_;
  bool give_up_hopeless_ = false;  //!< see run(): set only between parallel sections
  //! The stall bound (UntangleOptions::stall_work), written only between parallel sections:
  //! whether it is watched, the fewest inverted hexes so far, the work done since the count
  //! last fell, and whether it stopped the repair.
  bool watch_stall_ = false, stalled_ = false;
  size_t fewest_inverted_ = 0;
  long work_since_fall_ = 0;
  std::vector<Vec3> base_, tangent1_, tangent2_;
};

}  // namespace

UntangleReport untangle_and_smooth(HexMesh& mesh, const TriangleBvh& fine_bvh, const UntangleOptions& options) {
  if (mesh.hexes.empty()) return {};
  Untangler untangler(mesh, fine_bvh, options);
  return untangler.run();
}

}  // namespace dthex
