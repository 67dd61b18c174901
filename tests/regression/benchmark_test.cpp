// SPDX-License-Identifier: MIT
// The benchmark harness: its CSV rows are the pipeline's own numbers, each method runs
// with its options, and a run past the timeout is killed and reported as such.
#include <dthex/io/read_surface.h>
#include <dthex/io/write_surface.h>
#include <dthex/pipeline/pipeline.h>
#include "scratch_dir.h"
#include "bundled_meshes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {


using CsvRow = std::map<std::string, std::string>;

// Rows of a CSV without quoted commas (the benchmark quotes only its message column).
std::vector<CsvRow> read_csv(const fs::path& path, std::vector<std::string>& header) {
  std::ifstream in(path);
  std::vector<CsvRow> rows;
  std::string line;
  auto split = [](const std::string& text) {
    std::vector<std::string> fields;
    std::stringstream ss(text);
    for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
    if (!text.empty() && text.back() == ',') fields.emplace_back();
    return fields;
  };
  if (!std::getline(in, line)) return rows;
  header = split(line);
  while (std::getline(in, line)) {
    const auto fields = split(line);
    CsvRow row;
    for (size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(row);
  }
  return rows;
}

int run_benchmark(const std::string& args, const fs::path& dir) {
  const std::string command = std::string(DTHEX_BINARY_DIR) + "/benchmark " + args + " -q >" +
                              (dir / "stdout.txt").string() + " 2>" + (dir / "stderr.txt").string();
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

fs::path benchmark_scratch(const std::string& name) {
  return dthex_test::fresh_dir("benchmark_" + name);
}

}  // namespace

TEST(Benchmark, CsvRowsAreThePipelinesNumbers) {
  const fs::path dir = benchmark_scratch("csv");
  const fs::path csv = dir / "b.csv";
  ASSERT_EQ(run_benchmark(dthex_test::bundled_mesh("sphere728.off") + " --methods thex,dthex --timeout 120 --csv " + csv.string(), dir), 0);
  std::vector<std::string> header;
  const std::vector<CsvRow> rows = read_csv(csv, header);
  for (const char* column : {"mesh", "method", "status", "nodes", "hexes", "shape_avg", "shape_std", "shape_min",
                             "shape_max", "sj_min", "inverted", "conforming", "boundary_faces_inside", "hausdorff_pct", "volume_error_pct", "t_tetrahedralize",
                             "total_seconds", "peak_mb"})
    EXPECT_NE(std::find(header.begin(), header.end(), column), header.end()) << column;
  ASSERT_EQ(rows.size(), 2u);
  for (const CsvRow& row : rows) {
    SCOPED_TRACE(row.at("method"));
    EXPECT_EQ(row.at("mesh"), "sphere728");
    EXPECT_EQ(row.at("status"), "ok");
    dthex::PipelineOptions options;
    options.thex_only = row.at("method") == "thex";
    dthex::Progress quiet;
    const dthex::PipelineResult r = dthex::run_pipeline(dthex_test::bundled_mesh("sphere728.off"), options, quiet);
    EXPECT_EQ(std::stoul(row.at("input_triangles")), r.input.triangles.size());
    EXPECT_EQ(std::stoul(row.at("tets")), r.tets);
    EXPECT_EQ(std::stoul(row.at("nodes")), r.hexes.nodes.size());
    EXPECT_EQ(std::stoul(row.at("hexes")), r.hexes.hexes.size());
    EXPECT_EQ(std::stoul(row.at("inverted")), r.quality.inverted);
    EXPECT_EQ(row.at("conforming"), r.conforming ? "yes" : "no");
    EXPECT_EQ(std::stoul(row.at("boundary_faces_inside")), r.boundary_faces_inside);
    EXPECT_NEAR(std::stod(row.at("shape_avg")), r.quality.shape_stats.avg, 1e-8);
    EXPECT_NEAR(std::stod(row.at("shape_std")), r.quality.shape_stats.std_dev, 1e-8);
    EXPECT_NEAR(std::stod(row.at("shape_min")), r.quality.shape_stats.min, 1e-8);
    EXPECT_NEAR(std::stod(row.at("shape_max")), r.quality.shape_stats.max, 1e-8);
    EXPECT_NEAR(std::stod(row.at("sj_min")), r.quality.scaled_jacobian_stats.min, 1e-8);
    EXPECT_NEAR(std::stod(row.at("hausdorff_pct")), 100 * r.hausdorff / r.input_summary.bbox_diagonal, 1e-6);
    EXPECT_NEAR(std::stod(row.at("volume_error_pct")),
                100 * (r.hex_volume - r.input_summary.volume) / r.input_summary.volume, 1e-6);
    // THex has no coarsening stage and keeps the input surface; DTHex coarsens.
    EXPECT_EQ(row.at("t_coarsen").empty(), options.thex_only);
    EXPECT_EQ(std::stoul(row.at("coarse_triangles")), r.coarse.triangles.size());
    // The stages add up to no more than the total, which leaves out writing the mesh after
    // it; every stage the pipeline ran has its own column (none lands in "other").
    double stages = 0;
    for (const auto& [column, value] : row)
      if (column.rfind("t_", 0) == 0 && column != "t_write" && !value.empty()) stages += std::stod(value);
    EXPECT_LE(stages, std::stod(row.at("total_seconds")) + 1e-6);
    EXPECT_TRUE(row.at("t_other").empty()) << row.at("t_other");
    ASSERT_FALSE(row.at("t_write").empty());
    EXPECT_GT(std::stod(row.at("t_write")), 0.0);
    EXPECT_GT(std::stod(row.at("peak_mb")), 1.0);
    // Every timed stage has its peak resident set, sampled in the child: more than the
    // program alone, and no more than the run's own peak as the kernel counts it.
    size_t peaks = 0;
    for (const auto& [column, value] : row) {
      if (column.rfind("t_", 0) != 0 || value.empty()) continue;
      const std::string peak = "peak_mb_" + column.substr(2);
      ASSERT_TRUE(row.count(peak)) << peak;
      ASSERT_FALSE(row.at(peak).empty()) << peak;
      EXPECT_GT(std::stod(row.at(peak)), 1.0) << peak;
      EXPECT_LE(std::stod(row.at(peak)), std::stod(row.at("peak_mb")) + 0.5) << peak;
      ++peaks;
    }
    EXPECT_GE(peaks, 5u);
  }
  EXPECT_LT(std::stoul(rows[1].at("hexes")), std::stoul(rows[0].at("hexes")));  // dthex after thex, fewer hexes
  fs::remove_all(dir);
}

TEST(Benchmark, RunPastTheTimeoutIsKilledAndReported) {
  const fs::path dir = benchmark_scratch("timeout");
  const fs::path csv = dir / "t.csv";
  // The liver's DTHex takes seconds; 20 ms is not enough for anything past reading.
  EXPECT_EQ(run_benchmark(dthex_test::bundled_mesh("liver.off") + " --methods dthex --timeout 0.02 --csv " + csv.string(), dir), 3);
  std::vector<std::string> header;
  const std::vector<CsvRow> rows = read_csv(csv, header);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("status"), "timeout");
  EXPECT_EQ(rows[0].at("hexes"), "0");
  // Bad usage is exit 2 naming the option.
  EXPECT_EQ(run_benchmark(dthex_test::bundled_mesh("liver.off") + " --methods tetgen", dir), 2);
  std::ifstream err(dir / "stderr.txt");
  std::stringstream text;
  text << err.rdbuf();
  EXPECT_NE(text.str().find("--methods"), std::string::npos) << text.str();
  fs::remove_all(dir);
}

