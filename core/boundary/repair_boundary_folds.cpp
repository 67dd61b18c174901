// SPDX-License-Identifier: MIT
#include <dthex/boundary/repair_boundary_folds.h>

#include <dthex/mesh/hex_topology.h>
#include <dthex/mesh/incidence.h>
#include <dthex/mesh/quality.h>
#include <dthex/numerics/tangent_basis.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <unordered_map>

namespace dthex {
namespace {


using Box = Eigen::AlignedBox3d;
using Clock = std::chrono::steady_clock;

//! How folded one quad is: 0 when its probe lies in no hex, else 1 plus how deep it lies in
//! the hex that holds it (parametric distance to that hex's nearest face, in [0, 0.5]). The
//! depth lets a node that cannot yet free a probe still move it towards the way out.
//! A quad turned over (facing against the input surface at its centre) counts too, as 1 plus
//! how far it is turned: it is the fold line of a boundary that covers the surface twice,
//! where the probes of the quads on either side end up in each other's hexes.
struct QuadFold {
  Vec3 probe = Vec3::Zero();
  bool has_probe = false;
  bool inside = false;  //!< the probe lies in a hex: what find_boundary_faces_inside counts
  int hex = -1;         //!< then the hex where it lies deepest
  double value = 0;
};

class FoldRepairer {
 public:
  FoldRepairer(HexMesh& mesh, const TriangleBvh& surface, const std::vector<std::array<int, 4>>& quads,
               const std::vector<int>& owners, const RepairBoundaryFoldsOptions& options)
      : mesh_(mesh),
        surface_(surface),
        quads_(quads),
        owners_(owners),
        options_(options),
        node_hexes_(mesh.nodes.size(), mesh.hexes),
        node_quads_(mesh.nodes.size(), quads) {
    hex_stamp_.assign(mesh.hexes.size(), 0);
    deadline_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(options.time_limit_seconds));
  }

  bool out_of_time() {
    if (!time_limit_reached_ && Clock::now() > deadline_) time_limit_reached_ = true;
    return time_limit_reached_;
  }

  //! Works on the hexes within `rings` rings of `seeds` (one connected group of folds).
  void repair_region(const std::vector<int>& seeds, int rings, bool off_surface) {
    off_surface_ = off_surface;
    // The region: seeds grown ring by ring through shared nodes; its nodes may move, nearest first.
    std::vector<int> hexes = seeds, node_order;
    std::unordered_map<int, int> hex_ring, node_ring;
    for (int h : seeds) hex_ring.emplace(h, 0);
    for (int ring = 1; ring <= rings; ++ring) {
      const size_t count = hexes.size();
      for (size_t i = 0; i < count; ++i)
        for (int v : mesh_.hexes[size_t(hexes[i])])
          for (int g : node_hexes_[size_t(v)])
            if (hex_ring.emplace(g, ring).second) hexes.push_back(g);
    }
    for (int h : hexes)
      for (int v : mesh_.hexes[size_t(h)])
        if (node_ring.emplace(v, hex_ring[h]).second) node_order.push_back(v);
    std::stable_sort(node_order.begin(), node_order.end(),
                     [&](int a, int b) { return node_ring[a] < node_ring[b]; });

    // Where probes can matter: a box around the region, a margin of two of its longest
    // edges wide.
    Box box;
    double longest = 0, sum = 0;
    size_t edges = 0;
    for (int v : node_order) {
      box.extend(mesh_.nodes[size_t(v)]);
      for (int h : node_hexes_[size_t(v)])
        for (const auto& e : kHexEdges) {
          const double length = (mesh_.nodes[size_t(mesh_.hexes[size_t(h)][size_t(e[0])])] -
                                 mesh_.nodes[size_t(mesh_.hexes[size_t(h)][size_t(e[1])])]).norm();
          longest = std::max(longest, length);
          sum += length;
          ++edges;
        }
    }
    box.min() -= Vec3::Constant(2 * longest);
    box.max() += Vec3::Constant(2 * longest);

    // The hexes that can hold a probe there, in a uniform grid of about one hex per cell.
    cell_ = std::max(sum / double(std::max<size_t>(edges, 1)), 1e-300);
    grid_.clear();
    for (size_t h = 0; h < mesh_.hexes.size(); ++h)
      if (box.intersects(hex_box(int(h)))) add_to_grid(int(h));
    // The quads whose fold can change: those with a probe in the box or a node that moves.
    tracked_.clear();
    fold_.clear();
    std::vector<char> is_tracked(quads_.size(), 0);
    for (size_t q = 0; q < quads_.size(); ++q) {
      Vec3 probe;
      if (boundary_probe_point(mesh_, quads_[q], owner_of(q), options_.probe, probe) && box.contains(probe))
        is_tracked[q] = 1;
    }
    for (int v : node_order)
      for (int q : node_quads_[size_t(v)]) is_tracked[size_t(q)] = 1;
    for (size_t q = 0; q < quads_.size(); ++q)
      if (is_tracked[q]) {
        tracked_.push_back(int(q));
        fold_.push_back(fold_of(int(q), {}));
      }
    tracked_index_.clear();
    probe_grid_.clear();
    for (size_t i = 0; i < tracked_.size(); ++i) {
      tracked_index_[tracked_[i]] = int(i);
      if (fold_[i].has_probe) probe_grid_[cell_key(cell_of(fold_[i].probe))].push_back(int(i));
    }

    for (int sweep = 0; sweep < options_.sweeps && !unfolded() && !out_of_time(); ++sweep) {
      bool moved = false;
      for (int v : node_order) {
        if (out_of_time()) break;
        const Vec3 start = mesh_.nodes[size_t(v)];
        if (improve_node(v)) {
          moved = true;
          original_.emplace(v, start);  // keeps the first position only
        }
        if (unfolded()) break;
      }
      if (!moved) break;
    }
    for (size_t i = 0; i < tracked_.size(); ++i) {
      if (fold_[i].inside) folds_[tracked_[i]] = fold_[i].hex;
      else folds_.erase(tracked_[i]);
    }
  }

