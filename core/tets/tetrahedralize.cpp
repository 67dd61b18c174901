// SPDX-License-Identifier: MIT
#include <dthex/tets/tetrahedralize.h>

#include <dthex/mesh/closest_triangle_pair.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/numerics/signed_volume.h>
#include <dthex/pipeline/memory_budget.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <iomanip>
#include <sstream>
#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <tetgen.h>  // only here: it #defines REAL and friends

namespace dthex {
namespace {

constexpr const char* kAllowedSwitches = "pqaAYMTOSDcXJenQz0123456789./-+";

// Exit codes of the child besides TetGen's own error codes (1..10, see notes section 2).
constexpr int kExitUnknownException = 100;
constexpr int kExitBadSwitches = 101;
constexpr int kExitWriteFailed = 102;
constexpr int kExitNoMemory = 103;

struct Header {
  uint64_t magic = 0x7465746765'6e3135ULL;
  int64_t points = 0, tets = 0, faces = 0, markers = 0;
};

std::string tetgen_error_text(int code) {
  switch (code) {
    case 1: return "TetGen ran out of memory";
    case 2: return "TetGen hit an internal error";
    case 3: return "TetGen found a self-intersection in the surface";
    case 4: return "TetGen found a very small input feature (try a larger T tolerance)";
    case 5: return "TetGen found two very close facets (try the Y switch)";
    case 10: return "TetGen rejected the input";
    case kExitUnknownException: return "TetGen threw an unexpected exception";
    case kExitBadSwitches: return "TetGen rejected the switches";
    case kExitWriteFailed: return "TetGen's result could not be sent back";
    case kExitNoMemory: return "TetGen ran out of memory";
    default: return "TetGen failed with exit code " + std::to_string(code);
  }
}

std::string signal_name(int sig) {
  switch (sig) {
    case SIGSEGV: return "SIGSEGV";
    case SIGABRT: return "SIGABRT";
    case SIGBUS: return "SIGBUS";
    case SIGFPE: return "SIGFPE";
    case SIGKILL: return "SIGKILL";
    default: return "signal";
  }
}

bool write_all(int fd, const void* data, size_t bytes) {
  const char* p = static_cast<const char*>(data);
  while (bytes > 0) {
    const ssize_t n = ::write(fd, p, bytes);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    bytes -= size_t(n);
  }
  return true;
}

//! Keeps the child from outliving its parent (a killed om_dthex must not leave TetGen
//! running) and from taking more memory than the machine has: past the cap TetGen's
//! allocations fail and it exits with its out-of-memory code instead of making the
//! kernel kill something. AddressSanitizer reserves terabytes of address space, so
//! there the cap is left off.
void confine_child(pid_t parent, uint64_t address_space_cap) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(kExitUnknownException);  // the parent died before prctl
  if (!built_with_address_sanitizer() && address_space_cap > 0) {
    rlimit limit{rlim_t(address_space_cap), rlim_t(address_space_cap)};
    ::setrlimit(RLIMIT_AS, &limit);
  }
}

//! Runs in the child: builds TetGen's input, runs it, streams the result. Never returns.
[[noreturn]] void run_tetgen_child(const TriSurface& surface, const std::string& switches, int out_fd) {
  const int null_fd = ::open("/dev/null", O_WRONLY);
  if (null_fd >= 0) {
    ::dup2(null_fd, STDOUT_FILENO);
    ::dup2(null_fd, STDERR_FILENO);
  }
  int code = 0;
  try {
    tetgenio in, out;
    in.firstnumber = 0;
    in.numberofpoints = int(surface.points.size());
    in.pointlist = new REAL[3 * surface.points.size()];
    for (size_t i = 0; i < surface.points.size(); ++i)
      for (int k = 0; k < 3; ++k) in.pointlist[3 * i + size_t(k)] = surface.points[i][k];
    in.numberoffacets = int(surface.triangles.size());
    in.facetlist = new tetgenio::facet[surface.triangles.size()];
    in.facetmarkerlist = new int[surface.triangles.size()];
    for (size_t t = 0; t < surface.triangles.size(); ++t) {
      tetgenio::facet& f = in.facetlist[t];
      tetgenio::init(&f);
      f.numberofpolygons = 1;
      f.polygonlist = new tetgenio::polygon[1];
      tetgenio::init(&f.polygonlist[0]);
      f.polygonlist[0].numberofvertices = 3;
      f.polygonlist[0].vertexlist = new int[3];
      for (int k = 0; k < 3; ++k) f.polygonlist[0].vertexlist[k] = surface.triangles[t][size_t(k)];
      in.facetmarkerlist[t] = int(t);
    }
    std::vector<char> buffer(switches.begin(), switches.end());
    buffer.push_back('\0');
    tetgenbehavior behaviour;
    if (!behaviour.parse_commandline(buffer.data())) ::_exit(kExitBadSwitches);
    tetrahedralize(&behaviour, &in, &out);

    Header h;
    h.points = out.numberofpoints;
    h.tets = out.numberofcorners == 4 ? out.numberoftetrahedra : 0;
    h.faces = out.numberoftrifaces;
    h.markers = out.trifacemarkerlist ? out.numberoftrifaces : 0;
    const bool ok = write_all(out_fd, &h, sizeof h) &&
                    write_all(out_fd, out.pointlist, sizeof(REAL) * 3 * size_t(h.points)) &&
                    write_all(out_fd, out.tetrahedronlist, sizeof(int) * 4 * size_t(h.tets)) &&
                    write_all(out_fd, out.trifacelist, sizeof(int) * 3 * size_t(h.faces)) &&
                    write_all(out_fd, out.trifacemarkerlist, sizeof(int) * size_t(h.markers));
    code = ok ? 0 : kExitWriteFailed;
  } catch (int tetgen_code) {
    code = tetgen_code > 0 && tetgen_code < 100 ? tetgen_code : kExitUnknownException;
  } catch (const std::bad_alloc&) {
    code = kExitNoMemory;
  } catch (...) {
    code = kExitUnknownException;
  }
  ::close(out_fd);
  ::_exit(code);  // no atexit handlers, no flushing of the parent's stdio buffers
}

void validate(const TriSurface& surface, const TetgenOptions& options) {
  for (size_t i = 0; i < options.switches.size(); ++i)
    if (!std::strchr(kAllowedSwitches, options.switches[i]) || options.switches[i] == '\0')
      throw InputError("tetrahedralize: TetGen switch '" + std::string(1, options.switches[i]) + "' in \"" +
                       options.switches + "\" is not allowed (allowed: " + kAllowedSwitches +
                       "); switches that write or read files or change the output layout are refused");
  if (!(options.time_limit_seconds > 0))
    throw InputError("tetrahedralize: the time limit must be positive, got " + std::to_string(options.time_limit_seconds));
  if (surface.points.size() < 4 || surface.triangles.size() < 4)
    throw InputError("tetrahedralize: the surface has " + std::to_string(surface.points.size()) + " points and " +
                     std::to_string(surface.triangles.size()) + " triangles; a closed surface needs at least 4 of each");
  for (size_t t = 0; t < surface.triangles.size(); ++t) {
    const auto& tri = surface.triangles[t];
    for (int k = 0; k < 3; ++k) {
      if (tri[size_t(k)] < 0 || size_t(tri[size_t(k)]) >= surface.points.size())
        throw InputError("tetrahedralize: triangle " + std::to_string(t) + " refers to point " +
                         std::to_string(tri[size_t(k)]) + ", outside the " + std::to_string(surface.points.size()) +
                         " points");
      if (tri[size_t(k)] == tri[size_t((k + 1) % 3)])
        throw InputError("tetrahedralize: triangle " + std::to_string(t) + " repeats point " +
                         std::to_string(tri[size_t(k)]));
    }
  }
}

//! Reads the child's whole output, or kills the child at the deadline. Returns false on timeout.
bool read_until_eof(int fd, pid_t child, double seconds, std::vector<char>& data) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
  std::vector<char> chunk(1 << 16);
  for (;;) {
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0) {
      ::kill(child, SIGKILL);
      return false;
    }
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, int(std::min(std::ceil(left * 1000.0), 1e9)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready < 0) throw MeshingError(std::string("tetrahedralize: waiting for TetGen failed: ") + std::strerror(errno));
    if (ready == 0) continue;  // the deadline check above fires
    const ssize_t n = ::read(fd, chunk.data(), chunk.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw MeshingError(std::string("tetrahedralize: reading TetGen's result failed: ") + std::strerror(errno));
    if (n == 0) return true;
    data.insert(data.end(), chunk.data(), chunk.data() + n);
  }
}

