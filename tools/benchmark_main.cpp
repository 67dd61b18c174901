// SPDX-License-Identifier: MIT
// benchmark: THex and DTHex side by side over a set of surfaces, the paper-style table
// (nodes, hexes, shape avg/std/min/max, min scaled Jacobian, inverted, Hausdorff, volume
// error, seconds and peak memory per stage), printed, as CSV (--csv) and as Markdown
// (--markdown) for the README. Every run is a forked child with a timeout, so one mesh
// that hangs or crashes costs its row only, and its peak memory is its own (wait4). The
// child samples its own resident set while it runs, for the peak of each stage.
//
//   build/benchmark                      every surface in meshes/
//   build/benchmark --only femur --csv femur.csv
//   build/benchmark --subdivide 2 meshes/femur_proximal_ct.off   (Loop-subdivided twice: 16x triangles)
#include <dthex/hexes/mesh_sets.h>
#include <dthex/io/read_surface.h>
#include <dthex/io/write_hex_mesh.h>
#include <dthex/io/write_surface.h>
#include <dthex/mesh/surface_mesh.h>
#include <dthex/pipeline/pipeline.h>
#include <dthex/report/report.h>

#include <CLI/CLI.hpp>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#include <nlohmann/json.hpp>

#include <poll.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

namespace fs = std::filesystem;

namespace {

// The columns of seconds and peak memory, in the pipeline's order, and the stages each one
// sums (a stage run twice, as in a retry sized by thickness, counts twice). A stage listed
// nowhere (a future one) lands in "other". "write" is the harness's own: the mesh written as
// om_dthex writes it (.vtu, with its parts and boundary patches) to a temporary file.
struct StageColumn {
  std::string name;
  std::vector<std::string> stages;
};
const std::vector<StageColumn> kColumns = {
    {"read", {"read"}},
    {"verify", {"verify"}},
    {"remesh", {"remesh input"}},
    {"choose eps", {"choose eps"}},
    {"thin walls", {"predict thin walls", "thin walls"}},
    {"coarsen", {"coarsen"}},
    {"verify coarse", {"verify coarse"}},
    {"tetrahedralize", {"tetrahedralize"}},
    {"tet edits",
     {"flip boundary edges", "flip 3-2", "merge inner points", "split surface tets", "flip worst tets",
      "relax inner points", "thin boundary stars", "split crowded vertices"}},
    {"thex", {"thex"}},
    {"dice", {"dice"}},
    {"project", {"project"}},
    {"untangle", {"untangle"}},
    {"smooth", {"smooth worst", "lift worst", "slide on creases", "repair worst"}},
    {"regions", {"optimize worst regions"}},
    {"repair folds", {"repair folds"}},
    {"measure", {"measure"}},
    {"write", {"write"}}};

// The column a stage's seconds go to.
std::string column_of(const std::string& stage) {
  for (const StageColumn& c : kColumns)
    if (std::find(c.stages.begin(), c.stages.end(), stage) != c.stages.end()) return c.name;
  return "other";
}

// The column names, "other" last.
std::vector<std::string> column_names() {
  std::vector<std::string> names;
  for (const StageColumn& c : kColumns) names.push_back(c.name);
  names.push_back("other");
  return names;
}

struct Row {
  std::string mesh, method, status = "ok", message;
  size_t input_triangles = 0, coarse_triangles = 0, tets = 0, nodes = 0, hexes = 0, inverted = 0;
  bool conforming = false;
  size_t boundary_faces_inside = 0;  //!< the boundary folded into the mesh (geometric conformity)
  double shape_avg = 0, shape_std = 0, shape_min = 0, shape_max = 0, sj_min = 0;
  double hausdorff_percent = 0, volume_error_percent = 0;
  std::map<std::string, double> stage_seconds;
  std::map<std::string, double> stage_peak_mb;  //!< largest resident set seen during the stage
  double total_seconds = 0, peak_mb = 0, wall_seconds = 0;
};

std::string column_name(const std::string& stage, const std::string& prefix = "t_") {
  std::string name = prefix + stage;
  std::replace(name.begin(), name.end(), ' ', '_');
  return name;
}

// Fills a row from the JSON report the child wrote (the same one --report writes).
void read_report(const nlohmann::json& j, Row& row) {
  row.input_triangles = j["input"]["surface"]["triangles"];
  row.coarse_triangles = j.contains("coarse") ? j["coarse"]["triangles"].get<size_t>() : row.input_triangles;
  row.tets = j["tets"]["count"];
  const auto& hex = j["hex"];
  row.nodes = hex["nodes"];
  row.hexes = hex["hexes"];
  row.inverted = hex["inverted"];
  row.conforming = hex["conforming"];
  row.boundary_faces_inside = hex["boundary_faces_inside"];
  row.shape_avg = hex["shape"]["avg"];
  row.shape_std = hex["shape"]["std"];
  row.shape_min = hex["shape"]["min"];
  row.shape_max = hex["shape"]["max"];
  row.sj_min = hex["scaled_jacobian"]["min"];
  row.hausdorff_percent = 100.0 * j["distance"]["hausdorff_relative"].get<double>();
  const double input_volume = j["input"]["surface"]["volume"];
  row.volume_error_percent =
      input_volume != 0 ? 100.0 * (hex["volume"].get<double>() - input_volume) / input_volume : 0.0;
  const nlohmann::json& stages = j["stages"];
  const nlohmann::json peaks = j.value("stage_peak_mb", nlohmann::json::array());
  for (size_t i = 0; i < stages.size(); ++i) {
    const std::string column = column_of(stages[i]["name"]);
    row.stage_seconds[column] += stages[i]["seconds"].get<double>();
    if (i < peaks.size()) row.stage_peak_mb[column] = std::max(row.stage_peak_mb[column], peaks[i].get<double>());
  }
  row.total_seconds = j["total_seconds"];
}

// The resident set of this process, sampled every few milliseconds from a thread while it
// lives, and the time spans of the pipeline's stages, read from what its progress display
// writes when a stage begins and ends: the samples within a stage's span give its peak
// (memory held from earlier stages included, as it is in the process's peak).
class StageMemory {
 public:
  StageMemory()
      : start_(std::chrono::steady_clock::now()),
        stream_(::fopencookie(this, "w", cookie_io_functions_t{nullptr, &StageMemory::written, nullptr, nullptr})),
        thread_([this] { sample(); }) {}
  ~StageMemory() {
    stop();
    if (stream_) std::fclose(stream_);
  }
  StageMemory(const StageMemory&) = delete;
  StageMemory& operator=(const StageMemory&) = delete;