  //! The folds as the regions left them (quads far from every region as first found): what
  //! the next, wider regions start from, without a probe pass over the whole mesh.
  void set_folds(const BoundaryOverlapReport& found) {
    folds_.clear();
    for (size_t i = 0; i < found.faces.size(); ++i) folds_[found.faces[i]] = found.hexes[i];
  }
  BoundaryOverlapReport folds() const {
    BoundaryOverlapReport r;
    for (const auto& [face, hex] : folds_) {
      r.faces.push_back(face);
      r.hexes.push_back(hex);
    }
    r.faces_inside = r.faces.size();
    return r;
  }

  //! Puts every moved node back.
  void undo() {
    for (const auto& [v, x] : original_) mesh_.nodes[size_t(v)] = x;
    original_.clear();
  }
  size_t moved_nodes() const {
    size_t n = 0;
    for (const auto& [v, x] : original_) n += mesh_.nodes[size_t(v)] != x;
    return n;
  }
  //! The lowest scaled Jacobian of the hexes around the nodes that moved, as they are now or
  //! (`at_start`) as they were.
  double min_scaled_jacobian_around_moved(bool at_start) {
    if (at_start) swap_positions();
    double m = 1;
    for (const auto& entry : original_)
      for (int h : node_hexes_[size_t(entry.first)]) m = std::min(m, hex_scaled_jacobian(hex_corners(mesh_, size_t(h))));
    if (at_start) swap_positions();
    return m;
  }

 private:
  void swap_positions() {
    for (auto& entry : original_) std::swap(mesh_.nodes[size_t(entry.first)], entry.second);
  }
  int owner_of(size_t q) const { return owners_.empty() ? -1 : owners_[q]; }

  Box hex_box(int h) const {
    Box b;
    for (int v : mesh_.hexes[size_t(h)]) b.extend(mesh_.nodes[size_t(v)]);
    return b;
  }
  std::array<int64_t, 3> cell_of(const Vec3& p) const {
    return {int64_t(std::floor(p.x() / cell_)), int64_t(std::floor(p.y() / cell_)), int64_t(std::floor(p.z() / cell_))};
  }
  static uint64_t cell_key(const std::array<int64_t, 3>& c) {
    return uint64_t(c[0]) * 73856093ULL ^ uint64_t(c[1]) * 19349663ULL ^ uint64_t(c[2]) * 83492791ULL;
  }
  // Lists a hex in every cell its box meets (again after a move, where it is not yet: stale
  // entries only cost a box test, and the stamp keeps a hex from being tested twice for one
  // probe).
  void add_to_grid(int h) {
    const Box b = hex_box(h);
    const auto lo = cell_of(b.min()), hi = cell_of(b.max());
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z) {
          std::vector<int>& listed = grid_[cell_key({x, y, z})];
          if (std::find(listed.begin(), listed.end(), h) == listed.end()) listed.push_back(h);
        }
  }

