// SPDX-License-Identifier: MIT
#include <dthex/surface/split_in_halves.h>

#include <dthex/modules/DTHexGeometry.hh>

#include <algorithm>
#include <exception>
#include <string>

#include <Eigen/Geometry>

namespace dthex {

namespace {

using VertexHandle = SurfaceMesh::VertexHandle;

//! Sweeps over the vertices until every vertex's triangles on each side form one fan: a
//! vertex whose side changes more than twice around it gets all its triangles moved to the
//! side that has most of them. False if that has not settled after `max_sweeps`.
bool make_fans_whole(const SurfaceMesh& mesh, std::vector<char>& side, int max_sweeps = 50) {
  std::vector<char> around;
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    bool changed = false;
    for (auto v : mesh.vertices()) {
      around.clear();
      for (auto f : mesh.vf_range(v)) around.push_back(side[size_t(f.idx())]);
      size_t changes = 0, on_one = 0;
      for (size_t i = 0; i < around.size(); ++i) {
        changes += around[i] != around[(i + 1) % around.size()];
        on_one += around[i] == 1;
      }
      if (changes <= 2) continue;
      const char majority = 2 * on_one > around.size() ? 1 : 0;
      for (auto f : mesh.vf_range(v)) side[size_t(f.idx())] = majority;
      changed = true;
    }
    if (!changed) return true;
  }
  return false;
}

}  // namespace

bool split_connectivity(const SurfaceMesh& whole, SurfaceHalves& out) {
  out = SurfaceHalves();
  const size_t n_faces = whole.n_faces(), n_vertices = whole.n_vertices();
  if (n_faces < 2) return false;
  Eigen::AlignedBox3d box;
  for (auto v : whole.vertices()) box.extend(to_eigen(whole.point(v)));
  int axis = 0;
  box.sizes().maxCoeff(&axis);
  // Three times the centroid: the same order, without the division.
  std::vector<double> key(n_faces);
  for (auto f : whole.faces()) {
    double sum = 0;
    for (auto v : whole.fv_range(f)) sum += whole.point(v)[axis];
    key[size_t(f.idx())] = sum;
  }
  std::vector<double> sorted = key;
  std::nth_element(sorted.begin(), sorted.begin() + long(n_faces / 2), sorted.end());
  const double median = sorted[n_faces / 2];
  std::vector<char> side(n_faces);
  for (size_t f = 0; f < n_faces; ++f) side[f] = key[f] < median ? 0 : 1;
  if (!make_fans_whole(whole, side)) return false;
  const size_t on_one = size_t(std::count(side.begin(), side.end(), 1));
  if (on_one == 0 || on_one == n_faces) return false;

  out.cut.assign(n_vertices, 0);
  for (auto v : whole.vertices()) {
    bool seen[2] = {false, false};
    for (auto f : whole.vf_range(v)) seen[size_t(side[size_t(f.idx())])] = true;
    out.cut[size_t(v.idx())] = seen[0] && seen[1];
  }
  out.cut_vertices = size_t(std::count(out.cut.begin(), out.cut.end(), 1));

  // One half's triangles and vertices; false if they do not make an OpenMesh mesh.
  auto build_half = [&](int p) {
    std::vector<int> local(n_vertices, -1);
    std::vector<int>& whole_vertex = out.whole_vertex[size_t(p)];
    whole_vertex.clear();
    TriSurface part;
    for (auto f : whole.faces()) {
      if (side[size_t(f.idx())] != p) continue;
      std::array<int, 3> corners{};
      int k = 0;
      for (auto v : whole.fv_range(f)) {
        int& l = local[size_t(v.idx())];
        if (l < 0) {
          l = int(whole_vertex.size());
          whole_vertex.push_back(v.idx());
          part.points.push_back(to_eigen(whole.point(v)));
        }
        corners[size_t(k++)] = l;
      }
      part.triangles.push_back(corners);
    }
    try {
      fill_openmesh(out.halves[size_t(p)], part);
    } catch (const InputError&) {
      return false;
    }
    return true;
  };
  // The two halves are built at the same time (OpenMesh's face insertion is most of it). An
  // exception must not leave the parallel region (out of memory there ended the program):
  // each half's is carried out and thrown after it.
  bool built[2] = {false, false};
  std::exception_ptr failure[2];
#pragma omp parallel for num_threads(2) schedule(static, 1)
  for (int p = 0; p < 2; ++p) {
    try {
      built[p] = build_half(p);
    } catch (...) {
      failure[size_t(p)] = std::current_exception();
    }
  }
  for (const auto& f : failure)
    if (f) std::rethrow_exception(f);
  return built[0] && built[1];
}