  //! Where a Progress in Live mode (set_every_stage) writes; nullptr if it could not be made.
  std::FILE* stream() const { return stream_; }
  void stop() {
    if (done_) return;
    done_ = true;
    if (thread_.joinable()) thread_.join();
    // One more sample, now: a stage that began after the thread's last one (a short last stage,
    // or the thread held off its core on a busy machine) has it as its peak, not none.
    samples_.emplace_back(now(), resident_mb());
  }
  //! Per stage name in `names`, in order, the peak resident MB of the next span of that name
  //! (0 when there is none: a stage whose record was dropped, e.g. a failed coarsening, still
  //! has its span, which is then skipped).
  std::vector<double> peaks_mb(const std::vector<std::string>& names) const {
    std::vector<double> peaks;
    size_t next = 0;
    for (const std::string& name : names) {
      size_t k = next;
      while (k < spans_.size() && spans_[k].name != name) ++k;
      if (k == spans_.size()) {
        peaks.push_back(0);
        continue;
      }
      next = k + 1;
      // A span shorter than the sampling step gets the first sample after it began.
      double peak = 0;
      for (const auto& [t, mb] : samples_)
        if (t >= spans_[k].begin && (t <= spans_[k].end || peak == 0)) peak = std::max(peak, mb);
        else if (t > spans_[k].end) break;
      peaks.push_back(peak);
    }
    return peaks;
  }

