// SPDX-License-Identifier: MIT
// A downstream OpenMesh application: reads a closed surface with OpenMesh's IO, coarsens
// it with the stock OpenMesh::Decimater::DecimaterT and the DTHex modules (curvature sizing,
// normalized length), and checks the result: fewer faces than the input, still closed
// (every edge has two faces) and of the input's Euler characteristic. Exits 1 otherwise.
// Usage: decimate_with_modules INPUT.off
#include <dthex/modules/ModCurvatureSizingT.hh>
#include <dthex/modules/ModNormalizedLengthT.hh>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>

#include <cstdio>

namespace {

struct Traits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  FaceAttributes(OpenMesh::Attributes::Normal);
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

size_t boundary_edges(const Mesh& mesh) {
  size_t n = 0;
  for (auto e : mesh.edges()) n += mesh.is_boundary(e) ? 1 : 0;
  return n;
}

int euler_characteristic(const Mesh& mesh) {
  return int(mesh.n_vertices()) - int(mesh.n_edges()) + int(mesh.n_faces());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s INPUT.off\n", argv[0]);
    return 2;
  }
  Mesh mesh;
  if (!OpenMesh::IO::read_mesh(mesh, argv[1])) {
    std::fprintf(stderr, "cannot read %s\n", argv[1]);
    return 2;
  }
  const size_t input_faces = mesh.n_faces();
  const int input_euler = euler_characteristic(mesh);
  if (input_faces == 0 || boundary_edges(mesh) != 0) {
    std::fprintf(stderr, "%s is not a closed surface\n", argv[1]);
    return 2;
  }

  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  mesh.update_face_normals();
  size_t collapses = 0;
  {
    OpenMesh::Decimater::DecimaterT<Mesh> decimater(mesh);
    dthex::ModCurvatureSizingT<Mesh>::Handle sizing;  // writes h into "v:dthex_size"
    dthex::ModNormalizedLengthT<Mesh>::Handle length;  // priority: normalized length, legal while < 1
    decimater.add(sizing);
    decimater.add(length);
    dthex::CurvatureSizingOptions options;
    options.eps = 0.1;
    decimater.module(sizing).set_options(options);
    if (!decimater.initialize()) {
      std::fprintf(stderr, "the decimater did not initialize\n");
      return 1;
    }
    collapses = decimater.decimate();
  }
  mesh.garbage_collection();

  const size_t open_edges = boundary_edges(mesh);
  const int euler = euler_characteristic(mesh);
  std::printf("%s: %zu -> %zu faces in %zu collapses, %zu boundary edges, Euler characteristic %d -> %d\n",
              argv[1], input_faces, mesh.n_faces(), collapses, open_edges, input_euler, euler);
  const bool ok = collapses > 0 && mesh.n_faces() < input_faces && mesh.n_faces() >= 4 && open_edges == 0 &&
                  euler == input_euler;
  return ok ? 0 : 1;
}
