// SPDX-License-Identifier: MIT
#include <dthex/hexes/mesh_sets.h>

#include <dthex/hexes/conformity.h>
#include <dthex/mesh/half_edges.h>
#include <dthex/mesh/triangle_bvh.h>
#include <dthex/surface/features.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <regex>
#include <sstream>
#include <unordered_map>

namespace dthex {
namespace {

// A planar region is kept only if its in-plane spread across is at least this fraction of its
// spread along (the square roots of the in-plane covariance's eigenvalues).
constexpr double kPlanarMinSpreadRatio = 0.25;
// A hole in a planar region (other triangles bordered by it alone) joins it below this fraction
// of its area.
constexpr double kPlanarHoleFraction = 0.05;

// Union-find over nodes with path halving.
struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int v) {
    while (parent[size_t(v)] != v) v = parent[size_t(v)] = parent[size_t(parent[size_t(v)])];
    return v;
  }
  void join(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[size_t(std::max(a, b))] = std::min(a, b);
  }
};

// The side of hex h whose corners are the quad's nodes, or -1.
int side_of(const std::array<int, 8>& h, const std::array<int, 4>& quad) {
  std::array<int, 4> q = quad;
  std::sort(q.begin(), q.end());
  for (int s = 0; s < 6; ++s) {
    std::array<int, 4> f;
    for (int i = 0; i < 4; ++i) f[size_t(i)] = h[size_t(kHexFaces[size_t(s)][size_t(i)])];
    std::sort(f.begin(), f.end());
    if (f == q) return s;
  }
  return -1;
}

// Area vector of a quad (half the cross product of its diagonals): its length is the area of a
// planar quad, and its direction the outward normal for an outward ring.
Vec3 area_vector(const HexMesh& mesh, const std::array<int, 4>& q) {
  const Vec3 d0 = mesh.nodes[size_t(q[2])] - mesh.nodes[size_t(q[0])];
  const Vec3 d1 = mesh.nodes[size_t(q[3])] - mesh.nodes[size_t(q[1])];
  return 0.5 * d0.cross(d1);
}

double quad_area(const HexMesh& mesh, const std::array<int, 4>& q) {
  const Vec3& a = mesh.nodes[size_t(q[0])];
  const Vec3& b = mesh.nodes[size_t(q[1])];
  const Vec3& c = mesh.nodes[size_t(q[2])];
  const Vec3& d = mesh.nodes[size_t(q[3])];
  return 0.5 * ((b - a).cross(c - a).norm() + (c - a).cross(d - a).norm());
}

NodeSet nodes_of(const std::string& name, const std::vector<size_t>& quad_ids,
                 const std::vector<std::array<int, 4>>& quads) {
  NodeSet set{name, {}};
  for (size_t q : quad_ids) set.nodes.insert(set.nodes.end(), quads[q].begin(), quads[q].end());
  std::sort(set.nodes.begin(), set.nodes.end());
  set.nodes.erase(std::unique(set.nodes.begin(), set.nodes.end()), set.nodes.end());
  return set;
}

// Groups of item ids sharing a label, largest weight first (ties by first id, so the order
// does not depend on the sort's stability).
std::vector<std::vector<size_t>> groups_by_weight(const std::vector<int>& label, const std::vector<double>& weight) {
  std::unordered_map<int, size_t> index;
  std::vector<std::vector<size_t>> groups;
  std::vector<double> total;
  for (size_t i = 0; i < label.size(); ++i) {
    auto [it, fresh] = index.try_emplace(label[i], groups.size());
    if (fresh) {
      groups.emplace_back();
      total.push_back(0);
    }
    groups[it->second].push_back(i);
    total[it->second] += weight[i];
  }
  std::vector<size_t> order(groups.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    if (total[a] != total[b]) return total[a] > total[b];
    return groups[a].front() < groups[b].front();
  });
  std::vector<std::vector<size_t>> sorted;
  for (size_t g : order) sorted.push_back(std::move(groups[g]));
  return sorted;
}