  // Calls visit(i) for the tracked quads whose probe lies in `box` (some more than once).
  template <class Visit>
  void for_each_tracked_in(const Box& box, Visit visit) const {
    const auto lo = cell_of(box.min()), hi = cell_of(box.max());
    for (int64_t x = lo[0]; x <= hi[0]; ++x)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t z = lo[2]; z <= hi[2]; ++z) {
          const auto it = probe_grid_.find(cell_key({x, y, z}));
          if (it == probe_grid_.end()) continue;
          for (int i : it->second)
            if (fold_[size_t(i)].has_probe && box.contains(fold_[size_t(i)].probe)) visit(i);
        }
  }

  // The fold of quad q as the nodes are now; `moving` are hexes whose nodes moved since they
  // were listed in the grid (tested whatever cell they are listed in).
  QuadFold fold_of(int q, NodeCellIncidence::Range moving) {
    QuadFold f;
    f.has_probe = boundary_probe_point(mesh_, quads_[size_t(q)], owner_of(size_t(q)), options_.probe, f.probe);
    if (!f.has_probe) return f;
    ++stamp_;
    double deepest = -1;
    auto test = [&](int h) {
      if (hex_stamp_[size_t(h)] == stamp_) return;
      hex_stamp_[size_t(h)] = stamp_;
      if (!hex_box(h).contains(f.probe)) return;
      Vec3 rst;
      if (!point_in_hex(hex_corners(mesh_, size_t(h)), f.probe, options_.probe.parametric_tolerance, &rst)) return;
      const Vec3 inner = rst.cwiseMin(Vec3::Ones() - rst);
      if (std::max(0.0, inner.minCoeff()) > deepest) {
        deepest = std::max(0.0, inner.minCoeff());
        f.hex = h;
      }
    };
    for (int h : moving) test(h);
    const auto it = grid_.find(cell_key(cell_of(f.probe)));
    if (it != grid_.end())
      for (int h : it->second) test(h);
    if (deepest >= 0) {
      f.inside = true;
      f.value = 1 + deepest;
    }
    const double facing = facing_of(q);
    if (facing < 0) f.value += 1 - facing;
    return f;
  }

  // The cosine between quad q's normal and the input surface's normal nearest its centre.
  double facing_of(int q) const {
    const auto& r = quads_[size_t(q)];
    const Vec3 a = mesh_.nodes[size_t(r[0])], b = mesh_.nodes[size_t(r[1])], c = mesh_.nodes[size_t(r[2])],
               d = mesh_.nodes[size_t(r[3])];
    const Vec3 normal = (b - a).cross(c - a) + (c - a).cross(d - a);
    const double length = normal.norm();
    return length > 0 ? normal.dot(surface_normal_at(0.25 * (a + b + c + d))) / length : 0.0;
  }

  //! No tracked quad's probe in a hex, none turned over.
  bool unfolded() const {
    return std::all_of(fold_.begin(), fold_.end(), [](const QuadFold& f) { return f.value == 0; });
  }

  // The normal of the input surface nearest to x (zero when there is none).
  Vec3 surface_normal_at(const Vec3& x, Vec3* closest = nullptr) const {
    const TriangleBvh::ClosestPoint cp = surface_.closest_point(x);
    if (cp.triangle < 0) return Vec3::Zero();
    if (closest) *closest = cp.point;
    const auto& t = surface_.triangles()[size_t(cp.triangle)];
    const auto& p = surface_.points();
    const Vec3 n = (p[size_t(t[1])] - p[size_t(t[0])]).cross(p[size_t(t[2])] - p[size_t(t[0])]);
    return n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero();
  }
  // The quads of boundary node v that face against the input surface at their centre: a
  // fold the probe may miss (the probe of a quad turned over can land in the gap below it).
  int quads_facing_inward(int v) const {
    int n = 0;
    for (int q : node_quads_[size_t(v)]) n += facing_of(q) < 0;
    return n;
  }

  // Whether moving v to x lowers the folds around it while keeping its hexes above the
  // floor and turning no more of its quads inward; if so the move stays.
  bool try_move(int v, const Vec3& x, int inward_before) {
    const Vec3 old = mesh_.nodes[size_t(v)];
    const NodeCellIncidence::Range hexes = node_hexes_[size_t(v)];
    Box reach;
    for (int h : hexes) reach.extend(hex_box(h));
    // Each hex keeps min(its value, the floor): no hex falls below the floor, and one already
    // below it (around a fold the smoother could not raise) gets no worse.
    floors_.clear();
    for (int h : hexes)
      floors_.push_back(std::min(options_.min_scaled_jacobian, hex_scaled_jacobian(hex_corners(mesh_, size_t(h)))));
    mesh_.nodes[size_t(v)] = x;
    bool ok = true;
    for (size_t k = 0; k < hexes.size(); ++k)
      if (!(hex_scaled_jacobian(hex_corners(mesh_, size_t(hexes[k]))) >= floors_[k])) {
        ok = false;
        break;
      }
    if (ok && !node_quads_[size_t(v)].empty() && quads_facing_inward(v) > inward_before) ok = false;
    if (ok) {
      for (int h : hexes) reach.extend(hex_box(h));
      affected_.clear();
      for (int q : node_quads_[size_t(v)]) affected_.push_back(tracked_index_.at(q));
      for_each_tracked_in(reach, [&](int i) { affected_.push_back(i); });
      std::sort(affected_.begin(), affected_.end());
      affected_.erase(std::unique(affected_.begin(), affected_.end()), affected_.end());
      double before = 0, after = 0;
      trial_.clear();
      for (int i : affected_) {
        before += fold_[size_t(i)].value;
        trial_.push_back(fold_of(tracked_[size_t(i)], hexes));
        after += trial_.back().value;
      }
      ok = after < before - 1e-12;
    }
    if (!ok) {
      mesh_.nodes[size_t(v)] = old;
      return false;
    }
    for (size_t k = 0; k < affected_.size(); ++k) {
      QuadFold& f = fold_[size_t(affected_[k])];
      // A probe that moved is listed in its new cell too (stale entries are filtered out).
      if (trial_[k].has_probe && (!f.has_probe || cell_of(trial_[k].probe) != cell_of(f.probe)))
        probe_grid_[cell_key(cell_of(trial_[k].probe))].push_back(affected_[k]);
      f = trial_[k];
    }
    for (int h : hexes) add_to_grid(h);
    return true;
  }

  // Whether some fold lies where moving v can change it: in the hexes around v, grown by
  // the longest step, or on a quad of v.
  bool near_a_fold(int v, double reach) const {
    for (int q : node_quads_[size_t(v)])
      if (fold_[size_t(tracked_index_.at(q))].value > 0) return true;
    Box b;
    for (int h : node_hexes_[size_t(v)]) b.extend(hex_box(h));
    b.min() -= Vec3::Constant(reach);
    b.max() += Vec3::Constant(reach);
    bool found = false;
    for_each_tracked_in(b, [&](int i) { found = found || fold_[size_t(i)].value > 0; });
    return found;
  }

  // A compass search on v (in the tangent plane of the input surface for a boundary node),
  // the mean of its edge neighbours tried first.
  bool improve_node(int v) {
    const NodeCellIncidence::Range hexes = node_hexes_[size_t(v)];
    if (hexes.empty()) return false;
    const Vec3 x0 = mesh_.nodes[size_t(v)];
    Vec3 sum = Vec3::Zero();
    double length = 0;
    int n = 0;
    for (int h : hexes) {
      const auto& hex = mesh_.hexes[size_t(h)];
      for (const auto& e : kHexEdges) {
        const int a = hex[size_t(e[0])], b = hex[size_t(e[1])];
        if (a != v && b != v) continue;
        const Vec3& u = mesh_.nodes[size_t(a == v ? b : a)];
        const bool boundary_edge = !node_quads_[size_t(v)].empty() && !node_quads_[size_t(a == v ? b : a)].empty();
        if (node_quads_[size_t(v)].empty() || boundary_edge) sum += u, ++n;
        length += (u - x0).norm();
      }
    }
    const double scale = length / double(3 * hexes.size());  // 3 edges of each hex meet at v
    if (!(scale > 0) || !near_a_fold(v, options_.initial_step * scale)) return false;

    const bool boundary = !node_quads_[size_t(v)].empty();
    Vec3 normal = Vec3::Zero();
    int inward = 0;
    if (boundary) {
      normal = surface_normal_at(x0);
      if (normal.squaredNorm() == 0) return false;
      inward = quads_facing_inward(v);
    }
    // Where a step d from x lands: x + d inside; for a boundary node the nearest surface
    // point, refused when it is further from x + d than the step is long (another sheet).
    auto landing = [&](const Vec3& x, const Vec3& d, Vec3& out) {
      if (!boundary) {
        out = x + d;
        return true;
      }
      Vec3 cp = Vec3::Zero();
      if (off_surface_) {  // anywhere within the allowed distance of the surface
        out = x + d;
        return surface_normal_at(out, &cp).squaredNorm() > 0 &&
               (cp - out).norm() <= options_.max_off_surface * scale;
      }
      if (surface_normal_at(x + d, &cp).squaredNorm() == 0 || (cp - (x + d)).norm() > d.norm()) return false;
      out = cp;
      return true;
    };
    auto tangential = [&](const Vec3& d) { return boundary && !off_surface_ ? Vec3(d - d.dot(normal) * normal) : d; };

    bool moved = false;
    if (n > 0) {
      Vec3 y;
      const Vec3 d = tangential(sum / double(n) - x0);
      for (double t : {1.0, 0.5})
        if (d.norm() > 0 && landing(x0, t * d, y) && try_move(v, y, inward)) {
          moved = true;
          break;
        }
    }
    std::vector<Vec3> directions;
    if (boundary && !off_surface_) {
      const auto [t1, t2] = tangent_basis(normal);
      for (int k = 0; k < 8; ++k) directions.push_back(std::cos(k * M_PI / 4) * t1 + std::sin(k * M_PI / 4) * t2);
    } else {
      for (int axis = 0; axis < 3; ++axis)
        for (double sign : {-1.0, 1.0}) directions.push_back(sign * Vec3::Unit(axis));
      const double r = 1 / std::sqrt(3.0);
      for (double sx : {-r, r})
        for (double sy : {-r, r})
          for (double sz : {-r, r}) directions.push_back(Vec3(sx, sy, sz));
    }
    int last_good = 0;
    for (double step = options_.initial_step * scale; step >= options_.min_step * scale;) {
      bool improved = false;
      for (size_t k = 0; k < directions.size() && !improved; ++k) {
        const size_t dir = (size_t(last_good) + k) % directions.size();
        Vec3 y;
        if (!landing(mesh_.nodes[size_t(v)], step * directions[dir], y)) continue;
        if (try_move(v, y, boundary ? quads_facing_inward(v) : 0)) {
          improved = moved = true;
          last_good = int(dir);
        }
      }
      if (!improved) step *= 0.5;
      if (!near_a_fold(v, 0)) break;
    }
    return moved;
  }

  HexMesh& mesh_;
  const TriangleBvh& surface_;
  const std::vector<std::array<int, 4>>& quads_;
  const std::vector<int>& owners_;
  RepairBoundaryFoldsOptions options_;
  NodeCellIncidence node_hexes_, node_quads_;
  std::vector<unsigned> hex_stamp_;
  unsigned stamp_ = 0;
  Clock::time_point deadline_;
  bool time_limit_reached_ = false;
  double cell_ = 1;
  bool off_surface_ = false;
  std::unordered_map<uint64_t, std::vector<int>> grid_;        //!< hexes by cell
  std::unordered_map<uint64_t, std::vector<int>> probe_grid_;  //!< tracked quads by their probe's cell
  std::vector<int> tracked_;                   //!< quad ids whose fold is followed
  std::unordered_map<int, int> tracked_index_; //!< quad id -> position in tracked_
  std::vector<QuadFold> fold_;                 //!< per tracked quad
  std::vector<int> affected_;
  std::vector<double> floors_;
  std::vector<QuadFold> trial_;
  std::unordered_map<int, Vec3> original_;     //!< first position of every node moved
  std::map<int, int> folds_;                   //!< folded quad -> the hex that holds its probe
};

