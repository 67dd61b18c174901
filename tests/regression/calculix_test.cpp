// SPDX-License-Identifier: MIT
// A real solver on om_dthex's output: CalculiX (ccx, Debian's calculix-ccx) solves a deck that
// includes the .inp and uses only the names in it, one patch fixed and another under pressure.
#include <dthex/io/write_surface.h>
#include "boundary_fixtures.h"
#include "scratch_dir.h"
#include "subprocess_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

namespace fs = std::filesystem;
using dthex::Vec3;

namespace {

struct InpSets {
  std::map<int, Vec3> nodes;
  std::map<std::string, std::vector<int>> node_sets;
  std::vector<std::string> surfaces;
};

// Reads what the deck needs from our .inp: the nodes, the node sets and the surface names.
InpSets read_inp(const fs::path& file) {
  InpSets sets;
  std::ifstream in(file);
  std::string line, section, name;
  const std::regex nset(R"(\*NSET, NSET=(\w+))"), surface(R"(\*SURFACE, NAME=(\w+), TYPE=ELEMENT)");
  std::smatch m;
  while (std::getline(in, line)) {
    if (line.rfind("**", 0) == 0) continue;
    if (line.rfind("*", 0) == 0) {
      section = line == "*NODE" ? "node" : std::regex_match(line, m, nset) ? "nset" : "";
      if (section == "nset") name = m[1];
      if (std::regex_match(line, m, surface)) sets.surfaces.push_back(m[1]);
      continue;
    }
    std::stringstream fields(line);
    std::string field;
    if (section == "node") {
      std::vector<double> v;
      while (std::getline(fields, field, ',')) v.push_back(std::stod(field));
      sets.nodes[int(v[0])] = Vec3(v[1], v[2], v[3]);
    } else if (section == "nset") {
      while (std::getline(fields, field, ',')) sets.node_sets[name].push_back(std::stoi(field));
    }
  }
  return sets;
}

// The patch all of whose nodes have x equal to `x` (to 1e-9 of the box), or "".
std::string patch_at_x(const InpSets& sets, double x, double size) {
  for (const auto& [name, nodes] : sets.node_sets) {
    if (name.rfind("patch", 0) != 0) continue;
    if (std::all_of(nodes.begin(), nodes.end(),
                    [&](int n) { return std::abs(sets.nodes.at(n).x() - x) <= 1e-9 * size; }))
      return name;
  }
  return "";
}

}  // namespace

// A 2 x 1 x 1 box at two scales (millimetres and a model in metres, whose coordinates need all
// their digits read): fixed at its x = 0 end, pressure p on its x = 2 end. The reaction at the
// fixed end must balance the load: p times the end's area, along x, and nothing across.
TEST(Calculix, SolvesADeckThatIncludesOurMeshAndBalancesThePressure) {
  const auto which = dthex_test::run_command("command -v ccx");
  ASSERT_EQ(which.exit_code, 0) << "ccx not found: tools/setup.sh installs calculix-ccx";
  for (const double scale : {1.0, 1e-4}) {
    SCOPED_TRACE("scale " + std::to_string(scale));
    const fs::path dir = dthex_test::fresh_dir("calculix_" + std::to_string(scale == 1.0));
    const dthex::TriSurface box = dthex::testing::box_surface(Vec3(0, 0, 0), scale * Vec3(2, 1, 1), {8, 4, 4});
    dthex::write_surface(box, (dir / "box.off").string());
    const auto run = dthex_test::run_om_dthex("-q " + (dir / "box.off").string() + " -o " +
                                                  (dir / "box.inp").string(), dir);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const InpSets sets = read_inp(dir / "box.inp");
    const std::string fixed = patch_at_x(sets, 0.0, scale), loaded = patch_at_x(sets, 2.0 * scale, scale);
    ASSERT_FALSE(fixed.empty());
    ASSERT_FALSE(loaded.empty());
    ASSERT_NE(std::find(sets.surfaces.begin(), sets.surfaces.end(), loaded), sets.surfaces.end());
    const double pressure = 2.5;
    std::ofstream(dir / "deck.inp") << "*HEADING\nbox under pressure\n"
                                       "*INCLUDE, INPUT=box.inp\n"
                                       "*MATERIAL, NAME=BONE\n*ELASTIC\n17000., 0.3\n"
                                       "*SOLID SECTION, ELSET=SOLID, MATERIAL=BONE\n"
                                       "*STEP\n*STATIC\n*BOUNDARY\n"
                                    << fixed << ", 1, 3, 0.\n*DLOAD\n"
                                    << loaded << ", P, " << pressure << "\n"
                                    << "*NODE PRINT, NSET=" << fixed << ", TOTALS=ONLY\nRF\n*END STEP\n";
    const auto solve = dthex_test::run_command("cd " + dthex_test::shell_quote(dir.string()) +
                                               " && timeout 120 ccx -i deck 2>&1");
    ASSERT_EQ(solve.exit_code, 0) << solve.output;
    std::string lower = solve.output;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    EXPECT_EQ(lower.find("error"), std::string::npos) << solve.output;
    EXPECT_EQ(lower.find("warning"), std::string::npos) << solve.output;
    // deck.dat: "total force (fx,fy,fz) for set PATCHn ..." then a line of three numbers.
    std::ifstream dat(dir / "deck.dat");
    std::string line;
    bool found = false;
    double f[3] = {0, 0, 0};
    while (std::getline(dat, line))
      if (line.find("total force") != std::string::npos) {
        std::getline(dat, line);
        if (line.find_first_not_of(' ') == std::string::npos) std::getline(dat, line);
        std::stringstream(line) >> f[0] >> f[1] >> f[2];
        found = true;
      }
    ASSERT_TRUE(found) << "no total force in deck.dat";
    const double expected = pressure * scale * scale;  // the end face is scale x scale
    EXPECT_NEAR(f[0], expected, 1e-6 * expected);
    EXPECT_NEAR(f[1], 0.0, 1e-9 * expected);
    EXPECT_NEAR(f[2], 0.0, 1e-9 * expected);
  }
}
