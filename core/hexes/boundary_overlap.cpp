// SPDX-License-Identifier: MIT
#include <dthex/hexes/boundary_overlap.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace dthex {
namespace {

// Trilinear shape functions of the VTK hexahedron and their derivatives in (r, s, t).
void shape_functions(const Vec3& rst, double n[8], double dn[8][3]) {
  const double r = rst.x(), s = rst.y(), t = rst.z();
  const double rm = 1 - r, sm = 1 - s, tm = 1 - t;
  n[0] = rm * sm * tm, n[1] = r * sm * tm, n[2] = r * s * tm, n[3] = rm * s * tm;
  n[4] = rm * sm * t, n[5] = r * sm * t, n[6] = r * s * t, n[7] = rm * s * t;
  const double d[8][3] = {{-sm * tm, -rm * tm, -rm * sm}, {sm * tm, -r * tm, -r * sm}, {s * tm, r * tm, -r * s},
                          {-s * tm, rm * tm, -rm * s},    {-sm * t, -rm * t, rm * sm},  {sm * t, -r * t, r * sm},
                          {s * t, r * t, r * s},          {-s * t, rm * t, rm * s}};
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k) dn[i][k] = d[i][k];
}

std::array<Vec3, 8> corners_of(const HexMesh& mesh, size_t h) {
  std::array<Vec3, 8> c;
  for (size_t k = 0; k < 8; ++k) c[k] = mesh.nodes[size_t(mesh.hexes[h][k])];
  return c;
}

// Sign of the Jacobian at the hex centre: negative for an inverted hex.
double centre_jacobian(const std::array<Vec3, 8>& c) {
  double n[8], dn[8][3];
  shape_functions(Vec3::Constant(0.5), n, dn);
  Eigen::Matrix3d j = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k) j.col(k) += dn[i][k] * c[size_t(i)];
  return j.determinant();
}

}  // namespace

bool point_in_hex(const std::array<Vec3, 8>& corner, const Vec3& p, double parametric_tolerance, Vec3* rst_out) {
  // Newton's method from the centre; a trilinear map of a reasonable hex converges in a
  // few steps. No convergence, or a singular Jacobian, counts as outside (as in VTK).
  Vec3 lo = corner[0], hi = corner[0];
  for (const auto& c : corner) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
  const double size = (hi - lo).norm();
  const double singular = 1e-12 * size * size * size;  // relative: a flat hex has no inside
  Vec3 rst = Vec3::Constant(0.5);
  bool converged = false;
  for (int it = 0; it < 20; ++it) {
    double n[8], dn[8][3];
    shape_functions(rst, n, dn);
    Vec3 x = Vec3::Zero();
    Eigen::Matrix3d j = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 8; ++i) {
      x += n[i] * corner[size_t(i)];
      for (int k = 0; k < 3; ++k) j.col(k) += dn[i][k] * corner[size_t(i)];
    }
    const double det = j.determinant();
    if (!std::isfinite(det) || !(std::abs(det) > singular)) return false;
    const Vec3 step = j.inverse() * (p - x);
    rst += step;
    if (!rst.allFinite() || rst.cwiseAbs().maxCoeff() > 1e6) return false;
    if (step.cwiseAbs().maxCoeff() < 1e-10) {
      converged = true;
      break;
    }
  }
  if (!converged) return false;
  if (rst_out) *rst_out = rst;
  return (rst.array() >= -parametric_tolerance).all() && (rst.array() <= 1 + parametric_tolerance).all();
}

bool boundary_probe_point(const HexMesh& mesh, const std::array<int, 4>& quad, int owner,
                          const BoundaryOverlapOptions& options, Vec3& probe) {
  const Vec3 a = mesh.nodes[size_t(quad[0])], b = mesh.nodes[size_t(quad[1])], c = mesh.nodes[size_t(quad[2])],
             d = mesh.nodes[size_t(quad[3])];
  const Vec3 area_normal = 0.5 * ((b - a).cross(c - a) + (c - a).cross(d - a));
  const double area = area_normal.norm();
  if (!(area > 0) || !std::isfinite(area)) return false;  // a degenerate face: counted elsewhere
  Vec3 normal = area_normal / area;
  if (owner >= 0 && centre_jacobian(corners_of(mesh, size_t(owner))) < 0) normal = -normal;
  probe = 0.25 * (a + b + c + d) + options.probe_offset * std::sqrt(area) * normal;
  return probe.allFinite();
}