// Patch labels of boundary quads from the hex boundary alone: quads joined across edges of
// exactly two quads whose normals differ by at most the crease angle.
std::vector<int> patches_by_hex_creases(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads,
                                        double crease_angle_degrees) {
  std::vector<std::pair<std::pair<int, int>, int>> edge_uses;
  edge_uses.reserve(4 * quads.size());
  for (size_t q = 0; q < quads.size(); ++q)
    for (int i = 0; i < 4; ++i) {
      const int a = quads[q][size_t(i)], b = quads[q][size_t((i + 1) % 4)];
      edge_uses.push_back({{std::min(a, b), std::max(a, b)}, int(q)});
    }
  std::sort(edge_uses.begin(), edge_uses.end());
  const double cos_crease = std::cos(crease_angle_degrees * M_PI / 180.0);
  std::vector<Vec3> normal(quads.size());
  for (size_t q = 0; q < quads.size(); ++q) normal[q] = area_vector(mesh, quads[q]).normalized();
  DisjointSets patches(quads.size());
  for (size_t i = 0; i < edge_uses.size();) {
    size_t j = i;
    while (j < edge_uses.size() && edge_uses[j].first == edge_uses[i].first) ++j;
    if (j - i == 2) {
      const int a = edge_uses[i].second, b = edge_uses[i + 1].second;
      if (normal[size_t(a)].dot(normal[size_t(b)]) >= cos_crease) patches.join(a, b);
    }
    i = j;
  }
  std::vector<int> label(quads.size());
  for (size_t q = 0; q < quads.size(); ++q) label[q] = patches.find(int(q));
  return label;
}

// The triangles beside each triangle across its edges of exactly two triangles, from the
// surface's sorted_half_edges.
// At most three (one per edge), in the order of the edges' keys; -1 pads.
using TriangleNeighbours = std::array<int, 3>;
std::vector<TriangleNeighbours> triangle_neighbours(const std::vector<HalfEdge>& edge_uses, size_t triangles) {
  std::vector<TriangleNeighbours> neighbours(triangles, TriangleNeighbours{-1, -1, -1});
  auto add = [&](int t, int u) {
    for (int& slot : neighbours[size_t(t)])
      if (slot < 0) {
        slot = u;
        return;
      }
  };
  for (size_t i = 0; i < edge_uses.size();) {
    size_t j = i;
    while (j < edge_uses.size() && edge_uses[j].key == edge_uses[i].key) ++j;
    if (j - i == 2) {
      add(edge_uses[i].triangle, edge_uses[i + 1].triangle);
      add(edge_uses[i + 1].triangle, edge_uses[i].triangle);
    }
    i = j;
  }
  return neighbours;
}

