// SPDX-License-Identifier: MIT
#include <dthex/report/report_html.h>

#include <dthex/hexes/conformity.h>
#include <dthex/report/cluster_surface.h>
#include <dthex/report/report.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <sstream>

#ifndef DTHEX_VERSION
#define DTHEX_VERSION "dev"
#endif

namespace dthex {
namespace {

std::string escape_html(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string number(double value, int precision = 4) {
  if (!std::isfinite(value)) return "n/a";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", precision, value);
  return buffer;
}

std::string base64(const uint8_t* data, size_t size) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (size_t i = 0; i < size; i += 3) {
    const uint32_t b0 = data[i], b1 = i + 1 < size ? data[i + 1] : 0, b2 = i + 2 < size ? data[i + 2] : 0;
    const uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
    out += alphabet[(triple >> 18) & 63];
    out += alphabet[(triple >> 12) & 63];
    out += i + 1 < size ? alphabet[(triple >> 6) & 63] : '=';
    out += i + 2 < size ? alphabet[triple & 63] : '=';
  }
  return out;
}

template <class T>
std::string base64_of(const std::vector<T>& values) {
  // Little-endian typed arrays: what every browser's Uint16Array/Uint32Array reads on x86 and ARM.
  return base64(reinterpret_cast<const uint8_t*>(values.data()), values.size() * sizeof(T));
}

// ---------------------------------------------------------------- 3D geometry

// Positions are quantized to 16 bits in a cube around the input's bounding box: a
// 65535th of the size is far below a pixel and halves the page against float32.
struct Quantizer {
  Vec3 center = Vec3::Zero();
  double extent = 1;