BoundaryOverlapReport find_boundary_faces_inside(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads,
                                                 const std::vector<int>& owner,
                                                 const BoundaryOverlapOptions& options) {
  BoundaryOverlapReport report;
  if (quads.empty() || mesh.hexes.empty()) return report;

  // The probe points, one per quad.
  std::vector<Vec3> probe(quads.size());
  std::vector<char> has_probe(quads.size(), 0);
  for (size_t q = 0; q < quads.size(); ++q)
    has_probe[q] = boundary_probe_point(mesh, quads[q], owner.empty() ? -1 : owner[q], options, probe[q]);

  // A dense uniform grid over the probe points' bounding box listing the hexes whose box
  // meets each cell (counting sort into one array). Its cell is about two hex sizes, grown
  // when the box is mostly empty (a thin shell) so that cells stay within a few per hex.
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (size_t q = 0; q < quads.size(); ++q)
    if (has_probe[q]) lo = lo.cwiseMin(probe[q]), hi = hi.cwiseMax(probe[q]);
  if (!(lo.array() <= hi.array()).all()) return report;
  const size_t hex_count = mesh.hexes.size();
  std::vector<Vec3> box_lo(hex_count), box_hi(hex_count);
  double total_hex_size = 0;
  for (size_t h = 0; h < hex_count; ++h) {
    Vec3 a = mesh.nodes[size_t(mesh.hexes[h][0])], b = a;
    for (int v : mesh.hexes[h]) a = a.cwiseMin(mesh.nodes[size_t(v)]), b = b.cwiseMax(mesh.nodes[size_t(v)]);
    box_lo[h] = a, box_hi[h] = b;
    if ((b - a).allFinite()) total_hex_size += (b - a).maxCoeff();
  }
  const Vec3 extent = (hi - lo).cwiseMax(Vec3::Constant(1e-300));
  double cell = std::max(2 * total_hex_size / double(hex_count), extent.maxCoeff() * 1e-6);
  const double max_cells = 8.0 * double(hex_count) + 64;
  auto cells_along = [&](int k) { return std::max<int64_t>(1, int64_t(std::min(extent[k] / cell, 1e7)) + 1); };
  while (double(cells_along(0)) * double(cells_along(1)) * double(cells_along(2)) > max_cells) cell *= 1.5;
  const int64_t nx = cells_along(0), ny = cells_along(1), nz = cells_along(2);
  auto clamp_index = [](double x, int64_t n) { return int64_t(std::clamp(std::floor(x), 0.0, double(n - 1))); };
  auto cell_range = [&](const Vec3& a, const Vec3& b, std::array<int64_t, 3>& from, std::array<int64_t, 3>& to) {
    // False when the box misses the grid (or is not finite).
    if (!a.allFinite() || !b.allFinite() || (b.array() < lo.array()).any() || (a.array() > hi.array()).any())
      return false;
    const int64_t n[3] = {nx, ny, nz};
    for (int k = 0; k < 3; ++k) {
      from[size_t(k)] = clamp_index((a[k] - lo[k]) / cell, n[k]);
      to[size_t(k)] = clamp_index((b[k] - lo[k]) / cell, n[k]);
    }
    return true;
  };
  auto cell_id = [&](int64_t x, int64_t y, int64_t z) { return size_t((z * ny + y) * nx + x); };
  std::vector<size_t> start(size_t(nx * ny * nz) + 1, 0);
  std::vector<int> listed;
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t h = 0; h < hex_count; ++h) {
      std::array<int64_t, 3> from, to;
      if (!cell_range(box_lo[h], box_hi[h], from, to)) continue;
      for (int64_t z = from[2]; z <= to[2]; ++z)
        for (int64_t y = from[1]; y <= to[1]; ++y)
          for (int64_t x = from[0]; x <= to[0]; ++x) {
            const size_t c = cell_id(x, y, z);
            if (pass == 0) ++start[c + 1];
            else listed[start[c]++] = int(h);
          }
    }
    if (pass == 0) {
      for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
      listed.resize(start.back());
    } else {  // the fill advanced each start to the next cell's; shift back
      for (size_t c = start.size() - 1; c > 0; --c) start[c] = start[c - 1];
      start[0] = 0;
    }
  }

  // Each probe point against the hexes listed in its cell, lowest hex id first.
  std::vector<int> hit_hex(quads.size(), -1);
#pragma omp parallel for schedule(dynamic, 256)
  for (long q = 0; q < long(quads.size()); ++q) {
    if (!has_probe[size_t(q)]) continue;
    const Vec3& p = probe[size_t(q)];
    std::array<int64_t, 3> at, unused;
    if (!cell_range(p, p, at, unused)) continue;
    const size_t c = cell_id(at[0], at[1], at[2]);
    for (size_t i = start[c]; i < start[c + 1]; ++i) {
      const size_t h = size_t(listed[i]);
      if ((p.array() < box_lo[h].array()).any() || (p.array() > box_hi[h].array()).any()) continue;
      if (point_in_hex(corners_of(mesh, h), p, options.parametric_tolerance)) {
        hit_hex[size_t(q)] = int(h);
        break;
      }
    }
  }
  for (size_t q = 0; q < quads.size(); ++q) {
    if (hit_hex[q] < 0) continue;
    report.faces.push_back(int(q));
    report.hexes.push_back(hit_hex[q]);
    if (report.faces_inside++ == 0) {
      report.first_face = int(q);
      report.first_hex = hit_hex[q];
      report.first_point = probe[q];
    }
  }
  return report;
}

}  // namespace dthex
