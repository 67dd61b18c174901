// SPDX-License-Identifier: MIT
#include <dthex/mesh/surface_mesh.h>

#include <dthex/mesh/half_edges.h>

#include <algorithm>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace dthex {

SurfaceMesh to_openmesh(const TriSurface& surface) {
  SurfaceMesh mesh;
  fill_openmesh(mesh, surface);
  return mesh;
}

namespace {

// OpenMesh's own insertion: a face at a time, each edge found by walking around its vertex.
void add_faces_one_by_one(SurfaceMesh& mesh, const TriSurface& surface) {
  // A closed triangle surface has 3/2 edges per triangle: the arrays (and every property
  // array beside them) are sized once instead of regrown.
  mesh.reserve(surface.points.size(), 3 * surface.triangles.size() / 2 + 3, surface.triangles.size());
  std::vector<SurfaceMesh::VertexHandle> handles;
  handles.reserve(surface.points.size());
  for (const Vec3& p : surface.points) handles.push_back(mesh.add_vertex(to_openmesh(p)));
  for (size_t f = 0; f < surface.triangles.size(); ++f) {
    const auto& t = surface.triangles[f];
    const auto fh = mesh.add_face(handles[size_t(t[0])], handles[size_t(t[1])], handles[size_t(t[2])]);
    if (!fh.is_valid())
      throw InputError("triangle " + std::to_string(f) + " cannot be added to a manifold mesh");
  }
}

// Per corner edge (triangle t's edge k runs from corner k to corner k + 1; index 3t + k), the
// index of its undirected edge, numbered in the order add_face would create them: the first
// triangle that has an edge, in file order, creates it. Empty if a triangle repeats a vertex
// or names one out of range.
std::vector<int> number_edges(const TriSurface& surface, size_t& n_edges) {
  for (const auto& t : surface.triangles) {
    for (int v : t)
      if (v < 0 || size_t(v) >= surface.points.size()) return {};
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return {};
  }
  // The uses of an edge side by side (by lower vertex, upper vertex, corner edge): the first
  // is the first triangle's, and names the edge.
  struct Use {
    int lower, upper, corner_edge;
  };
  const auto use = [&](size_t c) {
    const auto& t = surface.triangles[c / 3];
    const int a = t[c % 3], b = t[(c + 1) % 3];
    return Use{std::min(a, b), std::max(a, b), int(c)};
  };
  const std::vector<Use> uses = sorted_by_lead_vertex<Use>(
      3 * surface.triangles.size(), use, [](const Use& u) { return int64_t(u.lower); },
      [](const Use& x, const Use& y) { return std::tie(x.lower, x.upper, x.corner_edge) < std::tie(y.lower, y.upper, y.corner_edge); });
  std::vector<int> first(uses.size(), -1);
  for (size_t i = 0; i < uses.size();) {
    size_t j = i;
    for (; j < uses.size() && uses[j].lower == uses[i].lower && uses[j].upper == uses[i].upper; ++j)
      first[size_t(uses[j].corner_edge)] = uses[i].corner_edge;
    i = j;
  }
  // Edge numbers in creation order, then every corner edge's.
  std::vector<int> number(first.size(), -1);
  n_edges = 0;
  for (size_t c = 0; c < first.size(); ++c)
    if (first[c] == int(c)) number[c] = int(n_edges++);
  for (int& c : first) c = number[size_t(c)];
  return first;
}

}  // namespace

