// SPDX-License-Identifier: MIT
// Element numbers in messages (vertex K, face K, triangle K) are 0-based, in file order;
// line numbers are 1-based.
#include <dthex/io/read_surface.h>

#include <dthex/pipeline/memory_budget.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string_view>
#include <unordered_map>

namespace dthex {

namespace {

constexpr uint64_t kMaxCount = uint64_t(std::numeric_limits<int>::max());

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw InputError(path + ": " + problem);
}

//! Refuses, before anything is allocated, a surface whose meshing could not fit in memory.
void check_triangle_budget(const std::string& path, uint64_t triangles) {
  check_memory_budget(path, "meshing " + std::to_string(triangles) + " triangles", pipeline_peak_bytes(triangles));
}

std::string at_line(size_t line) { return " (line " + std::to_string(line) + ")"; }

std::string to_lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

void split(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

bool parse_double(std::string_view s, double& value) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto result = std::from_chars(s.data(), s.data() + s.size(), value);
  return result.ec == std::errc() && result.ptr == s.data() + s.size();
}

bool parse_int(std::string_view s, int64_t& value) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto result = std::from_chars(s.data(), s.data() + s.size(), value);
  return result.ec == std::errc() && result.ptr == s.data() + s.size();
}

//! Quotes a piece of the file for a message: at most 40 bytes, and bytes that are not
//! printable ASCII (binary junk, NUL, escape sequences) shown as '?', so that the message
//! stays one readable line on any terminal.
std::string quote_text(std::string_view s) {
  std::string text(s.substr(0, 40));
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  return "'" + text + (s.size() > 40 ? "...'" : "'");
}

std::string load_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) fail(path, "no such file");
  if (fs::is_directory(status)) fail(path, "is a directory, not a surface file");
  if (!fs::is_regular_file(status)) fail(path, "is not a regular file");
  const uintmax_t size = fs::file_size(path, ec);
  if (ec) fail(path, "cannot determine the file size (" + ec.message() + ")");
  if (size == 0) fail(path, "is empty");
  check_memory_budget(path, "reading the " + std::to_string(size) + "-byte file", size);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot be opened for reading");
  std::string data(size_t(size), '\0');
  in.read(data.data(), std::streamsize(size));
  if (uintmax_t(in.gcount()) != size) fail(path, "could not be read completely");
  return data;
}

//! Walks a text line by line; strips comments and blank lines.
class LineReader {
 public:
  LineReader(std::string_view text, char comment) : text_(text), comment_(comment) {}
  //! Next line with content; false at the end of the text.
  bool next(std::string_view& line) {
    while (pos_ < text_.size()) {
      size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view raw = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_;
      if (comment_) {
        const size_t hash = raw.find(comment_);
        if (hash != std::string_view::npos) raw = raw.substr(0, hash);
      }
      raw = trim(raw);
      if (!raw.empty()) {
        line = raw;
        return true;
      }
    }
    return false;
  }
  size_t line() const { return line_; }
  uint64_t remaining_bytes() const { return pos_ >= text_.size() ? 0 : text_.size() - pos_; }

 private:
  std::string_view text_;
  char comment_;
  size_t pos_ = 0, line_ = 0;
};

//! Whitespace-separated tokens of a text with their line numbers.
class TokenReader {
 public:
  explicit TokenReader(std::string_view text, size_t pos = 0, size_t line = 1) : text_(text), pos_(pos), line_(line) {}
  bool next(std::string_view& token) {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ >= text_.size()) return false;
    const size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    token = text_.substr(start, pos_ - start);
    return true;
  }
  void skip_rest_of_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }
  size_t line() const { return line_; }

 private:
  std::string_view text_;
  size_t pos_;
  size_t line_;
};

//! Collects vertices and polygons, checking coordinates and indices as they arrive.
struct Builder {
  const std::string& path;
  TriSurface surface;

  void add_vertex(const Vec3& p, const std::string& where) {
    if (!p.allFinite())
      fail(path, "vertex " + std::to_string(surface.points.size()) + " has a non-finite coordinate" + where);
    surface.points.push_back(p);
  }

