// SPDX-License-Identifier: MIT
#include <dthex/mesh/surface_mesh.h>

namespace dthex {

SurfaceMesh to_openmesh(const TriSurface& surface) {
  SurfaceMesh mesh;
  fill_openmesh(mesh, surface);
  return mesh;
}

void fill_openmesh(SurfaceMesh& mesh, const TriSurface& surface) {
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
