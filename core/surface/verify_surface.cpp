// SPDX-License-Identifier: MIT
#include <dthex/surface/verify_surface.h>

#include <dthex/mesh/closest_triangle_pair.h>
#include <dthex/mesh/half_edges.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/mesh/triangle_crossing.h>
#include <dthex/numerics/signed_volume.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <iomanip>
#include <memory>
#include <numeric>
#include <sstream>

namespace dthex {

namespace {

using Triangle = std::array<int, 3>;

//! How many holes, intersecting pairs and such a refusal names one by one.
constexpr size_t kNamedExamples = 5;

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[size_t(x)] != x) {
      parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
      x = parent[size_t(x)];
    }
    return x;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
  }
};

//! Formats ids with coordinates for the messages.
class Describe {
 public:
  explicit Describe(const TriSurface& s) : s_(s) {}
  std::string point(const Vec3& p) const {
    std::ostringstream out;
    out.precision(10);
    out << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
    return out.str();
  }
  std::string vertex(int v) const { return "vertex " + std::to_string(v) + " " + point(s_.points[size_t(v)]); }
  std::string triangle(int t) const {
    const Triangle& tri = s_.triangles[size_t(t)];
    std::string text = "triangle " + std::to_string(t) + " [";
    for (int k = 0; k < 3; ++k) {
      if (k) text += ", ";
      text += std::to_string(tri[size_t(k)]);
      if (tri[size_t(k)] >= 0 && size_t(tri[size_t(k)]) < s_.points.size()) text += " " + point(s_.points[size_t(tri[size_t(k)])]);
    }
    return text + "]";
  }

 private:
  const TriSurface& s_;
};

//! Closed 2D segment intersection (used for coplanar configurations).
double orient2(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}
bool on_segment2(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= p.y() &&
         p.y() <= std::max(a.y(), b.y());
}
bool segments_intersect2(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const double d1 = orient2(a, b, p), d2 = orient2(a, b, q), d3 = orient2(p, q, a), d4 = orient2(p, q, b);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  if (d1 == 0 && on_segment2(a, b, p)) return true;
  if (d2 == 0 && on_segment2(a, b, q)) return true;
  if (d3 == 0 && on_segment2(p, q, a)) return true;
  if (d4 == 0 && on_segment2(p, q, b)) return true;
  return false;
}
bool point_in_triangle2(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                        const Eigen::Vector2d& c) {
  const double d1 = orient2(a, b, p), d2 = orient2(b, c, p), d3 = orient2(c, a, p);
  const bool has_neg = d1 < 0 || d2 < 0 || d3 < 0, has_pos = d1 > 0 || d2 > 0 || d3 > 0;
  return !(has_neg && has_pos);
}

//! Does the closed segment pq meet the closed triangle abc? The plane crossing is found
//! from the signed distances, and the crossing point is tested inside the triangle in the
//! triangle's dominant 2D projection: unlike sign tests of tetrahedra spanned by pq, this
//! stays well conditioned when pq lies almost in the plane (flat regions of CAD parts).
//! `where`, if given, receives a point they share (in the exactly coplanar case, one near it).
bool segment_meets_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                            Vec3* where = nullptr) {
  const double dp = signed_volume6(a, b, c, p), dq = signed_volume6(a, b, c, q);
  if ((dp > 0 && dq > 0) || (dp < 0 && dq < 0)) return false;
  const Vec3 n = (b - a).cross(c - a);
  int axis;
  n.cwiseAbs().maxCoeff(&axis);
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;
  auto flat = [&](const Vec3& v) { return Eigen::Vector2d(v[i], v[j]); };
  const Eigen::Vector2d A = flat(a), B = flat(b), C = flat(c);
  if (dp != 0 || dq != 0) {
    const double t = dp / (dp - dq);
    const Vec3 crossing = p + t * (q - p);
    if (where) *where = crossing;
    return point_in_triangle2(flat(crossing), A, B, C);
  }
  // Exactly coplanar.
  const Eigen::Vector2d P = flat(p), Q = flat(q);
  if (where) *where = point_in_triangle2(Q, A, B, C) ? q : p;
  if (point_in_triangle2(P, A, B, C) || point_in_triangle2(Q, A, B, C)) return true;
  return segments_intersect2(P, Q, A, B) || segments_intersect2(P, Q, B, C) || segments_intersect2(P, Q, C, A);
}