// Seeds of the connected groups of folds: the hexes of the folded quads and the hexes that
// hold their probes, grouped when within `rings` rings of each other (through shared nodes).
std::vector<std::vector<int>> fold_groups(const HexMesh& mesh, const BoundaryOverlapReport& folds,
                                          const std::vector<int>& owners) {
  std::vector<int> seeds;
  for (size_t i = 0; i < folds.faces.size(); ++i) {
    if (!owners.empty()) seeds.push_back(owners[size_t(folds.faces[i])]);
    seeds.push_back(folds.hexes[i]);
  }
  std::sort(seeds.begin(), seeds.end());
  seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
  // Union-find over the seeds: two are grouped when their hexes share a node or lie within
  // a few hex sizes (cheap, and separate groups only need separate regions for speed).
  std::vector<int> parent(seeds.size());
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = int(i);
  auto root = [&](int x) {
    while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
    return x;
  };
  auto centre = [&](int h) {
    Vec3 c = Vec3::Zero();
    double size = 0;
    for (int v : mesh.hexes[size_t(h)]) c += mesh.nodes[size_t(v)];
    c /= 8;
    for (int v : mesh.hexes[size_t(h)]) size = std::max(size, (mesh.nodes[size_t(v)] - c).norm());
    return std::make_pair(c, size);
  };
  for (size_t i = 0; i < seeds.size(); ++i)
    for (size_t j = i + 1; j < seeds.size(); ++j) {
      const auto [ci, si] = centre(seeds[i]);
      const auto [cj, sj] = centre(seeds[j]);
      if ((ci - cj).norm() < 4 * (si + sj)) parent[size_t(root(int(i)))] = root(int(j));
    }
  std::unordered_map<int, size_t> group_of_root;
  std::vector<std::vector<int>> groups;
  for (size_t i = 0; i < seeds.size(); ++i) {
    const int r = root(int(i));
    const auto it = group_of_root.emplace(r, groups.size());
    if (it.second) groups.emplace_back();
    groups[it.first->second].push_back(seeds[i]);
  }
  return groups;
}

}  // namespace