TetMesh decode(const std::vector<char>& data, size_t n_input_triangles) {
  Header h;
  const Header expected;
  if (data.size() < sizeof h) throw MeshingError("tetrahedralize: TetGen's result is truncated");
  std::memcpy(&h, data.data(), sizeof h);
  const size_t need = sizeof h + sizeof(double) * 3 * size_t(h.points) + sizeof(int) * (4 * size_t(h.tets) + 3 * size_t(h.faces) + size_t(h.markers));
  if (h.magic != expected.magic || h.points < 0 || h.tets < 0 || h.faces < 0 || h.markers < 0 || data.size() != need)
    throw MeshingError("tetrahedralize: TetGen's result is malformed");
  TetMesh mesh;
  const char* p = data.data() + sizeof h;
  std::vector<double> xyz(3 * size_t(h.points));
  std::memcpy(xyz.data(), p, sizeof(double) * xyz.size());
  p += sizeof(double) * xyz.size();
  mesh.points.resize(size_t(h.points));
  for (size_t i = 0; i < mesh.points.size(); ++i) mesh.points[i] = Vec3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  mesh.tets.resize(size_t(h.tets));
  std::memcpy(mesh.tets.data(), p, sizeof(int) * 4 * mesh.tets.size());
  p += sizeof(int) * 4 * mesh.tets.size();
  mesh.boundary_faces.resize(size_t(h.faces));
  std::memcpy(mesh.boundary_faces.data(), p, sizeof(int) * 3 * mesh.boundary_faces.size());
  p += sizeof(int) * 3 * mesh.boundary_faces.size();
  mesh.boundary_face_source.assign(size_t(h.faces), -1);
  if (h.markers == h.faces) std::memcpy(mesh.boundary_face_source.data(), p, sizeof(int) * size_t(h.markers));

  const auto n_points = mesh.points.size();
  auto valid = [&](int v) { return v >= 0 && size_t(v) < n_points; };
  for (const auto& t : mesh.tets)
    if (!std::all_of(t.begin(), t.end(), valid)) throw MeshingError("tetrahedralize: TetGen returned a tet with an invalid point index");
  for (const auto& f : mesh.boundary_faces)
    if (!std::all_of(f.begin(), f.end(), valid)) throw MeshingError("tetrahedralize: TetGen returned a face with an invalid point index");
  for (int& s : mesh.boundary_face_source)
    if (s < 0 || size_t(s) >= n_input_triangles) s = -1;
  return mesh;
}