//! Closed triangles intersect iff an edge of one meets the other (the intersection, when
//! not empty, has a point on the boundary of one of them).
bool triangles_intersect(const std::array<Vec3, 3>& A, const std::array<Vec3, 3>& B, Vec3* where) {
  for (int k = 0; k < 3; ++k)
    if (segment_meets_triangle(A[size_t(k)], A[size_t((k + 1) % 3)], B[0], B[1], B[2], where)) return true;
  for (int k = 0; k < 3; ++k)
    if (segment_meets_triangle(B[size_t(k)], B[size_t((k + 1) % 3)], A[0], A[1], A[2], where)) return true;
  return false;
}

//! A pair of intersecting triangles (a < b) and a point where they meet.
struct IntersectingPair {
  int a = -1, b = -1;
  Vec3 point = Vec3::Zero();
  bool operator<(const IntersectingPair& o) const { return std::make_pair(a, b) < std::make_pair(o.a, o.b); }
};

//! Keeps the kNamedExamples lowest pairs of `pairs` with `pair` added.
void keep_lowest(std::vector<IntersectingPair>& pairs, const IntersectingPair& pair, size_t count) {
  if (pairs.size() == count && !(pair < pairs.back())) return;
  pairs.insert(std::upper_bound(pairs.begin(), pairs.end(), pair), pair);
  if (pairs.size() > count) pairs.pop_back();
}

//! Solid angle of triangle abc seen from p, over 4 pi (Van Oosterom and Strackee).
double winding_contribution(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 A = a - p, B = b - p, C = c - p;
  const double la = A.norm(), lb = B.norm(), lc = C.norm();
  const double numerator = A.dot(B.cross(C));
  const double denominator = la * lb * lc + A.dot(B) * lc + B.dot(C) * la + C.dot(A) * lb;
  return 2.0 * std::atan2(numerator, denominator) / (4.0 * M_PI);
}

constexpr double kMaxCoordinate = 1e100;

//! The holes of an open surface: its open edges (each on one triangle only) joined through
//! their vertices into loops, each with its edge count, length and a vertex on it, and the
//! tools that close them.
std::string describe_holes(const TriSurface& s, const std::vector<HalfEdge>& half_edges,
                           const std::vector<size_t>& open_edges) {
  const Describe describe(s);
  UnionFind loops(s.points.size());
  for (size_t k : open_edges) loops.unite(int(half_edges[k].key >> 32), int(half_edges[k].key & 0xffffffffu));
  struct Hole {
    size_t edges = 0;
    double length = 0;
    int vertex = -1;  // the lowest vertex of its first edge
  };
  std::vector<Hole> holes;
  std::vector<int> hole_of(s.points.size(), -1);
  for (size_t k : open_edges) {
    const int a = int(half_edges[k].key >> 32), b = int(half_edges[k].key & 0xffffffffu);
    int& h = hole_of[size_t(loops.find(a))];
    if (h < 0) {
      h = int(holes.size());
      holes.push_back({0, 0.0, a});
    }
    ++holes[size_t(h)].edges;
    holes[size_t(h)].length += (s.points[size_t(b)] - s.points[size_t(a)]).norm();
  }
  std::ostringstream out;
  out.precision(6);
  out << holes.size() << (holes.size() == 1 ? " hole" : " holes") << " (loops of open boundary edges, "
      << open_edges.size() << " edge" << (open_edges.size() == 1 ? "" : "s") << " in all)";
  for (size_t h = 0; h < std::min(holes.size(), kNamedExamples); ++h)
    out << (h ? "; " : ": ") << "hole " << h + 1 << " of " << holes[h].edges << " edge" << (holes[h].edges == 1 ? "" : "s")
        << ", length " << holes[h].length << ", at " << describe.vertex(holes[h].vertex);
  if (holes.size() > kNamedExamples) out << "; ...";
  const HalfEdge& first = half_edges[open_edges[0]];
  out << "; the first open boundary edge (" << describe.vertex(int(first.key >> 32)) << ", "
      << describe.vertex(int(first.key & 0xffffffffu)) << ") belongs only to triangle " << first.triangle
      << "; close the holes with MeshLab (Close Holes), PyMeshFix or Blender (Fill Holes) and mesh the closed file";
  return out.str();
}

}  // namespace