bool replay_add_faces(SurfaceMesh& mesh, const TriSurface& surface) {
  using HH = SurfaceMesh::HalfedgeHandle;
  using VH = SurfaceMesh::VertexHandle;
  size_t n_edges = 0;
  const std::vector<int> edge = number_edges(surface, n_edges);
  if (edge.empty() && !surface.triangles.empty()) return false;
  mesh.resize(surface.points.size(), n_edges, surface.triangles.size());
  for (size_t v = 0; v < surface.points.size(); ++v) mesh.set_point(VH(int(v)), to_openmesh(surface.points[v]));
  for (size_t c = 0; c < edge.size(); ++c) {
    const auto& t = surface.triangles[c / 3];
    const HH h(2 * edge[c]);
    if (mesh.to_vertex_handle(h).is_valid()) continue;  // set by its first corner edge
    mesh.set_vertex_handle(h, VH(t[(c + 1) % 3]));
    mesh.set_vertex_handle(mesh.opposite_halfedge_handle(h), VH(t[c % 3]));
  }
  const auto boundary_vertex = [&](VH v) {
    const HH h = mesh.halfedge_handle(v);
    return !(h.is_valid() && mesh.face_handle(h).is_valid());
  };
  std::vector<char> made(n_edges, 0);
  std::pair<HH, HH> next_cache[18];
  for (size_t f = 0; f < surface.triangles.size(); ++f) {
    const auto& t = surface.triangles[f];
    const VH v[3] = {VH(t[0]), VH(t[1]), VH(t[2])};
    HH h[3];
    bool is_new[3], needs_adjust[3] = {false, false, false};
    for (int i = 0; i < 3; ++i) {
      if (!boundary_vertex(v[i])) return false;  // a complex vertex
      const int e = edge[3 * f + size_t(i)];
      is_new[i] = !made[size_t(e)];
      h[i] = HH(2 * e);
      if (mesh.to_vertex_handle(h[i]) != v[(i + 1) % 3]) h[i] = mesh.opposite_halfedge_handle(h[i]);
      if (!is_new[i] && mesh.face_handle(h[i]).is_valid()) return false;  // a complex edge
    }
    int cached = 0;
    for (int i = 0; i < 3; ++i) {  // re-link patches
      const int ii = (i + 1) % 3;
      if (is_new[i] || is_new[ii]) continue;
      const HH inner_prev = h[i], inner_next = h[ii];
      if (mesh.next_halfedge_handle(inner_prev) == inner_next) continue;
      HH boundary_prev = mesh.opposite_halfedge_handle(inner_next);
      do boundary_prev = mesh.opposite_halfedge_handle(mesh.next_halfedge_handle(boundary_prev));
      while (mesh.face_handle(boundary_prev).is_valid());
      const HH boundary_next = mesh.next_halfedge_handle(boundary_prev);
      if (boundary_prev == inner_prev) return false;  // no gap to re-link into
      next_cache[cached++] = {boundary_prev, mesh.next_halfedge_handle(inner_prev)};
      next_cache[cached++] = {mesh.prev_halfedge_handle(inner_next), boundary_next};
      next_cache[cached++] = {inner_prev, inner_next};
    }
    for (int i = 0; i < 3; ++i)
      if (is_new[i]) made[size_t(edge[3 * f + size_t(i)])] = 1;
    const SurfaceMesh::FaceHandle fh{int(f)};
    mesh.set_halfedge_handle(fh, h[2]);
    for (int i = 0; i < 3; ++i) {
      const int ii = (i + 1) % 3;
      const VH vh = v[ii];
      const HH inner_prev = h[i], inner_next = h[ii];
      const int id = (is_new[i] ? 1 : 0) | (is_new[ii] ? 2 : 0);
      if (id) {
        const HH outer_prev = mesh.opposite_halfedge_handle(inner_next);
        const HH outer_next = mesh.opposite_halfedge_handle(inner_prev);
        if (id == 1) {
          next_cache[cached++] = {mesh.prev_halfedge_handle(inner_next), outer_next};
          mesh.set_halfedge_handle(vh, outer_next);
        } else if (id == 2) {
          const HH boundary_next = mesh.next_halfedge_handle(inner_prev);
          next_cache[cached++] = {outer_prev, boundary_next};
          mesh.set_halfedge_handle(vh, boundary_next);
        } else if (!mesh.halfedge_handle(vh).is_valid()) {
          mesh.set_halfedge_handle(vh, outer_next);
          next_cache[cached++] = {outer_prev, outer_next};
        } else {
          const HH boundary_next = mesh.halfedge_handle(vh);
          next_cache[cached++] = {mesh.prev_halfedge_handle(boundary_next), outer_next};
          next_cache[cached++] = {outer_prev, boundary_next};
        }
        next_cache[cached++] = {inner_prev, inner_next};
      } else {
        needs_adjust[ii] = mesh.halfedge_handle(vh) == inner_next;
      }
      mesh.set_face_handle(h[i], fh);
    }
    for (int i = 0; i < cached; ++i) mesh.set_next_halfedge_handle(next_cache[i].first, next_cache[i].second);
    for (int i = 0; i < 3; ++i) {
      if (!needs_adjust[i]) continue;
      // The first boundary halfedge clockwise from the current one, as OpenMesh's circulator.
      const HH start = mesh.halfedge_handle(v[i]);
      HH around = start;
      do {
        if (!mesh.face_handle(around).is_valid()) {
          mesh.set_halfedge_handle(v[i], around);
          break;
        }
        around = mesh.cw_rotated_halfedge_handle(around);
      } while (around.is_valid() && around != start);
    }
  }
  return true;
}

void fill_openmesh(SurfaceMesh& mesh, const TriSurface& surface) {
  // The replay is the fast way to add_faces_one_by_one's mesh; where add_face refuses a face,
  // that is run from scratch so that the error names the triangle as OpenMesh finds it. A mesh
  // that is not empty (against the contract) is added to as before, a face at a time.
  if (mesh.n_vertices() == 0 && mesh.n_faces() == 0) {
    if (replay_add_faces(mesh, surface)) return;
    mesh.clear();
  }
  add_faces_one_by_one(mesh, surface);
}

TriSurface from_openmesh(const SurfaceMesh& mesh) {
  TriSurface surface;
  std::vector<int> index(mesh.n_vertices(), -1);
  for (auto v : mesh.vertices()) {
    if (mesh.status(v).deleted()) continue;
    index[size_t(v.idx())] = int(surface.points.size());
    surface.points.push_back(to_eigen(mesh.point(v)));
  }
  for (auto f : mesh.faces()) {
    if (mesh.status(f).deleted()) continue;
    std::array<int, 3> t{};
    int k = 0;
    for (auto v : mesh.fv_range(f)) t[size_t(k++)] = index[size_t(v.idx())];
    surface.triangles.push_back(t);
  }
  return surface;
}

}  // namespace dthex
