// SPDX-License-Identifier: MIT
// GCC 12 warns, wrongly, that OpenMesh's add_vertex copies an uninitialized default normal
// (a VectorT this file never reads: it computes its normals from the points).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <dthex/surface/remesh_isotropic.h>

#include <dthex/mesh/surface_mesh.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/triangle_crossing.h>
#include <dthex/surface/features.h>
#include <dthex/surface/wall_thickness.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <memory>
#include <optional>

namespace dthex {

namespace {

using VH = OpenMesh::VertexHandle;
using HH = OpenMesh::HalfedgeHandle;
using EH = OpenMesh::EdgeHandle;
using FH = OpenMesh::FaceHandle;

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * (b - a).cross(c - a).norm(); }

double surface_area(const TriSurface& s) {
  double area = 0;
  for (const auto& t : s.triangles)
    area += triangle_area(s.points[size_t(t[0])], s.points[size_t(t[1])], s.points[size_t(t[2])]);
  return area;
}

double smallest_angle_deg(const TriSurface& s) {
  double smallest = 180;
  for (const auto& t : s.triangles)
    for (int i = 0; i < 3; ++i) {
      const Vec3& p = s.points[size_t(t[size_t(i)])];
      const Vec3 u = s.points[size_t(t[size_t((i + 1) % 3)])] - p, w = s.points[size_t(t[size_t((i + 2) % 3)])] - p;
      const double nu = u.norm(), nw = w.norm();
      if (nu <= 0 || nw <= 0) return 0;
      smallest = std::min(smallest, std::acos(std::clamp(u.dot(w) / (nu * nw), -1.0, 1.0)) * 180 / M_PI);
    }
  return smallest;
}

// The remeshing state: the mesh being remeshed, and what its vertices are put back onto.
class Remesher {
 public:
  Remesher(const TriSurface& input, const TriangleBvh& input_bvh, const RemeshIsotropicOptions& options,
           double edge_length)
      : input_(input), input_bvh_(input_bvh), options_(options), length_(edge_length) {
    fill_openmesh(mesh_, input);  // not mesh_ = to_openmesh(input): that copies it
    mark_features(mesh_, options.feature_angle_deg);
    mesh_.add_property(off_input_);
    for (auto v : mesh_.vertices()) mesh_.property(off_input_, v) = false;
    // The input's feature lines as zero-area triangles (a, b, b): the tree's closest point
    // on them is the closest point on the segments.
    std::vector<std::array<int, 3>> segments;
    for (const auto& e : detect_features(input, options.feature_angle_deg).edges) segments.push_back({e[0], e[1], e[1]});
    if (!segments.empty()) feature_bvh_ = std::make_unique<TriangleBvh>(input.points, segments);
    input_normals_ = unit_triangle_normals(input.points, input.triangles);
  }

  // Runs the rounds; false, and stops, once the mesh has more than `most_triangles`: where
  // feature lines converge (a spike's tip) collapses across them are refused while splits go
  // on, and the mesh only grows.
  bool run(size_t most_triangles) {
    for (int round = 0; round < options_.rounds; ++round) {
      split_long_edges();
      collapse_short_edges();
      flip_towards_valence_six();
      relax_tangentially();
      const auto live = mesh_.faces();  // skips deleted faces (no garbage collection here:
                                        // it would renumber, and change the order of the rounds)
      if (size_t(std::distance(live.begin(), live.end())) > most_triangles) return false;
      if (options_.progress) options_.progress(double(round + 1) / options_.rounds);
    }
    put_back_on_input();
    mesh_.garbage_collection();
    return true;
  }

  TriSurface result() const { return from_openmesh(mesh_); }
  size_t refused_crossings() const { return refused_crossings_; }
  size_t off_input_vertices() const { return off_input_vertices_; }