// Per input triangle, the planar region it belongs to, or -1 (docs/METHOD.md, Sets for the
// solver). A region grows from each triangle not yet tried, in index order, across edges to
// triangles whose normal is within the angle of the region's plane and whose corners are within
// the distance of it; the plane (area-weighted mean normal through the area-weighted centroid)
// is refitted as the region grows. A region is kept when its area is at least the fraction of
// the surface's and it is not a band (across its plane it spreads at least a quarter as far as
// along: a band is what a tolerance finds on a gently curved surface); otherwise its triangles
// are released, and not tried as seeds again. Last, a small hole (a group of other triangles
// bordered by one region only, under a twentieth of its area) is given to its region.
std::vector<int> planar_regions(const TriSurface& input, const std::vector<TriangleNeighbours>& neighbours,
                                const MeshSetsOptions& options) {
  const size_t n = input.triangles.size();
  std::vector<int> region(n, -1);
  if (options.planar_min_area_fraction <= 0 || options.planar_min_area_fraction > 1 || n == 0) return region;
  std::vector<Vec3> normal(n), centroid(n);
  std::vector<double> area(n);
  double total_area = 0;
  Vec3 lo = input.points.front(), hi = input.points.front();
  for (const Vec3& p : input.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  for (size_t t = 0; t < n; ++t) {
    const Vec3& a = input.points[size_t(input.triangles[t][0])];
    const Vec3& b = input.points[size_t(input.triangles[t][1])];
    const Vec3& c = input.points[size_t(input.triangles[t][2])];
    const Vec3 cross = (b - a).cross(c - a);
    area[t] = 0.5 * cross.norm();
    normal[t] = area[t] > 0 ? Vec3(cross / (2 * area[t])) : Vec3::Zero();
    centroid[t] = (a + b + c) / 3.0;
    total_area += area[t];
  }
  const double distance = options.planar_distance_fraction * (hi - lo).norm();
  const double cos_angle = std::cos(options.planar_angle_degrees * M_PI / 180.0);
  std::vector<char> tried(n, 0);
  std::vector<int> members;
  std::vector<char> in_members(n, 0);
  int regions = 0;
  std::vector<double> region_area;
  for (size_t seed = 0; seed < n; ++seed) {
    if (region[seed] >= 0 || tried[seed] || area[seed] <= 0) continue;
    members.assign(1, int(seed));
    in_members[seed] = 1;
    Vec3 plane_normal = normal[seed], plane_point = centroid[seed];
    Vec3 normal_sum = area[seed] * normal[seed], centroid_sum = area[seed] * centroid[seed];
    double area_sum = area[seed];
    for (size_t next = 0; next < members.size(); ++next)
      for (int u : neighbours[size_t(members[next])]) {
        if (u < 0) break;
        if (in_members[size_t(u)] || region[size_t(u)] >= 0 || area[size_t(u)] <= 0) continue;
        if (normal[size_t(u)].dot(plane_normal) < cos_angle) continue;
        bool near = true;
        for (int v : input.triangles[size_t(u)])
          near = near && std::abs((input.points[size_t(v)] - plane_point).dot(plane_normal)) <= distance;
        if (!near) continue;
        in_members[size_t(u)] = 1;
        members.push_back(u);
        normal_sum += area[size_t(u)] * normal[size_t(u)];
        centroid_sum += area[size_t(u)] * centroid[size_t(u)];
        area_sum += area[size_t(u)];
        if (members.size() % 32 == 0 && normal_sum.norm() > 0) {
          plane_normal = normal_sum.normalized();
          plane_point = centroid_sum / area_sum;
        }
      }
    for (int t : members) in_members[size_t(t)] = 0;
    bool keep = area_sum >= options.planar_min_area_fraction * total_area && normal_sum.norm() > 0;
    if (keep) {
      // In-plane spread: the area-weighted covariance of the centroids, projected on the plane.
      const Vec3 nrm = normal_sum.normalized(), mean = centroid_sum / area_sum;
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (int t : members) {
        Vec3 d = centroid[size_t(t)] - mean;
        d -= d.dot(nrm) * nrm;
        covariance += area[size_t(t)] * d * d.transpose();
      }
      const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance / area_sum).eigenvalues();
      // Ascending; the smallest is the (near-zero) spread along the normal.
      keep = spread[1] >= kPlanarMinSpreadRatio * kPlanarMinSpreadRatio * spread[2];
    }
    for (int t : members) {
      if (keep)
        region[size_t(t)] = regions;
      else
        tried[size_t(t)] = 1;
    }
    if (keep) {
      region_area.push_back(area_sum);
      ++regions;
    }
  }
  // Holes: groups of other triangles that border one region only and are small beside it.
  std::vector<int> group(n, -1);
  for (size_t start = 0; start < n && regions > 0; ++start) {
    if (region[start] >= 0 || group[start] >= 0) continue;
    members.assign(1, int(start));
    group[start] = int(start);
    double group_area = 0;
    int border = -1;
    bool one_border = true;
    for (size_t next = 0; next < members.size(); ++next) {
      const int t = members[next];
      group_area += area[size_t(t)];
      for (int u : neighbours[size_t(t)]) {
        if (u < 0) break;
        if (region[size_t(u)] >= 0) {
          if (border >= 0 && border != region[size_t(u)]) one_border = false;
          border = region[size_t(u)];
        } else if (group[size_t(u)] < 0) {
          group[size_t(u)] = int(start);
          members.push_back(u);
        }
      }
    }
    if (border >= 0 && one_border && group_area < kPlanarHoleFraction * region_area[size_t(border)])
      for (int t : members) region[size_t(t)] = border;
  }
  return region;
}

