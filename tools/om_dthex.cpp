// SPDX-License-Identifier: MIT
// om_dthex: closed triangle surface in, all-hexahedral mesh out (DTHex).
// Exit codes: 0 success; 2 bad input or usage, or an output that cannot be written
// (missing or unwritable folder, a directory, disk full, file-size limit); 3 meshing
// failed; 1 internal error; 128 + N when stopped by signal N (130 for Ctrl-C).
#include <dthex/hexes/mesh_sets.h>
#include <dthex/io/atomic_file.h>
#include <dthex/io/read_surface.h>
#include <dthex/io/write_hex_mesh.h>
#include <dthex/io/write_surface.h>
#include <dthex/pipeline/pipeline.h>
#include <dthex/report/report.h>
#include <dthex/report/report_html.h>

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <memory>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

size_t sets_hexes(const dthex::MeshSets& sets) {
  size_t n = 0;
  for (const auto& p : sets.parts) n += p.hexes.size();
  return n;
}

//! The named sets the output file carries (in formats that have sets), one line each kind, with
//! each part's worst hex (`quality` of the mesh the sets are of).
std::string sets_summary(const dthex::MeshSets& sets, const dthex::HexQuality& quality) {
  std::string parts, patches;
  for (const auto& p : sets.parts) {
    double worst = 1;
    for (int h : p.hexes) worst = std::min(worst, quality.scaled_jacobian[size_t(h)]);
    char figure[64];
    std::snprintf(figure, sizeof figure, ", min SJ %.3f", worst);
    parts += " " + p.name + " (" + std::to_string(p.hexes.size()) + " hexes" +
             (quality.scaled_jacobian.size() == sets_hexes(sets) ? figure : "") + ")";
  }
  size_t patch_count = 0;
  for (const auto& s : sets.surfaces)
    if (s.name.rfind("patch", 0) == 0 && ++patch_count <= 6) {
      char area[64];
      std::snprintf(area, sizeof area, "%.4g", s.area);
      patches += " " + s.name + " (" + std::to_string(s.faces.size()) + " faces, area " + area + ")";
    }
  if (patch_count > 6) patches += " ...";
  std::string user;
  for (const auto& s : sets.surfaces)
    if (s.name.rfind("patch", 0) != 0 && s.name.find("_boundary") == std::string::npos &&
        s.name.find("_interface") == std::string::npos)
      user += "\n  set " + s.name + ": " + std::to_string(s.faces.size()) + " faces";
  std::string interfaces;
  for (const auto& s : sets.surfaces)
    if (s.name.find("_interface") != std::string::npos)
      interfaces += "\n  interface " + s.name + ": " + std::to_string(s.faces.size()) + " faces";
  return "  parts: " + std::to_string(sets.parts.size()) + parts + interfaces +
         "\n  boundary patches at planar regions and creases: " + std::to_string(patch_count) + patches + user + "\n";
}


constexpr int kExitOk = 0, kExitInternal = 1, kExitInput = 2, kExitMeshing = 3;

struct CommandLine {
  std::string input, output, report, coarse_surface;
  dthex::PipelineOptions pipeline;
  bool quiet = false, verbose = false, verify_only = false, compare_thex = false;
  std::vector<std::string> set_texts;         //!< --set, as given
  std::vector<dthex::UserSetSpec> user_sets;  //!< --set, parsed
  dthex::HexWriteOptions write;               //!< --msh-version
};

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// Fails early, before any meshing, when an output could never be written.
void check_writable(const std::string& option, const std::string& path) { dthex::check_output_path(option, path); }