//! Every face of every tet as (sorted corners, tet, corner opposite), sorted by corners: the
//! two tets sharing a face are neighbours in the list.
struct TetFace {
  std::array<int, 3> key;
  int tet, opposite;
  bool operator<(const TetFace& o) const { return key < o.key; }
};
std::vector<TetFace> sorted_tet_faces(const TetMesh& mesh) {
  std::vector<TetFace> faces;
  faces.reserve(4 * mesh.tets.size());
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      const auto& tet = mesh.tets[t];
      std::array<int, 3> key = {tet[size_t((f + 1) % 4)], tet[size_t((f + 2) % 4)], tet[size_t((f + 3) % 4)]};
      std::sort(key.begin(), key.end());
      faces.push_back({key, int(t), tet[size_t(f)]});
    }
  std::sort(faces.begin(), faces.end());
  return faces;
}

//! mesh.tet_region from the union-find regions (`root` of a tet) and their depths (at the
//! roots): region 0 the shallowest, ties broken by the region's first tet, so an interface
//! always runs from a lower region number to a higher one. A region never reached (none is,
//! for a closed surface) counts as depth 0.
template <class Root>
void label_regions_by_depth(TetMesh& mesh, const std::vector<int>& depth, Root&& root) {
  std::vector<std::pair<int, int>> regions;  // (depth, first tet) per root, in tet order
  std::vector<int> slot(mesh.tets.size(), -1);
  mesh.tet_region.assign(mesh.tets.size(), 0);
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const int r = root(int(t));
    if (slot[size_t(r)] < 0) {
      slot[size_t(r)] = int(regions.size());
      regions.push_back({std::max(depth[size_t(r)], 0), int(t)});
    }
    mesh.tet_region[t] = slot[size_t(r)];
  }
  std::vector<int> order(regions.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = int(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return regions[size_t(a)] < regions[size_t(b)]; });
  std::vector<int> label(regions.size());
  for (size_t i = 0; i < order.size(); ++i) label[size_t(order[i])] = int(i);
  for (int& r : mesh.tet_region) r = label[size_t(r)];
  if (regions.size() <= 1) mesh.tet_region.clear();
}