 private:
  Vec3 point(VH v) const { return to_eigen(mesh_.point(v)); }
  bool is_feature(EH e) const { return mesh_.status(e).feature(); }
  bool is_feature(VH v) const { return mesh_.status(v).feature(); }
  bool is_corner(VH v) const { return mesh_.status(v).locked(); }

  Vec3 face_normal(FH f) const { return to_eigen(mesh_.calc_face_normal(f)); }
  // Area-weighted, from the current points (the mesh's stored normals are not kept up to date).
  Vec3 vertex_normal(VH v) const {
    Vec3 sum = Vec3::Zero();
    for (auto h : mesh_.voh_range(v)) {
      if (!mesh_.face_handle(h).is_valid()) continue;
      const Vec3 p = point(v), a = point(mesh_.to_vertex_handle(h)),
                 b = point(mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h)));
      sum += (a - p).cross(b - p);
    }
    const double length = sum.norm();
    return length > 0 ? Vec3(sum / length) : Vec3::Zero();
  }

  // An edge longer than 4/3 L is split at its midpoint, put on the input. Where the point on
  // the input would make a triangle of zero area, turned over or through the other side of a
  // thin wall (acceptable), the midpoint stays on the chord, its triangles halves of the two
  // split, and the relaxation puts it on the input when it can.
  void split_long_edges() {
    const double high = 4.0 / 3.0 * length_;
    const size_t n = mesh_.n_edges();  // the new edges are short enough
    for (size_t i = 0; i < n; ++i) {
      const EH e{int(i)};
      if (mesh_.status(e).deleted()) continue;
      const HH h = mesh_.halfedge_handle(e, 0);
      const VH a = mesh_.from_vertex_handle(h), b = mesh_.to_vertex_handle(h);
      if ((point(a) - point(b)).norm() <= high) continue;
      const bool feature = is_feature(e);
      const Vec3 middle = 0.5 * (point(a) + point(b));
      // The two triangles' area-weighted normal: the new vertex's once it is split in.
      const FH f0 = mesh_.face_handle(h), f1 = mesh_.face_handle(mesh_.opposite_halfedge_handle(h));
      Vec3 to = on_input(middle, (face_cross(f0) + face_cross(f1)).normalized(), feature).value_or(middle);
      // Each triangle (p, q, c) of the edge p-q becomes (p, m, c) and (m, q, c).
      std::vector<std::array<Vec3, 3>> made;
      std::vector<Vec3> was;
      for (HH side : {h, mesh_.opposite_halfedge_handle(h)}) {
        const Vec3 p = point(mesh_.from_vertex_handle(side)), q = point(mesh_.to_vertex_handle(side));
        const Vec3 c = point(mesh_.to_vertex_handle(mesh_.next_halfedge_handle(side)));
        made.push_back({p, to, c});
        made.push_back({to, q, c});
        was.push_back(face_normal(mesh_.face_handle(side)));
        was.push_back(was.back());
      }
      if (to != middle && !acceptable(made, was)) to = middle;
      const VH m = mesh_.add_vertex(to_openmesh(to));
      mesh_.split(e, m);
      mesh_.status(m).set_feature(feature);
      mesh_.property(off_input_, m) = to == middle;
      if (feature)
        for (auto vh : mesh_.voh_range(m)) {
          const VH other = mesh_.to_vertex_handle(vh);
          if (other == a || other == b) mesh_.status(mesh_.edge_handle(vh)).set_feature(true);
        }
    }
  }

  // Collapses from v0 into v1 are allowed when they keep the feature lines (a feature vertex
  // moves only along its line, a corner never), make no edge long and turn no triangle over.
  bool collapse_allowed(HH h) {
    const VH v0 = mesh_.from_vertex_handle(h), v1 = mesh_.to_vertex_handle(h);
    if (is_corner(v0)) return false;
    if (is_feature(v0) && !is_feature(mesh_.edge_handle(h))) return false;
    if (!mesh_.is_collapse_ok(h)) return false;
    const double high = 4.0 / 3.0 * length_;
    const Vec3 p1 = point(v1);
    for (auto w : mesh_.vv_range(v0))
      if ((point(w) - p1).norm() > high) return false;
    const FH left = mesh_.face_handle(h), right = mesh_.face_handle(mesh_.opposite_halfedge_handle(h));
    std::vector<std::array<Vec3, 3>> made;
    std::vector<Vec3> was;
    for (auto f : mesh_.vf_range(v0)) {
      if (f == left || f == right) continue;
      made.push_back(corners_with(f, v0, p1));
      was.push_back(face_normal(f));
    }
    return acceptable(made, was);
  }

  void collapse_short_edges() {
    const double low = 4.0 / 5.0 * length_;
    for (size_t i = 0; i < mesh_.n_edges(); ++i) {
      const EH e{int(i)};
      if (mesh_.status(e).deleted()) continue;
      HH h = mesh_.halfedge_handle(e, 0);
      if ((point(mesh_.from_vertex_handle(h)) - point(mesh_.to_vertex_handle(h))).norm() >= low) continue;
      if (!collapse_allowed(h)) {
        h = mesh_.opposite_halfedge_handle(h);
        if (!collapse_allowed(h)) continue;
      }
      const VH v0 = mesh_.from_vertex_handle(h), v1 = mesh_.to_vertex_handle(h);
      // v0's other feature neighbour: its edge to v1 carries the line on (the collapse may
      // keep the parallel non-feature edge of the triangle they share instead).
      VH line_next;
      if (is_feature(v0))
        for (auto vh : mesh_.voh_range(v0))
          if (mesh_.to_vertex_handle(vh) != v1 && is_feature(mesh_.edge_handle(vh))) line_next = mesh_.to_vertex_handle(vh);
      mesh_.collapse(h);
      if (line_next.is_valid()) {
        const HH joined = mesh_.find_halfedge(v1, line_next);
        if (joined.is_valid()) mesh_.status(mesh_.edge_handle(joined)).set_feature(true);
      }
    }
  }

  void flip_towards_valence_six() {
    for (auto e : mesh_.edges()) {
      if (mesh_.status(e).deleted() || is_feature(e) || !mesh_.is_flip_ok(e)) continue;
      const HH h0 = mesh_.halfedge_handle(e, 0), h1 = mesh_.halfedge_handle(e, 1);
      const VH a = mesh_.to_vertex_handle(h0), b = mesh_.to_vertex_handle(h1);
      const VH c = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h0));
      const VH d = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h1));
      // Valence 6 is a flat vertex's (and that of a vertex on a line between two flat sides);
      // a corner's depends on its angles and does not count.
      auto deviation = [&](VH v, int change) {
        if (is_corner(v)) return 0;
        const int dv = int(mesh_.valence(v)) + change - 6;
        return dv * dv;
      };
      const int before = deviation(a, 0) + deviation(b, 0) + deviation(c, 0) + deviation(d, 0);
      const int after = deviation(a, -1) + deviation(b, -1) + deviation(c, 1) + deviation(d, 1);
      if (after >= before) continue;
      // Only within a nearly flat pair, and never to a triangle turned over or degenerate:
      // h0 runs b -> a with c after it, h1 runs a -> b with d after it.
      const Vec3 n0 = face_normal(mesh_.face_handle(h0)), n1 = face_normal(mesh_.face_handle(h1));
      if (n0.dot(n1) < kFlipFlatCos) continue;
      const Vec3 m0 = (point(c) - point(b)).cross(point(d) - point(b));  // new triangle b c d
      const Vec3 m1 = (point(d) - point(a)).cross(point(c) - point(a));  // new triangle a d c
      const Vec3 mean = (n0 + n1).normalized();
      if (m0.norm() <= 0 || m1.norm() <= 0) continue;
      if (m0.normalized().dot(mean) < kKeepFacingCos || m1.normalized().dot(mean) < kKeepFacingCos) continue;
      if (crosses_other_side({point(b), point(c), point(d)}) || crosses_other_side({point(a), point(d), point(c)})) continue;
      mesh_.flip(e);
    }
  }

  // Each vertex moves to the mean of its neighbours, within its tangent plane (along its
  // line for a feature vertex), and back onto the input; a move that turns a triangle over
  // is not made.
  void relax_tangentially() {
    std::vector<Vec3> target(mesh_.n_vertices());
    std::vector<char> move(mesh_.n_vertices(), 0);
    for (auto v : mesh_.vertices()) {
      if (mesh_.status(v).deleted() || is_corner(v)) continue;
      const Vec3 p = point(v);
      Vec3 sum = Vec3::Zero();
      int count = 0;
      std::vector<VH> line;
      for (auto vh : mesh_.voh_range(v)) {
        sum += point(mesh_.to_vertex_handle(vh));
        ++count;
        if (is_feature(mesh_.edge_handle(vh))) line.push_back(mesh_.to_vertex_handle(vh));
      }
      if (count == 0) continue;
      if (is_feature(v)) {
        if (line.size() != 2) continue;
        const Vec3 dir = (point(line[1]) - point(line[0])).normalized();
        const Vec3 mid = 0.5 * (point(line[0]) + point(line[1]));
        target[size_t(v.idx())] = p + dir * dir.dot(mid - p);
      } else {
        const Vec3 n = vertex_normal(v);
        const Vec3 q = sum / count;
        target[size_t(v.idx())] = q + n * n.dot(p - q);
      }
      move[size_t(v.idx())] = 1;
    }
    for (auto v : mesh_.vertices()) {
      if (!move[size_t(v.idx())]) continue;
      // On the input with the normal of the fan moved there.
      const auto old = mesh_.point(v);
      const Vec3 moved = target[size_t(v.idx())];
      mesh_.set_point(v, to_openmesh(moved));
      const std::optional<Vec3> on = on_input(moved, vertex_normal(v), is_feature(v));
      mesh_.set_point(v, old);
      const Vec3 to = on.value_or(moved);
      std::vector<std::array<Vec3, 3>> made;
      std::vector<Vec3> was;
      for (auto f : mesh_.vf_range(v)) {
        made.push_back(corners_with(f, v, to));
        was.push_back(face_normal(f));
      }
      if (!acceptable(made, was)) continue;
      mesh_.set_point(v, to_openmesh(to));
      mesh_.property(off_input_, v) = !on;
    }
  }

  // After the rounds: a vertex left off the input (a split's midpoint, or a move with nothing
  // facing its way within reach) goes onto it where that turns no triangle by more than 90
  // degrees and crosses nothing (on a chord of a needle the triangles may turn further than
  // in a relaxation); those still off it are counted.
  void put_back_on_input() {
    for (auto v : mesh_.vertices()) {
      if (mesh_.status(v).deleted() || !mesh_.property(off_input_, v)) continue;
      const std::optional<Vec3> on = on_input(point(v), vertex_normal(v), is_feature(v));
      std::vector<std::array<Vec3, 3>> made;
      std::vector<Vec3> was;
      if (on)
        for (auto f : mesh_.vf_range(v)) {
          made.push_back(corners_with(f, v, *on));
          was.push_back(face_normal(f));
        }
      if (on && acceptable(made, was, kNotTurnedOverCos)) {
        mesh_.set_point(v, to_openmesh(*on));
        mesh_.property(off_input_, v) = false;
      } else {
        ++off_input_vertices_;
      }
    }
  }

  // Where point p (of a feature line, or with vertex normal `normal`) goes on the input: a
  // point of a feature line to the nearest point of the input's feature lines, any other to
  // the nearest point of the input's triangles that face its way; nothing if none is within an
  // edge length.
  std::optional<Vec3> on_input(const Vec3& p, const Vec3& normal, bool feature) const {
    if (feature && feature_bvh_) return feature_bvh_->closest_point(p).point;
    if (!(normal.norm() > 0.5)) return std::nullopt;
    // Within one edge length: the vertex moved less than that from the surface, and a
    // triangle facing its way further off belongs to some other part of the surface.
    const auto hit = input_bvh_.closest_point_within(p, length_, [&](int t) {
      return input_normals_[size_t(t)].dot(normal) > kProjectFacingCos;
    });
    if (hit.triangle < 0) return std::nullopt;
    return hit.point;
  }

  Vec3 face_cross(FH f) const {
    const HH h = mesh_.halfedge_handle(f);
    const Vec3 a = point(mesh_.from_vertex_handle(h)), b = point(mesh_.to_vertex_handle(h));
    return (b - a).cross(point(mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h))) - a);
  }

  // The corners of triangle f with vertex v at p.
  std::array<Vec3, 3> corners_with(FH f, VH v, const Vec3& p) const {
    std::array<Vec3, 3> corners;
    size_t k = 0;
    for (auto w : mesh_.fv_range(f)) corners[k++] = w == v ? p : point(w);
    return corners;
  }

  // Triangles an edit would make, each with the unit normal of the one it replaces: none may
  // have zero area as the verification counts it (has_zero_area: two vertices put on the
  // input at one point, as at the tip of a pit, or a flip onto a split edge's midpoint),
  // turn further than to `keep_facing_cos`, or pass through the other side of a thin wall.
  bool acceptable(const std::vector<std::array<Vec3, 3>>& made, const std::vector<Vec3>& was,
                  double keep_facing_cos = kKeepFacingCos) {
    for (size_t i = 0; i < made.size(); ++i) {
      if (has_zero_area(made[i][0], made[i][1], made[i][2])) return false;
      const Vec3 n = (made[i][1] - made[i][0]).cross(made[i][2] - made[i][0]);
      if (n.normalized().dot(was[i]) < keep_facing_cos) return false;
    }
    for (const auto& t : made)
      if (crosses_other_side(t)) return false;
    return true;
  }

  // Does triangle t pass through an input triangle facing away from it by more than 120
  // degrees (the other side of a thin wall, as the wall thickness counts it)? Counted in
  // refused_crossings(). t is first shrunk by a millionth towards its centroid, so that
  // touching the input at a corner (a vertex on a knife edge lies on both its faces) is no
  // crossing.
  bool crosses_other_side(const std::array<Vec3, 3>& t) {
    const Vec3 centroid = (t[0] + t[1] + t[2]) / 3;
    std::array<Vec3, 3> shrunk;
    Eigen::AlignedBox3d box;
    for (size_t k = 0; k < 3; ++k) box.extend(shrunk[k] = centroid + (1 - 1e-6) * (t[k] - centroid));
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
    bool crossed = false;
    input_bvh_.for_each_in_box(box, [&](int f) {
      if (crossed || !(input_normals_[size_t(f)].dot(n) < kOppositeCos)) return;
      const auto& c = input_.triangles[size_t(f)];
      crossed = triangles_cross(shrunk, {input_.points[size_t(c[0])], input_.points[size_t(c[1])], input_.points[size_t(c[2])]});
    });
    refused_crossings_ += crossed;
    return crossed;
  }

  // A triangle may turn by at most acos(0.7) = 46 degrees in a collapse, flip or relaxation.
  static constexpr double kKeepFacingCos = 0.7;
  // Flips only across edges whose triangles turn by less than 20 degrees.
  static constexpr double kFlipFlatCos = 0.94;
  // Projection only onto input triangles within 60 degrees of the vertex normal (the
  // feature angle): never onto the far side of a crease or a thin wall.
  static constexpr double kProjectFacingCos = 0.5;
  // Putting a vertex left on a chord onto the input may turn its triangles up to 90 degrees:
  // the chord's triangles are themselves far from the input's.
  static constexpr double kNotTurnedOverCos = 0;
  // The other side of a wall faces more than 120 degrees away
  // (WallThicknessOptions::opposite_angle_deg).
  static constexpr double kOppositeCos = -0.5;

  const TriSurface& input_;
  const TriangleBvh& input_bvh_;
  std::unique_ptr<TriangleBvh> feature_bvh_;
  std::vector<Vec3> input_normals_;
  RemeshIsotropicOptions options_;
  double length_;
  SurfaceMesh mesh_;
  OpenMesh::VPropHandleT<bool> off_input_;  // per vertex: left on a chord, not on the input
  size_t refused_crossings_ = 0, off_input_vertices_ = 0;
};

}  // namespace

