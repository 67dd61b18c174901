// SPDX-License-Identifier: MIT
#include <dthex/tets/remove_flat_valence3_vertices.h>

#include <dthex/surface/surface_distance.h>
#include <dthex/surface/verify_surface.h>

#include <gtest/gtest.h>

using namespace dthex;

namespace {

// The octahedron with vertices at +-1 on the axes, outward oriented, with its face in the
// + + + octant split 1-3 at `apex`: a vertex with three triangles.
TriSurface octahedron_with_face_split_at(const Vec3& apex) {
  TriSurface s;
  s.points = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, apex};
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
      for (int sz = 0; sz < 2; ++sz) {
        std::array<int, 3> t{sx, 2 + sy, 4 + sz};
        if ((sx + sy + sz) % 2) std::swap(t[1], t[2]);
        if (sx + sy + sz == 0) {
          s.triangles.push_back({t[0], t[1], 6});
          s.triangles.push_back({t[1], t[2], 6});
          s.triangles.push_back({t[2], t[0], 6});
        } else {
          s.triangles.push_back(t);
        }
      }
  return s;
}

}  // namespace

// Just outside the face's centroid the cap is flat: the vertex goes, the octahedron is back
// (6 points, 8 triangles, closed and outward, volume 4/3).
TEST(RemoveFlatValence3Vertices, FlatCapBecomesOneTriangle) {
  TriSurface s = octahedron_with_face_split_at({0.34, 0.34, 0.34});
  verify_surface(s, "split octahedron");
  EXPECT_EQ(remove_flat_valence3_vertices(s), 1u);
  EXPECT_EQ(s.points.size(), 6u);
  EXPECT_EQ(s.triangles.size(), 8u);
  const SurfaceStats stats = verify_surface(s, "octahedron");
  EXPECT_EQ(stats.flipped_components, 0u);
  EXPECT_NEAR(enclosed_volume(s), 4.0 / 3.0, 1e-12);
}

// At (1, 1, 1) the cap is a regular tet (shape 1): a sharp corner, kept.
TEST(RemoveFlatValence3Vertices, SharpCornerIsKept) {
  TriSurface s = octahedron_with_face_split_at({1, 1, 1});
  verify_surface(s, "octahedron with a corner");
  const TriSurface before = s;
  EXPECT_EQ(remove_flat_valence3_vertices(s), 0u);
  EXPECT_EQ(s.triangles, before.triangles);
  EXPECT_EQ(s.points.size(), 7u);
}

// A tetrahedron: every vertex has three triangles, but removing one would duplicate the
// opposite triangle (and leave the others with two): nothing is removed, however flat.
TEST(RemoveFlatValence3Vertices, FlatTetrahedronIsLeftAlone) {
  TriSurface s;
  s.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.3, 0.01}};
  s.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  EXPECT_EQ(remove_flat_valence3_vertices(s), 0u);
  EXPECT_EQ(s.triangles.size(), 4u);
}
