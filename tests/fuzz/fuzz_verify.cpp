// SPDX-License-Identifier: MIT
// libFuzzer target: the safe repairs (repair_surface, unless a flag byte turns them off, as
// --repair none) and verify_surface on arbitrary small indexed surfaces. Points come
// from a small integer grid (so coincidences, touching and crossing triangles are
// frequent) or, when a flag byte says so, raw doubles (NaN, inf, huge, denormal).
// Verification may refuse (InputError) but must never crash or throw anything else, and
// what it accepts must satisfy its promises: indices in range, every edge shared by
// exactly two triangles, positive enclosed volume (when self-intersections are checked).
// The repairs (with --min-island, by triangles and by volume, when a flag bit says so; the
// sliver flips always) must never crash, and never turn a surface that verifies into one
// that does not.
#include <dthex/repair/repair_surface.h>
#include <dthex/surface/verify_surface.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <utility>

namespace {

struct Bytes {
  const uint8_t* data;
  size_t size, pos = 0;
  bool empty() const { return pos >= size; }
  uint8_t byte() { return pos < size ? data[pos++] : 0; }
  double raw_double() {
    double d = 0;
    if (pos + sizeof d <= size) std::memcpy(&d, data + pos, sizeof d);
    pos += sizeof d;
    return d;
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in{data, size};
  const uint8_t flags = in.byte();
  const bool raw_coordinates = flags & 1;
  const size_t n_points = 1 + in.byte() % 32;
  dthex::TriSurface surface;
  for (size_t i = 0; i < n_points; ++i) {
    dthex::Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = raw_coordinates ? in.raw_double() : double(int(in.byte() % 9) - 4);
    surface.points.push_back(p);
  }
  while (!in.empty() && surface.triangles.size() < 64) {
    std::array<int, 3> t;
    // Mostly valid indices; occasionally out of range or negative.
    for (int& v : t) v = (flags & 2) ? int(int8_t(in.byte())) : int(in.byte() % n_points);
    surface.triangles.push_back(t);
  }
  dthex::VerifyOptions options;
  options.check_self_intersections = !(flags & 4);
  const bool repair = !(flags & 8);
  const dthex::TriSurface given = surface;
  if (repair) {
    dthex::SurfaceRepairOptions repair_options;
    if (flags & 16) {
      repair_options.islands.min_triangles = 1 + flags / 32;               // --min-island 1..8
      repair_options.islands.min_volume_fraction = 0.1 * double(flags / 32);  // and 0% to 70% of the volume
    }
    const dthex::SurfaceRepairReport report = dthex::repair_surface(surface, repair_options);
    if (surface.points.size() != given.points.size()) std::abort();  // repairs renumber no vertex
    if (surface.triangles.size() + report.islands.triangles_dropped + report.redundant.collapsed_removed +
            report.redundant.duplicates_removed !=
        given.triangles.size())
      std::abort();
  }
  try {
    const dthex::SurfaceStats stats = dthex::verify_surface(surface, "fuzz", options);
    std::map<std::pair<int, int>, int> edge_uses;
    for (const auto& t : surface.triangles)
      for (int k = 0; k < 3; ++k) {
        const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
        if (a < 0 || b < 0 || size_t(a) >= surface.points.size() || size_t(b) >= surface.points.size()) std::abort();
        ++edge_uses[{std::min(a, b), std::max(a, b)}];
      }
    for (const auto& [edge, uses] : edge_uses)
      if (uses != 2) std::abort();
    // Without the self-intersection check, interpenetrating components are accepted and
    // one may count as the other's cavity: the net volume promise needs the check.
    if (options.check_self_intersections && !(stats.volume > 0)) std::abort();
  } catch (const dthex::InputError&) {
    // With self-intersections checked, a valid surface has no coincident vertices in use, so
    // the repairs cannot have made it invalid: the surface as given must be refused too.
    if (repair && options.check_self_intersections) {
      dthex::TriSurface copy = given;
      try {
        dthex::verify_surface(copy, "fuzz", options);
        std::abort();
      } catch (const dthex::InputError&) {
      }
    }
  }
  return 0;
}