  //! Fan-triangulates a polygon; indices are 0-based and checked against vertex_count.
  void add_polygon(const std::vector<int64_t>& corners, size_t face, int64_t vertex_count, const std::string& where) {
    if (corners.size() < 3)
      fail(path, "face " + std::to_string(face) + " has " + std::to_string(corners.size()) +
                     " corners, at least 3 are needed" + where);
    for (int64_t v : corners)
      if (v < 0 || v >= vertex_count)
        fail(path, "face " + std::to_string(face) + " refers to vertex " + std::to_string(v) + " but there are only " +
                       std::to_string(vertex_count) + " vertices (valid 0.." + std::to_string(vertex_count - 1) + ")" +
                       where);
    for (size_t k = 1; k + 1 < corners.size(); ++k)
      surface.triangles.push_back({int(corners[0]), int(corners[k]), int(corners[k + 1])});
  }

  TriSurface finish() {
    if (surface.triangles.empty()) fail(path, "contains no triangles");
    return std::move(surface);
  }
};

//! Merges exactly equal positions (bitwise after mapping -0 to +0) of a triangle soup.
class VertexMerger {
 public:
  explicit VertexMerger(TriSurface& surface, size_t expected) : surface_(surface) { map_.reserve(expected); }
  int index_of(Vec3 p) {
    for (int k = 0; k < 3; ++k)
      if (p[k] == 0.0) p[k] = 0.0;  // -0.0 == 0.0: one vertex
    const auto [it, inserted] = map_.try_emplace(Key{p.x(), p.y(), p.z()}, int(surface_.points.size()));
    if (inserted) surface_.points.push_back(p);
    return it->second;
  }

 private:
  using Key = std::array<double, 3>;
  struct Hash {
    size_t operator()(const Key& k) const {
      uint64_t h = 0x9e3779b97f4a7c15ull;
      for (double d : k) {
        uint64_t bits;
        std::memcpy(&bits, &d, sizeof bits);
        h ^= bits + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h *= 0xff51afd7ed558ccdull;
      }
      return size_t(h ^ (h >> 33));
    }
  };
  TriSurface& surface_;
  std::unordered_map<Key, int, Hash> map_;
};

// ---------------------------------------------------------------------------------------- OFF

