// SPDX-License-Identifier: MIT
// The HTML report: its numbers agree with the run, its histograms count every hex, its
// embedded geometry stays bounded, and headless Chromium runs its script without errors.
#include <dthex/hexes/conformity.h>
#include <dthex/io/read_surface.h>
#include <dthex/mesh/quality.h>
#include <dthex/pipeline/pipeline.h>
#include <dthex/report/report_html.h>
#include "scratch_dir.h"
#include "bundled_meshes.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace dthex;

namespace {


std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The text of the element that starts with `open_tag_start` up to its closing tag.
std::string element(const std::string& page, const std::string& open_tag_start, const std::string& close_tag) {
  const size_t begin = page.find(open_tag_start);
  if (begin == std::string::npos) return "";
  const size_t end = page.find(close_tag, begin);
  return end == std::string::npos ? "" : page.substr(begin, end + close_tag.size() - begin);
}

// Per-bin counts of one series of a histogram SVG, in bin order.
std::vector<size_t> bar_counts(const std::string& svg, const std::string& series) {
  std::map<size_t, size_t> by_bin;
  const std::regex bar("data-series=\"" + series + "\" data-bin=\"([0-9]+)\" data-count=\"([0-9]+)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), bar); it != std::sregex_iterator(); ++it)
    by_bin[std::stoul((*it)[1])] = std::stoul((*it)[2]);
  std::vector<size_t> counts;
  for (const auto& [bin, count] : by_bin) {
    EXPECT_EQ(bin, counts.size()) << "bins are not contiguous";
    counts.push_back(count);
  }
  return counts;
}

std::string cell(const std::string& page, const std::string& key) {
  const std::regex pattern("data-key=\"" + key + "\">([^<]*)<");
  std::smatch match;
  return std::regex_search(page, match, pattern) ? match[1].str() : std::string("missing ") + key;
}

nlohmann::json embedded_geometry(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"geometry\">";
  const size_t begin = page.find(open);
  if (begin == std::string::npos) return {};
  const size_t end = page.find("</script>", begin);
  return nlohmann::json::parse(page.substr(begin + open.size(), end - begin - open.size()));
}

std::vector<uint8_t> decode_base64(const std::string& text) {
  std::vector<uint8_t> out;
  uint32_t buffer = 0;
  int bits = 0;
  for (char c : text) {
    int v;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    else if (c >= '0' && c <= '9') v = c - '0' + 52;
    else if (c == '+') v = 62;
    else if (c == '/') v = 63;
    else break;  // '=' padding
    buffer = (buffer << 6) | uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(uint8_t((buffer >> bits) & 0xff));
    }
  }
  return out;
}

std::string thousands(size_t n) {
  std::string digits = std::to_string(n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

const nlohmann::json* layer_named(const nlohmann::json& geometry, const std::string& name) {
  for (const auto& layer : geometry["layers"])
    if (layer["name"] == name) return &layer;
  return nullptr;
}

// One embedded layer decoded: positions in the page's normalized cube, faces, metric bytes.
struct ShownLayer {
  size_t arity = 0;
  std::vector<uint16_t> quantized;  // 3 per vertex
  std::vector<uint32_t> faces;      // arity per face
  std::vector<std::vector<uint8_t>> metrics;

  size_t face_count() const { return arity ? faces.size() / arity : 0; }
  Vec3 position(uint32_t v) const {
    return Vec3(quantized[3 * v], quantized[3 * v + 1], quantized[3 * v + 2]) / 65535.0;
  }
  // Area of the faces (quads split along their 0-2 diagonal), in the normalized cube.
  double area() const {
    double a = 0;
    for (size_t f = 0; f < face_count(); ++f)
      for (size_t k = 1; k + 1 < arity; ++k) {
        const Vec3 p = position(faces[arity * f]), q = position(faces[arity * f + k]),
                   r = position(faces[arity * f + k + 1]);
        a += 0.5 * (q - p).cross(r - p).norm();
      }
    return a;
  }
  // Edges used by fewer than two faces: the holes a person sees.
  size_t open_edges() const {
    std::map<std::pair<uint32_t, uint32_t>, int> uses;
    for (size_t f = 0; f < face_count(); ++f)
      for (size_t k = 0; k < arity; ++k)
        ++uses[std::minmax(faces[arity * f + k], faces[arity * f + (k + 1) % arity])];
    size_t open = 0;
    for (const auto& [edge, count] : uses) open += count < 2;
    return open;
  }
  // A face's corners as quantized coordinates, starting at the given corner.
  std::vector<uint16_t> corners(size_t f, size_t first, const std::vector<size_t>& order) const {
    std::vector<uint16_t> out;
    for (size_t k : order)
      for (int c = 0; c < 3; ++c) out.push_back(quantized[3 * faces[arity * f + (first + k) % arity] + c]);
    return out;
  }
};

template <class T>
std::vector<T> decode_array(const std::string& text) {
  const std::vector<uint8_t> bytes = decode_base64(text);
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

ShownLayer shown_layer(const nlohmann::json& layer) {
  ShownLayer s;
  s.arity = layer["arity"];
  s.quantized = decode_array<uint16_t>(layer["positions"]);
  s.faces = decode_array<uint32_t>(layer["faces"]);
  for (const auto& m : layer["metrics"]) s.metrics.push_back(decode_base64(m["values"]));
  return s;
}

struct SphereRuns {
  PipelineOptions options, thex_options;
  PipelineResult dthex, thex;
};

// The 728-triangle sphere meshed by DTHex and by THex, shared by the tests (well under a second).
const SphereRuns& sphere_runs() {
  static const SphereRuns runs = [] {
    SphereRuns r;
    Progress quiet;
    r.dthex = run_pipeline(dthex_test::bundled_mesh("sphere728.off"), r.options, quiet);
    r.thex_options.thex_only = true;
    r.thex = run_pipeline(dthex_test::bundled_mesh("sphere728.off"), r.thex_options, quiet);
    return r;
  }();
  return runs;
}

}  // namespace

TEST(ReportHtml, HistogramsCountEveryHexOfBothRuns) {
  const SphereRuns& runs = sphere_runs();
  const std::string page = report_html(runs.dthex, runs.options, &runs.thex);
  const std::string shape_svg = element(page, "<svg id=\"hist-shape\"", "</svg>");
  const std::string sj_svg = element(page, "<svg id=\"hist-scaled-jacobian\"", "</svg>");
  ASSERT_FALSE(shape_svg.empty());
  ASSERT_FALSE(sj_svg.empty());
  for (const auto& [series, run] : {std::pair<std::string, const PipelineResult*>{"dthex", &runs.dthex},
                                    std::pair<std::string, const PipelineResult*>{"thex", &runs.thex}}) {
    const std::vector<size_t> shape = bar_counts(shape_svg, series), sj = bar_counts(sj_svg, series);
    ASSERT_EQ(shape.size(), 20u) << series;
    ASSERT_EQ(sj.size(), 40u) << series;
    size_t shape_total = 0, sj_total = 0;
    for (size_t c : shape) shape_total += c;
    for (size_t c : sj) sj_total += c;
    EXPECT_EQ(shape_total, run->hexes.hexes.size()) << series;
    EXPECT_EQ(sj_total, run->hexes.hexes.size()) << series;
    // Each bar holds exactly the hexes whose shape falls in its twentieth of [0, 1].
    std::vector<size_t> expected(20, 0);
    for (double q : run->quality.shape) expected[std::min<size_t>(19, size_t(std::floor(q * 20)))]++;
    EXPECT_EQ(shape, expected) << series;
    size_t positive = 0;  // scaled Jacobian bins 20..39 cover (0, 1]
    for (size_t b = 20; b < 40; ++b) positive += sj[b];
    EXPECT_EQ(positive + run->quality.inverted, run->hexes.hexes.size()) << series;
  }
}

TEST(ReportHtml, TablesAgreeWithTheRun) {
  const SphereRuns& runs = sphere_runs();
  const std::string page = report_html(runs.dthex, runs.options, &runs.thex);
  const PipelineResult& d = runs.dthex;
  EXPECT_EQ(cell(page, "dthex.nodes"), std::to_string(d.hexes.nodes.size()));
  EXPECT_EQ(cell(page, "dthex.hexes"), std::to_string(d.hexes.hexes.size()));
  EXPECT_EQ(cell(page, "thex.hexes"), std::to_string(runs.thex.hexes.hexes.size()));
  EXPECT_EQ(cell(page, "thex.hexes"), std::to_string(4 * runs.thex.tets));  // THex: 4 hexes per tet
  EXPECT_EQ(cell(page, "dthex.inverted"), std::to_string(d.quality.inverted));
  EXPECT_NEAR(std::stod(cell(page, "dthex.shape_avg")), d.quality.shape_stats.avg, 5e-5);
  EXPECT_NEAR(std::stod(cell(page, "dthex.sj_min")), d.quality.scaled_jacobian_stats.min, 5e-5);
  EXPECT_NEAR(std::stod(cell(page, "thex.shape_min")), runs.thex.quality.shape_stats.min, 5e-5);
  EXPECT_NEAR(std::stod(cell(page, "dthex.hausdorff_percent")), 100 * d.hausdorff / d.input_summary.bbox_diagonal,
              5e-4);
  EXPECT_NEAR(std::stod(cell(page, "thex.hausdorff_percent")), 0.0, 5e-4);  // THex keeps the input surface
  // Every stage of both runs is listed.
  for (const auto* run : {&runs.dthex, &runs.thex})
    for (const StageRecord& s : run->stages) EXPECT_NE(page.find("<td>" + s.name + "</td>"), std::string::npos) << s.name;
  // Without a baseline there is no THex column and no second series.
  const std::string alone = report_html(runs.dthex, runs.options);
  EXPECT_EQ(alone.find("data-key=\"thex."), std::string::npos);
  EXPECT_EQ(alone.find("data-series=\"thex\""), std::string::npos);
  EXPECT_EQ(cell(alone, "dthex.hexes"), std::to_string(d.hexes.hexes.size()));
}

TEST(ReportHtml, EmbedsTheThreeSurfacesAndTheWorstHexes) {
  const SphereRuns& runs = sphere_runs();
  const PipelineResult& d = runs.dthex;
  const std::string page = report_html(d, runs.options, &runs.thex);
  EXPECT_EQ(page.find("http://"), page.find("http://www.w3.org/2000/svg"));  // no network: only the SVG namespace
  EXPECT_EQ(page.find("https://"), std::string::npos);
  const nlohmann::json geometry = embedded_geometry(page);
  const nlohmann::json* hex = layer_named(geometry, "hex boundary");
  const nlohmann::json* coarse = layer_named(geometry, "coarse surface");
  const nlohmann::json* input = layer_named(geometry, "input surface");
  ASSERT_TRUE(hex && coarse && input);
  const size_t quads = check_conformity(d.hexes).boundary_faces;
  EXPECT_EQ((*hex)["total"].get<size_t>(), quads);
  EXPECT_EQ((*hex)["shown"].get<size_t>(), quads);
  EXPECT_EQ(decode_base64((*hex)["faces"]).size(), quads * 4 * sizeof(uint32_t));
  EXPECT_EQ((*coarse)["total"].get<size_t>(), d.coarse.triangles.size());
  EXPECT_EQ((*input)["total"].get<size_t>(), d.input.triangles.size());
  EXPECT_EQ(decode_base64((*input)["positions"]).size(), d.input.points.size() * 3 * sizeof(uint16_t));
  // The quad colours are their hexes' scaled Jacobians: the worst boundary quad is no better than the mesh minimum.
  const auto& sj = (*hex)["metrics"][0];
  ASSERT_EQ(sj["name"], "scaled Jacobian");
  const std::vector<uint8_t> values = decode_base64(sj["values"]);
  ASSERT_EQ(values.size(), quads);
  const double lowest = -1.0 + 2.0 * (*std::min_element(values.begin(), values.end())) / 255.0;
  EXPECT_GE(lowest, d.quality.scaled_jacobian_stats.min - 1.0 / 255);
  EXPECT_EQ(geometry["worst"].size(), d.worst_hexes.size());
  EXPECT_NEAR(geometry["worst"][0]["scaled_jacobian"].get<double>(), d.quality.scaled_jacobian_stats.min, 1e-12);
}

// A slab of 400 x 400 hexes has 321,600 boundary quads, twice the cap: the page shows a
// reduced surface that is still closed (a sample of the faces would be full of holes),
// has the slab's area, fits the cap, and keeps every quad of a poor hex unchanged.
TEST(ReportHtml, LargeBoundaryIsReducedClosedAndKeepsEveryPoorHex) {
  const int n = 400;
  PipelineResult r;
  r.input_path = "slab";
  auto id = [&](int i, int j, int k) { return (k * (n + 1) + j) * (n + 1) + i; };
  for (int k = 0; k <= 1; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) r.hexes.nodes.emplace_back(i, j, k);
  // Push every 997th top node below the bottom face: its four hexes invert. None of them
  // touches the slab's sides, so each owns exactly two boundary quads (top and bottom).
  size_t sunk = 0;
  for (int j = 2; j < n - 1; ++j)
    for (int i = 2; i < n - 1; ++i)
      if (id(i, j, 1) % 997 == 0) {
        r.hexes.nodes[size_t(id(i, j, 1))].z() = -0.5;
        ++sunk;
      }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      r.hexes.hexes.push_back({id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0), id(i, j + 1, 0), id(i, j, 1),
                               id(i + 1, j, 1), id(i + 1, j + 1, 1), id(i, j + 1, 1)});
  r.quality = measure_hex_quality(r.hexes);
  r.input.points = {Vec3(0, 0, 0), Vec3(n, 0, 0), Vec3(0, n, 0), Vec3(0, 0, 1)};
  r.input.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  PipelineOptions options;
  options.thex_only = true;
  ASSERT_GT(sunk, 100u);
  const std::vector<std::array<int, 4>> quads = boundary_quads(r.hexes);
  ASSERT_GT(quads.size(), 2 * kReportMaxFacesPerLayer);
  const std::string page = report_html(r, options);
  EXPECT_LT(page.size(), size_t(8) << 20);
  const nlohmann::json geometry = embedded_geometry(page);
  const nlohmann::json* hex = layer_named(geometry, "hex boundary");
  ASSERT_TRUE(hex);
  EXPECT_EQ((*hex)["total"].get<size_t>(), quads.size());
  const ShownLayer shown = shown_layer(*hex);
  EXPECT_EQ(shown.open_edges(), 0u);
  EXPECT_EQ(shown.face_count(), (*hex)["shown"].get<size_t>());
  EXPECT_LE(shown.face_count(), kReportMaxFacesPerLayer);
  EXPECT_GT(shown.face_count(), kReportMaxFacesPerLayer / 2);  // the budget is used, not wasted
  ASSERT_EQ(shown.arity, 3u);  // quads merged by clustering may become triangles

  // The same page without a cap shows every quad: the reference for area and poor faces.
  ReportHtmlOptions uncapped;
  uncapped.max_faces_per_layer = quads.size();
  const ShownLayer all = shown_layer(*layer_named(embedded_geometry(report_html(r, options, nullptr, uncapped)),
                                                  "hex boundary"));
  ASSERT_EQ(all.arity, 4u);
  ASSERT_EQ(all.face_count(), quads.size());
  EXPECT_EQ(all.open_edges(), 0u);
  EXPECT_NEAR(shown.area() / all.area(), 1.0, 0.03);

  // Every quad of a poor hex is shown as its two triangles, same corners, same colour.
  auto poor = [](uint8_t v) { return -1.0 + 2.0 * v / 255.0 < 0.2; };
  std::map<std::vector<uint16_t>, uint8_t> shown_triangles;  // corners (any rotation) -> scaled Jacobian byte
  for (size_t t = 0; t < shown.face_count(); ++t)
    for (size_t first = 0; first < 3; ++first) shown_triangles[shown.corners(t, first, {0, 1, 2})] = shown.metrics[0][t];
  size_t poor_hexes = 0, poor_quads = 0, poor_quads_shown = 0;
  for (double q : r.quality.scaled_jacobian) poor_hexes += q < 0.2;
  for (size_t q = 0; q < all.face_count(); ++q) {
    if (!poor(all.metrics[0][q])) continue;
    ++poor_quads;
    const auto a = shown_triangles.find(all.corners(q, 0, {0, 1, 2})), b = shown_triangles.find(all.corners(q, 0, {0, 2, 3}));
    poor_quads_shown += a != shown_triangles.end() && b != shown_triangles.end() && a->second == all.metrics[0][q] &&
                        b->second == all.metrics[0][q];
  }
  EXPECT_EQ(poor_hexes, 4 * sunk);
  EXPECT_EQ(poor_quads, 2 * poor_hexes);
  EXPECT_EQ(poor_quads_shown, poor_quads);

  // The caption says what is shown.
  const std::string caption = (*hex)["caption"];
  EXPECT_NE(caption.find("reduced to " + thousands(shown.face_count()) + " triangles by vertex clustering"),
            std::string::npos) << caption;
  EXPECT_NE(caption.find("all " + thousands(poor_quads) + " faces of poor hexes are shown unchanged"),
            std::string::npos) << caption;
  EXPECT_EQ((*hex)["reduction"]["method"], "vertex clustering");
}

// A real closed surface over a (lowered) cap: the input layer is reduced, closed, and
// keeps the bone's area; under the cap a layer is shown whole and says so.
TEST(ReportHtml, InputSurfaceOverTheCapIsReducedWithoutHoles) {
  PipelineResult r;
  r.input_path = "femur";
  r.input = read_surface(dthex_test::bundled_mesh("femur_proximal_ct.off"));
  PipelineOptions options;
  options.thex_only = true;
  ReportHtmlOptions html;
  html.max_faces_per_layer = 8000;
  ASSERT_GT(r.input.triangles.size(), 8 * html.max_faces_per_layer);
  const nlohmann::json* input_layer;
  const nlohmann::json reduced_geometry = embedded_geometry(report_html(r, options, nullptr, html));
  input_layer = layer_named(reduced_geometry, "input surface");
  ASSERT_TRUE(input_layer);
  const ShownLayer reduced = shown_layer(*input_layer);
  EXPECT_LE(reduced.face_count(), html.max_faces_per_layer);
  EXPECT_GT(reduced.face_count(), html.max_faces_per_layer / 2);
  EXPECT_EQ(reduced.open_edges(), 0u);
  EXPECT_NE((*input_layer)["caption"].get<std::string>().find("by vertex clustering"), std::string::npos);

  html.max_faces_per_layer = r.input.triangles.size();
  const nlohmann::json whole_geometry = embedded_geometry(report_html(r, options, nullptr, html));
  const ShownLayer whole = shown_layer(*layer_named(whole_geometry, "input surface"));
  ASSERT_EQ(whole.face_count(), r.input.triangles.size());
  EXPECT_EQ(whole.open_edges(), 0u);
  EXPECT_NEAR(reduced.area() / whole.area(), 1.0, 0.03);
  EXPECT_EQ((*layer_named(whole_geometry, "input surface"))["caption"],
            "input surface: all " + thousands(r.input.triangles.size()) + " triangles");
}

TEST(ReportHtml, HeadlessChromiumRendersItWithoutConsoleErrors) {
  const char* chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) GTEST_SKIP() << "chromium is not installed (tools/setup.sh installs it)";
  const SphereRuns& runs = sphere_runs();
  const fs::path dir = dthex_test::fresh_dir("report_html");
  auto render = [&](const std::string& name, const std::string& page, std::string& log) {
    const fs::path file = dir / name, dom = dir / (name + ".dom"), err = dir / (name + ".err");
    std::ofstream(file, std::ios::binary) << page;
    const std::string command = std::string("timeout 120 ") + chromium +
                                " --headless=new --no-sandbox --disable-gpu --no-first-run --user-data-dir=" +
                                (dir / "profile").string() + " --enable-logging=stderr --v=0 --dump-dom file://" +
                                file.string() + " >" + dom.string() + " 2>" + err.string();
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    log = slurp(err);
    return slurp(dom);
  };
  std::string log;
  const std::string dom = render("report.html", report_html(runs.dthex, runs.options, &runs.thex), log);
  EXPECT_NE(dom.find("data-render=\"ok\""), std::string::npos) << dom.substr(0, 2000);
  EXPECT_NE(dom.find("<svg id=\"hist-shape\""), std::string::npos);
  EXPECT_NE(dom.find("<svg id=\"hist-scaled-jacobian\""), std::string::npos);
  std::smatch drawn;
  ASSERT_TRUE(std::regex_search(dom, drawn, std::regex("data-faces-drawn=\"([0-9]+)\"")));
  EXPECT_GT(std::stoul(drawn[1]), 0u);  // the back-face-culled hex boundary: some, not all, quads face the camera
  EXPECT_LT(std::stoul(drawn[1]), check_conformity(runs.dthex.hexes).boundary_faces);
  EXPECT_EQ(log.find(":CONSOLE"), std::string::npos) << log;
  EXPECT_EQ(log.find("Uncaught"), std::string::npos) << log;

  // A page whose layers are reduced (a lowered cap) draws them too and captions them.
  ReportHtmlOptions small;
  small.max_faces_per_layer = check_conformity(runs.dthex.hexes).boundary_faces / 2;
  const std::string reduced_dom = render("reduced.html", report_html(runs.dthex, runs.options, nullptr, small), log);
  EXPECT_NE(reduced_dom.find("data-render=\"ok\""), std::string::npos) << reduced_dom.substr(0, 2000);
  EXPECT_TRUE(std::regex_search(reduced_dom, std::regex("id=\"view-info\">hex boundary: [0-9,]+ quads reduced to "
                                                        "[0-9,]+ triangles by vertex clustering")))
      << reduced_dom.substr(reduced_dom.find("view-info"), 400);
  EXPECT_EQ(log.find(":CONSOLE"), std::string::npos) << log;

  // The marker is not set blindly: a page whose geometry is broken reports the error.
  std::string broken = report_html(runs.dthex, runs.options);
  const size_t at = broken.find("id=\"geometry\">");
  ASSERT_NE(at, std::string::npos);
  broken.insert(at + 14, "{oops");
  const std::string broken_dom = render("broken.html", broken, log);
  EXPECT_NE(broken_dom.find("data-render=\"error\""), std::string::npos);
  EXPECT_EQ(broken_dom.find("data-render=\"ok\""), std::string::npos);
  fs::remove_all(dir);
}
