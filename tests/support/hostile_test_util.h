// SPDX-License-Identifier: MIT
// Helpers for the tests that feed om_dthex hostile inputs and broken environments: small
// surfaces written in every format. Running the command is in subprocess_util.h.
#pragma once

#include "subprocess_util.h"

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace dthex_test {

namespace fs = std::filesystem;

struct Surface {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> triangles;
};

//! Axis-aligned cube [x0, x0+s] x [y0, y0+s] x [z0, z0+s], 12 triangles, outward.
inline Surface cube(double x0 = 0, double y0 = 0, double z0 = 0, double s = 1) {
  Surface c;
  for (int i = 0; i < 8; ++i) c.points.push_back({x0 + s * (i & 1), y0 + s * ((i >> 1) & 1), z0 + s * ((i >> 2) & 1)});
  c.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return c;
}

//! a and b in one surface, b's indices shifted (no vertex shared).
inline Surface join(const Surface& a, const Surface& b) {
  Surface s = a;
  const int offset = int(a.points.size());
  s.points.insert(s.points.end(), b.points.begin(), b.points.end());
  for (auto t : b.triangles) s.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return s;
}

inline Surface reversed(Surface s) {
  for (auto& t : s.triangles) std::swap(t[1], t[2]);
  return s;
}

inline std::string off_text(const Surface& s) {
  std::ostringstream out;
  out.precision(17);
  out << "OFF\n" << s.points.size() << " " << s.triangles.size() << " 0\n";
  for (const auto& p : s.points) out << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (const auto& t : s.triangles) out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return out.str();
}

inline std::string ascii_stl_text(const Surface& s) {
  std::ostringstream out;
  out.precision(17);
  out << "solid test\n";
  for (const auto& t : s.triangles) {
    out << "facet normal 0 0 0\nouter loop\n";
    for (int v : t) out << "vertex " << s.points[size_t(v)][0] << " " << s.points[size_t(v)][1] << " " << s.points[size_t(v)][2] << "\n";
    out << "endloop\nendfacet\n";
  }
  out << "endsolid test\n";
  return out.str();
}

//! Binary STL; header is padded to 80 bytes, count_override replaces the stored count.
inline std::string binary_stl_bytes(const Surface& s, const std::string& header = "binary",
                                    int64_t count_override = -1) {
  std::string out(80, ' ');
  std::memcpy(out.data(), header.data(), std::min<size_t>(header.size(), 80));
  const uint32_t count = count_override >= 0 ? uint32_t(count_override) : uint32_t(s.triangles.size());
  out.append(reinterpret_cast<const char*>(&count), 4);  // little-endian host assumed (x86, arm)
  for (const auto& t : s.triangles) {
    float values[12] = {0, 0, 0};
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) values[3 + 3 * c + k] = float(s.points[size_t(t[size_t(c)])][size_t(k)]);
    out.append(reinterpret_cast<const char*>(values), sizeof values);
    out.append(2, '\0');
  }
  return out;
}

}  // namespace dthex_test