double needle_share(const TriSurface& surface) {
  if (surface.triangles.empty()) return 0;
  size_t needles = 0;
  for (const auto& t : surface.triangles) {
    const Vec3 &a = surface.points[size_t(t[0])], &b = surface.points[size_t(t[1])], &c = surface.points[size_t(t[2])];
    const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if (longest2 > 10 * 2 * triangle_area(a, b, c)) ++needles;
  }
  return double(needles) / double(surface.triangles.size());
}

double remesh_edge_length(const TriSurface& surface, size_t max_triangles, const TriangleBvh* surface_bvh) {
  const double area = surface_area(surface);
  if (surface.triangles.empty() || !(area > 0)) return 0;
  if (max_triangles == 0) max_triangles = std::clamp<size_t>(100 * surface.triangles.size(), 1000, 400000);
  auto equilateral_edge = [](double triangle_area) { return std::sqrt(4 * triangle_area / std::sqrt(3.0)); };
  const double mean_area_edge = equilateral_edge(area / double(surface.triangles.size()));
  const double shortest = equilateral_edge(area / double(std::max<size_t>(max_triangles, 1)));
  // Wall thickness, where it is thinner than twice that edge: the inner ball's radius.
  std::unique_ptr<TriangleBvh> own_bvh;
  if (!surface_bvh) surface_bvh = (own_bvh = std::make_unique<TriangleBvh>(surface)).get();
  std::vector<double> radius =
      inner_wall_radii(surface, *surface_bvh, std::vector<double>(surface.points.size(), mean_area_edge));
  const size_t k = radius.size() / 20;  // the thinner 5%
  std::nth_element(radius.begin(), radius.begin() + long(k), radius.end());
  const double thin = radius.empty() ? mean_area_edge : radius[k];
  return std::max(shortest, std::min(mean_area_edge, thin));
}