//! TetGen fills every region the facets enclose, a cavity included (it removes only what
//! lies outside the outermost surface, unless given a hole point, which a cavity of any
//! shape makes hard to place). So the tets are grouped into regions joined across faces
//! that lie on no facet; a region touching the mesh's outside is material, and crossing a
//! facet between two regions alternates material and cavity, as the nesting of the
//! surface's components does. This needs no orientation of the input, only its facets.
//! Tets of cavity regions, and the points only they use, are dropped. With `keep_nested`
//! (TetgenOptions::keep_nested_regions) nothing is dropped: every region is material, and
//! mesh.tet_region numbers them by depth, then by their first tet.
void keep_material_tets(TetMesh& mesh, bool keep_nested) {
  const std::vector<TetFace> faces = sorted_tet_faces(mesh);
  std::vector<std::array<int, 3>> facet_faces = mesh.boundary_faces;
  for (auto& f : facet_faces) std::sort(f.begin(), f.end());
  std::sort(facet_faces.begin(), facet_faces.end());
  auto on_facet = [&](const std::array<int, 3>& key) {
    return std::binary_search(facet_faces.begin(), facet_faces.end(), key);
  };

  // Regions: union-find over tets sharing a face that lies on no facet.
  std::vector<int> parent(mesh.tets.size());
  for (size_t t = 0; t < parent.size(); ++t) parent[t] = int(t);
  auto find = [&](int t) {
    while (parent[size_t(t)] != t) t = parent[size_t(t)] = parent[size_t(parent[size_t(t)])];
    return t;
  };
  for (size_t i = 0; i + 1 < faces.size(); ++i)
    if (faces[i].key == faces[i + 1].key && !on_facet(faces[i].key)) parent[size_t(find(faces[i].tet))] = find(faces[i + 1].tet);

  // Depth of each region: 0 where a face has one tet (the outside), +1 across each facet.
  std::vector<int> depth(mesh.tets.size(), -1);
  std::vector<std::vector<int>> across(mesh.tets.size());
  std::vector<int> queue;
  for (size_t i = 0; i < faces.size();) {
    size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    const int a = find(faces[i].tet);
    if (j - i == 1 && depth[size_t(a)] < 0) {
      depth[size_t(a)] = 0;
      queue.push_back(a);
    } else if (j - i == 2) {
      const int b = find(faces[i + 1].tet);
      if (a != b) {
        across[size_t(a)].push_back(b);
        across[size_t(b)].push_back(a);
      }
    }
    i = j;
  }
  for (size_t q = 0; q < queue.size(); ++q)
    for (int r : across[size_t(queue[q])])
      if (depth[size_t(r)] < 0) {
        depth[size_t(r)] = depth[size_t(queue[q])] + 1;
        queue.push_back(r);
      }
  if (keep_nested) {
    label_regions_by_depth(mesh, depth, find);
    return;
  }
  // A region never reached (it cannot happen for a closed surface) is kept as it was.
  auto is_cavity = [&](size_t t) { return depth[size_t(find(int(t)))] % 2 == 1; };
  size_t cavity_tets = 0;
  for (size_t t = 0; t < mesh.tets.size(); ++t) cavity_tets += is_cavity(t);
  if (cavity_tets == 0) return;

  std::vector<std::array<int, 4>> kept;
  kept.reserve(mesh.tets.size() - cavity_tets);
  for (size_t t = 0; t < mesh.tets.size(); ++t)
    if (!is_cavity(t)) kept.push_back(mesh.tets[t]);
  mesh.tets = std::move(kept);
  // The points keep their order: TetGen lists the surface's own points first, with their
  // indices, and every one of them still has a material tet (only points inside a cavity go).
  std::vector<int> new_index(mesh.points.size(), -1);
  for (const auto& tet : mesh.tets)
    for (int v : tet) new_index[size_t(v)] = 0;
  std::vector<Vec3> points;
  for (size_t v = 0; v < mesh.points.size(); ++v)
    if (new_index[v] == 0) {
      new_index[v] = int(points.size());
      points.push_back(mesh.points[v]);
    }
  for (auto& tet : mesh.tets)
    for (int& v : tet) v = new_index[size_t(v)];
  mesh.points = std::move(points);
  // A facet separates a material region from a cavity, so each facet face keeps a tet;
  // one that would not (no closed surface makes one) is dropped with its region.
  size_t kept_faces = 0;
  for (size_t i = 0; i < mesh.boundary_faces.size(); ++i) {
    std::array<int, 3> f = mesh.boundary_faces[i];
    for (int& v : f) v = new_index[size_t(v)];
    if (std::min({f[0], f[1], f[2]}) < 0) continue;
    mesh.boundary_faces[kept_faces] = f;
    mesh.boundary_face_source[kept_faces++] = mesh.boundary_face_source[i];
  }
  mesh.boundary_faces.resize(kept_faces);
  mesh.boundary_face_source.resize(kept_faces);
}