// Patch labels of boundary quads from the input surface: its planar regions, and the rest of its
// triangles joined across every edge that is not a feature edge; each quad is labelled by the
// triangle closest to its centre.
std::vector<int> patches_by_input_creases(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads,
                                          const TriSurface& input, const MeshSetsOptions& options) {
  // The feature edges of detect_features at the crease angle, tested edge by edge.
  const CreaseTest crease(input, options.crease_angle_degrees);
  const std::vector<HalfEdge> edge_uses = sorted_half_edges(input.triangles);
  const std::vector<int> planar =
      planar_regions(input, triangle_neighbours(edge_uses, input.triangles.size()), options);
  DisjointSets regions(input.triangles.size());
  for (size_t i = 0; i < edge_uses.size();) {
    size_t j = i;
    while (j < edge_uses.size() && edge_uses[j].key == edge_uses[i].key) ++j;
    if (j - i == 2) {
      const int a = edge_uses[i].triangle, b = edge_uses[i + 1].triangle;
      // Triangles of one planar region are joined; a region's rim separates it from the rest.
      if (planar[size_t(a)] == planar[size_t(b)] && (planar[size_t(a)] >= 0 || !crease(a, b)))
        regions.join(a, b);
    }
    i = j;
  }
  std::unique_ptr<TriangleBvh> own_tree;
  if (!options.input_tree) own_tree = std::make_unique<TriangleBvh>(input);
  const TriangleBvh& tree = options.input_tree ? *options.input_tree : *own_tree;
  std::vector<int> label(quads.size());
  int hint = -1;
  for (size_t q = 0; q < quads.size(); ++q) {
    Vec3 centre = Vec3::Zero();
    for (int n : quads[q]) centre += mesh.nodes[size_t(n)] / 4.0;
    const TriangleBvh::ClosestPoint c = hint < 0 ? tree.closest_point(centre) : tree.closest_point_near(centre, hint);
    hint = c.triangle;
    label[q] = c.triangle < 0 ? -1 : regions.find(c.triangle);
  }
  return label;
}

