// SPDX-License-Identifier: MIT
#include <dthex/report/report.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <sstream>

#ifndef DTHEX_VERSION
#define DTHEX_VERSION "dev"
#endif

namespace dthex {
namespace {

std::string format(const char* fmt, double a, double b, double c, double d) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, fmt, a, b, c, d);
  return buffer;
}

std::string quality_row(const std::string& name, size_t count, const QualityStats& s) {
  char head[64];
  std::snprintf(head, sizeof head, "  %-16s %10zu ", name.c_str(), count);
  return head + format("%8.4f %8.4f %8.4f %8.4f\n", s.avg, s.std_dev, s.min, s.max);
}

nlohmann::json stats_json(const QualityStats& s) {
  return {{"count", s.count}, {"avg", s.avg}, {"std", s.std_dev}, {"min", s.min}, {"max", s.max}};
}

nlohmann::json surface_json(const SurfaceSummary& s) {
  return {{"vertices", s.vertices},   {"triangles", s.triangles},        {"components", s.components},
          {"cavities", s.cavities},   {"genus", s.genus},                {"volume", s.volume},
          {"bbox_diagonal", s.bbox_diagonal}, {"flipped_components", s.flipped_components},
          {"triangle_shape", stats_json(s.shape)}};
}

}  // namespace

std::string summary_table(const PipelineResult& r, const PipelineOptions& o) {
  std::ostringstream out;
  out << "om_dthex " << DTHEX_VERSION << ": " << r.input_path;
  if (o.thex_only)
    out << " (THex only)";
  else
    out << " (eps " << r.eps << ", dice " << o.dice << (o.project ? "" : ", not projected") << ")";
  out << "\n";
  out << "  stage                  seconds  result\n";
  for (const auto& s : r.stages) {
    // The detail is appended, not formatted into the buffer: a long one lost its end and
    // the line break with it.
    char line[96];
    std::snprintf(line, sizeof line, "  %-20s %9.3f  ", s.name.c_str(), s.seconds);
    out << line << s.detail << "\n";
  }
  char total[96];
  std::snprintf(total, sizeof total, "  %-20s %9.3f\n", "total", r.total_seconds);
  out << total << "\n";
  out << "  quality (Verdict)     elements      avg      std      min      max\n";
  out << quality_row("input triangles", r.input_summary.triangles, r.input_summary.shape);
  if (!o.thex_only) out << quality_row("coarse triangles", r.coarse_summary.triangles, r.coarse_summary.shape);
  out << quality_row("tets", r.tets, r.tet_shape);
  out << quality_row("hex shape", r.hexes.hexes.size(), r.quality.shape_stats);
  out << quality_row("hex scaled Jac.", r.hexes.hexes.size(), r.quality.scaled_jacobian_stats);
  out << "\n";
  const double diag = r.input_summary.bbox_diagonal > 0 ? r.input_summary.bbox_diagonal : 1.0;
  char tail[512];
  std::snprintf(tail, sizeof tail,
                "  nodes %zu, hexes %zu, inverted %zu, scaled Jacobian < 0.2: %zu, conforming: %s\n"
                "  distance to input: Hausdorff %.4g (%.3f%% of the bbox diagonal), mean %.4g\n"
                "  volume: hexes %.6g, input %.6g (%+.3f%%)\n",
                r.hexes.nodes.size(), r.hexes.hexes.size(), r.quality.inverted, r.quality.below_0_2,
                r.conforming ? "yes" : "NO", r.hausdorff, 100.0 * r.hausdorff / diag, r.mean_distance, r.hex_volume,
                r.input_summary.volume,
                r.input_summary.volume != 0 ? 100.0 * (r.hex_volume - r.input_summary.volume) / r.input_summary.volume
                                            : 0.0);
  out << tail;
  if (r.quality.inverted > 0) {
    out << "  WARNING: " << r.quality.inverted << " inverted hexes remain; worst:";
    for (size_t i = 0; i < r.worst_hexes.size() && i < 5; ++i)
      out << " " << r.worst_hexes[i] << " (SJ " << r.quality.scaled_jacobian[r.worst_hexes[i]] << ")";
    out << "\n";
  }
  if (r.boundary_faces_inside > 0) {
    char where[160];
    std::snprintf(where, sizeof where, "(%.6g, %.6g, %.6g)", r.first_inside_point.x(), r.first_inside_point.y(),
                  r.first_inside_point.z());
    out << "  WARNING: " << r.boundary_faces_inside
        << " boundary faces lie inside the mesh (its boundary folds into its own volume), the first near " << where << "\n";
  }
  // Thin walls sized by curvature alone are the commonest cause of poor hexes left over.
  const bool poor = r.quality.inverted > 0 || r.quality.below_0_2 > 0;
  if (!r.thickness_retry.empty())
    out << "  thin walls: " << r.thickness_retry << "\n";
  else if (poor && !o.thex_only && o.thickness_ratio <= 0 &&
           r.thin_wall_vertices * 20 >= r.coarsening_input().points.size())
    out << "  hint: " << r.thin_wall_vertices << " of " << r.coarsening_input().points.size()
        << " input vertices lie on walls thinner than their coarse size; --thickness-ratio 1 sizes such walls by their\n"
           "  thickness (more nodes, better hexes: the shared pelvis went from min scaled Jacobian 0.04 to 0.21)\n";
  return out.str();
}