void validate(CommandLine& cl) {
  if (cl.output.empty()) {
    const fs::path in(cl.input);
    cl.output = (in.parent_path() / (in.stem().string() + "_hex.vtu")).string();
  }
  try {
    dthex::hex_format_from_path(cl.output);
  } catch (const dthex::InputError& e) {
    throw dthex::InputError(std::string("-o/--output: ") + e.what());
  }
  check_writable("-o/--output", cl.output);
  for (const std::string& text : cl.set_texts) cl.user_sets.push_back(dthex::parse_user_set(text));
  if (!cl.report.empty()) {
    const std::string ext = lower_extension(cl.report);
    if (ext != ".json" && ext != ".html")
      throw dthex::InputError("--report '" + cl.report + "': unsupported extension '" + ext + "' (use .json or .html)");
    check_writable("--report", cl.report);
  }
  if (!cl.coarse_surface.empty()) {
    const std::string ext = lower_extension(cl.coarse_surface);
    if (ext != ".off" && ext != ".obj" && ext != ".stl" && ext != ".ply")
      throw dthex::InputError("--coarse-surface '" + cl.coarse_surface + "': unsupported extension '" + ext +
                              "' (use .off, .obj, .stl or .ply)");
    check_writable("--coarse-surface", cl.coarse_surface);
    std::error_code ec;
    if (fs::equivalent(cl.input, cl.coarse_surface, ec))
      throw dthex::InputError("--coarse-surface '" + cl.coarse_surface + "' is the input file; it would be overwritten");
  }
}

void write_text(const std::string& path, const std::string& text) {
  dthex::write_atomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary);
    out << text;
    out.flush();
    if (!out) throw std::runtime_error("cannot write '" + path + "' (disk full?)");
  });
}