MeshSets sets_with_patches(const HexMesh& mesh, const std::vector<std::array<int, 4>>& quads,
                           const std::vector<int>& owners, const std::vector<int>& patch_label) {
  MeshSets sets;
  std::vector<int> part_label(mesh.hexes.size());
  if (mesh.region.size() != mesh.hexes.size()) {
    // Parts: hexes connected through shared nodes.
    DisjointSets nodes(mesh.nodes.size());
    for (const auto& h : mesh.hexes)
      for (int i = 1; i < 8; ++i) nodes.join(h[0], h[size_t(i)]);
    for (size_t h = 0; h < mesh.hexes.size(); ++h) part_label[h] = nodes.find(mesh.hexes[h][0]);
  } else {
    // ... of one region: hexes joined when they share a node and their region.
    std::vector<std::pair<std::pair<int, int>, int>> uses;  // ((node, region), hex)
    uses.reserve(8 * mesh.hexes.size());
    for (size_t h = 0; h < mesh.hexes.size(); ++h)
      for (int v : mesh.hexes[h]) uses.push_back({{v, mesh.region[h]}, int(h)});
    std::sort(uses.begin(), uses.end());
    DisjointSets hexes(mesh.hexes.size());
    for (size_t i = 1; i < uses.size(); ++i)
      if (uses[i].first == uses[i - 1].first) hexes.join(uses[i].second, uses[i - 1].second);
    for (size_t h = 0; h < mesh.hexes.size(); ++h) part_label[h] = hexes.find(int(h));
  }
  const std::vector<std::vector<size_t>> parts =
      groups_by_weight(part_label, std::vector<double>(mesh.hexes.size(), 1.0));
  std::vector<int> part_of_hex(mesh.hexes.size(), -1);
  for (size_t p = 0; p < parts.size(); ++p) {
    HexSet part{"body" + std::to_string(p + 1), {}};
    for (size_t h : parts[p]) {
      part.hexes.push_back(int(h));
      part_of_hex[h] = int(p);
    }
    sets.parts.push_back(std::move(part));
  }

  // Boundary faces, each with its hex's side.
  std::vector<HexFace> faces(quads.size());
  std::vector<double> areas(quads.size());
  for (size_t q = 0; q < quads.size(); ++q) {
    faces[q] = {owners[q], side_of(mesh.hexes[size_t(owners[q])], quads[q])};
    areas[q] = quad_area(mesh, quads[q]);
  }
  std::vector<std::array<int, 4>> all_quads = quads;  // and the interfaces' below
  auto face_set = [&](const std::string& name, const std::vector<size_t>& ids) {
    FaceSet set{name, {}, 0};
    for (size_t q : ids) {
      set.faces.push_back(faces[q]);
      set.area += areas[q];
    }
    sets.surfaces.push_back(std::move(set));
    sets.node_sets.push_back(nodes_of(name, ids, all_quads));
  };
  std::vector<std::vector<size_t>> boundary_of_part(parts.size());
  for (size_t q = 0; q < quads.size(); ++q) boundary_of_part[size_t(part_of_hex[size_t(owners[q])])].push_back(q);
  // The faces between regions: on both parts' boundaries (each as a face of its own hex), and
  // one surface per pair of parts, faced from the lower region's part into the higher one's.
  std::vector<int> interface_owners, interface_others;
  std::vector<std::array<int, 4>> interface = interface_quads(mesh, &interface_owners, &interface_others);
  std::map<std::pair<int, int>, std::vector<size_t>> interface_of_pair;
  for (size_t i = 0; i < interface.size(); ++i) {
    const int a = part_of_hex[size_t(interface_owners[i])], b = part_of_hex[size_t(interface_others[i])];
    const HexFace inner{interface_others[i], side_of(mesh.hexes[size_t(interface_others[i])], interface[i])};
    std::array<int, 4> reversed = interface[i];
    std::reverse(reversed.begin(), reversed.end());
    interface_of_pair[{std::min(a, b), std::max(a, b)}].push_back(faces.size());
    boundary_of_part[size_t(a)].push_back(faces.size());
    faces.push_back({interface_owners[i], side_of(mesh.hexes[size_t(interface_owners[i])], interface[i])});
    areas.push_back(quad_area(mesh, interface[i]));
    all_quads.push_back(interface[i]);
    boundary_of_part[size_t(b)].push_back(faces.size());
    faces.push_back(inner);
    areas.push_back(areas.back());
    all_quads.push_back(reversed);
  }
  for (size_t p = 0; p < parts.size(); ++p) face_set(sets.parts[p].name + "_boundary", boundary_of_part[p]);
  for (const auto& [pair, ids] : interface_of_pair)
    face_set(sets.parts[size_t(pair.first)].name + "_" + sets.parts[size_t(pair.second)].name + "_interface", ids);
  // A patch never spans two parts: the label is made unique per part.
  std::vector<int> label(quads.size());
  std::map<std::pair<int, int>, int> unique;
  for (size_t q = 0; q < quads.size(); ++q)
    label[q] = unique.try_emplace({part_of_hex[size_t(owners[q])], patch_label[q]}, int(unique.size())).first->second;
  const std::vector<std::vector<size_t>> patch_groups = groups_by_weight(label, areas);
  for (size_t p = 0; p < patch_groups.size(); ++p) face_set("patch" + std::to_string(p + 1), patch_groups[p]);
  return sets;
}

}  // namespace

MeshSets find_mesh_sets(const HexMesh& mesh, const MeshSetsOptions& options) {
  std::vector<int> owners;
  const std::vector<std::array<int, 4>> quads = boundary_quads(mesh, &owners);
  return sets_with_patches(mesh, quads, owners, patches_by_hex_creases(mesh, quads, options.crease_angle_degrees));
}

MeshSets find_mesh_sets(const HexMesh& mesh, const TriSurface& input, const MeshSetsOptions& options) {
  std::vector<int> owners;
  const std::vector<std::array<int, 4>> quads = boundary_quads(mesh, &owners);
  return sets_with_patches(mesh, quads, owners,
                           patches_by_input_creases(mesh, quads, input, options));
}

namespace {

bool is_generated_name(const std::string& name) {
  static const std::regex generated(R"((body\d+(_boundary)?)|(patch\d+)|(body\d+_body\d+_interface))");
  return std::regex_match(name, generated);
}

}  // namespace

