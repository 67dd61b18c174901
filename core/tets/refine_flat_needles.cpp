// SPDX-License-Identifier: MIT
#include <dthex/tets/refine_flat_needles.h>

#include <dthex/mesh/surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace dthex {
namespace {

using Point = SurfaceMesh::Point;
using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::VertexHandle;

//! The angle at p of the triangle (p, q, r), in radians (0 for a degenerate one).
double angle_at(const Point& p, const Point& q, const Point& r) {
  const Point u = q - p, w = r - p;
  const double lu = u.norm(), lw = w.norm();
  if (!(lu > 0 && lw > 0)) return 0;
  return std::acos(std::clamp(double(u | w) / (lu * lw), -1.0, 1.0));
}

class NeedleRefiner {
 public:
  NeedleRefiner(SurfaceMesh& mesh, const RefineFlatNeedlesOptions& options)
      : m_(mesh),
        options_(options),
        min_angle_(options.min_angle_deg * M_PI / 180),
        cos_coplanar_(std::cos(options.coplanar_deg * M_PI / 180)) {}

  RefineFlatNeedlesReport run() {
    RefineFlatNeedlesReport report;
    std::vector<FaceHandle> needles = workable_needles();
    report.needles_before = report.needles_after = needles.size();
    if (needles.empty()) return report;
    // A round can leave more needles than it found (the splits' new triangles next to the
    // outline are needles too, and the count can grow from round to round): the mesh of the
    // last round that left the fewest is kept, the mesh as it came if every round left more.
    SurfaceMesh fewest_mesh = m_;
    RefineFlatNeedlesReport fewest = report;
    const size_t budget =
        std::max<size_t>(64, size_t(options_.max_added_fraction * double(m_.n_vertices())));
    int rounds = 0, fewest_round = 0;
    for (int round = 0; round < options_.max_rounds && report.vertices_added < budget; ++round) {
      size_t splits = 0;
      for (FaceHandle f : needles) {
        if (report.vertices_added >= budget) break;
        // An earlier split in this pass may have changed the face.
        if (m_.status(f).deleted()) continue;
        const EdgeHandle e = edge_to_split(f);
        if (!e.is_valid()) continue;
        const HalfedgeHandle h = m_.halfedge_handle(e, 0);
        const Point mid = (m_.point(m_.from_vertex_handle(h)) + m_.point(m_.to_vertex_handle(h))) * 0.5;
        added_.push_back(m_.split(e, mid));
        ++splits;
        ++report.vertices_added;
      }
      if (splits == 0) break;
      report.flips += make_delaunay();
      relax_added_vertices();
      report.flips += make_delaunay();
      rounds = round + 1;
      needles = workable_needles();  // the next round's, counted here
      report.needles_after = needles.size();
      if (report.needles_after <= fewest.needles_after) {
        fewest = report;
        fewest_round = rounds;
        fewest_mesh = m_;
      }
    }
    if (fewest_round < rounds) {
      m_ = fewest_mesh;
      report = fewest;
      report.rounds_taken_back = size_t(rounds - fewest_round);
    }
    return report;
  }

 private:
  Point raw_normal(FaceHandle f) const {
    auto it = m_.cfv_iter(f);
    const Point a = m_.point(*it), b = m_.point(*++it), c = m_.point(*++it);
    return (b - a) % (c - a);
  }

  //! An edge inside a flat region: two triangles whose normals differ by less than the bound.
  bool flat_edge(EdgeHandle e) const {
    if (m_.is_boundary(e)) return false;
    const Point n0 = raw_normal(m_.face_handle(m_.halfedge_handle(e, 0)));
    const Point n1 = raw_normal(m_.face_handle(m_.halfedge_handle(e, 1)));
    const double l0 = n0.norm(), l1 = n1.norm();
    return l0 > 0 && l1 > 0 && double(n0 | n1) >= cos_coplanar_ * l0 * l1;
  }

  //! The face's three halfedges, and the angle opposite each (at the vertex not on it).
  void corners(FaceHandle f, HalfedgeHandle h[3], double opposite[3]) const {
    h[0] = m_.halfedge_handle(f);
    h[1] = m_.next_halfedge_handle(h[0]);
    h[2] = m_.next_halfedge_handle(h[1]);
    for (int i = 0; i < 3; ++i) {
      const Point p = m_.point(m_.to_vertex_handle(h[(i + 1) % 3]));  // the vertex opposite h[i]
      opposite[i] = angle_at(p, m_.point(m_.from_vertex_handle(h[i])), m_.point(m_.to_vertex_handle(h[i])));
    }
  }

  //! The longest edge of a needle, if it may be split: it lies inside a flat region, and so
  //! do both edges at the needle's smallest angle. An angle with an edge on the region's
  //! outline is the outline's: a strip between two feature lines (a thin side of a prism)
  //! stays as thin however it is split, and splitting it only adds caps.
  EdgeHandle edge_to_split(FaceHandle f) const {
    HalfedgeHandle h[3];
    double opposite[3];
    corners(f, h, opposite);
    const int smallest = int(std::min_element(opposite, opposite + 3) - opposite);
    if (!(opposite[smallest] < min_angle_)) return EdgeHandle();
    // The two edges at the smallest angle's vertex are the other two.
    const EdgeHandle at_a = m_.edge_handle(h[(smallest + 1) % 3]), at_b = m_.edge_handle(h[(smallest + 2) % 3]);
    if (!flat_edge(at_a) || !flat_edge(at_b)) return EdgeHandle();
    const int longest = int(std::max_element(opposite, opposite + 3) - opposite);
    const EdgeHandle e = m_.edge_handle(h[longest]);
    return flat_edge(e) ? e : EdgeHandle();
  }

