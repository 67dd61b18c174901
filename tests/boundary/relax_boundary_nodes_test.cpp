// SPDX-License-Identifier: MIT
#include <dthex/boundary/relax_boundary_nodes.h>
#include <dthex/hexes/conformity.h>

#include "boundary_fixtures.h"

#include <gtest/gtest.h>

using namespace dthex;
using namespace dthex::testing;

namespace {

// A unit cube of 8 x 8 x 8 hexes whose boundary nodes are labelled with the cube's coarse
// triangles; the surface to slide on is the same cube, finer triangulated.
struct Cube {
  TriSurface coarse = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 1);
  TriSurface fine = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 4);
  HexMesh mesh = hex_block(Vec3(0, 0, 0), Vec3(1, 1, 1), 8, 8, 8);
  Cube() { label_boundary(mesh, coarse); }
  int node_at(const Vec3& p) const {
    for (size_t v = 0; v < mesh.nodes.size(); ++v)
      if ((mesh.nodes[v] - p).norm() < 1e-12) return int(v);
    return -1;
  }
};

bool on_cube_edge(const Vec3& p) {
  int on_side = 0;
  for (int i = 0; i < 3; ++i) on_side += std::abs(p[i]) < 1e-12 || std::abs(p[i] - 1) < 1e-12;
  return on_side >= 2;
}

}  // namespace

// A node of the top face pushed off its grid place (as projection leaves a facet's centre in a
// pit) goes most of the way back, on the face; the cube's edges, which are features, keep every
// node, even one pushed along its edge; the displacement handed to the interior placement is
// exactly what the nodes moved.
TEST(RelaxBoundaryNodes, PushedFaceNodeGoesBackAndStaysOnTheFace) {
  Cube cube;
  const Vec3 home(0.5, 0.5, 1.0);
  const int v = cube.node_at(home);
  ASSERT_GE(v, 0);
  cube.mesh.nodes[size_t(v)] = home + Vec3(0.06, 0.035, 0.0);
  // And a node of a cube edge pushed along its edge: its neighbours' mean lies off the edge,
  // where a slide would round the edge off.
  const int e = cube.node_at(Vec3(0.5, 0.0, 1.0));
  ASSERT_GE(e, 0);
  cube.mesh.nodes[size_t(e)].x() += 0.05;
  const std::vector<Vec3> before = cube.mesh.nodes;
  const double pushed = (before[size_t(v)] - home).norm();

  const TriangleBvh bvh(cube.fine);
  std::vector<Vec3> displacement(before.size(), Vec3::Zero());
  const RelaxBoundaryReport report = relax_boundary_nodes(cube.mesh, cube.coarse, bvh, {}, displacement);
  EXPECT_GT(report.moves, 0u);

  // Back most of the way (a uniform Laplacian with its neighbours following part of the way).
  EXPECT_LT((cube.mesh.nodes[size_t(v)] - home).norm(), 0.5 * pushed);
  for (size_t u = 0; u < before.size(); ++u) {
    EXPECT_NEAR((displacement[u] - (cube.mesh.nodes[u] - before[u])).norm(), 0.0, 1e-15) << "node " << u;
    if (cube.mesh.boundary_facet[u] < 0) {
      EXPECT_EQ(cube.mesh.nodes[u], before[u]) << "interior node " << u;  // only the boundary relaxes
      continue;
    }
    if (on_cube_edge(before[u])) EXPECT_EQ(cube.mesh.nodes[u], before[u]) << "edge node " << u;
    if (std::abs(before[u].z() - 1) < 1e-12) EXPECT_NEAR(cube.mesh.nodes[u].z(), 1.0, 1e-12) << "top node " << u;
  }
  // Far from the pushed node, a regular grid is already relaxed.
  const int far = cube.node_at(Vec3(0.5, 0.5, 0.0));
  ASSERT_GE(far, 0);
  EXPECT_NEAR((cube.mesh.nodes[size_t(far)] - before[size_t(far)]).norm(), 0.0, 1e-12);
}

// A held node (on a feature line of the coarse surface) stays, wherever it is.
TEST(RelaxBoundaryNodes, HeldNodesStay) {
  Cube cube;
  const int v = cube.node_at(Vec3(0.5, 0.5, 1.0));
  ASSERT_GE(v, 0);
  cube.mesh.nodes[size_t(v)] += Vec3(0.06, 0.035, 0.0);
  const Vec3 pushed = cube.mesh.nodes[size_t(v)];
  std::vector<char> held(cube.mesh.nodes.size(), 0);
  held[size_t(v)] = 1;
  const TriangleBvh bvh(cube.fine);
  std::vector<Vec3> displacement(cube.mesh.nodes.size(), Vec3::Zero());
  const RelaxBoundaryReport report = relax_boundary_nodes(cube.mesh, cube.coarse, bvh, held, displacement);
  EXPECT_EQ(cube.mesh.nodes[size_t(v)], pushed);
  EXPECT_EQ(report.held, 1u);
  EXPECT_GT(report.moves, 0u);  // its neighbours still move toward it
}

TEST(RelaxBoundaryNodes, GivenQuadsAreUsedAsFound) {
  // The caller's boundary quads (the pipeline finds them once) move the nodes exactly as the
  // ones found here; an empty list gives every node no neighbour, so nothing moves.
  Cube found, given, none;
  for (Cube* cube : {&found, &given, &none}) {
    const int v = cube->node_at(Vec3(0.5, 0.5, 1.0));
    ASSERT_GE(v, 0);
    cube->mesh.nodes[size_t(v)] += Vec3(0.06, 0.035, 0.0);
  }
  const TriangleBvh bvh(found.fine);
  std::vector<Vec3> displacement(found.mesh.nodes.size(), Vec3::Zero());
  const RelaxBoundaryReport by_itself = relax_boundary_nodes(found.mesh, found.coarse, bvh, {}, displacement);

  NodeConstraints constraints;
  constraints.boundary_quads = boundary_quads(given.mesh);
  RelaxBoundaryOptions options;
  options.constraints = &constraints;
  std::fill(displacement.begin(), displacement.end(), Vec3::Zero());
  const RelaxBoundaryReport with_quads =
      relax_boundary_nodes(given.mesh, given.coarse, bvh, {}, displacement, options);
  EXPECT_GT(by_itself.moves, 0u);
  EXPECT_EQ(with_quads.moves, by_itself.moves);
  EXPECT_EQ(given.mesh.nodes, found.mesh.nodes);

  NodeConstraints no_quads;
  options.constraints = &no_quads;
  const std::vector<Vec3> before = none.mesh.nodes;
  EXPECT_EQ(relax_boundary_nodes(none.mesh, none.coarse, bvh, {}, displacement, options).moves, 0u);
  EXPECT_EQ(none.mesh.nodes, before);
}