int run(CommandLine& cl) {
  validate(cl);
  dthex::install_interrupt_cleanup();
  dthex::Progress progress(dthex::Progress::mode_for(stderr, cl.quiet));
  progress.set_every_stage(cl.verbose);

  if (cl.verify_only) {
    const dthex::PipelineResult r = dthex::read_and_verify(cl.input, progress, nullptr, cl.pipeline);
    if (!cl.quiet) {
      std::fputs(dthex::describe(r.repairs).c_str(), stdout);
      const auto& s = r.input_summary;
      std::printf("%s: valid closed surface: %zu vertices, %zu triangles, %zu component(s), %zu cavit%s, genus %d\n"
                  "  volume %.6g, bbox diagonal %.6g%s\n"
                  "  triangle shape avg %.4f std %.4f min %.4f max %.4f\n",
                  cl.input.c_str(), s.vertices, s.triangles, s.components, s.cavities, s.cavities == 1 ? "y" : "ies",
                  s.genus, s.volume, s.bbox_diagonal, s.flipped_components ? " (orientation flipped to outward)" : "",
                  s.shape.avg, s.shape.std_dev, s.shape.min, s.shape.max);
    }
    return kExitOk;
  }

  dthex::PipelineResult result = dthex::run_pipeline(cl.input, cl.pipeline, progress);
  // --compare-thex: the classic THex of the same input, for the report's side-by-side view.
  std::unique_ptr<dthex::PipelineResult> baseline;
  dthex::PipelineOptions baseline_options = cl.pipeline;
  baseline_options.thex_only = true;
  baseline_options.target_nodes = 0;
  baseline_options.strict = false;
  if (cl.compare_thex && !cl.pipeline.thex_only) {
    progress.message("THex baseline (--compare-thex)");
    try {
      baseline = std::make_unique<dthex::PipelineResult>(dthex::run_pipeline(cl.input, baseline_options, progress));
    } catch (const dthex::MeshingError& e) {
      // The DTHex result stands on its own: a baseline that fails (TetGen's time limit on a
      // large input) leaves it out of the report rather than failing the run.
      std::fprintf(stderr, "om_dthex: warning: THex baseline failed, left out of the report: %s\n", e.what());
    }
  }

  progress.begin("write");
  dthex::HexFields fields{result.quality.shape, result.quality.scaled_jacobian};
  dthex::AtomicWriteGroup outputs;  // all outputs appear together, or none does
  // An empty user set is an error here, before any file is written.
  const dthex::MeshSets sets = dthex::find_result_sets(result, cl.input, cl.user_sets);
  dthex::write_hex_mesh(result.hexes, cl.output, fields, &sets, cl.write);
  if (!cl.coarse_surface.empty()) dthex::write_surface(result.coarse, cl.coarse_surface);
  if (!cl.report.empty()) {
    const bool html = lower_extension(cl.report) == ".html";
    write_text(cl.report, html ? dthex::report_html(result, cl.pipeline, baseline.get())
                               : dthex::report_json(result, cl.pipeline, baseline.get()));
  }
  outputs.commit();
  progress.end(cl.output);

  if (!cl.quiet) {
    std::fputs(dthex::summary_table(result, cl.pipeline).c_str(), stdout);
    if (baseline) std::fputs(("\n" + dthex::summary_table(*baseline, baseline_options)).c_str(), stdout);
    std::fputs(sets_summary(sets, result.quality).c_str(), stdout);
    std::printf("  wrote %s\n", cl.output.c_str());
  }
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CommandLine cl;
  CLI::App app{
      "om_dthex: turns a closed triangle surface (OFF, OBJ, STL, PLY) into an all-hexahedral mesh by DTHex:\n"
      "coarsen by curvature, tet-mesh (TetGen), THex, dice, put the boundary back on the input surface,\n"
      "untangle. Exit codes: 0 success, 2 bad input or usage or an unwritable output (also a full disk),\n"
      "3 meshing failed, 1 internal error, 130 interrupted.",
      "om_dthex"};
  app.add_option("INPUT", cl.input, "closed triangle surface: .off .obj .stl (ASCII or binary) .ply")->required();
  app.add_option("-o,--output", cl.output,
                 "hex mesh to write; the extension picks the format: .vtu (ParaView), .vtk (legacy), .msh (Gmsh 4.1),\n"
                 ".inp (Abaqus), .feb (FEBio 4), .exo (Exodus II). Default: INPUT-stem_hex.vtu beside the input");
  app.add_option("--eps", cl.pipeline.eps,
                 "coarsening factor eps in (0,1): allowed sagitta / curvature radius; target edge\n"
                 "h = 2 sqrt(eps (2 - eps)) * radius. Larger = coarser. If the coarsening fails there (it still\n"
                 "self-intersects after its repairs), it is tried at 0.7 x eps, up to 4 times, and the summary says so")
      ->default_val(0.1)
      ->check(CLI::Range(1e-6, 0.999999).description("in (0, 1)"));
  CLI::Option* dice_option =
      app.add_option("--dice", cl.pipeline.dice,
                     "split every THex hex into N^3 hexes (with --target-nodes and no --dice: chosen, 2 if it can\n"
                     "reach the budget)")
      ->default_val(2)
      ->check(CLI::Range(1, 8));
  app.add_option("--hmin", cl.pipeline.h_min,
                 "smallest target edge length, in input units: a floor under the curvature size so that scan noise\n"
                 "does not keep tiny triangles (0 = automatic: the input's mean edge length)")
      ->default_val(0.0)
      ->check(CLI::NonNegativeNumber);
  app.add_option("--hmax", cl.pipeline.h_max,
                 "largest coarse edge length, in input units (0 = automatic: half the bounding-box diagonal; flat regions are bounded by their outline)")
      ->default_val(0.0)
      ->check(CLI::NonNegativeNumber);
  std::string thickness_ratio = "auto";
  app.add_option("--thickness-ratio", thickness_ratio,
                 "largest target edge length in wall thicknesses, for thin-walled inputs (a pelvis wing, a skull vault):\n"
                 "where a wall is thinner than the curvature size, the size follows the thickness. 0 = curvature alone,\n"
                 "as the paper; 1 is a good value. auto (default): 1 from the start where 2.5% or more of the input\n"
                 "lies on walls 2x thinner than their curvature size (a membrane, a quarter on walls 4x thinner: 1.25,\n"
                 "dice 1 unless --dice is given, no edge shorter than the wall); else curvature alone, and when that\n"
                 "leaves poor hexes (inverted, or scaled Jacobian < 0.2) with 5% or more of the input on walls thinner\n"
                 "than their size, mesh again at 1 and keep the better mesh (conforming, fewer inverted, higher min\n"
                 "scaled Jacobian); auto neither predicts nor retries with --target-nodes")
      ->default_val("auto")
      ->check(CLI::Validator(
          [](std::string& value) -> std::string {
            if (value == "auto") return "";
            char* end = nullptr;
            const double ratio = std::strtod(value.c_str(), &end);
            if (end == value.c_str() || *end != '\0' || !(ratio >= 0) || !std::isfinite(ratio))
              return "must be auto or a number >= 0, not " + value;
            return "";
          },
          "auto|NUMBER>=0"));
  app.add_option("--max-edge-ratio", cl.pipeline.max_edge_ratio,
                 "a collapse is refused if it makes an edge longer than this times the local size (normalized length)")
      ->capture_default_str()  // sqrt 2 exactly: default_val would round it to the 6 digits it prints
      ->check(CLI::Range(1.0, 4.0));
  app.add_option("--knife-edge-slide", cl.pipeline.knife_edge_slide,
                 "how far the nodes of a knife edge (a convex edge of the surface under 30 degrees, e.g. where a cut\n"
                 "plane meets a bone at a grazing angle) may slide off it, as a fraction of the bounding-box diagonal:\n"
                 "the hexes in such a wedge are thin, and rounding it off a little lifts them. 0 keeps knife edges sharp")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.05));
  app.add_option("--boundary-slack", cl.pipeline.boundary_slack,
                 "where the worst hexes cannot be raised further with the boundary on the input, their boundary\n"
                 "nodes where the input curves (off planes, edges and corners) may end this fraction of their hex edge\n"
                 "off it, and at most 0.2% of the bounding-box diagonal: a little distance to the input for sounder\n"
                 "hexes (Spot's worst 0.346 -> 0.400). 0 keeps every boundary node on the input surface")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.5));
  app.add_option("--min-dihedral", cl.pipeline.min_dihedral_deg,
                 "smallest dihedral angle of the coarse tets, in degrees (0 = none): TetGen adds points inside to\n"
                 "remove slivers and the smoothing raises hexes towards scaled Jacobian 0.4, then up to 0.5, instead of\n"
                 "0.3 and 0.4. 18 lifts the liver's worst hex from 0.37 to 0.43 for 5% more nodes (10-40% on other\n"
                 "meshes); above 20 TetGen may not finish")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 20.0));
  std::string repair = "safe";
  app.add_option("--repair", repair,
                 "safe (default): before verification, repair what cannot change the shape and say so in the summary\n"
                 "and the report: coincident vertices merged (every format), collapsed and duplicate triangles removed\n"
                 "where the surface stays closed and manifold, triangles wound against their neighbours turned (per\n"
                 "component, the minority), zero-area slivers flipped away with their neighbour. none: refuse every\n"
                 "defect as found, ids as in the file")
      ->default_val("safe")
      ->check(CLI::IsMember({"safe", "none"}));
  std::string min_island = "0";
  app.add_option("--min-island", min_island,
                 "with --repair safe, also drop islands (parts joined through shared vertices), such as a segmentation's\n"
                 "noise voxels: N = of fewer than N triangles; F% = closed ones enclosing less than F percent of the\n"
                 "largest part's volume (e.g. 0.1%), whatever their triangle count. The largest part is always kept.\n"
                 "0 (default): none")
      ->default_val("0")
      ->check(CLI::Validator(
          [](std::string& value) -> std::string {
            char* end = nullptr;
            const bool percent = !value.empty() && value.back() == '%';
            const std::string number = percent ? value.substr(0, value.size() - 1) : value;
            if (!percent) {
              const long long count = std::strtoll(number.c_str(), &end, 10);
              if (end == number.c_str() || *end != '\0' || count < 0)
                return "must be a triangle count N >= 0 or a volume percentage such as 0.1%, not " + value;
              return "";
            }
            const double fraction = std::strtod(number.c_str(), &end);
            if (end == number.c_str() || *end != '\0' || !(fraction > 0 && fraction < 100))
              return "a volume percentage must be in (0%, 100%), not " + value;
            return "";
          },
          "N|F%"));
  std::string nested = "cavity";
  app.add_option("--nested", nested,
                 "a closed surface inside another: cavity (default) leaves its inside empty; material meshes it as a\n"
                 "second region, conforming with the outer one (shared interface nodes on the inner surface): a\n"
                 "cortical shell and its trabecular core, a tumour in an organ. Each region is a part of its own, and\n"
                 "the faces between two are a set bodyM_bodyN_interface")
      ->default_val("cavity")
      ->check(CLI::IsMember({"cavity", "material"}));
  std::string remesh = "auto";
  app.add_option("--remesh", remesh,
                 "remesh the input with even triangles before coarsening (split, collapse, flip, relax; feature lines\n"
                 "kept): CAD exports are made of long needles, which the coarsening cannot undo and which become sliver\n"
                 "tets. auto (default): when 0.5% or more of the triangles are needles (longest edge squared over twice\n"
                 "the area above 10); on: always; off: never")
      ->default_val("auto")
      ->check(CLI::IsMember({"auto", "on", "off"}));
  app.add_option("--target-nodes", cl.pipeline.target_nodes,
                 "choose eps so the hex mesh has about N nodes (within 10%); overrides --eps. Without --dice the\n"
                 "dicing is chosen too: 2 when some eps reaches N with it (better boundary fit), else the nearest\n"
                 "that does (1 for a small budget, 3, 4, ... for a large one); an eps whose coarsening fails is\n"
                 "taken as too coarse")
      ->check(CLI::PositiveNumber);
  app.add_flag("--thex-only", cl.pipeline.thex_only,
               "classic THex of the input (tet-mesh, 4 hexes per tet): no coarsening, dicing or projection; the baseline");
  app.add_flag("--no-project", [&](std::int64_t) { cl.pipeline.project = false; },
               "keep the coarse geometry: no projection onto the input surface, no untangling");
  app.add_flag("--no-finer-retry", [&](std::int64_t) { cl.pipeline.finer_retry = false; },
               "keep an unsound mesh (an inverted hex, or the boundary folded into the mesh) as it is; by default it\n"
               "is meshed again at 0.7 x eps, up to twice, and the better mesh kept (not with --target-nodes)");
  app.add_flag("--strict", cl.pipeline.strict, "exit 3 and write nothing if any inverted hex remains (at a corner or a 2x2x2 Gauss point) or the\nboundary folds into the mesh");
  app.add_flag("--global-smoothing", cl.pipeline.global_smoothing,
               "also smooth the coarse surface globally (area-weighted centroid pull), as the paper compares");
  app.add_flag("--judge-after-smoothing,!--judge-in-place", cl.pipeline.judge_after_smoothing,
               "(default) judge a coarsening collapse's edge, normal and shape bounds where the local smoothing that "
               "follows puts the kept vertex: coarser surfaces that reach the sizes (the paper's sphere at eps 0.1: 14 "
               "vertices, not 20). --judge-in-place judges them with the kept vertex in place, as the paper prints it");
  app.add_option("--tetgen", cl.pipeline.tetgen_switches,
                 "TetGen switches (Y keeps the surface; q radius-edge ratio bound[/min dihedral]; a volume bound). Default:\n"
                 "pq1.5Y (pq1.5/DEG Y with --min-dihedral) for DTHex's coarse surface, pq1.2Y for --thex-only and --compare-thex's baseline (the paper's THex)");
  app.add_option("--time-limit", cl.pipeline.time_limit_seconds,
                 "seconds allowed for TetGen (exceeded: exit 3) and for the untangling optimizer (it stops there and\nreports what it reached; with --strict a remaining inverted hex is exit 3)")
      ->default_val(600.0)
      ->check(CLI::PositiveNumber);
  app.add_option("--set", cl.set_texts,
                 "name a set of boundary faces and nodes, written where the format has sets (.inp .msh .feb .exo):\n"
                 "NAME=box:X0,Y0,Z0,X1,Y1,Z1 (faces with every corner in the box) or\n"
                 "NAME=plane:PX,PY,PZ,NX,NY,NZ,DISTANCE (every corner within DISTANCE of the plane\n"
                 "through P with normal N); repeatable; a set that selects no face is an error");
  app.add_option_function<std::string>(
         "--msh-version",
         [&](const std::string& v) {
           cl.write.msh_version =
               v == "2.2" ? dthex::HexWriteOptions::MshVersion::V22 : dthex::HexWriteOptions::MshVersion::V41;
         },
         "version of a .msh output: 4.1 (default) or 2.2 (ASCII, for readers that take only that, as code_aster)")
      ->check(CLI::IsMember({"4.1", "2.2"}));
  app.add_option("--report", cl.report,
                 "write a report; the extension picks it: .json (statistics, histograms, timings, options) or .html\n"
                 "(one self-contained page: stage table, quality histograms, 3D view coloured by quality)");
  app.add_flag("--compare-thex", cl.compare_thex,
               "also run the classic THex of the input (as --thex-only) and put it beside the result in the\n"
               "summary and the report");
  app.add_option("--coarse-surface", cl.coarse_surface, "also write the coarse surface (.off .obj .stl .ply)");
  app.add_flag("--verify-only", cl.verify_only, "only read and verify the input, print its statistics");
  app.add_flag("-q,--quiet", cl.quiet, "no progress and no summary; errors still go to stderr");
  app.add_flag("-v,--verbose", cl.verbose, "print every stage as it ends, not only those over a second");
  app.set_version_flag("--version", std::string("om_dthex ") + DTHEX_VERSION);

  try {
    app.parse(argc, argv);
    cl.pipeline.choose_dice = dice_option->count() == 0;
    cl.pipeline.thickness_retry = thickness_ratio == "auto";
    cl.pipeline.thickness_ratio = cl.pipeline.thickness_retry ? 0.0 : std::stod(thickness_ratio);
    cl.pipeline.repair = repair == "none" ? dthex::PipelineOptions::Repair::none : dthex::PipelineOptions::Repair::safe;
    if (!min_island.empty() && min_island.back() == '%')
      cl.pipeline.min_island_volume_fraction = std::strtod(min_island.substr(0, min_island.size() - 1).c_str(), nullptr) / 100.0;
    else
      cl.pipeline.min_island_triangles = size_t(std::strtoull(min_island.c_str(), nullptr, 10));
    if (cl.pipeline.repair == dthex::PipelineOptions::Repair::none &&
        (cl.pipeline.min_island_triangles > 0 || cl.pipeline.min_island_volume_fraction > 0))
      throw CLI::ValidationError("--min-island", "drops triangles, a repair: it needs --repair safe, not none");
    if (cl.pipeline.h_min > 0 && cl.pipeline.h_max > 0 && cl.pipeline.h_min > cl.pipeline.h_max) {
      std::ostringstream why;
      why << cl.pipeline.h_min << " is larger than --hmax " << cl.pipeline.h_max
          << ": the smallest coarse edge cannot be longer than the largest; lower --hmin or raise --hmax";
      throw CLI::ValidationError("--hmin", why.str());
    }
    if (cl.pipeline.thex_only) {
      std::string ignored;
      for (const char* name : {"--eps", "--dice", "--target-nodes", "--hmin", "--hmax", "--thickness-ratio",
                               "--max-edge-ratio", "--min-dihedral", "--knife-edge-slide", "--boundary-slack",
                               "--no-project", "--no-finer-retry", "--global-smoothing", "--remesh"})
        if (app.get_option(name)->count() > 0) ignored += std::string(ignored.empty() ? "" : ", ") + name;
      if (!ignored.empty())
        std::fprintf(stderr, "om_dthex: warning: --thex-only tet-meshes the input as it is, so %s %s no effect\n",
                     ignored.c_str(), ignored.find(',') == std::string::npos ? "has" : "have");
    }
    cl.pipeline.nested =
        nested == "material" ? dthex::PipelineOptions::Nested::material : dthex::PipelineOptions::Nested::cavity;
    cl.pipeline.remesh = remesh == "on"    ? dthex::PipelineOptions::Remesh::always
                         : remesh == "off" ? dthex::PipelineOptions::Remesh::never
                                           : dthex::PipelineOptions::Remesh::automatic;
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "om_dthex: %s (see om_dthex --help)\n", e.what());
    return kExitInput;
  }

  try {
    return run(cl);
  } catch (const dthex::InputError& e) {
    std::fprintf(stderr, "om_dthex: error: %s\n", e.what());
    return kExitInput;
  } catch (const dthex::MeshingError& e) {
    std::fprintf(stderr, "om_dthex: meshing failed: %s: %s\n", cl.input.c_str(), e.what());
    return kExitMeshing;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "om_dthex: error: %s: out of memory\n", cl.input.c_str());
    dthex::remove_pending_temporaries();
    return kExitMeshing;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "om_dthex: internal error on %s: %s\n", cl.input.c_str(), e.what());
    dthex::remove_pending_temporaries();
    return kExitInternal;
  }
}