  std::vector<FaceHandle> workable_needles() const {
    std::vector<std::pair<double, FaceHandle>> needles;
    for (FaceHandle f : m_.faces()) {
      if (!edge_to_split(f).is_valid()) continue;
      HalfedgeHandle h[3];
      double opposite[3];
      corners(f, h, opposite);
      needles.emplace_back(*std::min_element(opposite, opposite + 3), f);
    }
    std::sort(needles.begin(), needles.end(),
              [](const auto& a, const auto& b) { return a.first < b.first || (a.first == b.first && a.second < b.second); });
    std::vector<FaceHandle> faces;
    for (const auto& n : needles) faces.push_back(n.second);
    return faces;
  }

  //! Flips flat edges whose two opposite angles add up to more than pi (the planar Delaunay
  //! test: a flip then raises the smaller angles), where the flipped pair keeps its
  //! orientation (the quad is convex).
  size_t make_delaunay() {
    size_t flips = 0;
    for (int pass = 0; pass < 20; ++pass) {
      size_t flipped = 0;
      for (EdgeHandle e : m_.edges()) {
        if (!flat_edge(e) || !m_.is_flip_ok(e)) continue;
        const HalfedgeHandle h0 = m_.halfedge_handle(e, 0), h1 = m_.halfedge_handle(e, 1);
        const Point a = m_.point(m_.from_vertex_handle(h0)), b = m_.point(m_.to_vertex_handle(h0));
        const Point c = m_.point(m_.to_vertex_handle(m_.next_halfedge_handle(h0)));
        const Point d = m_.point(m_.to_vertex_handle(m_.next_halfedge_handle(h1)));
        if (!(angle_at(c, a, b) + angle_at(d, b, a) > M_PI + 1e-9)) continue;
        // After the flip: triangles (a, d, c) and (b, c, d), both facing as before.
        const Point n = raw_normal(m_.face_handle(h0));
        const Point n_left = (d - a) % (c - a), n_right = (c - b) % (d - b);
        const double scale = n.norm();
        if (!(double(n_left | n) > 1e-12 * scale * scale && double(n_right | n) > 1e-12 * scale * scale)) continue;
        m_.flip(e);
        ++flipped;
      }
      flips += flipped;
      if (!flipped) break;
    }
    return flips;
  }

  //! Each added vertex moves toward the mean of its neighbours, within its plane, when every
  //! triangle around it keeps its orientation and the smallest angle around it grows.
  void relax_added_vertices() {
    for (int iteration = 0; iteration < 3; ++iteration)
      for (VertexHandle v : added_) {
        if (m_.status(v).deleted()) continue;
        bool flat = true;
        for (EdgeHandle e : m_.ve_range(v)) flat = flat && flat_edge(e);
        if (!flat) continue;
        const Point old = m_.point(v);
        Point mean(0, 0, 0);
        int count = 0;
        for (VertexHandle u : m_.vv_range(v)) mean += m_.point(u), ++count;
        if (count < 3) continue;
        mean /= double(count);
        Point n = raw_normal(*m_.vf_iter(v));
        if (!(n.norm() > 0)) continue;
        n /= n.norm();
        const Point target = mean - n * double((mean - old) | n);
        const double before = smallest_angle_around(v, n);
        m_.set_point(v, target);
        const double after = smallest_angle_around(v, n);
        if (!(after > before)) m_.set_point(v, old);
      }
  }

  //! The smallest angle of the triangles around v; -1 if one of them no longer faces along n.
  double smallest_angle_around(VertexHandle v, const Point& n) const {
    double smallest = M_PI;
    for (FaceHandle f : m_.vf_range(v)) {
      const Point fn = raw_normal(f);
      if (!(double(fn | n) > 1e-12 * fn.norm())) return -1;
      HalfedgeHandle h[3];
      double opposite[3];
      corners(f, h, opposite);
      smallest = std::min(smallest, *std::min_element(opposite, opposite + 3));
    }
    return smallest;
  }

  SurfaceMesh& m_;
  RefineFlatNeedlesOptions options_;
  double min_angle_, cos_coplanar_;
  std::vector<VertexHandle> added_;
};

}  // namespace

RefineFlatNeedlesReport refine_flat_needles(TriSurface& surface, const RefineFlatNeedlesOptions& options) {
  SurfaceMesh mesh = to_openmesh(surface);
  NeedleRefiner refiner(mesh, options);
  const RefineFlatNeedlesReport report = refiner.run();
  if (report.vertices_added || report.flips) {
    mesh.garbage_collection();
    surface = from_openmesh(mesh);
  }
  return report;
}

}  // namespace dthex