TriSurface read_off(const std::string& path, std::string_view text) {
  LineReader lines(text, '#');
  std::string_view line;
  std::vector<std::string_view> tokens;
  if (!lines.next(line)) fail(path, "has no content, only comments or blank lines");
  split(line, tokens);
  static const char* const keywords[] = {"OFF", "COFF", "NOFF", "CNOFF", "NCOFF"};
  if (std::none_of(std::begin(keywords), std::end(keywords), [&](const char* k) { return tokens[0] == k; }))
    fail(path, "does not start with the OFF keyword, found " + quote_text(tokens[0]) + at_line(lines.line()));
  tokens.erase(tokens.begin());
  if (tokens.empty()) {
    if (!lines.next(line)) fail(path, "ends after the OFF keyword, the counts line is missing" + at_line(lines.line()));
    split(line, tokens);
  }
  int64_t nv = 0, nf = 0;
  if (tokens.size() < 2 || !parse_int(tokens[0], nv) || !parse_int(tokens[1], nf))
    fail(path, "the counts line must start with the vertex and face counts" + at_line(lines.line()));
  if (nv < 0 || nf < 0 || uint64_t(nv) > kMaxCount || uint64_t(nf) > kMaxCount)
    fail(path, "header counts " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                   " faces are out of range" + at_line(lines.line()));
  // A vertex line needs at least 6 bytes ("0 0 0\n"), any face line at least 2; the last
  // line may lack its newline.
  const uint64_t needed = uint64_t(nv) * 6 + uint64_t(nf) * 2;
  if (needed > lines.remaining_bytes() + 1)
    fail(path, "header claims " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                   " faces, more than the remaining " + std::to_string(lines.remaining_bytes()) +
                   " bytes can hold" + at_line(lines.line()));

  Builder builder{path, {}};
  builder.surface.points.reserve(size_t(nv));
  check_triangle_budget(path, uint64_t(nf));
  builder.surface.triangles.reserve(size_t(nf));
  for (int64_t i = 0; i < nv; ++i) {
    if (!lines.next(line))
      fail(path, "file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices" +
                     at_line(lines.line()));
    split(line, tokens);
    Vec3 p;
    if (tokens.size() < 3 || !parse_double(tokens[0], p.x()) || !parse_double(tokens[1], p.y()) ||
        !parse_double(tokens[2], p.z()))
      fail(path, "vertex " + std::to_string(i) + " is not three numbers" + at_line(lines.line()));
    builder.add_vertex(p, at_line(lines.line()));
  }
  std::vector<int64_t> corners;
  for (int64_t f = 0; f < nf; ++f) {
    if (!lines.next(line))
      fail(path, "file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces" +
                     at_line(lines.line()));
    split(line, tokens);
    int64_t k = 0;
    if (tokens.empty() || !parse_int(tokens[0], k) || k < 0)
      fail(path, "face " + std::to_string(f) + " does not start with its corner count" + at_line(lines.line()));
    if (int64_t(tokens.size()) < 1 + k)
      fail(path, "face " + std::to_string(f) + " announces " + std::to_string(k) + " corners but lists only " +
                     std::to_string(tokens.size() - 1) + at_line(lines.line()));
    corners.resize(size_t(k));
    for (int64_t c = 0; c < k; ++c)
      if (!parse_int(tokens[size_t(c + 1)], corners[size_t(c)]))
        fail(path, "face " + std::to_string(f) + " has a corner index " + quote_text(tokens[size_t(c + 1)]) +
                       " that is not an integer" + at_line(lines.line()));
    builder.add_polygon(corners, size_t(f), nv, at_line(lines.line()));
  }
  return builder.finish();
}

// ---------------------------------------------------------------------------------------- OBJ

// `names` and `triangle_name`, when given, receive the names of the file's `o` and `g` lines
// and, per triangle, the index of the latest one before its face (-1 before any).
TriSurface read_obj_with_names(const std::string& path, std::string_view text, std::vector<std::string>* names,
                               std::vector<int>* triangle_name) {
  LineReader lines(text, '#');
  int current_name = -1;
  std::string_view line;
  std::vector<std::string_view> tokens;
  std::vector<int64_t> corners;
  Builder builder{path, {}};
  size_t face = 0;
  while (lines.next(line)) {
    split(line, tokens);
    if (tokens[0] == "v") {
      Vec3 p;
      if (tokens.size() < 4 || !parse_double(tokens[1], p.x()) || !parse_double(tokens[2], p.y()) ||
          !parse_double(tokens[3], p.z()))
        fail(path, "vertex " + std::to_string(builder.surface.points.size()) + " is not three numbers" +
                       at_line(lines.line()));
      builder.add_vertex(p, at_line(lines.line()));
    } else if (tokens[0] == "f") {
      const int64_t count = int64_t(builder.surface.points.size());
      corners.clear();
      for (size_t c = 1; c < tokens.size(); ++c) {
        const std::string_view corner = tokens[c].substr(0, tokens[c].find('/'));
        int64_t index = 0;
        if (!parse_int(corner, index) || index == 0)
          fail(path, "face " + std::to_string(face) + " has a corner " + quote_text(tokens[c]) +
                         " that is not a non-zero vertex index" + at_line(lines.line()));
        // 1-based; negative counts back from the last vertex defined so far.
        corners.push_back(index > 0 ? index - 1 : count + index);
      }
      builder.add_polygon(corners, face, count,
                          " among the vertices defined before it" + at_line(lines.line()));
      if (triangle_name) triangle_name->resize(builder.surface.triangles.size(), current_name);
      ++face;
    } else if ((tokens[0] == "o" || tokens[0] == "g") && names) {
      // An object's name is the rest of its line; a group line with several names puts the
      // faces in each, and the first is taken.
      current_name = -1;
      if (tokens.size() >= 2) {
        std::string name(tokens[1]);
        if (tokens[0] == "o")
          for (size_t k = 2; k < tokens.size(); ++k) name += " " + std::string(tokens[k]);
        const auto known = std::find(names->begin(), names->end(), name);
        current_name = int(known - names->begin());
        if (known == names->end()) names->push_back(name);
      }
    }
  }
  return builder.finish();
}