// --subdivide on a surface with many triangles at a vertex: a double cone of 64 rim points,
// each apex in 64 triangles. Loop subdivision moves every point to an average of points of
// the input, so the subdivided copy stays inside the input's bounding box; OpenMesh's LoopT,
// whose weights were made for fewer than 50 triangles at a vertex, had sent the apexes far out
// of it (of the ear drum's two poles, 160 triangles each, one became a spike).
TEST(Benchmark, SubdividedCopyOfAManyValencedApexStaysInsideTheInputsBox) {
  const fs::path dir = benchmark_scratch("subdivide");
  dthex::TriSurface cone;
  const int n = 64;
  for (int i = 0; i < n; ++i)
    cone.points.push_back({std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0.0});
  cone.points.push_back({0, 0, 1});
  cone.points.push_back({0, 0, -1});
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    cone.triangles.push_back({i, j, n});
    cone.triangles.push_back({j, i, n + 1});
  }
  const fs::path input = dir / "double_cone.off";
  dthex::write_surface(cone, input.string());
  ASSERT_EQ(run_benchmark(input.string() + " --subdivide 1 --methods thex --timeout 120 --work-dir " + dir.string(), dir), 0);
  const dthex::TriSurface copy = dthex::read_surface((dir / "double_cone_loop1.off").string());
  ASSERT_EQ(copy.triangles.size(), 4 * cone.triangles.size());
  for (const auto& p : copy.points) {
    EXPECT_LE(std::abs(p.z()), 1.0) << p.transpose();
    EXPECT_LE(p.head<2>().norm(), 1.0 + 1e-9) << p.transpose();
  }
  fs::remove_all(dir);
}