size_t name_parts_by_input(MeshSets& sets, const HexMesh& mesh, const TriSurface& named,
                           const std::vector<int>& triangle_name, const std::vector<std::string>& names) {
  if (names.empty() || named.triangles.empty() || triangle_name.size() != named.triangles.size()) return 0;
  const TriangleBvh tree(named);
  // The votes of each part's boundary faces.
  std::vector<std::string> chosen(sets.parts.size());
  for (size_t p = 0; p < sets.parts.size(); ++p) {
    const std::string boundary = sets.parts[p].name + "_boundary";
    const auto set = std::find_if(sets.surfaces.begin(), sets.surfaces.end(),
                                  [&](const FaceSet& f) { return f.name == boundary; });
    if (set == sets.surfaces.end()) continue;
    std::map<int, size_t> votes;
    int hint = -1;
    for (const HexFace& f : set->faces) {
      Vec3 centre = Vec3::Zero();
      for (int c : kHexFaces[size_t(f.side)]) centre += mesh.nodes[size_t(mesh.hexes[size_t(f.hex)][size_t(c)])] / 4.0;
      const TriangleBvh::ClosestPoint cp = hint < 0 ? tree.closest_point(centre) : tree.closest_point_near(centre, hint);
      hint = cp.triangle;
      if (cp.triangle >= 0 && triangle_name[size_t(cp.triangle)] >= 0) ++votes[triangle_name[size_t(cp.triangle)]];
    }
    size_t best = 0;
    for (const auto& [name, count] : votes)
      if (count > best) best = count, chosen[p] = names[size_t(name)];
    // A valid set name, and none of the generated kind.
    for (char& c : chosen[p])
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
    if (!chosen[p].empty() && !std::isalpha(static_cast<unsigned char>(chosen[p][0]))) chosen[p] = "part_" + chosen[p];
    if (is_generated_name(chosen[p])) chosen[p].clear();
  }
  // Parts come largest first, so the first to take a name keeps it.
  std::map<std::string, int> taken;
  std::map<std::string, std::string> renamed;  // bodyN -> its new name
  for (size_t p = 0; p < sets.parts.size(); ++p) {
    if (chosen[p].empty()) continue;
    const int n = ++taken[chosen[p]];
    renamed[sets.parts[p].name] = n == 1 ? chosen[p] : chosen[p] + "_" + std::to_string(n);
  }
  auto new_name = [&](const std::string& part) {
    const auto it = renamed.find(part);
    return it == renamed.end() ? part : it->second;
  };
  static const std::regex boundary(R"((body\d+)_boundary)"), interface(R"((body\d+)_(body\d+)_interface)");
  auto rename_set = [&](std::string& name) {
    std::smatch m;
    if (std::regex_match(name, m, boundary)) name = new_name(m[1]) + "_boundary";
    else if (std::regex_match(name, m, interface)) name = new_name(m[1]) + "_" + new_name(m[2]) + "_interface";
  };
  for (HexSet& part : sets.parts) part.name = new_name(part.name);
  for (FaceSet& f : sets.surfaces) rename_set(f.name);
  for (NodeSet& n : sets.node_sets) rename_set(n.name);
  return renamed.size();
}

