// SPDX-License-Identifier: MIT
#include "core/surface_distance.h"

#include "boundary_fixtures.h"
#include "core/read_surface.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace dthex;
using namespace dthex::testing;

// Scanner coordinates put a model far from the origin; the volume must not lose its digits
// to the distance (about the origin, a liver at 1e6 summed to -646 for 1.15).
TEST(SurfaceDistance, EnclosedVolumeFarFromTheOrigin) {
  TriSurface liver = read_surface(DTHEX_SOURCE_DIR "/meshes/liver.off");
  const double volume = enclosed_volume(liver);
  ASSERT_GT(volume, 1.0);
  for (Vec3& p : liver.points) p += Vec3(1e6, -2e6, 3e6);
  EXPECT_NEAR(enclosed_volume(liver), volume, 1e-6 * volume);
  const TriSurface unit = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 1);
  EXPECT_NEAR(enclosed_volume(unit), 1.0, 1e-15);
}

// A unit cube against one 10% larger from the same corner: the far corner (1.1, 1.1, 1.1)
// is sqrt(3) * 0.1 from the unit cube, and that is the Hausdorff distance.
TEST(SurfaceDistance, HausdorffOfTwoCubesIsTheirFarCorners) {
  const TriSurface a = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1), 2);
  const TriSurface b = box_surface(Vec3(0, 0, 0), Vec3(1.1, 1.1, 1.1), 2);
  const TriangleBvh a_bvh(a), b_bvh(b);
  const SurfaceDistance d = surface_distance(a, a_bvh, b, b_bvh);
  EXPECT_NEAR(d.hausdorff, std::sqrt(3.0) * 0.1, 1e-12);
  EXPECT_GT(d.mean, 0.0);
  EXPECT_LT(d.mean, d.hausdorff);
}
