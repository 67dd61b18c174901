// SPDX-License-Identifier: MIT
#include "core/features.h"

#include "boundary_fixtures.h"

#include <gtest/gtest.h>

using namespace dthex;
using dthex::testing::box_surface;

// The unit cube, each face two triangles: its 12 edges are features (90 degrees), the 6 face
// diagonals are not. Hex nodes named on a triangle: on a cube edge or corner (feature), on a
// diagonal or inside a face (not), a hair off an edge (not), interior (not).
TEST(Features, NodesOnTheCoarseSurfacesFeatureEdgesAreFound) {
  const TriSurface cube = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 1);
  ASSERT_EQ(cube.triangles.size(), 12u);
  ASSERT_EQ(feature_edges(cube).size(), 12u);
  // Every node on triangle 0's plane: find that triangle's three corners.
  const auto& t = cube.triangles[0];
  const Vec3 a = cube.points[size_t(t[0])], b = cube.points[size_t(t[1])], c = cube.points[size_t(t[2])];
  // Which of the triangle's edges is the face diagonal (not a feature): the longest one.
  const std::array<std::pair<Vec3, Vec3>, 3> edges = {{{a, b}, {b, c}, {c, a}}};
  int diagonal = 0;
  for (int k = 1; k < 3; ++k)
    if ((edges[size_t(k)].second - edges[size_t(k)].first).norm() >
        (edges[size_t(diagonal)].second - edges[size_t(diagonal)].first).norm())
      diagonal = k;
  const auto& side = edges[size_t((diagonal + 1) % 3)];
  const auto& diag = edges[size_t(diagonal)];
  const Vec3 inward = (a + b + c) / 3 - (side.first + side.second) / 2;

  HexMesh mesh;
  mesh.nodes = {
      0.3 * side.first + 0.7 * side.second,                    // on a cube edge: feature
      side.first,                                              // a cube corner: feature
      0.5 * (diag.first + diag.second),                        // mid-diagonal: not
      (a + b + c) / 3,                                         // inside the face: not
      0.5 * (side.first + side.second) + 1e-3 * inward,        // a hair off the edge: not
      0.5 * (side.first + side.second),                        // on the edge, but interior: not
  };
  mesh.boundary_facet = {0, 0, 0, 0, 0, -1};
  const std::vector<char> on = nodes_on_feature_edges(mesh, cube);
  EXPECT_EQ(on, (std::vector<char>{1, 1, 0, 0, 0, 0}));
}