TriSurface read_obj(const std::string& path, std::string_view text) { return read_obj_with_names(path, text, nullptr, nullptr); }

// ---------------------------------------------------------------------------------------- STL

uint32_t read_u32_le(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
}

float read_f32_le(const char* p) {
  const uint32_t bits = read_u32_le(p);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

TriSurface read_binary_stl(const std::string& path, std::string_view data, uint32_t count) {
  check_triangle_budget(path, count);
  TriSurface surface;
  surface.triangles.reserve(count);
  VertexMerger merger(surface, size_t(count) / 2 + 3);
  const char* p = data.data() + 84;
  for (uint32_t t = 0; t < count; ++t, p += 50) {
    std::array<int, 3> tri;
    for (int c = 0; c < 3; ++c) {
      const char* q = p + 12 + 12 * c;
      const Vec3 v(read_f32_le(q), read_f32_le(q + 4), read_f32_le(q + 8));
      if (!v.allFinite())
        fail(path, "triangle " + std::to_string(t) + " has a non-finite vertex coordinate (byte offset " +
                       std::to_string(q - data.data()) + ")");
      tri[size_t(c)] = merger.index_of(v);
    }
    surface.triangles.push_back(tri);
  }
  if (surface.triangles.empty()) fail(path, "contains no triangles (binary STL with a count of 0)");
  return surface;
}

TriSurface read_ascii_stl(const std::string& path, std::string_view text) {
  TokenReader tokens(text);
  std::string_view token;
  TriSurface surface;
  VertexMerger merger(surface, text.size() / 400 + 3);
  auto next = [&](const char* what) {
    if (!tokens.next(token)) fail(path, std::string("file ends where '") + what + "' was expected" + at_line(tokens.line()));
    return to_lower(std::string(token));
  };
  auto expect = [&](const char* keyword) {
    if (next(keyword) != keyword)
      fail(path, std::string("expected '") + keyword + "' but found " + quote_text(token) + at_line(tokens.line()));
  };
  auto number = [&](const char* what) {
    next(what);
    double value;
    if (!parse_double(token, value))
      fail(path, std::string("expected a number (") + what + ") but found " + quote_text(token) + at_line(tokens.line()));
    return value;
  };
  expect("solid");
  tokens.skip_rest_of_line();  // the solid's name
  for (;;) {
    const std::string keyword = next("facet' or 'endsolid");
    if (keyword == "endsolid") {
      tokens.skip_rest_of_line();
      if (!tokens.next(token)) break;
      if (to_lower(std::string(token)) != "solid")
        fail(path, "expected 'solid' or the end of the file after 'endsolid' but found " + quote_text(token) +
                       at_line(tokens.line()));
      tokens.skip_rest_of_line();
      continue;
    }
    if (keyword != "facet")
      fail(path, "expected 'facet' or 'endsolid' but found " + quote_text(token) + at_line(tokens.line()));
    const size_t t = surface.triangles.size();
    expect("normal");
    for (int k = 0; k < 3; ++k) number("normal component");
    expect("outer");
    expect("loop");
    std::array<int, 3> tri;
    for (int c = 0; c < 3; ++c) {
      expect("vertex");
      Vec3 v;
      for (int k = 0; k < 3; ++k) v[k] = number("vertex coordinate");
      if (!v.allFinite())
        fail(path, "triangle " + std::to_string(t) + " has a non-finite vertex coordinate" + at_line(tokens.line()));
      tri[size_t(c)] = merger.index_of(v);
    }
    expect("endloop");
    expect("endfacet");
    surface.triangles.push_back(tri);
  }
  if (surface.triangles.empty()) fail(path, "contains no triangles");
  return surface;
}

//! Binary STL starting with "solid" is common; binary data after the header has bytes
//! that never occur in an ASCII STL.
bool looks_like_text(std::string_view data) {
  const size_t n = std::min<size_t>(data.size(), 1024);
  for (size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(data[i]);
    if (c >= 0x80 || (c < 0x20 && !is_space(char(c)))) return false;
  }
  return true;
}

TriSurface read_stl(const std::string& path, std::string_view data) {
  const uint64_t size = data.size();
  if (size >= 84) {
    const uint32_t count = read_u32_le(data.data() + 80);
    if (84 + 50 * uint64_t(count) == size) return read_binary_stl(path, data, count);
  }
  const std::string_view start = trim(data.substr(0, 512));
  const bool says_solid = start.size() >= 5 && to_lower(std::string(start.substr(0, 5))) == "solid";
  if (says_solid && looks_like_text(data)) return read_ascii_stl(path, data);
  if (size < 84)
    fail(path, "is neither ASCII STL (no 'solid' keyword) nor binary STL (" + std::to_string(size) +
                   " bytes, a binary STL has at least 84)");
  const uint32_t count = read_u32_le(data.data() + 80);
  fail(path, "binary STL header claims " + std::to_string(count) + " triangles, which need " +
                 std::to_string(84 + 50 * uint64_t(count)) + " bytes, but the file has " + std::to_string(size) +
                 " bytes (truncated or corrupt)");
}

// ---------------------------------------------------------------------------------------- PLY

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool ply_type(std::string_view name, PlyType& type) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::Int8},     {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},   {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},   {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const auto& [n, t] : names)
    if (name == n) {
      type = t;
      return true;
    }
  return false;
}