TriSurface remesh_isotropic(const TriSurface& surface, const RemeshIsotropicOptions& options,
                            RemeshIsotropicReport* report, const TriangleBvh* surface_bvh) {
  std::unique_ptr<TriangleBvh> own_bvh;
  if (!surface_bvh) surface_bvh = (own_bvh = std::make_unique<TriangleBvh>(surface)).get();
  const double length = options.edge_length > 0 ? options.edge_length : remesh_edge_length(surface, 0, surface_bvh);
  const double expected = length > 0 ? surface_area(surface) / (std::sqrt(3.0) / 4 * length * length) : 0;
  const size_t most = size_t(std::min(16 * expected, 4e8)) + 2 * surface.triangles.size();
  Remesher remesher(surface, *surface_bvh, options, length);
  const bool finished = remesher.run(most);
  TriSurface result = finished ? remesher.result() : surface;
  if (report) {
    report->gave_up = !finished;
    report->triangles_before = surface.triangles.size();
    report->triangles_after = result.triangles.size();
    report->edge_length = length;
    report->refused_crossings = remesher.refused_crossings();
    report->off_input_vertices = finished ? remesher.off_input_vertices() : 0;
    report->min_angle_before_deg = smallest_angle_deg(surface);
    report->min_angle_after_deg = smallest_angle_deg(result);
  }
  return result;
}

}  // namespace dthex