std::string report_json(const PipelineResult& r, const PipelineOptions& o, const PipelineResult* thex_baseline) {
  nlohmann::json j;
  j["tool"] = "om_dthex";
  j["version"] = DTHEX_VERSION;
  j["input"] = {{"path", r.input_path}, {"surface", surface_json(r.input_summary)}};
  // The surface the coarsening started from, when the input was remeshed first.
  if (!r.remeshed.triangles.empty())
    j["input"]["remeshed"] = {{"vertices", r.remeshed.points.size()}, {"triangles", r.remeshed.triangles.size()}};
  j["options"] = {{"eps", r.eps},
                  {"target_nodes", o.target_nodes},
                  {"dice", o.dice},
                  {"h_min", o.h_min},
                  {"h_max", o.h_max},
                  {"max_edge_ratio", o.max_edge_ratio},
                  {"thickness_ratio", o.thickness_ratio},
                  {"thickness_retry", o.thickness_retry},
                  {"thex_only", o.thex_only},
                  {"project", o.project},
                  {"strict", o.strict},
                  {"knife_edge_slide", o.knife_edge_slide},
                  {"remesh", o.remesh == PipelineOptions::Remesh::always  ? "on"
                             : o.remesh == PipelineOptions::Remesh::never ? "off"
                                                                          : "auto"},
                  {"tetgen", tetgen_switches_for(o)},
                  {"time_limit_seconds", o.time_limit_seconds}};
  if (!o.thex_only) {
    j["coarse"] = surface_json(r.coarse_summary);
    j["coarse"]["thin_wall_input_vertices"] = r.thin_wall_vertices;
    j["coarse"]["thickness_ratio_used"] = r.thickness_ratio_used;
    j["coarse"]["thickness_retry"] = r.thickness_retry;
  }
  j["tets"] = {{"count", r.tets}, {"shape", stats_json(r.tet_shape)}};
  j["hex"] = {{"nodes", r.hexes.nodes.size()},
              {"hexes", r.hexes.hexes.size()},
              {"shape", stats_json(r.quality.shape_stats)},
              {"scaled_jacobian", stats_json(r.quality.scaled_jacobian_stats)},
              {"inverted", r.quality.inverted},
              {"inverted_before_untangle", r.inverted_before_untangle},
              {"scaled_jacobian_below_0_2", r.quality.below_0_2},
              {"conforming", r.conforming},
              {"boundary_faces_inside", r.boundary_faces_inside},
              {"volume", r.hex_volume},
              {"worst_hexes", r.worst_hexes},
              {"shape_histogram", {{"lo", 0.0}, {"hi", 1.0}, {"counts", histogram(r.quality.shape, 20, 0.0, 1.0)}}},
              {"scaled_jacobian_histogram",
               {{"lo", -1.0}, {"hi", 1.0}, {"counts", histogram(r.quality.scaled_jacobian, 40, -1.0, 1.0)}}}};
  j["distance"] = {{"hausdorff", r.hausdorff},
                   {"hausdorff_relative", r.input_summary.bbox_diagonal > 0 ? r.hausdorff / r.input_summary.bbox_diagonal : 0.0},
                   {"mean", r.mean_distance}};
  nlohmann::json stages = nlohmann::json::array();
  for (const auto& s : r.stages) stages.push_back({{"name", s.name}, {"seconds", s.seconds}, {"result", s.detail}});
  j["stages"] = stages;
  j["total_seconds"] = r.total_seconds;
  if (thex_baseline) {
    PipelineOptions thex_options = o;
    thex_options.thex_only = true;
    j["thex_baseline"] = nlohmann::json::parse(report_json(*thex_baseline, thex_options));
  }
  return j.dump(2) + "\n";
}

}  // namespace dthex