SurfaceStats verify_surface(TriSurface& surface, const std::string& name, const VerifyOptions& options) {
  auto refuse = [&](const std::string& rule, const std::string& detail) {
    throw InputError(name + ": " + rule + ": " + detail);
  };
  const Describe describe(surface);
  const auto& P = surface.points;
  auto& T = surface.triangles;
  const int nv = int(P.size()), nt = int(T.size());

  // 1. empty
  if (T.empty()) refuse("empty", "the surface has no triangles (" + std::to_string(P.size()) + " vertices)");
  // 2. non-finite coordinates
  for (int v = 0; v < nv; ++v)
    if (!P[size_t(v)].allFinite()) refuse("non-finite coordinates", describe.vertex(v));
  // Volumes and cross products cube and square coordinates: beyond 1e100 they overflow
  // to inf later, in stages with far less helpful messages. No real geometry is that big.
  for (int v = 0; v < nv; ++v)
    if (P[size_t(v)].cwiseAbs().maxCoeff() > kMaxCoordinate)
      refuse("coordinate out of range", describe.vertex(v) + " has a coordinate beyond +-1e100");
  // 3. face index out of range
  for (int t = 0; t < nt; ++t)
    for (int v : T[size_t(t)])
      if (v < 0 || v >= nv)
        refuse("face index out of range", describe.triangle(t) + " refers to vertex " + std::to_string(v) +
                                              " but there are " + std::to_string(nv) + " vertices");
  // 4. degenerate triangles
  for (int t = 0; t < nt; ++t) {
    const Triangle& tri = T[size_t(t)];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0])
      refuse("degenerate triangle", describe.triangle(t) + " repeats a vertex");
    if (has_zero_area(P[size_t(tri[0])], P[size_t(tri[1])], P[size_t(tri[2])]))
      refuse("degenerate triangle",
             describe.triangle(t) + " has zero area; --repair safe flips such a sliver away where its neighbour " +
                 "allows, else remove it in MeshLab (Remove Zero Area Faces) or with PyMeshFix and close the hole");
  }
  // 5. duplicate triangles
  {
    std::vector<int> all(static_cast<size_t>(nt));
    for (int t = 0; t < nt; ++t) all[size_t(t)] = t;
    const std::vector<TriangleKey> sorted = sorted_triangle_keys(T, all);
    int first_a = -1, first_b = -1;
    for (size_t k = 1; k < sorted.size(); ++k)
      if (sorted[k].first == sorted[k - 1].first) {
        const int a = sorted[k - 1].second, b = sorted[k].second;
        if (first_a < 0 || a < first_a) {
          first_a = a;
          first_b = b;
        }
      }
    if (first_a >= 0)
      refuse("duplicate triangles", describe.triangle(first_a) + " and triangle " + std::to_string(first_b) +
                                        " use the same three vertices");
  }
  // 6. every edge shared by exactly two triangles
  const std::vector<HalfEdge> half_edges = sorted_half_edges(T);
  auto edge_text = [&](uint64_t key) {
    const int a = int(key >> 32), b = int(key & 0xffffffffu);
    return "edge (" + describe.vertex(a) + ", " + describe.vertex(b) + ")";
  };
  size_t edge_count = 0;
  std::vector<size_t> open_edges;  // into half_edges, in key order
  std::string non_manifold;        // the first edge on three or more triangles
  for (size_t k = 0; k < half_edges.size();) {
    size_t end = k;
    while (end < half_edges.size() && half_edges[end].key == half_edges[k].key) ++end;
    const size_t count = end - k;
    if (count == 1) open_edges.push_back(k);
    if (count > 2 && non_manifold.empty()) {
      std::string list;
      for (size_t i = k; i < end; ++i) list += (i > k ? ", " : "") + std::to_string(half_edges[i].triangle);
      non_manifold = edge_text(half_edges[k].key) + " is shared by " + std::to_string(count) + " triangles (" + list + ")";
    }
    ++edge_count;
    k = end;
  }
  if (!open_edges.empty()) refuse("open surface", describe_holes(surface, half_edges, open_edges));
  if (!non_manifold.empty()) refuse("non-manifold edge", non_manifold);
  // 7. non-manifold vertices: corners (t, k) around a vertex joined across shared edges must form one fan.
  auto corner_of = [&](int t, int v) {
    const Triangle& tri = T[size_t(t)];
    return 3 * t + (tri[0] == v ? 0 : tri[1] == v ? 1 : 2);
  };
  {
    UnionFind corners(size_t(nt) * 3);
    for (size_t k = 0; k < half_edges.size(); k += 2) {
      const int t1 = half_edges[k].triangle, t2 = half_edges[k + 1].triangle;
      const int a = int(half_edges[k].key >> 32), b = int(half_edges[k].key & 0xffffffffu);
      corners.unite(corner_of(t1, a), corner_of(t2, a));
      corners.unite(corner_of(t1, b), corner_of(t2, b));
    }
    std::vector<int> fan(size_t(nv), -1);
    std::vector<int> fans(size_t(nv), 0);
    for (int c = 0; c < 3 * nt; ++c) {
      const int v = T[size_t(c / 3)][size_t(c % 3)];
      const int root = corners.find(c);
      if (fan[size_t(v)] < 0) {
        fan[size_t(v)] = root;
        fans[size_t(v)] = 1;
      } else if (fan[size_t(v)] != root) {
        // Count distinct fans only roughly (enough to say "more than one").
        ++fans[size_t(v)];
      }
    }
    for (int v = 0; v < nv; ++v)
      if (fans[size_t(v)] > 1)
        refuse("non-manifold vertex", describe.vertex(v) + " joins several separate fans of triangles");
  }
  // 8. consistent orientation, and components over shared edges
  UnionFind components_uf(static_cast<size_t>(nt));
  for (size_t k = 0; k < half_edges.size(); k += 2) {
    const HalfEdge &e1 = half_edges[k], &e2 = half_edges[k + 1];
    if (e1.from == e2.from)
      refuse("inconsistent orientation",
             "triangles " + std::to_string(e1.triangle) + " and " + std::to_string(e2.triangle) +
                 " traverse their shared " + edge_text(e1.key) + " in the same direction");
    components_uf.unite(e1.triangle, e2.triangle);
  }
  // 9. folded edges: the two triangles on an edge lying (nearly) on each other, a fin the
  // coarsening's check refuses at every eps, and TetGen cannot tell apart.
  if (options.check_self_intersections) {
    const size_t none = half_edges.size();
    size_t folded = 0;
    size_t first = none;  // the fold whose triangle pair is lowest (the same on any core count)
    auto tri_points = [&](int t) {
      const Triangle& tri = T[size_t(t)];
      return std::array<Vec3, 3>{P[size_t(tri[0])], P[size_t(tri[1])], P[size_t(tri[2])]};
    };
    auto pair_of = [&](size_t k) {
      const int a = half_edges[k].triangle, b = half_edges[k + 1].triangle;
      return std::array<int, 2>{std::min(a, b), std::max(a, b)};
    };
    auto lower = [&](size_t k, size_t than) { return k != none && (than == none || pair_of(k) < pair_of(than)); };
    // Both cores: at 4.7M triangles the pass took 0.55 s on one.
#pragma omp parallel if (nt > 20000)
    {
      size_t mine = none;
#pragma omp for reduction(+ : folded) schedule(static)
      for (long e = 0; e < long(half_edges.size() / 2); ++e) {
        const size_t k = 2 * size_t(e);
        if (!triangles_fold_onto_each_other(tri_points(half_edges[k].triangle), tri_points(half_edges[k + 1].triangle)))
          continue;
        ++folded;
        if (lower(k, mine)) mine = k;
      }
#pragma omp critical(dthex_verify_fold)
      if (lower(mine, first)) first = mine;
    }
    if (folded) {
      const auto [a, b] = pair_of(first);
      std::ostringstream angle;
      angle << std::setprecision(2) << angle_between_sides_deg(tri_points(a), tri_points(b));
      refuse("folded edge",
             std::to_string(folded) + " edge" + (folded > 1 ? "s" : "") +
                 " where the surface folds back onto itself, first " + describe.triangle(a) + " and " +
                 describe.triangle(b) + " on their shared " + edge_text(half_edges[first].key) + ", their sides " +
                 angle.str() + " degrees apart (under 0.0008 degrees, a fin no tet mesher resolves); "
                 "a needle-thin spike or fin: smooth the surface there (a few Laplacian steps open it) or "
                 "cut it away and close the hole, and mesh the repaired file");
    }
  }
  // 10. self-intersections
  std::unique_ptr<TriangleBvh> tree;
  if (options.check_self_intersections) {
    tree = std::make_unique<TriangleBvh>(surface);
    const TriangleBvh& bvh = *tree;
    // Do triangles a and b (their boxes overlapping) meet anywhere but in what they share?
    // If so, `where` receives a point they share.
    auto pair_intersects = [&](int a, int b, Vec3& where) {
      const Triangle &ta = T[size_t(a)], &tb = T[size_t(b)];
      int shared = 0;
      for (int u : ta)
        for (int w : tb) shared += u == w;
      const std::array<Vec3, 3> A{P[size_t(ta[0])], P[size_t(ta[1])], P[size_t(ta[2])]};
      const std::array<Vec3, 3> B{P[size_t(tb[0])], P[size_t(tb[1])], P[size_t(tb[2])]};
      bool hit = false;
      if (shared == 0) {
        hit = triangles_intersect(A, B, &where);
      } else if (shared == 1) {
        // Meeting beyond the shared vertex means an edge opposite it meets the other triangle.
        int ia = 0, ib = 0;
        for (int k = 0; k < 3; ++k) {
          if (std::find(tb.begin(), tb.end(), ta[size_t(k)]) != tb.end()) ia = k;
          if (std::find(ta.begin(), ta.end(), tb[size_t(k)]) != ta.end()) ib = k;
        }
        hit = segment_meets_triangle(A[size_t((ia + 1) % 3)], A[size_t((ia + 2) % 3)], B[0], B[1], B[2], &where) ||
              segment_meets_triangle(B[size_t((ib + 1) % 3)], B[size_t((ib + 2) % 3)], A[0], A[1], A[2], &where);
      }
      // Sharing an edge, they overlap only if folded onto each other: refused above.
      return hit;
    };
    // The pairs are split into parts over the cores, each part counting its own hits and
    // keeping its lowest pairs; the totals do not depend on how the parts were shared out.
    const std::vector<std::array<int, 2>> parts = bvh.overlapping_pair_parts(64);
    std::vector<size_t> found_in(parts.size(), 0);
    std::vector<std::vector<IntersectingPair>> first_in(parts.size());
    std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, 1) if (nt > 20000)
    for (long i = 0; i < long(parts.size()); ++i) {
      try {
        bvh.for_each_overlapping_pair_in(parts[size_t(i)], [&](int a, int b) {
          Vec3 where;
          if (!pair_intersects(a, b, where)) return;
          ++found_in[size_t(i)];
          keep_lowest(first_in[size_t(i)], {a, b, where}, kNamedExamples);
        });
      } catch (...) {
#pragma omp critical(dthex_verify_failure)
        failure = std::current_exception();
      }
    }
    if (failure) std::rethrow_exception(failure);
    size_t found = 0;
    std::vector<IntersectingPair> first;
    for (size_t i = 0; i < parts.size(); ++i) {
      found += found_in[i];
      for (const IntersectingPair& pair : first_in[i]) keep_lowest(first, pair, kNamedExamples);
    }
    if (found) {
      std::string pairs;
      for (size_t k = 0; k < first.size(); ++k)
        pairs += (k ? ", " : "") + std::to_string(first[k].a) + " and " + std::to_string(first[k].b) + " at " +
                 describe.point(first[k].point);
      refuse("self-intersection",
             std::to_string(found) + " intersecting triangle pair" + (found > 1 ? "s" : "") + ", first " +
                 describe.triangle(first[0].a) + " and " + describe.triangle(first[0].b) + "; " +
                 (found > 1 ? "the first " + std::to_string(first.size()) + " pairs: " : "where: ") + pairs +
                 (found > first.size() ? ", ..." : "") +
                 "; remove them in MeshLab (Select Self Intersecting Faces, delete, then Close Holes) or with "
                 "PyMeshFix, and mesh the repaired file");
    }
  }

  // Components: ids in order of their first triangle.
  std::vector<int> component(static_cast<size_t>(nt));
  std::vector<int> root_to_component(size_t(nt), -1);
  int component_count = 0;
  for (int t = 0; t < nt; ++t) {
    const int root = components_uf.find(t);
    if (root_to_component[size_t(root)] < 0) root_to_component[size_t(root)] = component_count++;
    component[size_t(t)] = root_to_component[size_t(root)];
  }
  std::vector<double> volume(size_t(component_count), 0.0);
  std::vector<Eigen::AlignedBox3d> component_box(static_cast<size_t>(component_count));
  std::vector<int> first_triangle(size_t(component_count), -1);
  Eigen::AlignedBox3d bounds;
  for (int v = 0; v < nv; ++v) bounds.extend(P[size_t(v)]);
  const Vec3 origin = bounds.center();  // signed volumes about the centre lose less precision
  for (int t = 0; t < nt; ++t) {
    const Triangle& tri = T[size_t(t)];
    const int c = component[size_t(t)];
    const Vec3 a = P[size_t(tri[0])] - origin, b = P[size_t(tri[1])] - origin, d = P[size_t(tri[2])] - origin;
    volume[size_t(c)] += a.dot(b.cross(d)) / 6.0;
    for (int v : tri) component_box[size_t(c)].extend(P[size_t(v)]);
    if (first_triangle[size_t(c)] < 0) first_triangle[size_t(c)] = t;
  }
  // 11. zero volume
  for (int c = 0; c < component_count; ++c) {
    const double diagonal = component_box[size_t(c)].diagonal().norm();
    if (std::abs(volume[size_t(c)]) <= 1e-9 * diagonal * diagonal * diagonal)
      refuse("zero volume", "component " + std::to_string(c) + " (containing " +
                                describe.triangle(first_triangle[size_t(c)]) + ") encloses volume " +
                                std::to_string(volume[size_t(c)]));
  }

  // 12. bodies closer than the tet mesher can tell apart
  if (options.near_contact_tolerance > 0 && component_count > 1) {
    if (!tree) tree = std::make_unique<TriangleBvh>(surface);
    const double diagonal = bounds.diagonal().norm(), tolerance = options.near_contact_tolerance * diagonal;
    const TrianglePairDistance near = closest_separate_pair(
        *tree, tolerance, [&](int a, int b) { return component[size_t(a)] != component[size_t(b)]; });
    if (near.a >= 0) {
      std::vector<size_t> triangles_in(size_t(component_count), 0);
      for (int t = 0; t < nt; ++t) ++triangles_in[size_t(component[size_t(t)])];
      auto body = [&](int t) {
        const int c = component[size_t(t)];
        return "component " + std::to_string(c) + " (" + std::to_string(triangles_in[size_t(c)]) + " triangles, here triangle " +
               std::to_string(t) + ")";
      };
      std::ostringstream gap;
      gap.precision(3);
      gap << near.distance << " apart at " << describe.point(near.point_a) << ", below " << options.near_contact_tolerance
          << " of the bounding-box diagonal (" << tolerance << ")";
      refuse("bodies too close",
             body(near.a) + " and " + body(near.b) + " are " + gap.str() +
                 ", closer than the tet mesher can tell apart; move one away from the other, or merge them into one "
                 "body by a boolean union (MeshLab, Blender's Boolean modifier, or the segmentation tool)");
    }
  }

  // Nesting: component c lies inside d when d's winding number at a point of c is +-1.
  std::vector<std::vector<int>> triangles_of(static_cast<size_t>(component_count));
  if (component_count > 1)
    for (int t = 0; t < nt; ++t) triangles_of[size_t(component[size_t(t)])].push_back(t);
  SurfaceStats stats;
  for (int c = 0; c < component_count; ++c) {
    int depth = 0;
    const Triangle& probe_tri = T[size_t(first_triangle[size_t(c)])];
    const Vec3 probe = (P[size_t(probe_tri[0])] + P[size_t(probe_tri[1])] + P[size_t(probe_tri[2])]) / 3.0;
    for (int d = 0; d < component_count; ++d) {
      if (d == c || !component_box[size_t(d)].contains(probe)) continue;
      double winding = 0;
      for (int t : triangles_of[size_t(d)]) {
        const Triangle& tri = T[size_t(t)];
        winding += winding_contribution(probe, P[size_t(tri[0])], P[size_t(tri[1])], P[size_t(tri[2])]);
      }
      if (std::abs(winding) > 0.5) ++depth;
    }
    const bool cavity = depth % 2 == 1;
    stats.cavities += cavity;
    if ((volume[size_t(c)] > 0) == cavity) {
      volume[size_t(c)] = -volume[size_t(c)];
      ++stats.flipped_components;
      if (component_count == 1)
        for (Triangle& tri : T) std::swap(tri[1], tri[2]);
      else
        for (int t : triangles_of[size_t(c)]) std::swap(T[size_t(t)][1], T[size_t(t)][2]);
    }
  }

  // Drop unreferenced vertices.
  std::vector<int> new_index(size_t(nv), -1);
  for (const Triangle& tri : T)
    for (int v : tri) new_index[size_t(v)] = 0;
  int kept = 0;
  for (int v = 0; v < nv; ++v)
    if (new_index[size_t(v)] == 0) new_index[size_t(v)] = kept++;
  std::vector<int> vertex_component(size_t(nv), -1);
  for (int t = 0; t < nt; ++t)
    for (int v : T[size_t(t)]) vertex_component[size_t(v)] = component[size_t(t)];
  std::vector<long> component_vertices(size_t(component_count), 0), component_triangles(size_t(component_count), 0);
  for (int v = 0; v < nv; ++v)
    if (vertex_component[size_t(v)] >= 0) ++component_vertices[size_t(vertex_component[size_t(v)])];
  for (int t = 0; t < nt; ++t) ++component_triangles[size_t(component[size_t(t)])];
  if (kept < nv) {
    std::vector<Vec3> points;
    points.reserve(size_t(kept));
    for (int v = 0; v < nv; ++v)
      if (new_index[size_t(v)] >= 0) points.push_back(P[size_t(v)]);
    for (Triangle& tri : T)
      for (int& v : tri) v = new_index[size_t(v)];
    stats.unreferenced_vertices = size_t(nv - kept);
    surface.points = std::move(points);
  }

  stats.vertices = surface.points.size();
  stats.triangles = T.size();
  stats.edges = edge_count;
  stats.components = size_t(component_count);
  for (int c = 0; c < component_count; ++c) {
    // Each closed component: F = 2E/3, so V - E + F = V - F/2.
    const long euler = component_vertices[size_t(c)] - component_triangles[size_t(c)] / 2;
    const int genus = int((2 - euler) / 2);
    stats.component_genus.push_back(genus);
    stats.genus += genus;
    stats.volume += volume[size_t(c)];
  }
  for (const Triangle& tri : T)
    stats.area += 0.5 * (surface.points[size_t(tri[1])] - surface.points[size_t(tri[0])])
                            .cross(surface.points[size_t(tri[2])] - surface.points[size_t(tri[0])])
                            .norm();
  stats.bounds = Eigen::AlignedBox3d();
  for (const Vec3& p : surface.points) stats.bounds.extend(p);
  stats.bbox_diagonal = stats.bounds.diagonal().norm();
  stats.triangle_shape = summarize(triangle_shapes(surface));
  // A flip reverses triangles the tree holds copies of, a removal renumbers vertices.
  if (options.search_tree && tree && stats.flipped_components == 0 && stats.unreferenced_vertices == 0)
    *options.search_tree = std::move(tree);
  return stats;
}

}  // namespace dthex