size_t ply_size(PlyType type) {
  switch (type) {
    case PlyType::Int8: case PlyType::UInt8: return 1;
    case PlyType::Int16: case PlyType::UInt16: return 2;
    case PlyType::Int32: case PlyType::UInt32: case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
  size_t header_line = 0;
};

//! Reads PLY values either from ASCII tokens or from binary bytes of either byte order.
class PlyValues {
 public:
  PlyValues(const std::string& path, std::string_view data, size_t start, size_t start_line, bool ascii,
            bool big_endian)
      : path_(path), data_(data), pos_(start), ascii_(ascii), big_endian_(big_endian),
        tokens_(data, start, start_line) {}

  double read(PlyType type, const std::string& what) {
    if (ascii_) {
      std::string_view token;
      if (!tokens_.next(token)) fail(path_, "file ends inside " + what + at_line(tokens_.line()));
      double value;
      if (!parse_double(token, value))
        fail(path_, "expected a number in " + what + " but found " + quote_text(token) + at_line(tokens_.line()));
      return value;
    }
    const size_t n = ply_size(type);
    if (pos_ + n > data_.size())
      fail(path_, "file ends inside " + what + " (byte offset " + std::to_string(pos_) + ")");
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, n);
    pos_ += n;
    if (big_endian_ != host_is_big_endian()) std::reverse(b, b + n);
    switch (type) {
      case PlyType::Int8: return double(int8_t(b[0]));
      case PlyType::UInt8: return double(b[0]);
      case PlyType::Int16: { int16_t v; std::memcpy(&v, b, 2); return double(v); }
      case PlyType::UInt16: { uint16_t v; std::memcpy(&v, b, 2); return double(v); }
      case PlyType::Int32: { int32_t v; std::memcpy(&v, b, 4); return double(v); }
      case PlyType::UInt32: { uint32_t v; std::memcpy(&v, b, 4); return double(v); }
      case PlyType::Float32: { float v; std::memcpy(&v, b, 4); return double(v); }
      case PlyType::Float64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0;
  }

  std::string where() const {
    return ascii_ ? at_line(tokens_.line()) : " (byte offset " + std::to_string(pos_) + ")";
  }

 private:
  static bool host_is_big_endian() {
    const uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    return first == 0;
  }
  const std::string& path_;
  std::string_view data_;
  size_t pos_;
  bool ascii_, big_endian_;
  TokenReader tokens_;
};

TriSurface read_ply(const std::string& path, std::string_view data) {
  // Header: lines up to "end_header".
  size_t pos = 0, line_number = 0;
  auto next_line = [&](std::string_view& line) {
    if (pos >= data.size()) return false;
    size_t end = data.find('\n', pos);
    if (end == std::string_view::npos) end = data.size();
    line = trim(data.substr(pos, end - pos));
    pos = end + 1;
    ++line_number;
    return true;
  };
  std::string_view line;
  std::vector<std::string_view> tokens;
  if (!next_line(line) || line != "ply") fail(path, "does not start with the 'ply' keyword (line 1)");
  std::string format;
  std::vector<PlyElement> elements;
  bool ended = false;
  while (next_line(line)) {
    split(line, tokens);
    if (tokens.empty() || tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    if (tokens[0] == "end_header") {
      ended = true;
      break;
    }
    if (tokens[0] == "format") {
      if (tokens.size() < 2) fail(path, "the format line names no format" + at_line(line_number));
      format = std::string(tokens[1]);
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        fail(path, "unknown PLY format " + quote_text(format) + at_line(line_number));
    } else if (tokens[0] == "element") {
      int64_t count = 0;
      if (tokens.size() != 3 || !parse_int(tokens[2], count) || count < 0)
        fail(path, "an element line must be 'element <name> <count>'" + at_line(line_number));
      elements.push_back({std::string(tokens[1]), uint64_t(count), {}, line_number});
    } else if (tokens[0] == "property") {
      if (elements.empty()) fail(path, "a property is declared before any element" + at_line(line_number));
      PlyProperty property;
      bool ok;
      if (tokens.size() >= 2 && tokens[1] == "list") {
        ok = tokens.size() == 5 && ply_type(tokens[2], property.count_type) && ply_type(tokens[3], property.type);
        property.is_list = true;
        if (ok) property.name = std::string(tokens[4]);
      } else {
        ok = tokens.size() == 3 && ply_type(tokens[1], property.type);
        if (ok) property.name = std::string(tokens[2]);
      }
      if (!ok) fail(path, "cannot understand the property line " + quote_text(line) + at_line(line_number));
      elements.back().properties.push_back(property);
    } else {
      fail(path, "unexpected header line " + quote_text(line) + at_line(line_number));
    }
  }
  if (!ended) fail(path, "the header has no 'end_header' line" + at_line(line_number));
  if (format.empty()) fail(path, "the header has no format line" + at_line(line_number));
  const bool ascii = format == "ascii";

  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") vertex = &e;
    if (e.name == "face") face = &e;
  }
  if (!vertex) fail(path, "the header declares no 'vertex' element");
  if (!face) fail(path, "the header declares no 'face' element");
  int coordinate_property[3] = {-1, -1, -1};
  for (size_t i = 0; i < vertex->properties.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (vertex->properties[i].name == std::string(1, char('x' + k)) && !vertex->properties[i].is_list)
        coordinate_property[k] = int(i);
  if (std::count(coordinate_property, coordinate_property + 3, -1) > 0)
    fail(path, "the vertex element lacks one of the scalar properties x, y, z" + at_line(vertex->header_line));
  int index_property = -1;
  for (size_t i = 0; i < face->properties.size(); ++i)
    if (face->properties[i].is_list &&
        (face->properties[i].name == "vertex_indices" || face->properties[i].name == "vertex_index"))
      index_property = int(i);
  if (index_property < 0)
    fail(path, "the face element has no list property vertex_indices" + at_line(face->header_line));

  // Smallest possible size of the body: refuse impossible counts before allocating.
  const uint64_t body = data.size() > pos ? data.size() - pos : 0;
  double needed = 0;
  for (const PlyElement& e : elements) {
    double record = 0;
    for (const PlyProperty& p : e.properties) {
      const bool corners = &e == face && p.is_list;
      if (ascii)
        record += p.is_list ? (corners ? 8 : 2) : 2;  // "n a b c " or "0 ", "x "
      else
        record += p.is_list ? double(ply_size(p.count_type)) + (corners ? 3.0 * double(ply_size(p.type)) : 0.0)
                            : double(ply_size(p.type));
    }
    needed += double(e.count) * record;
  }
  if (vertex->count > kMaxCount || face->count > kMaxCount || needed > double(body))
    fail(path, "header claims " + std::to_string(vertex->count) + " vertices and " + std::to_string(face->count) +
                   " faces, more than the " + std::to_string(body) + " bytes after the header can hold");

  Builder builder{path, {}};
  builder.surface.points.reserve(size_t(vertex->count));
  check_triangle_budget(path, face->count);
  builder.surface.triangles.reserve(size_t(face->count));
  PlyValues values(path, data, pos, line_number + 1, ascii, format == "binary_big_endian");
  std::vector<int64_t> corners;
  for (const PlyElement& e : elements) {
    // An element without properties occupies no bytes: its count, however large, is
    // not checked by the size bound above and must not drive a loop.
    if (e.properties.empty()) continue;
    for (uint64_t r = 0; r < e.count; ++r) {
      const std::string what = e.name + " " + std::to_string(r);
      Vec3 p = Vec3::Zero();
      for (size_t i = 0; i < e.properties.size(); ++i) {
        const PlyProperty& property = e.properties[i];
        if (!property.is_list) {
          const double value = values.read(property.type, what);
          if (&e == vertex)
            for (int k = 0; k < 3; ++k)
              if (coordinate_property[k] == int(i)) p[k] = value;
          continue;
        }
        const double n = values.read(property.count_type, what);
        if (!(n >= 0) || n != std::floor(n) || n > double(kMaxCount))
          fail(path, what + " has an invalid list length" + values.where());
        const bool is_corners = &e == face && int(i) == index_property;
        if (is_corners) corners.clear();
        for (double k = 0; k < n; ++k) {
          const double v = values.read(property.type, what);
          if (is_corners) {
            if (v != std::floor(v)) fail(path, what + " has a non-integer vertex index" + values.where());
            corners.push_back(int64_t(std::clamp(v, -1e18, 1e18)));
          }
        }
      }
      if (&e == vertex) builder.add_vertex(p, values.where());
      if (&e == face) builder.add_polygon(corners, size_t(r), int64_t(vertex->count), values.where());
    }
  }
  return builder.finish();
}

using Reader = TriSurface (*)(const std::string&, std::string_view);

Reader reader_for(const std::string& name, const std::string& extension_as_given) {
  const std::string extension = to_lower(extension_as_given);
  if (extension == ".off") return read_off;
  if (extension == ".obj") return read_obj;
  if (extension == ".stl") return read_stl;
  if (extension == ".ply") return read_ply;
  fail(name, "unknown surface format " + quote_text(extension.empty() ? std::string("(no extension)") : extension) +
                 ", expected .off, .obj, .stl or .ply");
}

}  // namespace

TriSurface read_surface(const std::string& path) {
  const Reader reader = reader_for(path, std::filesystem::path(path).extension().string());
  const std::string data = load_file(path);
  TriSurface surface = reader(path, data);
  check_triangle_budget(path, surface.triangles.size());  // OBJ and ASCII STL announce no count
  return surface;
}

SurfaceNames read_surface_names(const std::string& path) {
  SurfaceNames out;
  if (to_lower(std::filesystem::path(path).extension().string()) != ".obj") return out;
  const std::string data = load_file(path);
  out.surface = read_obj_with_names(path, data, &out.names, &out.triangle_name);
  if (out.names.empty()) out = SurfaceNames();
  return out;
}

TriSurface read_surface_from_memory(std::string_view bytes, const std::string& extension, const std::string& name) {
  const Reader reader = reader_for(name, extension);
  if (bytes.empty()) fail(name, "is empty");
  return reader(name, bytes);
}

}  // namespace dthex