UserSetSpec parse_user_set(const std::string& text) {
  const std::string forms = "expected NAME=box:X0,Y0,Z0,X1,Y1,Z1 or NAME=plane:PX,PY,PZ,NX,NY,NZ,DISTANCE";
  static const std::regex form(R"(([A-Za-z][A-Za-z0-9_]*)=(box|plane):(.*))");
  std::smatch m;
  if (!std::regex_match(text, m, form)) throw InputError("--set '" + text + "': " + forms);
  UserSetSpec spec;
  spec.name = m[1];
  if (is_generated_name(spec.name))
    throw InputError("--set '" + text + "': the name '" + spec.name +
                     "' is one om_dthex gives its own sets (bodyN, bodyN_boundary, patchN, bodyM_bodyN_interface); choose another");
  spec.kind = m[2] == "box" ? UserSetSpec::Kind::Box : UserSetSpec::Kind::Plane;
  std::vector<double> values;
  std::stringstream list(m[3].str());
  std::string field;
  while (std::getline(list, field, ',')) {
    char* end = nullptr;
    const double v = std::strtod(field.c_str(), &end);
    if (field.empty() || end != field.c_str() + field.size() || !std::isfinite(v))
      throw InputError("--set '" + text + "': '" + field + "' is not a number; " + forms);
    values.push_back(v);
  }
  const size_t wanted = spec.kind == UserSetSpec::Kind::Box ? 6 : 7;
  if (values.size() != wanted)
    throw InputError("--set '" + text + "': " + std::to_string(values.size()) + " numbers where " +
                     std::to_string(wanted) + " are needed; " + forms);
  if (spec.kind == UserSetSpec::Kind::Box) {
    spec.lo = Vec3(std::min(values[0], values[3]), std::min(values[1], values[4]), std::min(values[2], values[5]));
    spec.hi = Vec3(std::max(values[0], values[3]), std::max(values[1], values[4]), std::max(values[2], values[5]));
  } else {
    spec.point = Vec3(values[0], values[1], values[2]);
    spec.normal = Vec3(values[3], values[4], values[5]);
    spec.distance = values[6];
    if (spec.normal.norm() == 0) throw InputError("--set '" + text + "': the plane's normal is zero");
    if (spec.distance < 0) throw InputError("--set '" + text + "': the distance is negative");
    spec.normal.normalize();
  }
  return spec;
}

void add_user_sets(MeshSets& sets, const HexMesh& mesh, const std::vector<UserSetSpec>& specs) {
  if (specs.empty()) return;
  // The faces of the mesh's boundary (not those between material regions).
  std::vector<int> owners;
  const std::vector<std::array<int, 4>> quads = boundary_quads(mesh, &owners);
  std::vector<HexFace> boundary(quads.size());
  for (size_t q = 0; q < quads.size(); ++q) boundary[q] = {owners[q], side_of(mesh.hexes[size_t(owners[q])], quads[q])};
  std::vector<size_t> part_of_hex(mesh.hexes.size(), 0);  // part by part, as the parts' boundaries list them
  for (size_t p = 0; p < sets.parts.size(); ++p)
    for (int h : sets.parts[p].hexes) part_of_hex[size_t(h)] = p;
  std::stable_sort(boundary.begin(), boundary.end(),
                   [&](const HexFace& a, const HexFace& b) { return part_of_hex[size_t(a.hex)] < part_of_hex[size_t(b.hex)]; });
  for (const UserSetSpec& spec : specs) {
    for (const FaceSet& s : sets.surfaces)
      if (s.name == spec.name) throw InputError("--set " + spec.name + ": the name is given twice");
    auto inside = [&](const Vec3& x) {
      if (spec.kind == UserSetSpec::Kind::Box)
        return (x.array() >= spec.lo.array()).all() && (x.array() <= spec.hi.array()).all();
      return std::abs((x - spec.point).dot(spec.normal)) <= spec.distance;
    };
    FaceSet faces{spec.name, {}, 0};
    NodeSet nodes{spec.name, {}};
    for (const HexFace& f : boundary) {
      std::array<int, 4> q;
      for (int i = 0; i < 4; ++i)
        q[size_t(i)] = mesh.hexes[size_t(f.hex)][size_t(kHexFaces[size_t(f.side)][size_t(i)])];
      if (!std::all_of(q.begin(), q.end(), [&](int n) { return inside(mesh.nodes[size_t(n)]); })) continue;
      faces.faces.push_back(f);
      faces.area += quad_area(mesh, q);
      nodes.nodes.insert(nodes.nodes.end(), q.begin(), q.end());
    }
    if (faces.faces.empty())
      throw InputError("--set " + spec.name + ": no boundary face of the mesh lies " +
                       (spec.kind == UserSetSpec::Kind::Box ? "inside the box" : "within the distance of the plane") +
                       " (every corner of a face must); check the coordinates against the input's bounding box");
    std::sort(nodes.nodes.begin(), nodes.nodes.end());
    nodes.nodes.erase(std::unique(nodes.nodes.begin(), nodes.nodes.end()), nodes.nodes.end());
    sets.surfaces.push_back(std::move(faces));
    sets.node_sets.push_back(std::move(nodes));
  }
}

}  // namespace dthex