//! Positive tets, outward boundary faces: checked against the geometry, not assumed.
void orient(TetMesh& mesh) {
  auto volume6 = [&](int a, int b, int c, int d) {
    return signed_volume6(mesh.points[size_t(a)], mesh.points[size_t(b)], mesh.points[size_t(c)], mesh.points[size_t(d)]);
  };
  for (auto& t : mesh.tets)
    if (volume6(t[0], t[1], t[2], t[3]) < 0) std::swap(t[1], t[2]);

  // Each boundary face's tet, and the tet's corner opposite it.
  const std::vector<TetFace> faces = sorted_tet_faces(mesh);
  for (auto& bf : mesh.boundary_faces) {
    TetFace probe{bf, -1, -1};
    std::sort(probe.key.begin(), probe.key.end());
    const auto it = std::lower_bound(faces.begin(), faces.end(), probe);
    if (it == faces.end() || it->key != probe.key)
      throw MeshingError("tetrahedralize: TetGen returned a boundary face that is not a face of any tet");
    // Outward: the tet's opposite vertex lies behind the face.
    if (volume6(bf[0], bf[1], bf[2], it->opposite) > 0) std::swap(bf[1], bf[2]);
  }
}

//! Where TetGen most likely failed, for its self-intersection and close-facet errors: the
//! closest two triangles that share no corner (searched within growing distances, up to a
//! hundredth of the bounding-box diagonal), with the way out; "" when none is that close.
std::string nearest_pair_text(const TriSurface& surface) {
  const TriangleBvh tree(surface);
  const double diagonal = tree.bounds().diagonal().norm();
  auto separate = [&](int a, int b) {
    for (int u : surface.triangles[size_t(a)])
      for (int w : surface.triangles[size_t(b)])
        if (u == w) return false;
    return true;
  };
  for (double fraction = 1e-9; fraction <= 1e-2; fraction *= 10) {
    const TrianglePairDistance near = closest_separate_pair(tree, fraction * diagonal, separate);
    if (near.a < 0) continue;
    std::ostringstream out;
    out.precision(10);
    out << "; the closest triangles sharing no corner are " << near.a << " and " << near.b << " of the surface it was "
        << "given, " << std::setprecision(3) << near.distance << std::setprecision(10) << " apart at (" << near.point_a.x()
        << ", " << near.point_a.y() << ", " << near.point_a.z()
        << "): move the parts there apart, or merge them by a boolean union";
    return out.str();
  }
  return "";
}

}  // namespace

