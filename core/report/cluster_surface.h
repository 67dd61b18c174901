// SPDX-License-Identifier: MIT
// Vertex clustering (Rossignac and Borrel 1993): shrink a big closed surface to a
// triangle budget without opening holes, so the HTML report can show it whole.
#pragma once

#include <dthex/mesh/types.h>

#include <array>
#include <vector>

namespace dthex {

struct ClusterSurfaceOptions {
  //! The result has at most this many triangles.
  size_t max_triangles = 150000;
  //! Of the faces flagged `keep`, at most this share of max_triangles is kept unchanged
  //! (the worst by priority first); the rest are clustered like any other face.
  double max_kept_share = 0.125;
};

struct ClusteredSurface {
  std::vector<Vec3> points;                  //!< one per cluster: the mean of its vertices
  std::vector<std::array<int, 3>> triangles; //!< oriented like the input faces they come from
  //! Per triangle: the input face mapped onto it with the lowest priority (the worst), so
  //! a triangle shows the worst quality of what it stands for.
  std::vector<size_t> source_face;
  size_t grid_cells = 0;  //!< grid cells along the bounding box's longest side; 0 = not reduced
  size_t kept_faces = 0;  //!< flagged faces kept unchanged (their vertices are not merged)
};

//! Snaps the vertices of a surface (triangles or quads; quads are split in two) to a
//! uniform grid, one cluster per cell and per side of the cell's principal normal
//! direction (so the two sides of a sheet thinner than a cell do not merge, while a
//! smooth patch stays one cluster), moves each cluster to the mean of its vertices and keeps the triangles whose three corners land in three
//! clusters. Triangles that land on the same three clusters add up as oriented chains:
//! opposite copies cancel, equal copies count once. The map of a closed surface is then
//! still closed (the boundary of the image is the image of the empty boundary): every
//! edge of the result is shared by at least two of its triangles, so no holes appear.
//! The grid is the finest found with at most options.max_triangles triangles. Vertices
//! of faces flagged in `keep` are not merged, so those faces survive unchanged (up to
//! the options' share, worst priority first). `priority` (lower = worse; may be empty)
//! picks each triangle's source_face. A surface already within the budget comes back
//! unchanged (quads split) with grid_cells 0.
ClusteredSurface cluster_surface(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& faces,
                                 const std::vector<double>& priority, const std::vector<char>& keep,
                                 const ClusterSurfaceOptions& options);
ClusteredSurface cluster_surface(const std::vector<Vec3>& points, const std::vector<std::array<int, 4>>& faces,
                                 const std::vector<double>& priority, const std::vector<char>& keep,
                                 const ClusterSurfaceOptions& options);

}  // namespace dthex
