// SPDX-License-Identifier: MIT
#include <dthex/io/write_surface.h>

#include <dthex/io/atomic_file.h>
#include <dthex/io/output_file.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace dthex {
namespace {

enum class SurfaceFormat { Off, Obj, Ply, Stl };

const std::vector<std::pair<std::string, SurfaceFormat>>& surface_extension_table() {
  static const std::vector<std::pair<std::string, SurfaceFormat>> table = {
      {".off", SurfaceFormat::Off}, {".obj", SurfaceFormat::Obj}, {".ply", SurfaceFormat::Ply}, {".stl", SurfaceFormat::Stl}};
  return table;
}

SurfaceFormat surface_format_from_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  for (const auto& [known, format] : surface_extension_table())
    if (ext == known) return format;
  std::string supported;
  for (const auto& known : supported_surface_extensions()) supported += " " + known;
  throw InputError("cannot write surface '" + path + "': unknown extension '" + (ext.empty() ? "(none)" : ext) +
                   "' (supported:" + supported + ")");
}

void check_surface(const TriSurface& surface, const std::string& path) {
  const std::string prefix = "cannot write surface '" + path + "': ";
  if (surface.triangles.empty()) throw InputError(prefix + "the surface has no triangles");
  const int point_count = int(surface.points.size());
  for (size_t t = 0; t < surface.triangles.size(); ++t)
    for (int v : surface.triangles[t])
      if (v < 0 || v >= point_count)
        throw InputError(prefix + "triangle " + std::to_string(t) + " refers to point " + std::to_string(v) +
                         " but the surface has " + std::to_string(point_count) + " points");
}

void write_points(const TriSurface& surface, OutputFile& file, const char* prefix) {
  for (const Vec3& p : surface.points) file.print("%s%.17g %.17g %.17g\n", prefix, p.x(), p.y(), p.z());
}

void write_off(const TriSurface& surface, OutputFile& file) {
  file.print("OFF\n%zu %zu 0\n", surface.points.size(), surface.triangles.size());
  write_points(surface, file, "");
  for (const auto& t : surface.triangles) file.print("3 %d %d %d\n", t[0], t[1], t[2]);
}

void write_obj(const TriSurface& surface, OutputFile& file) {
  file.print("# om_dthex surface: %zu vertices, %zu triangles\n", surface.points.size(), surface.triangles.size());
  write_points(surface, file, "v ");
  for (const auto& t : surface.triangles) file.print("f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1);
}

void write_ply(const TriSurface& surface, OutputFile& file) {
  file.print("ply\nformat ascii 1.0\ncomment om_dthex surface\n"
             "element vertex %zu\nproperty double x\nproperty double y\nproperty double z\n"
             "element face %zu\nproperty list uchar int vertex_indices\nend_header\n",
             surface.points.size(), surface.triangles.size());
  write_points(surface, file, "");
  for (const auto& t : surface.triangles) file.print("3 %d %d %d\n", t[0], t[1], t[2]);
}

void write_stl(const TriSurface& surface, OutputFile& file) {
  file.print("solid om_dthex\n");
  for (const auto& t : surface.triangles) {
    const Vec3& a = surface.points[size_t(t[0])];
    const Vec3& b = surface.points[size_t(t[1])];
    const Vec3& c = surface.points[size_t(t[2])];
    Vec3 normal = (b - a).cross(c - a);
    const double length = normal.norm();
    normal = length > 0 ? Vec3(normal / length) : Vec3::Zero();
    file.print("facet normal %.17g %.17g %.17g\n  outer loop\n", normal.x(), normal.y(), normal.z());
    for (const Vec3* p : {&a, &b, &c}) file.print("    vertex %.17g %.17g %.17g\n", p->x(), p->y(), p->z());
    file.print("  endloop\nendfacet\n");
  }
  file.print("endsolid om_dthex\n");
}

}  // namespace

std::vector<std::string> supported_surface_extensions() {
  std::vector<std::string> extensions;
  for (const auto& entry : surface_extension_table()) extensions.push_back(entry.first);
  return extensions;
}

void write_surface(const TriSurface& surface, const std::string& path) {
  const SurfaceFormat format = surface_format_from_path(path);
  check_surface(surface, path);
  write_atomically(path, [&](const std::string& temporary) {
    OutputFile file(temporary, path);
    switch (format) {
      case SurfaceFormat::Off: write_off(surface, file); break;
      case SurfaceFormat::Obj: write_obj(surface, file); break;
      case SurfaceFormat::Ply: write_ply(surface, file); break;
      case SurfaceFormat::Stl: write_stl(surface, file); break;
    }
    file.close();
  });
}

}  // namespace dthex