void mark_halves(const SurfaceMesh& whole, SurfaceHalves& out, const SplitExtras& extras) {
  const size_t n_vertices = whole.n_vertices();
  OpenMesh::VPropHandleT<double> whole_size;
  const bool own_sizes = whole.get_property_handle(whole_size, size_property_name());
  const bool given_sizes = extras.sizes && extras.sizes->size() == n_vertices;
  const bool with_sizes = own_sizes || given_sizes;
  const bool given_locks = extras.locked && extras.locked->size() == n_vertices;
  for (int p = 0; p < 2; ++p) {
    SurfaceMesh& half = out.halves[size_t(p)];
    const std::vector<int>& whole_vertex = out.whole_vertex[size_t(p)];
    OpenMesh::VPropHandleT<double> size;
    if (with_sizes && !half.get_property_handle(size, size_property_name()))
      half.add_property(size, size_property_name());
    for (auto v : half.vertices()) {
      const VertexHandle w(whole_vertex[size_t(v.idx())]);
      half.status(v).set_feature(whole.status(w).feature());
      const bool extra_lock = given_locks && (*extras.locked)[size_t(w.idx())];
      half.status(v).set_locked(whole.status(w).locked() || extra_lock || out.cut[size_t(w.idx())]);
      if (with_sizes)
        half.property(size, v) = given_sizes ? (*extras.sizes)[size_t(w.idx())] : whole.property(whole_size, w);
    }
    for (auto e : half.edges()) {
      const auto h = half.halfedge_handle(e, 0);
      const VertexHandle a(whole_vertex[size_t(half.from_vertex_handle(h).idx())]);
      const VertexHandle b(whole_vertex[size_t(half.to_vertex_handle(h).idx())]);
      half.status(e).set_feature(whole.status(whole.edge_handle(whole.find_halfedge(a, b))).feature());
    }
  }
}

bool split_in_halves(const SurfaceMesh& whole, SurfaceHalves& out, const SplitExtras& extras) {
  if (!split_connectivity(whole, out)) return false;
  mark_halves(whole, out, extras);
  return true;
}

SurfaceMesh join_halves(const SurfaceHalves& in, const SurfaceMesh& whole, const SplitExtras& extras) {
  const size_t n_vertices = whole.n_vertices();
  OpenMesh::VPropHandleT<double> half_size;
  const bool with_sizes = in.halves[0].get_property_handle(half_size, size_property_name());
  const bool given_locks = extras.locked && extras.locked->size() == n_vertices;
  // Where each whole vertex is now and its size; a cut vertex is in both halves, unmoved.
  std::vector<OpenMesh::Vec3d> position(n_vertices);
  std::vector<double> size_of(n_vertices, 0);
  std::vector<int> joined(n_vertices, -1);
  for (int p = 1; p >= 0; --p) {
    const SurfaceMesh& half = in.halves[size_t(p)];
    OpenMesh::VPropHandleT<double> size;
    if (with_sizes && !half.get_property_handle(size, size_property_name()))
      throw MeshingError("joining the coarsened halves: a half lost its sizes");
    for (auto v : half.vertices()) {
      if (half.status(v).deleted()) continue;
      const size_t w = size_t(in.whole_vertex[size_t(p)][size_t(v.idx())]);
      position[w] = half.point(v);
      if (with_sizes) size_of[w] = half.property(size, v);
      joined[w] = 0;
    }
  }
  TriSurface surface;
  for (size_t w = 0; w < n_vertices; ++w) {
    if (joined[w] < 0) continue;
    joined[w] = int(surface.points.size());
    surface.points.push_back(to_eigen(position[w]));
  }
  auto to_joined = [&](int p, VertexHandle v) {
    return VertexHandle(joined[size_t(in.whole_vertex[size_t(p)][size_t(v.idx())])]);
  };
  for (int p = 0; p < 2; ++p) {
    const SurfaceMesh& half = in.halves[size_t(p)];
    for (auto f : half.faces()) {
      if (half.status(f).deleted()) continue;
      std::array<int, 3> corners{};
      int k = 0;
      for (auto v : half.fv_range(f)) corners[size_t(k++)] = to_joined(p, v).idx();
      surface.triangles.push_back(corners);
    }
  }
  SurfaceMesh mesh;
  try {
    fill_openmesh(mesh, surface);
  } catch (const InputError& e) {
    throw MeshingError(std::string("joining the coarsened halves: ") + e.what());
  }
  OpenMesh::VPropHandleT<double> size;
  if (with_sizes) mesh.add_property(size, size_property_name());
  for (size_t w = 0; w < n_vertices; ++w) {
    if (joined[w] < 0) continue;
    const VertexHandle v(joined[w]);
    const auto& status = whole.status(VertexHandle(int(w)));
    mesh.status(v).set_feature(status.feature());
    mesh.status(v).set_locked(status.locked() || (given_locks && (*extras.locked)[w]));
    if (with_sizes) mesh.property(size, v) = size_of[w];
  }
  for (int p = 0; p < 2; ++p) {
    const SurfaceMesh& half = in.halves[size_t(p)];
    for (auto e : half.edges()) {
      if (half.status(e).deleted() || !half.status(e).feature()) continue;
      const auto h = half.halfedge_handle(e, 0);
      const auto joined_h = mesh.find_halfedge(to_joined(p, half.from_vertex_handle(h)),
                                               to_joined(p, half.to_vertex_handle(h)));
      if (joined_h.is_valid()) mesh.status(mesh.edge_handle(joined_h)).set_feature(true);
    }
  }
  for (auto v : mesh.vertices())
    if (mesh.is_boundary(v))
      throw MeshingError("joining the coarsened halves: vertex " + std::to_string(v.idx()) + " is on a hole");
  return mesh;
}

}  // namespace dthex