 private:
  struct Span {
    std::string name;
    double begin = 0, end = 0;
  };
  double now() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  // Live mode writes "\r  NAME ..." when a stage begins (then flushes) and "\r\033[K..."
  // when it ends; progress bars in between are ignored.
  static ssize_t written(void* cookie, const char* data, size_t size) {
    auto* self = static_cast<StageMemory*>(cookie);
    const std::string text(data, size);
    const double t = self->now();
    if (text.find("\033[K") != std::string::npos && !self->spans_.empty() && self->spans_.back().end == 0)
      self->spans_.back().end = t;
    const size_t dots = text.rfind(" ...");
    if (text.rfind("\r  ", 0) == 0 && dots != std::string::npos && dots + 4 == text.size()) {
      std::string name = text.substr(3, dots - 3);
      while (!name.empty() && name.back() == ' ') name.pop_back();
      self->spans_.push_back({name, t, 0});
    }
    return ssize_t(size);
  }
  static double resident_mb() {
    unsigned long long size = 0, resident = 0;
    if (std::FILE* statm = std::fopen("/proc/self/statm", "r")) {
      if (std::fscanf(statm, "%llu %llu", &size, &resident) != 2) resident = 0;
      std::fclose(statm);
    }
    return double(resident) * double(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
  }
  void sample() {
    std::vector<std::pair<double, double>> samples;
    while (!done_) {
      samples.emplace_back(now(), resident_mb());
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    samples_ = std::move(samples);  // read only after stop()
  }

  std::chrono::steady_clock::time_point start_;
  std::FILE* stream_;
  std::vector<Span> spans_;
  std::atomic<bool> done_{false};
  std::vector<std::pair<double, double>> samples_;  // seconds, MB
  std::thread thread_;  // last: starts once the members above exist
};

// Where the child `pid` writes its mesh (write_as_om_dthex_does).
fs::path written_mesh_path(pid_t pid) {
  return fs::temp_directory_path() / ("om_dthex_benchmark_" + std::to_string(pid) + ".vtu");
}

// Writes the mesh as om_dthex does by default (.vtu with its parts and boundary patches,
// find_result_sets()) to a temporary file, then removes it;
// returns the seconds it took. A user waits for this too, after the pipeline's total.
double write_as_om_dthex_does(const dthex::PipelineResult& result, const std::string& input_path,
                              dthex::Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  progress.begin("write");
  const fs::path path = written_mesh_path(::getpid());
  const dthex::MeshSets sets = dthex::find_result_sets(result, input_path);
  const dthex::HexFields fields{result.quality.shape, result.quality.scaled_jacobian};
  dthex::write_hex_mesh(result.hexes, path.string(), fields, &sets);
  std::error_code ignored;
  fs::remove(path, ignored);
  progress.end("written");
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Runs the pipeline in a child; the child sends its JSON report through a pipe, with the
// peak resident set of each stage added ("stage_peak_mb", in the order of "stages").
Row run_one(const std::string& path, const std::string& mesh, const std::string& method,
            const dthex::PipelineOptions& options, double timeout_seconds) {
  Row row;
  row.mesh = mesh;
  row.method = method;
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error("pipe failed");
  std::fflush(nullptr);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    ::close(fds[0]);
    std::string text;
    int code = 0;
    try {
      StageMemory memory;
      dthex::Progress progress(memory.stream() ? dthex::Progress::Mode::Live : dthex::Progress::Mode::Quiet,
                               memory.stream());
      progress.set_every_stage(true);
      const dthex::PipelineResult result = dthex::run_pipeline(path, options, progress);
      const double write_seconds = write_as_om_dthex_does(result, path, progress);
      if (memory.stream()) std::fflush(memory.stream());
      memory.stop();
      nlohmann::json j = nlohmann::json::parse(dthex::report_json(result, options));
      j["stages"].push_back({{"name", "write"}, {"seconds", write_seconds}});
      std::vector<std::string> names;
      for (const auto& stage : result.stages) names.push_back(stage.name);
      names.push_back("write");
      if (memory.stream()) j["stage_peak_mb"] = memory.peaks_mb(names);
      text = j.dump();
    } catch (const std::exception& e) {
      text = nlohmann::json{{"error", e.what()}}.dump();
      code = 3;
    }
    for (size_t done = 0; done < text.size();) {
      const ssize_t n = ::write(fds[1], text.data() + done, text.size() - done);
      if (n <= 0) break;
      done += size_t(n);
    }
    ::close(fds[1]);
    ::_exit(code);
  }
  ::close(fds[1]);
  std::string text;
  bool timed_out = false;
  char buffer[65536];
  for (;;) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const int wait_ms = int(std::max(0.0, timeout_seconds - elapsed) * 1000);
    pollfd p{fds[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, wait_ms);
    if (ready == 0) {
      timed_out = true;
      ::kill(pid, SIGKILL);
      break;
    }
    if (ready < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n <= 0) break;  // EOF: the child is done
    text.append(buffer, size_t(n));
  }
  ::close(fds[0]);
  int status = 0;
  rusage usage{};
  ::wait4(pid, &status, 0, &usage);
  std::error_code ignored;
  fs::remove(written_mesh_path(pid), ignored);  // a child killed while writing leaves it
  row.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  row.peak_mb = double(usage.ru_maxrss) / 1024.0;  // Linux reports kilobytes
  if (timed_out) {
    row.status = "timeout";
    char text_limit[64];
    std::snprintf(text_limit, sizeof text_limit, "no result within %g s (killed)", timeout_seconds);
    row.message = text_limit;
    return row;
  }
  if (WIFSIGNALED(status)) {
    row.status = "crashed";
    row.message = std::string("signal ") + strsignal(WTERMSIG(status));
    return row;
  }
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    if (j.contains("error")) {
      row.status = "failed";
      row.message = j["error"];
    } else {
      read_report(j, row);
    }
  } catch (const std::exception& e) {
    row.status = "failed";
    row.message = std::string("unreadable result: ") + e.what();
  }
  return row;
}

// Loop subdivision (smooth, 4x triangles per level): large inputs of a real shape, made
// here so no big mesh is committed.
std::string subdivided_copy(const std::string& path, int levels, const fs::path& folder, std::string& name) {
  name = fs::path(path).stem().string() + "_loop" + std::to_string(levels);
  const fs::path out = folder / (name + ".off");
  if (fs::exists(out)) return out.string();
  dthex::SurfaceMesh mesh = dthex::to_openmesh(dthex::read_surface(path));
  OpenMesh::Subdivider::Uniform::LoopT<dthex::SurfaceMesh> loop;
  // LoopT's vertex weights are made for valences below 50 and read past their end above: of
  // the ear drum's two poles, 160 triangles each, one became a spike seven times the drum's
  // depth. Subdivision keeps the valence of old vertices and gives new ones 6.
  size_t most_triangles_at_a_vertex = 6;
  for (auto v : mesh.vertices()) most_triangles_at_a_vertex = std::max(most_triangles_at_a_vertex, size_t(mesh.valence(v)));
  loop.init_weights(most_triangles_at_a_vertex + 1);
  loop.attach(mesh);
  loop(mesh, size_t(levels));
  loop.detach();
  mesh.garbage_collection();
  fs::create_directories(folder);
  dthex::write_surface(dthex::from_openmesh(mesh), out.string());
  return out.string();
}

std::string fixed(double v, int precision) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", precision, v);
  return buffer;
}

std::vector<std::string> csv_header() {
  std::vector<std::string> h = {"mesh",      "method",    "status",   "input_triangles", "coarse_triangles",
                                "tets",      "nodes",     "hexes",    "shape_avg",       "shape_std",
                                "shape_min", "shape_max", "sj_min",   "inverted",        "conforming",
                                "boundary_faces_inside", "hausdorff_pct", "volume_error_pct"};
  for (const auto& s : column_names()) h.push_back(column_name(s));
  h.insert(h.end(), {"total_seconds", "peak_mb"});
  for (const auto& s : column_names()) h.push_back(column_name(s, "peak_mb_"));
  h.push_back("message");
  return h;
}

std::string csv_quote(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::vector<std::string> csv_fields(const Row& r) {
  auto num = [](double v) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.10g", v);
    return std::string(buffer);
  };
  std::vector<std::string> f = {r.mesh,
                                r.method,
                                r.status,
                                std::to_string(r.input_triangles),
                                std::to_string(r.coarse_triangles),
                                std::to_string(r.tets),
                                std::to_string(r.nodes),
                                std::to_string(r.hexes),
                                num(r.shape_avg),
                                num(r.shape_std),
                                num(r.shape_min),
                                num(r.shape_max),
                                num(r.sj_min),
                                std::to_string(r.inverted),
                                r.conforming ? "yes" : "no",
                                std::to_string(r.boundary_faces_inside),
                                num(r.hausdorff_percent),
                                num(r.volume_error_percent)};
  for (const auto& s : column_names()) {
    const auto it = r.stage_seconds.find(s);
    f.push_back(it == r.stage_seconds.end() ? "" : num(it->second));
  }
  f.push_back(num(r.total_seconds));
  f.push_back(num(r.peak_mb));
  for (const auto& s : column_names()) {
    const auto it = r.stage_peak_mb.find(s);
    f.push_back(it == r.stage_peak_mb.end() ? "" : num(it->second));
  }
  f.push_back(r.message);
  return f;
}

void write_csv(const std::vector<Row>& rows, const std::string& path) {
  std::ostringstream out;
  const auto header = csv_header();
  for (size_t i = 0; i < header.size(); ++i) out << (i ? "," : "") << header[i];
  out << "\n";
  for (const Row& r : rows) {
    const auto fields = csv_fields(r);
    for (size_t i = 0; i < fields.size(); ++i) out << (i ? "," : "") << csv_quote(fields[i]);
    out << "\n";
  }
  std::ofstream file(path, std::ios::binary);
  file << out.str();
  if (!file) throw std::runtime_error("cannot write " + path);
}

// "yes", or "NO" with the boundary faces lying inside the mesh when that is why.
std::string conforming_text(const Row& r) {
  if (r.conforming) return "yes";
  return r.boundary_faces_inside > 0 ? "NO (" + std::to_string(r.boundary_faces_inside) + " faces inside)" : "NO";
}

// One table of the headline columns and one of the seconds per stage, as aligned text or Markdown.
std::string tables(const std::vector<Row>& rows, bool markdown) {
  std::vector<std::vector<std::string>> quality = {{"mesh", "method", "triangles", "nodes", "hexes", "shape avg",
                                                    "shape std", "shape min", "shape max", "min SJ", "inverted",
                                                    "conforming", "Hausdorff %", "volume err %", "seconds", "peak MB"}};
  std::vector<std::vector<std::string>> timing = {{"mesh", "method"}}, memory = {{"mesh", "method"}};
  // The columns some row has, "write" apart: it comes after the pipeline's total, which
  // does not include it (the headline's seconds are that total).
  std::vector<std::string> stages_seen;
  bool written = false;
  for (const auto& s : column_names())
    for (const Row& r : rows)
      if (r.stage_seconds.count(s)) {
        if (s == "write")
          written = true;
        else
          stages_seen.push_back(s);
        break;
      }
  for (const auto& s : stages_seen) timing[0].push_back(s);
  timing[0].push_back("total");
  if (written) timing[0].push_back("then write");
  for (const auto& s : stages_seen) memory[0].push_back(s);
  if (written) memory[0].push_back("write");
  memory[0].push_back("whole run");
  for (const Row& r : rows) {
    if (r.status != "ok") {
      std::vector<std::string> line = {r.mesh, r.method, r.status + ": " + r.message};
      line.resize(quality[0].size() - 1);
      line.push_back(fixed(r.peak_mb, 0));
      quality.push_back(line);
      continue;
    }
    quality.push_back({r.mesh, r.method, std::to_string(r.input_triangles), std::to_string(r.nodes),
                       std::to_string(r.hexes), fixed(r.shape_avg, 3), fixed(r.shape_std, 3), fixed(r.shape_min, 3),
                       fixed(r.shape_max, 3), fixed(r.sj_min, 3), std::to_string(r.inverted),
                       conforming_text(r), fixed(r.hausdorff_percent, 3), fixed(r.volume_error_percent, 2), fixed(r.total_seconds, 2),
                       fixed(r.peak_mb, 0)});
    std::vector<std::string> line = {r.mesh, r.method};
    for (const auto& s : stages_seen) {
      const auto it = r.stage_seconds.find(s);
      line.push_back(it == r.stage_seconds.end() ? "-" : fixed(it->second, 2));
    }
    line.push_back(fixed(r.total_seconds, 2));
    const auto write_seconds = r.stage_seconds.find("write");
    if (written) line.push_back(write_seconds == r.stage_seconds.end() ? "-" : fixed(write_seconds->second, 2));
    timing.push_back(line);
    std::vector<std::string> peaks = {r.mesh, r.method};
    for (const auto& s : stages_seen) {
      const auto it = r.stage_peak_mb.find(s);
      peaks.push_back(it == r.stage_peak_mb.end() ? "-" : fixed(it->second, 0));
    }
    const auto write_peak = r.stage_peak_mb.find("write");
    if (written) peaks.push_back(write_peak == r.stage_peak_mb.end() ? "-" : fixed(write_peak->second, 0));
    peaks.push_back(fixed(r.peak_mb, 0));
    memory.push_back(peaks);
  }
  auto render = [&](const std::vector<std::vector<std::string>>& table) {
    std::vector<size_t> width(table[0].size(), 0);
    for (const auto& line : table)
      for (size_t c = 0; c < line.size() && c < width.size(); ++c)
        width[c] = std::max(width[c], line[c].size());
    std::ostringstream out;
    for (size_t l = 0; l < table.size(); ++l) {
      const auto& line = table[l];
      if (markdown) {
        out << "|";
        for (const auto& cell : line) out << " " << cell << " |";
        out << "\n";
        if (l == 0) {
          out << "|";
          for (size_t c = 0; c < line.size(); ++c) out << (c < 2 ? "---|" : "---:|");
          out << "\n";
        }
      } else {
        for (size_t c = 0; c < line.size(); ++c) {
          const bool left = c < 2;
          char cell[512];
          std::snprintf(cell, sizeof cell, left ? "%-*s  " : "%*s  ", int(width[c]), line[c].c_str());
          out << cell;
        }
        out << "\n";
      }
    }
    return out.str();
  };
  std::ostringstream out;
  out << render(quality) << "\n" << (markdown ? "Seconds per stage:\n\n" : "seconds per stage\n") << render(timing);
  // The largest resident set sampled while each stage ran (what earlier stages still hold
  // included); the last column is the run's own peak as the kernel counts it.
  out << "\n" << (markdown ? "Peak MB per stage:\n\n" : "peak MB per stage\n") << render(memory);
  // THex time / DTHex time per mesh: the speed-up the method is about.
  std::ostringstream ratios;
  for (const Row& d : rows) {
    if (d.method != "dthex" || d.status != "ok") continue;
    for (const Row& t : rows)
      if (t.mesh == d.mesh && t.method == "thex" && t.status == "ok" && d.total_seconds > 0)
        ratios << (markdown ? "- " : "  ") << d.mesh << ": THex seconds / DTHex seconds = "
               << fixed(t.total_seconds / d.total_seconds, 2) << ", THex hexes / DTHex hexes = "
               << fixed(double(t.hexes) / double(std::max<size_t>(d.hexes, 1)), 2) << "\n";
  }
  if (!ratios.str().empty()) out << "\n" << ratios.str();
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  std::string meshes_folder = "meshes", only, csv, methods_text = "thex,dthex", work_dir;
  double timeout_seconds = 300;
  bool markdown = false, quiet = false;
  int subdivide = 0;
  dthex::PipelineOptions dthex_options;
  CLI::App app{"benchmark: THex and DTHex side by side, every run in a child process with a timeout", "benchmark"};
  app.add_option("FILES", files, "surfaces to run (default: every .off .obj .stl .ply in --meshes)");
  app.add_option("--meshes", meshes_folder, "folder of surfaces when no FILES are given")->default_val("meshes");
  app.add_option("--only", only, "only surfaces whose file name contains this");
  app.add_option("--methods", methods_text, "comma-separated: thex, dthex")->default_val("thex,dthex");
  app.add_option("--timeout", timeout_seconds, "seconds per run before it is killed")
      ->default_val(300.0)
      ->check(CLI::PositiveNumber);
  app.add_option("--csv", csv, "also write every row (with all stage times) as CSV");
  app.add_flag("--markdown", markdown, "print the tables as Markdown (for the README)");
  app.add_option("--subdivide", subdivide, "Loop-subdivide every input this many times first (4^K triangles)")
      ->check(CLI::Range(0, 6));
  app.add_option("--work-dir", work_dir, "where subdivided surfaces are written (default: the temp folder)");
  app.add_option("--eps", dthex_options.eps, "DTHex coarsening factor")->default_val(0.1)->check(CLI::Range(1e-6, 0.999999));
  app.add_option("--dice", dthex_options.dice, "DTHex dicing")->default_val(2)->check(CLI::Range(1, 8));
  app.add_option("--time-limit", dthex_options.time_limit_seconds,
                 "seconds for TetGen and for the untangling optimizer each, in both methods (as om_dthex --time-limit)")
      ->default_val(600.0)
      ->check(CLI::PositiveNumber);
  app.add_flag("-q,--quiet", quiet, "no progress lines on stderr");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "benchmark: %s\n", e.what());
    return 2;
  }

  std::vector<std::string> methods;
  {
    std::stringstream ss(methods_text);
    for (std::string m; std::getline(ss, m, ',');) {
      if (m != "thex" && m != "dthex") {
        std::fprintf(stderr, "benchmark: --methods: unknown method '%s' (use thex, dthex)\n", m.c_str());
        return 2;
      }
      methods.push_back(m);
    }
  }
  if (files.empty()) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(meshes_folder, ec)) {
      std::string ext = entry.path().extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
      if (ext == ".off" || ext == ".obj" || ext == ".stl" || ext == ".ply") files.push_back(entry.path().string());
    }
    if (ec) {
      std::fprintf(stderr, "benchmark: --meshes: cannot list '%s': %s\n", meshes_folder.c_str(), ec.message().c_str());
      return 2;
    }
    std::sort(files.begin(), files.end());
  }
  if (!only.empty())
    files.erase(std::remove_if(files.begin(), files.end(),
                               [&](const std::string& f) { return fs::path(f).filename().string().find(only) == std::string::npos; }),
                files.end());
  if (files.empty()) {
    std::fprintf(stderr, "benchmark: no surfaces to run\n");
    return 2;
  }
  const fs::path folder = work_dir.empty() ? fs::temp_directory_path() / "dthex_benchmark" : fs::path(work_dir);

  dthex::PipelineOptions thex_options = dthex_options;
  thex_options.thex_only = true;
  std::vector<Row> rows;
  for (const std::string& file : files) {
    std::string name = fs::path(file).stem().string(), path = file;
    if (subdivide > 0) {
      try {
        path = subdivided_copy(file, subdivide, folder, name);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "benchmark: %s: cannot subdivide: %s\n", file.c_str(), e.what());
        return 2;
      }
      if (!quiet) std::fprintf(stderr, "benchmark: %s -> %s\n", file.c_str(), path.c_str());
    }
    for (const std::string& method : methods) {
      if (!quiet) std::fprintf(stderr, "benchmark: %s %s ...\n", name.c_str(), method.c_str());
      rows.push_back(run_one(path, name, method, method == "thex" ? thex_options : dthex_options, timeout_seconds));
      const Row& r = rows.back();
      if (!quiet)
        std::fprintf(stderr, "benchmark: %s %s: %s, %.2f s, %.0f MB%s%s\n", name.c_str(), method.c_str(),
                     r.status.c_str(), r.wall_seconds, r.peak_mb, r.message.empty() ? "" : ": ", r.message.c_str());
    }
  }

  char date[64];
  const std::time_t now = std::time(nullptr);
  std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
  const long cores = ::sysconf(_SC_NPROCESSORS_ONLN);
  if (markdown)
    std::printf("Measured %s on %ld cores (DTHex eps %g, dice %d; THex = --thex-only; each run alone in a child "
                "process; peak MB = its maximum resident set).\n\n",
                date, cores, dthex_options.eps, dthex_options.dice);
  else
    std::printf("benchmark %s, %ld cores, DTHex eps %g dice %d, time limit %g s\n", date, cores, dthex_options.eps,
                dthex_options.dice, dthex_options.time_limit_seconds);
  std::fputs(tables(rows, markdown).c_str(), stdout);
  if (!csv.empty()) {
    try {
      write_csv(rows, csv);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "benchmark: --csv: %s\n", e.what());
      return 2;
    }
  }
  const bool all_ok = std::all_of(rows.begin(), rows.end(), [](const Row& r) { return r.status == "ok"; });
  return all_ok ? 0 : 3;
}
