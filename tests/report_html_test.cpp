// SPDX-License-Identifier: MIT
// The HTML report: its numbers agree with the run, its histograms count every hex, its
// embedded geometry stays bounded, and headless Chromium runs its script without errors.
#include "core/conformity.h"
#include "core/pipeline.h"
#include "core/quality.h"
#include "core/report_html.h"
#include "scratch_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace dthex;

namespace {

std::string mesh(const std::string& name) { return std::string(DTHEX_SOURCE_DIR) + "/meshes/" + name; }

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

const nlohmann::json* layer_named(const nlohmann::json& geometry, const std::string& name) {
  for (const auto& layer : geometry["layers"])
    if (layer["name"] == name) return &layer;
  return nullptr;
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
    r.dthex = run_pipeline(mesh("sphere728.off"), r.options, quiet);
    r.thex_options.thex_only = true;
    r.thex = run_pipeline(mesh("sphere728.off"), r.thex_options, quiet);
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

// A slab of 400 x 400 hexes has 321,600 boundary quads: the page shows a sample of them,
// bounded, and every quad of a poor hex regardless of the sampling.
TEST(ReportHtml, LargeBoundaryIsSampledButKeepsEveryPoorHex) {
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
  const size_t shown = (*hex)["shown"];
  EXPECT_LE(shown, kReportMaxFacesPerLayer + 4 * sunk);
  EXPECT_GT(shown, kReportMaxFacesPerLayer / 2);
  // Every poor hex's boundary quads are shown: each slab hex owns its top and bottom quad.
  size_t poor_hexes = 0, poor_shown = 0;
  for (double q : r.quality.scaled_jacobian) poor_hexes += q < 0.2;
  for (uint8_t v : decode_base64((*hex)["metrics"][0]["values"])) poor_shown += (-1.0 + 2.0 * v / 255.0) < 0.2;
  EXPECT_EQ(poor_hexes, 4 * sunk);
  EXPECT_EQ(poor_shown, 2 * poor_hexes);
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