  explicit Quantizer(const std::vector<Vec3>& points) {
    if (points.empty()) return;
    Vec3 lo = points.front(), hi = points.front();
    for (const Vec3& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    center = 0.5 * (lo + hi);
    // 10% margin: the hex boundary may stick out a little past the input.
    extent = std::max(1e-300, 1.1 * (hi - lo).maxCoeff());
  }
  Vec3 normalized(const Vec3& p) const { return (p - center) / extent; }  // in [-0.5, 0.5]
  uint16_t quantize(double coordinate) const {
    return uint16_t(std::lround(std::clamp(coordinate + 0.5, 0.0, 1.0) * 65535.0));
  }
};

struct LayerMetric {
  std::string name;
  double lo = 0, hi = 1;
  std::vector<double> per_face;
};

// The embedded arrays of one layer: quantized positions of the vertices the faces use,
// face indices, and per metric one byte per face (the value of source_face[f]).
template <size_t N>
nlohmann::json layer_arrays(const std::vector<Vec3>& points, const std::vector<std::array<int, N>>& faces,
                            const std::vector<size_t>& source_face, const std::vector<LayerMetric>& metrics,
                            const Quantizer& quantizer) {
  std::vector<int> new_index(points.size(), -1);
  std::vector<uint16_t> positions;
  std::vector<uint32_t> indices;
  indices.reserve(faces.size() * N);
  for (const auto& face : faces) {
    for (int v : face) {
      if (new_index[size_t(v)] < 0) {
        new_index[size_t(v)] = int(positions.size() / 3);
        const Vec3 p = quantizer.normalized(points[size_t(v)]);
        for (int k = 0; k < 3; ++k) positions.push_back(quantizer.quantize(p[k]));
      }
      indices.push_back(uint32_t(new_index[size_t(v)]));
    }
  }
  nlohmann::json metric_list = nlohmann::json::array();
  for (const LayerMetric& m : metrics) {
    std::vector<uint8_t> values;
    values.reserve(faces.size());
    for (size_t f = 0; f < faces.size(); ++f) {
      const double t = (m.per_face[source_face[f]] - m.lo) / (m.hi - m.lo);
      values.push_back(uint8_t(std::lround(std::clamp(t, 0.0, 1.0) * 255.0)));
    }
    metric_list.push_back({{"name", m.name}, {"lo", m.lo}, {"hi", m.hi}, {"values", base64_of(values)}});
  }
  return {{"arity", N}, {"shown", faces.size()}, {"positions", base64_of(positions)},
          {"faces", base64_of(indices)}, {"metrics", metric_list}};
}

std::string thousands(size_t n) {
  std::string digits = std::to_string(n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

// One surface of the viewer: triangles or quads, a quality value per face. Above the
// cap the layer is reduced by vertex clustering, which keeps it closed (a sample of the
// faces would leave holes); faces flagged always_keep (poor hexes) are kept unchanged and
// every reduced triangle shows the worst quality among the faces merged into it.
template <size_t N>
nlohmann::json layer_json(const std::string& name, const std::vector<Vec3>& points,
                          const std::vector<std::array<int, N>>& faces, const std::vector<LayerMetric>& metrics,
                          const std::vector<char>& always_keep, const Quantizer& quantizer, size_t cap) {
  const char* unit = N == 4 ? " quads" : " triangles";
  nlohmann::json layer;
  if (faces.size() <= cap) {
    std::vector<size_t> identity(faces.size());
    std::iota(identity.begin(), identity.end(), size_t(0));
    layer = layer_arrays(points, faces, identity, metrics, quantizer);
    layer["caption"] = name + ": all " + thousands(faces.size()) + unit;
  } else {
    ClusterSurfaceOptions cluster_options;
    cluster_options.max_triangles = cap;
    const ClusteredSurface reduced = cluster_surface(
        points, faces, metrics.empty() ? std::vector<double>() : metrics.front().per_face, always_keep, cluster_options);
    layer = layer_arrays(reduced.points, reduced.triangles, reduced.source_face, metrics, quantizer);
    size_t flagged = 0;
    for (char keep : always_keep) flagged += keep ? 1 : 0;
    std::string caption = name + ": " + thousands(faces.size()) + unit + " reduced to " +
                          thousands(reduced.triangles.size()) + " triangles by vertex clustering on a grid of " +
                          std::to_string(reduced.grid_cells) +
                          " cells along the longest side, to keep the page small (this adds no holes; each "
                          "triangle takes the worst quality of the original faces mapped onto it)";
    if (flagged > 0)
      caption += reduced.kept_faces == flagged
                     ? "; all " + thousands(flagged) + " faces of poor hexes are shown unchanged"
                     : "; the worst " + thousands(reduced.kept_faces) + " of " + thousands(flagged) +
                           " faces of poor hexes are shown unchanged, the others merged like the rest";
    layer["caption"] = caption;
    layer["reduction"] = {{"method", "vertex clustering"}, {"grid_cells", reduced.grid_cells},
                          {"kept_faces", reduced.kept_faces}, {"source_arity", N}};
  }
  layer["name"] = name;
  layer["total"] = faces.size();
  return layer;
}

// The hex owning each boundary quad, found through the hexes of the quad's first node.
std::vector<size_t> quad_owners(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads) {
  std::vector<size_t> start(mesh.nodes.size() + 1, 0);
  for (const auto& hex : mesh.hexes)
    for (int n : hex) ++start[size_t(n) + 1];
  for (size_t i = 0; i < mesh.nodes.size(); ++i) start[i + 1] += start[i];
  std::vector<size_t> fill(start.begin(), start.end() - 1), incident(start.back());
  for (size_t h = 0; h < mesh.hexes.size(); ++h)
    for (int n : mesh.hexes[h]) incident[fill[size_t(n)]++] = h;
  std::vector<size_t> owners(quads.size(), 0);
  for (size_t q = 0; q < quads.size(); ++q) {
    const size_t first = size_t(quads[q][0]);
    for (size_t i = start[first]; i < start[first + 1]; ++i) {
      const auto& hex = mesh.hexes[incident[i]];
      const bool has_all = std::all_of(quads[q].begin() + 1, quads[q].end(), [&](int n) {
        return std::find(hex.begin(), hex.end(), n) != hex.end();
      });
      if (has_all) {
        owners[q] = incident[i];
        break;
      }
    }
  }
  return owners;
}

nlohmann::json geometry_json(const PipelineResult& r, const PipelineOptions& options, size_t cap) {
  const Quantizer quantizer(r.input.points);
  nlohmann::json layers = nlohmann::json::array();

  const std::vector<std::array<int, 4>> quads = boundary_quads(r.hexes);
  const std::vector<size_t> owners = quad_owners(r.hexes, quads);
  LayerMetric sj{"scaled Jacobian", -1.0, 1.0, {}}, shape{"hex shape", 0.0, 1.0, {}};
  std::vector<char> poor(quads.size(), 0);
  for (size_t q = 0; q < quads.size(); ++q) {
    const size_t h = owners[q];
    const double j = h < r.quality.scaled_jacobian.size() ? r.quality.scaled_jacobian[h] : 0.0;
    sj.per_face.push_back(j);
    shape.per_face.push_back(h < r.quality.shape.size() ? r.quality.shape[h] : 0.0);
    poor[q] = j < 0.2;
  }
  layers.push_back(layer_json<4>("hex boundary", r.hexes.nodes, quads, {sj, shape}, poor, quantizer, cap));

  if (!options.thex_only) {
    LayerMetric coarse_shape{"triangle shape", 0.0, 1.0, triangle_shapes(r.coarse)};
    layers.push_back(layer_json<3>("coarse surface", r.coarse.points, r.coarse.triangles, {coarse_shape}, {}, quantizer, cap));
  }
  LayerMetric input_shape{"triangle shape", 0.0, 1.0, triangle_shapes(r.input)};
  layers.push_back(layer_json<3>("input surface", r.input.points, r.input.triangles, {input_shape}, {}, quantizer, cap));

  nlohmann::json worst = nlohmann::json::array();
  for (size_t h : r.worst_hexes) {
    if (h >= r.hexes.hexes.size()) continue;
    Vec3 centroid = Vec3::Zero();
    for (int n : r.hexes.hexes[h]) centroid += r.hexes.nodes[size_t(n)];
    const Vec3 p = quantizer.normalized(centroid / 8.0);
    worst.push_back({{"hex", h},
                     {"scaled_jacobian", r.quality.scaled_jacobian[h]},
                     {"shape", r.quality.shape[h]},
                     {"at", {p.x(), p.y(), p.z()}}});
  }
  return {{"layers", layers}, {"worst", worst}};
}

// ---------------------------------------------------------------- histograms

struct HistogramSeries {
  std::string key, label, color;
  std::vector<size_t> counts;
};

// Bars are the percentage of each run's hexes, so meshes of different sizes compare;
// every bar carries its raw count (data-count) and a tooltip.
std::string svg_histogram(const std::string& id, const std::string& title, double lo, double hi,
                          const std::vector<HistogramSeries>& series) {
  const double width = 640, height = 250, left = 52, right = 12, top = 30, bottom = 42;
  const double plot_w = width - left - right, plot_h = height - top - bottom;
  const size_t bins = series.front().counts.size();
  double max_fraction = 0;
  std::vector<double> totals;
  for (const auto& s : series) {
    size_t total = 0;
    for (size_t c : s.counts) total += c;
    totals.push_back(double(std::max<size_t>(total, 1)));
    for (size_t c : s.counts) max_fraction = std::max(max_fraction, double(c) / totals.back());
  }
  if (max_fraction <= 0) max_fraction = 1;
  std::ostringstream svg;
  svg << "<svg id=\"" << id << "\" class=\"histogram\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << width
      << ' ' << height << "\" width=\"" << width << "\" height=\"" << height << "\" role=\"img\" aria-label=\""
      << escape_html(title) << "\">\n";
  svg << "<text x=\"" << left << "\" y=\"18\" class=\"title\">" << escape_html(title) << "</text>\n";
  if (lo < 0 && hi > 0) {  // inverted elements: the negative half is shaded
    const double x0 = left + plot_w * (0 - lo) / (hi - lo);
    svg << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << number(x0 - left, 1) << "\" height=\""
        << plot_h << "\" class=\"inverted-zone\"><title>inverted (scaled Jacobian &lt;= 0)</title></rect>\n";
  }
  const double group_w = plot_w / double(bins), bar_w = std::max(1.0, (group_w - 1) / double(series.size()));
  for (size_t si = 0; si < series.size(); ++si) {
    const auto& s = series[si];
    for (size_t b = 0; b < bins; ++b) {
      const double fraction = double(s.counts[b]) / totals[si];
      double h = plot_h * fraction / max_fraction;
      if (s.counts[b] > 0) h = std::max(h, 1.0);
      const double x = left + double(b) * group_w + double(si) * bar_w + 0.5;
      const double bin_lo = lo + (hi - lo) * double(b) / double(bins), bin_hi = lo + (hi - lo) * double(b + 1) / double(bins);
      svg << "<rect class=\"bar\" data-series=\"" << s.key << "\" data-bin=\"" << b << "\" data-count=\""
          << s.counts[b] << "\" x=\"" << number(x, 2) << "\" y=\"" << number(top + plot_h - h, 2) << "\" width=\""
          << number(bar_w - 0.5, 2) << "\" height=\"" << number(h, 2) << "\" fill=\"" << s.color << "\"><title>"
          << escape_html(s.label) << ": " << s.counts[b] << " hexes (" << number(100 * fraction, 2) << "%) in ["
          << number(bin_lo, 2) << ", " << number(bin_hi, 2) << ")</title></rect>\n";
    }
  }
  // Axes, ticks, legend.
  svg << "<line x1=\"" << left << "\" y1=\"" << top + plot_h << "\" x2=\"" << left + plot_w << "\" y2=\""
      << top + plot_h << "\" class=\"axis\"/>\n";
  svg << "<line x1=\"" << left << "\" y1=\"" << top << "\" x2=\"" << left << "\" y2=\"" << top + plot_h
      << "\" class=\"axis\"/>\n";
  for (int k = 0; k <= 4; ++k) {
    const double x = left + plot_w * k / 4.0;
    svg << "<text x=\"" << number(x, 1) << "\" y=\"" << top + plot_h + 16 << "\" class=\"tick\" text-anchor=\"middle\">"
        << number(lo + (hi - lo) * k / 4.0, 2) << "</text>\n";
  }
  svg << "<text x=\"" << left - 6 << "\" y=\"" << top + 4 << "\" class=\"tick\" text-anchor=\"end\">"
      << number(100 * max_fraction, 1) << "%</text>\n";
  svg << "<text x=\"" << left - 6 << "\" y=\"" << top + plot_h << "\" class=\"tick\" text-anchor=\"end\">0</text>\n";
  svg << "<text x=\"" << left + plot_w / 2 << "\" y=\"" << height - 6 << "\" class=\"tick\" text-anchor=\"middle\">"
      << escape_html(title) << " (share of each run's hexes)</text>\n";
  for (size_t si = 0; si < series.size(); ++si) {
    // In the title row, right-aligned, so it never covers a bar.
    const double x = left + plot_w - 130 * double(series.size() - si), y = 9;
    svg << "<rect x=\"" << x << "\" y=\"" << y << "\" width=\"10\" height=\"10\" fill=\"" << series[si].color
        << "\"/><text x=\"" << x + 14 << "\" y=\"" << y + 9 << "\" class=\"tick\">" << escape_html(series[si].label)
        << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

// ---------------------------------------------------------------- tables

std::string stage_table(const PipelineResult& r) {
  std::ostringstream out;
  out << "<table class=\"stages\"><thead><tr><th>stage</th><th>seconds</th><th>result</th></tr></thead><tbody>\n";
  for (const auto& s : r.stages)
    out << "<tr><td>" << escape_html(s.name) << "</td><td class=\"num\">" << number(s.seconds, 3) << "</td><td>"
        << escape_html(describe(s.report)) << "</td></tr>\n";
  out << "<tr class=\"total\"><td>total</td><td class=\"num\">" << number(r.total_seconds, 3)
      << "</td><td></td></tr>\n</tbody></table>\n";
  return out.str();
}

std::string quality_html_row(const std::string& name, size_t count, const QualityStats& s) {
  std::ostringstream out;
  out << "<tr><td>" << escape_html(name) << "</td><td class=\"num\">" << count << "</td><td class=\"num\">"
      << number(s.avg) << "</td><td class=\"num\">" << number(s.std_dev) << "</td><td class=\"num\">" << number(s.min)
      << "</td><td class=\"num\">" << number(s.max) << "</td></tr>\n";
  return out.str();
}

std::string quality_table(const PipelineResult& r, bool thex_only) {
  std::ostringstream out;
  out << "<table class=\"quality\"><thead><tr><th>quality (Verdict)</th><th>elements</th><th>avg</th><th>std</th>"
         "<th>min</th><th>max</th></tr></thead><tbody>\n";
  out << quality_html_row("input triangles (shape)", r.input_summary.triangles, r.input_summary.shape);
  if (!thex_only) out << quality_html_row("coarse triangles (shape)", r.coarse_summary.triangles, r.coarse_summary.shape);
  out << quality_html_row("tets (shape)", r.tets, r.tet_shape);
  out << quality_html_row("hexes (shape)", r.hexes.hexes.size(), r.quality.shape_stats);
  out << quality_html_row("hexes (scaled Jacobian)", r.hexes.hexes.size(), r.quality.scaled_jacobian_stats);
  out << "</tbody></table>\n";
  return out.str();
}

double volume_error_percent(const PipelineResult& r) {
  const double v = r.input_summary.volume;
  return v != 0 ? 100.0 * (r.hex_volume - v) / v : 0.0;
}

double hausdorff_percent(const PipelineResult& r) {
  const double d = r.input_summary.bbox_diagonal;
  return d > 0 ? 100.0 * r.hausdorff / d : 0.0;
}

// The headline numbers, one column per run; each cell carries data-key="run.metric".
std::string comparison_table(const std::vector<std::pair<std::string, const PipelineResult*>>& runs) {
  struct Row {
    std::string key, label;
    std::string (*value)(const PipelineResult&);
  };
  static const Row rows[] = {
      {"nodes", "nodes", [](const PipelineResult& r) { return std::to_string(r.hexes.nodes.size()); }},
      {"hexes", "hexes", [](const PipelineResult& r) { return std::to_string(r.hexes.hexes.size()); }},
      {"tets", "tets", [](const PipelineResult& r) { return std::to_string(r.tets); }},
      {"shape_avg", "shape avg", [](const PipelineResult& r) { return number(r.quality.shape_stats.avg); }},
      {"shape_std", "shape std", [](const PipelineResult& r) { return number(r.quality.shape_stats.std_dev); }},
      {"shape_min", "shape min", [](const PipelineResult& r) { return number(r.quality.shape_stats.min); }},
      {"shape_max", "shape max", [](const PipelineResult& r) { return number(r.quality.shape_stats.max); }},
      {"sj_min", "min scaled Jacobian",
       [](const PipelineResult& r) { return number(r.quality.scaled_jacobian_stats.min); }},
      {"inverted", "inverted hexes", [](const PipelineResult& r) { return std::to_string(r.quality.inverted); }},
      {"below_0_2", "scaled Jacobian &lt; 0.2",
       [](const PipelineResult& r) { return std::to_string(r.quality.below_0_2); }},
      {"conforming", "conforming", [](const PipelineResult& r) { return std::string(r.conforming ? "yes" : "NO"); }},
      {"boundary_faces_inside", "boundary faces inside the mesh",
       [](const PipelineResult& r) { return std::to_string(r.boundary_faces_inside); }},
      {"hausdorff_percent", "Hausdorff, % of bbox diagonal",
       [](const PipelineResult& r) { return number(hausdorff_percent(r), 3); }},
      {"volume_error_percent", "volume error %",
       [](const PipelineResult& r) { return number(volume_error_percent(r), 3); }},
      {"total_seconds", "seconds", [](const PipelineResult& r) { return number(r.total_seconds, 2); }},
  };
  std::ostringstream out;
  out << "<table class=\"comparison\"><thead><tr><th></th>";
  for (const auto& run : runs) out << "<th>" << escape_html(run.first) << "</th>";
  out << "</tr></thead><tbody>\n";
  for (const Row& row : rows) {
    out << "<tr><td>" << row.label << "</td>";
    for (const auto& run : runs) {
      const std::string key = run.second == runs.front().second ? "dthex" : "thex";
      out << "<td class=\"num\" data-key=\"" << key << '.' << row.key << "\">" << row.value(*run.second) << "</td>";
    }
    out << "</tr>\n";
  }
  out << "</tbody></table>\n";
  return out.str();
}

std::string worst_table(const PipelineResult& r) {
  std::ostringstream out;
  out << "<table class=\"worst\"><thead><tr><th>mark</th><th>hex</th><th>scaled Jacobian</th><th>shape</th></tr></thead>"
         "<tbody>\n";
  for (size_t i = 0; i < r.worst_hexes.size(); ++i) {
    const size_t h = r.worst_hexes[i];
    if (h >= r.hexes.hexes.size()) continue;
    out << "<tr><td>" << i + 1 << "</td><td class=\"num\">" << h << "</td><td class=\"num\">"
        << number(r.quality.scaled_jacobian[h]) << "</td><td class=\"num\">" << number(r.quality.shape[h])
        << "</td></tr>\n";
  }
  out << "</tbody></table>\n";
  return out.str();
}

// ---------------------------------------------------------------- page

const char* kStyle = R"CSS(
body { font: 14px/1.45 system-ui, -apple-system, "Segoe UI", sans-serif; margin: 24px; color: #1d232b; max-width: 1400px; }
h1 { font-size: 20px; margin: 0 0 4px; } h2 { font-size: 16px; margin: 28px 0 8px; border-bottom: 1px solid #dde2e8; }
.meta { color: #5a6673; }
table { border-collapse: collapse; margin: 4px 24px 12px 0; display: inline-table; vertical-align: top; }
th, td { padding: 3px 10px; border-bottom: 1px solid #e6e9ee; text-align: left; }
th { background: #f3f5f8; font-weight: 600; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
tr.total td { font-weight: 600; }
.runs { display: flex; flex-wrap: wrap; gap: 12px 32px; } .runs h3 { font-size: 14px; margin: 4px 0; }
svg.histogram { margin: 4px 16px 8px 0; background: #fff; }
svg .title { font-weight: 600; font-size: 13px; } svg .tick { font-size: 11px; fill: #3a4653; }
svg .axis { stroke: #3a4653; stroke-width: 1; } svg .inverted-zone { fill: #fbe9ec; }
#viewer { display: flex; gap: 16px; flex-wrap: wrap; align-items: flex-start; }
#view { border: 1px solid #cfd6de; cursor: grab; touch-action: none; background: #fff; }
.controls label { display: block; margin: 6px 0; } .controls select { margin-left: 6px; }
#legend { width: 220px; height: 12px; border: 1px solid #aab4bf; }
.legend-labels { display: flex; justify-content: space-between; width: 222px; font-size: 11px; color: #3a4653; }
#render-message { color: #b00020; font-weight: 600; } .note { color: #5a6673; font-size: 12px; max-width: 320px; }
)CSS";

const char* kScript = R"JS(
(function () {
  'use strict';
  var body = document.body;
  function fail(error) {
    var message = String((error && (error.stack || error.message)) || error);
    body.dataset.render = 'error';
    body.dataset.renderError = message;
    var box = document.getElementById('render-message');
    if (box) box.textContent = '3D view failed: ' + message;
  }
  window.addEventListener('error', function (event) { fail(event.error || event.message); });
  try {
    var data = JSON.parse(document.getElementById('geometry').textContent);
    var decode = function (text) {
      var raw = atob(text), bytes = new Uint8Array(raw.length);
      for (var i = 0; i < raw.length; ++i) bytes[i] = raw.charCodeAt(i);
      return bytes;
    };
    var layers = data.layers.map(function (layer) {
      var q = decode(layer.positions), f = decode(layer.faces);
      var quantized = new Uint16Array(q.buffer, 0, q.length >> 1), positions = new Float32Array(quantized.length);
      for (var i = 0; i < quantized.length; ++i) positions[i] = quantized[i] / 65535 - 0.5;
      var count = positions.length / 3;
      return {
        name: layer.name, caption: layer.caption, arity: layer.arity, total: layer.total, shown: layer.shown,
        positions: positions, faces: new Uint32Array(f.buffer, 0, f.length >> 2),
        metrics: layer.metrics.map(function (m) { return { name: m.name, lo: m.lo, hi: m.hi, values: decode(m.values) }; }),
        sx: new Float32Array(count), sy: new Float32Array(count), sz: new Float32Array(count)
      };
    });
    var canvas = document.getElementById('view'), context = canvas.getContext('2d');
    var layerSelect = document.getElementById('layer'), metricSelect = document.getElementById('metric');
    var edgesBox = document.getElementById('edges'), marksBox = document.getElementById('marks');
    var info = document.getElementById('view-info');
    layers.forEach(function (layer, i) {
      var option = document.createElement('option');
      option.value = String(i); option.textContent = layer.name; layerSelect.appendChild(option);
    });
    var view = { yaw: 0.7, pitch: -0.45, zoom: 1, panX: 0, panY: 0 };
    // Quality colour: red (0) - yellow - green (1); inverted (scaled Jacobian <= 0) purple.
    function colourTable(metric) {
      var table = [];
      for (var k = 0; k < 256; ++k) {
        var value = metric.lo + (metric.hi - metric.lo) * k / 255, r, g, b;
        if (value <= 0 && metric.lo < 0) { r = 128; g = 0; b = 160; }
        else {
          var t = Math.max(0, Math.min(1, value));
          if (t < 0.5) { r = 220; g = Math.round(40 + 360 * t); b = 40; }
          else { r = Math.round(220 - 360 * (t - 0.5)); g = 220; b = 40 + Math.round(60 * (t - 0.5)); }
        }
        table.push([r, g, b]);
      }
      return table;
    }
    function fillMetrics() {
      var layer = layers[Number(layerSelect.value)];
      metricSelect.innerHTML = '';
      layer.metrics.forEach(function (m, i) {
        var option = document.createElement('option');
        option.value = String(i); option.textContent = m.name; metricSelect.appendChild(option);
      });
      info.textContent = layer.caption;
    }
    function updateLegend() {
      var layer = layers[Number(layerSelect.value)], metric = layer.metrics[Number(metricSelect.value)];
      var table = colourTable(metric), stops = [];
      for (var k = 0; k <= 8; ++k) { var c = table[Math.round(255 * k / 8)]; stops.push('rgb(' + c.join(',') + ') ' + (100 * k / 8) + '%'); }
      document.getElementById('legend').style.background = 'linear-gradient(to right,' + stops.join(',') + ')';
      document.getElementById('legend-lo').textContent = String(metric.lo);
      document.getElementById('legend-hi').textContent = String(metric.hi);
      document.getElementById('legend-name').textContent = metric.name;
    }
    var pending = 0;
    function draw(fast) {
      var ratio = window.devicePixelRatio || 1, width = canvas.clientWidth, height = canvas.clientHeight;
      if (canvas.width !== Math.round(width * ratio)) { canvas.width = Math.round(width * ratio); canvas.height = Math.round(height * ratio); }
      context.setTransform(ratio, 0, 0, ratio, 0, 0);
      context.fillStyle = '#ffffff'; context.fillRect(0, 0, width, height);
      var layer = layers[Number(layerSelect.value)], metric = layer.metrics[Number(metricSelect.value)] || layer.metrics[0];
      var table = colourTable(metric);
      var scale = 0.95 * Math.min(width, height) * view.zoom, cx = width / 2 + view.panX, cy = height / 2 + view.panY;
      var cosY = Math.cos(view.yaw), sinY = Math.sin(view.yaw), cosP = Math.cos(view.pitch), sinP = Math.sin(view.pitch);
      var p = layer.positions, sx = layer.sx, sy = layer.sy, sz = layer.sz, n = p.length / 3;
      function project(x, y, z, out) {
        var x1 = cosY * x + sinY * z, z1 = -sinY * x + cosY * z;
        var y2 = cosP * y - sinP * z1, z2 = sinP * y + cosP * z1;
        out[0] = cx + x1 * scale; out[1] = cy - y2 * scale; out[2] = z2 * scale;
      }
      var tmp = [0, 0, 0];
      for (var i = 0; i < n; ++i) { project(p[3 * i], p[3 * i + 1], p[3 * i + 2], tmp); sx[i] = tmp[0]; sy[i] = tmp[1]; sz[i] = tmp[2]; }
      var faces = layer.faces, arity = layer.arity, count = faces.length / arity;
      var step = fast && count > 60000 ? Math.ceil(count / 60000) : 1;
      var visible = [], depth = new Float32Array(count), light = new Float32Array(count);
      for (var f = 0; f < count; f += step) {
        var a = faces[arity * f], b = faces[arity * f + 1], c = faces[arity * f + 2], d = arity === 4 ? faces[arity * f + 3] : a;
        // Outward normal in view space (screen y points down, so y differences are negated).
        var ux, uy, uz, vx, vy, vz;
        if (arity === 4) { ux = sx[c] - sx[a]; uy = sy[a] - sy[c]; uz = sz[c] - sz[a]; vx = sx[d] - sx[b]; vy = sy[b] - sy[d]; vz = sz[d] - sz[b]; }
        else { ux = sx[b] - sx[a]; uy = sy[a] - sy[b]; uz = sz[b] - sz[a]; vx = sx[c] - sx[a]; vy = sy[a] - sy[c]; vz = sz[c] - sz[a]; }
        var nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
        if (nz <= 0) continue;  // facing away: closed, outward-oriented surfaces
        var length = Math.sqrt(nx * nx + ny * ny + nz * nz) || 1;
        light[f] = 0.35 + 0.65 * nz / length;
        depth[f] = (sz[a] + sz[b] + sz[c] + (arity === 4 ? sz[d] : 0)) / arity;
        visible.push(f);
      }
      visible.sort(function (u, v) { return depth[u] - depth[v]; });
      var stroke = !fast && edgesBox.checked;
      context.lineJoin = 'round';
      for (var k = 0; k < visible.length; ++k) {
        var g = visible[k], base = arity * g, colour = table[metric.values[g]], shade = light[g];
        var style = 'rgb(' + Math.round(colour[0] * shade) + ',' + Math.round(colour[1] * shade) + ',' + Math.round(colour[2] * shade) + ')';
        context.beginPath();
        context.moveTo(sx[faces[base]], sy[faces[base]]);
        for (var m = 1; m < arity; ++m) context.lineTo(sx[faces[base + m]], sy[faces[base + m]]);
        context.closePath();
        context.fillStyle = style; context.fill();
        if (stroke) { context.strokeStyle = 'rgba(20,30,40,0.45)'; context.lineWidth = 0.5; context.stroke(); }
        else if (!fast) { context.strokeStyle = style; context.lineWidth = 0.6; context.stroke(); }
      }
      if (marksBox.checked) {
        context.font = '12px sans-serif';
        data.worst.forEach(function (w, i) {
          project(w.at[0], w.at[1], w.at[2], tmp);
          context.beginPath(); context.arc(tmp[0], tmp[1], 7, 0, 2 * Math.PI);
          context.strokeStyle = '#d0002a'; context.lineWidth = 2; context.stroke();
          context.fillStyle = '#d0002a'; context.fillText(String(i + 1), tmp[0] + 9, tmp[1] - 6);
        });
      }
      body.dataset.facesDrawn = String(visible.length);
    }
    function schedule(fast) {
      if (pending) cancelAnimationFrame(pending);
      pending = requestAnimationFrame(function () { pending = 0; try { draw(fast); } catch (e) { fail(e); } });
    }
    var drag = null;
    canvas.addEventListener('pointerdown', function (e) { drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 }; canvas.setPointerCapture(e.pointerId); });
    canvas.addEventListener('pointermove', function (e) {
      if (!drag) return;
      var dx = e.clientX - drag.x, dy = e.clientY - drag.y; drag.x = e.clientX; drag.y = e.clientY;
      if (drag.pan) { view.panX += dx; view.panY += dy; }
      else { view.yaw += 0.01 * dx; view.pitch = Math.max(-1.57, Math.min(1.57, view.pitch + 0.01 * dy)); }
      schedule(true);
    });
    canvas.addEventListener('pointerup', function () { drag = null; schedule(false); });
    canvas.addEventListener('contextmenu', function (e) { e.preventDefault(); });
    canvas.addEventListener('wheel', function (e) {
      e.preventDefault();
      view.zoom = Math.max(0.1, Math.min(50, view.zoom * Math.exp(-0.0015 * e.deltaY)));
      schedule(true); clearTimeout(canvas.settle); canvas.settle = setTimeout(function () { schedule(false); }, 200);
    }, { passive: false });
    canvas.addEventListener('dblclick', function () { view = { yaw: 0.7, pitch: -0.45, zoom: 1, panX: 0, panY: 0 }; schedule(false); });
    layerSelect.addEventListener('change', function () { fillMetrics(); updateLegend(); schedule(false); });
    metricSelect.addEventListener('change', function () { updateLegend(); schedule(false); });
    edgesBox.addEventListener('change', function () { schedule(false); });
    marksBox.addEventListener('change', function () { schedule(false); });
    fillMetrics();
    updateLegend();
    draw(false);
    body.dataset.render = 'ok';
  } catch (error) {
    fail(error);
  }
})();
)JS";

}  // namespace

std::string report_html(const PipelineResult& r, const PipelineOptions& options, const PipelineResult* thex_baseline,
                        const ReportHtmlOptions& html_options) {
  std::vector<std::pair<std::string, const PipelineResult*>> runs;
  runs.emplace_back(options.thex_only ? "THex" : "DTHex", &r);
  if (thex_baseline) runs.emplace_back("THex baseline", thex_baseline);

  std::vector<HistogramSeries> shape_series, sj_series;
  const char* colours[] = {"#2f6fb0", "#e08a1e"};
  for (size_t i = 0; i < runs.size(); ++i) {
    const PipelineResult& run = *runs[i].second;
    const std::string key = i == 0 ? "dthex" : "thex";
    shape_series.push_back({key, runs[i].first, colours[i], histogram(run.quality.shape, 20, 0.0, 1.0)});
    sj_series.push_back({key, runs[i].first, colours[i], histogram(run.quality.scaled_jacobian, 40, -1.0, 1.0)});
  }

  std::string geometry = geometry_json(r, options, std::max<size_t>(html_options.max_faces_per_layer, 1)).dump();
  // Nothing in it can close the script element, but keep it so whatever the data.
  for (size_t at = geometry.find("</"); at != std::string::npos; at = geometry.find("</", at + 3))
    geometry.replace(at, 2, "<\\/");

  std::ostringstream page;
  page << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
       << "<title>om_dthex report: " << escape_html(r.input_path) << "</title>\n<style>" << kStyle << "</style>\n"
       << "</head>\n<body>\n";
  page << "<h1>om_dthex report: " << escape_html(r.input_path) << "</h1>\n";
  page << "<p class=\"meta\">om_dthex " << DTHEX_VERSION << " &middot; ";
  if (options.thex_only)
    page << "THex only";
  else
    page << "eps " << number(r.eps, 4) << (options.target_nodes ? " (chosen for --target-nodes " +
                                                                      std::to_string(options.target_nodes) + ")"
                                                                : std::string())
         << ", dice " << r.dice << (options.project ? "" : ", not projected");
  page << ", TetGen " << escape_html(tetgen_switches_for(options)) << " &middot; input " << r.input_summary.vertices
       << " vertices, " << r.input_summary.triangles << " triangles, genus " << r.input_summary.genus << "</p>\n";

  page << "<h2>Result</h2>\n" << comparison_table(runs);
  if (r.quality.inverted > 0)
    page << "<p id=\"inverted-warning\" style=\"color:#b00020\"><b>" << r.quality.inverted
         << " inverted hexes remain.</b></p>\n";

  page << "<h2>Quality histograms</h2>\n<div id=\"histograms\">\n"
       << svg_histogram("hist-shape", "hex shape", 0.0, 1.0, shape_series)
       << svg_histogram("hist-scaled-jacobian", "hex scaled Jacobian", -1.0, 1.0, sj_series) << "</div>\n";

  page << "<h2>Stages</h2>\n<div class=\"runs\">\n";
  for (const auto& run : runs)
    page << "<div><h3>" << escape_html(run.first) << "</h3>\n" << stage_table(*run.second)
         << quality_table(*run.second, run.second != &r || options.thex_only) << "</div>\n";
  page << "</div>\n";

  page << "<h2>3D view</h2>\n<div id=\"viewer\">\n"
       << "<canvas id=\"view\" width=\"900\" height=\"620\" style=\"width:900px;height:620px\"></canvas>\n"
       << "<div class=\"controls\">\n"
       << "<label>surface<select id=\"layer\"></select></label>\n"
       << "<label>colour by<select id=\"metric\"></select></label>\n"
       << "<div id=\"legend-name\"></div><div id=\"legend\"></div>"
       << "<div class=\"legend-labels\"><span id=\"legend-lo\"></span><span id=\"legend-hi\"></span></div>\n"
       << "<label><input type=\"checkbox\" id=\"edges\" checked> element edges</label>\n"
       << "<label><input type=\"checkbox\" id=\"marks\" checked> mark the worst hexes (red circles, numbered)</label>\n"
       << "<p class=\"note\">Drag to rotate, shift-drag to pan, wheel to zoom, double-click to reset. Hex boundary "
          "faces take the quality of their hex; purple is inverted.</p>\n"
       << "<p class=\"note\" id=\"view-info\"></p><p id=\"render-message\"></p>\n"
       << "<h3>Worst hexes</h3>\n" << worst_table(r) << "</div>\n</div>\n";

  page << "<script type=\"application/json\" id=\"geometry\">" << geometry << "</script>\n";
  page << "<script>" << kScript << "</script>\n</body>\n</html>\n";
  return page.str();
}

}  // namespace dthex