TetMesh tetrahedralize(const TriSurface& surface, const TetgenOptions& options) {
  validate(surface, options);
  const std::string switches = options.switches + "Qz";

  // Computed before fork(): the child only calls async-signal-safe functions until TetGen.
  const uint64_t used = virtual_size_bytes(), available = available_memory_bytes();
  const uint64_t address_space_cap = used > 0 && available < UINT64_MAX - used ? used + available : 0;
  const pid_t parent = ::getpid();

  int fds[2];
  if (::pipe(fds) != 0) throw MeshingError(std::string("tetrahedralize: cannot create a pipe: ") + std::strerror(errno));
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw MeshingError(std::string("tetrahedralize: cannot start TetGen's process: ") + std::strerror(errno));
  }
  if (child == 0) {
    ::close(fds[0]);
    confine_child(parent, address_space_cap);
    run_tetgen_child(surface, switches, fds[1]);
  }
  ::close(fds[1]);
  std::vector<char> data;
  bool finished = false;
  try {
    finished = read_until_eof(fds[0], child, options.time_limit_seconds, data);
  } catch (...) {
    ::kill(child, SIGKILL);
    ::close(fds[0]);
    ::waitpid(child, nullptr, 0);
    throw;
  }
  ::close(fds[0]);
  // EOF may come before the exit (the child closes the pipe first): wait, bounded by the limit too.
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (!finished) {
    std::ostringstream limit;
    limit << options.time_limit_seconds;
    throw MeshingError("TetGen exceeded the time limit of " + limit.str() + " s and was stopped; coarsen the surface, relax the quality switches (\"" + options.switches +
                       "\") or raise the limit");
  }
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    throw MeshingError("TetGen crashed (signal " + std::to_string(sig) + ", " + signal_name(sig) +
                       ") on the surface: it is probably self-intersecting or has nearly coincident facets" +
                       nearest_pair_text(surface));
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    const bool near_contact = code == 3 || code == 5;
    throw MeshingError(tetgen_error_text(code) + " (switches \"" + switches + "\")" +
                       (near_contact ? nearest_pair_text(surface) : std::string()));
  }
  TetMesh mesh = decode(data, surface.triangles.size());
  if (mesh.tets.empty()) throw MeshingError("TetGen returned no tetrahedra for the surface (switches \"" + switches + "\")");
  keep_material_tets(mesh, options.keep_nested_regions);
  orient(mesh);
  return mesh;
}

}  // namespace dthex