RepairBoundaryFoldsReport repair_boundary_folds(HexMesh& mesh, const TriangleBvh& surface,
                                                const std::vector<std::array<int, 4>>& quads,
                                                const std::vector<int>& owners,
                                                const RepairBoundaryFoldsOptions& options) {
  RepairBoundaryFoldsReport report;
  BoundaryOverlapReport folds = find_boundary_faces_inside(mesh, quads, owners, options.probe);
  report.faces_inside_before = report.faces_inside_after = folds.faces_inside;
  report.first_face_after = folds.first_face;
  report.first_point_after = folds.first_point;
  if (folds.faces_inside == 0) return report;

  FoldRepairer repairer(mesh, surface, quads, owners, options);
  repairer.set_folds(folds);
  for (bool off_surface : {false, true}) {
    if (off_surface && !(options.max_off_surface > 0)) break;
    // Wider regions only while they pay: a ring count that removes no fold ends the phase
    // (on a wall folded through, every further ring took as long again for nothing).
    for (int rings = options.rings; rings <= options.max_rings && folds.faces_inside > 0 && !repairer.out_of_time();
         ++rings) {
      const auto groups = fold_groups(mesh, folds, owners);
      report.regions = std::max(report.regions, groups.size());
      const size_t inside_before = folds.faces_inside;
      for (const auto& seeds : groups) repairer.repair_region(seeds, rings, off_surface);
      folds = repairer.folds();
      if (folds.faces_inside >= inside_before) {
        ++report.phases_ended_without_gain;
        break;
      }
    }
  }
  folds = find_boundary_faces_inside(mesh, quads, owners, options.probe);
  report.region_min_scaled_jacobian_before = repairer.min_scaled_jacobian_around_moved(true);
  report.region_min_scaled_jacobian_after = repairer.min_scaled_jacobian_around_moved(false);
  if (folds.faces_inside >= report.faces_inside_before) {
    repairer.undo();
    report.undone = true;
    folds = find_boundary_faces_inside(mesh, quads, owners, options.probe);
  }
  report.faces_inside_after = folds.faces_inside;
  report.first_face_after = folds.first_face;
  report.first_point_after = folds.first_point;
  report.moved_nodes = repairer.moved_nodes();
  report.time_limit_reached = repairer.out_of_time();
  if (report.undone) report.region_min_scaled_jacobian_after = report.region_min_scaled_jacobian_before;
  return report;
}

}  // namespace dthex
