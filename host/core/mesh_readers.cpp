#include "core/mesh_readers.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <unordered_map>


#include "runtime/error.hpp"

namespace splatcl::mesh_io {
namespace {

constexpr std::int64_t kBad = -1;                                       // an unreadable or impossible index
constexpr std::int64_t kNone = std::numeric_limits<std::int64_t>::min();  // no index given

[[noreturn]] void refuse(const std::string& path, const std::string& why) { throw Error("cannot read mesh " + path + ": " + why); }
[[noreturn]] void refuse_ply(const std::string& prefix, const std::string& why) { throw Error(prefix + ": " + why); }

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

void split(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > begin) tokens.push_back(line.substr(begin, i - begin));
  }
}

// Lines of a text, without their '\n' (and '\r').
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    line = text_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    return true;
  }
  std::size_t position() const { return pos_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
};

std::string_view strip_comment(std::string_view line) {
  const std::size_t hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

// A coordinate as a float: false where it is not finite there (nan, inf, beyond ±3.4e38).
bool to_float(double v, float& out) {
  out = static_cast<float>(v);
  return std::isfinite(out);
}

bool parse_integer(std::string_view token, std::int64_t& value) {
  long long v = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || end != token.data() + token.size()) return false;
  value = v;
  return true;
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

bool known_mesh_extension(const std::string& ext) { return ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl"; }

// A keyword of a text format, in any case: some exporters write ASCII STL as "SOLID ... FACET NORMAL".
bool is_keyword(std::string_view token, std::string_view word) {
  return token.size() == word.size() &&
         std::equal(token.begin(), token.end(), word.begin(), [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

// A UTF-8 byte-order mark some editors put before a text file's first line.
constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";

std::string plural(std::uint64_t n, const char* one, const char* many) { return fmt::format("{} {}", n, n == 1 ? one : many); }

// Three coordinates from tokens[first, first + 3): counted as unreadable or non-finite into `raw`.
void add_vertex_tokens(RawMesh& raw, const std::vector<std::string_view>& tokens, std::size_t first, bool readable) {
  double c[3] = {0, 0, 0};
  readable = readable && tokens.size() >= first + 3;
  for (std::size_t i = 0; readable && i < 3; ++i) readable = parse_number(tokens[first + i], c[i]);
  if (!readable) {
    ++raw.problems.unreadable_vertices;
    raw.add_vertex({}, true);
    return;
  }
  Vec3 p;
  if (!(to_float(c[0], p.x) && to_float(c[1], p.y) && to_float(c[2], p.z))) {
    ++raw.problems.non_finite_vertices;
    raw.add_vertex({}, true);
    return;
  }
  raw.add_vertex({c[0], c[1], c[2]}, p, false);
}

Vec3 vec_tokens(const std::vector<std::string_view>& tokens, std::size_t first) {
  double c[3] = {0, 0, 0};
  for (std::size_t i = 0; i < 3 && first + i < tokens.size(); ++i)
    if (!parse_number(tokens[first + i], c[i])) c[i] = 0;
  return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
}

// ---------------------------------------------------------------------------------------------- OBJ

// An OBJ index: 1-based, or negative counting back from the last element defined so far. Positive
// ones are checked against the final count later (a forward reference is allowed).
std::int64_t obj_index(std::string_view token, std::size_t so_far) {
  std::int64_t i = 0;
  if (!parse_integer(token, i) || i == 0) return kBad;
  if (i > 0) return i - 1;
  const std::int64_t back = static_cast<std::int64_t>(so_far) + i;
  return back >= 0 ? back : kBad;
}

RawMesh read_obj(const std::string& path, std::string_view text) {
  RawMesh raw;
  std::vector<std::array<float, 2>> texcoords;
  std::vector<Vec3> normals;
  std::vector<std::int64_t> corner_t, corner_n;  // per corner: texture and normal index, kNone when not given
  bool any_t = false, any_n = false;
  std::size_t vertex_lines = 0, face_lines = 0;
  std::vector<std::string_view> tokens;
  std::string joined;  // a line continued with '\' at its end
  Lines lines(text);
  std::string_view line;
  while (lines.next(line)) {
    if (!line.empty() && line.back() == '\\') {
      joined.append(line.substr(0, line.size() - 1)).push_back(' ');
      continue;
    }
    if (!joined.empty()) {
      joined.append(line);
      line = joined;
    }
    split(strip_comment(line), tokens);
    if (!tokens.empty()) {
      const std::string_view key = tokens[0];
      if (key == "v") {
        ++vertex_lines;
        // x y z, then an optional w or colour: every value must be a number (`v 1.2.3 -3 1.8` is not).
        bool readable = tokens.size() >= 4;
        double ignored = 0;
        for (std::size_t i = 4; readable && i < tokens.size(); ++i) readable = parse_number(tokens[i], ignored);
        add_vertex_tokens(raw, tokens, 1, readable);
      } else if (key == "vt") {
        const Vec3 t = vec_tokens(tokens, 1);
        texcoords.push_back({t.x, tokens.size() > 2 ? t.y : 0.0f});
      } else if (key == "vn") {
        normals.push_back(vec_tokens(tokens, 1));
      } else if (key == "f" || key == "fo") {
        ++face_lines;
        for (std::size_t i = 1; i < tokens.size(); ++i) {
          const std::string_view corner = tokens[i];
          const std::size_t slash1 = corner.find('/');
          const std::size_t slash2 = slash1 == std::string_view::npos ? slash1 : corner.find('/', slash1 + 1);
          raw.corners.push_back(obj_index(corner.substr(0, slash1), raw.positions.size()));
          std::int64_t t = kNone, n = kNone;
          if (slash1 != std::string_view::npos) {
            const std::string_view ts = corner.substr(slash1 + 1, slash2 == std::string_view::npos ? std::string_view::npos : slash2 - slash1 - 1);
            if (!ts.empty()) t = obj_index(ts, texcoords.size());
            if (slash2 != std::string_view::npos) n = obj_index(corner.substr(slash2 + 1), normals.size());
          }
          corner_t.push_back(t);
          corner_n.push_back(n);
          any_t |= t != kNone;
          any_n |= n != kNone;
        }
        raw.end_face();
      }
      // Everything else (o, g, s, l, p, usemtl, mtllib, ...) carries no surface we use.
    }
    joined.clear();
  }
  if (vertex_lines == 0 && face_lines == 0) refuse(path, "no vertex or face lines (not an OBJ file)");
  const auto vertex_count = static_cast<std::int64_t>(raw.positions.size());
  if (any_n) {
    raw.normals.assign(raw.positions.size(), Vec3{});
    raw.has_normal.assign(raw.positions.size(), 0);
  }
  if (any_t) raw.corner_texcoords.assign(raw.corners.size(), {0.0f, 0.0f});
  for (std::size_t c = 0; c < raw.corners.size(); ++c) {
    const std::int64_t v = raw.corners[c], t = corner_t[c], n = corner_n[c];
    if (t != kNone) {
      if (t < 0 || t >= static_cast<std::int64_t>(texcoords.size()))
        raw.corners[c] = kBad;
      else
        raw.corner_texcoords[c] = texcoords[static_cast<std::size_t>(t)];
    }
    if (n != kNone) {
      if (n < 0 || n >= static_cast<std::int64_t>(normals.size())) {
        raw.corners[c] = kBad;
      } else if (v >= 0 && v < vertex_count) {
        raw.normals[static_cast<std::size_t>(v)] = normals[static_cast<std::size_t>(n)];
        raw.has_normal[static_cast<std::size_t>(v)] = 1;
      }
    }
  }
  return raw;
}

// ---------------------------------------------------------------------------------------------- OFF

// Non-empty lines with their '#' comments removed, and whether any is left.
class OffLines {
 public:
  explicit OffLines(std::string_view text) : lines_(text) { advance(); }
  bool next(std::vector<std::string_view>& tokens) {
    if (!has_next_) return false;
    tokens = next_;
    advance();
    return true;
  }
  bool more() const { return has_next_; }

 private:
  void advance() {
    std::string_view line;
    has_next_ = false;
    while (lines_.next(line)) {
      split(strip_comment(line), next_);
      if (!next_.empty()) {
        has_next_ = true;
        return;
      }
    }
  }
  Lines lines_;
  std::vector<std::string_view> next_;
  bool has_next_ = false;
};

// What an OFF header's keyword [ST][C][N][4][n]OFF says of each vertex record (nOFF must be 3D).
struct OffLayout {
  bool texcoords = false, colors = false, normals = false, homogeneous = false;
  std::size_t coordinates() const { return homogeneous ? 4 : 3; }
};

// A point from its coordinates: the first three, divided by the last with 4OFF (homogeneous).
// False where it is not finite then (a zero or non-finite w included).
bool off_point(const double* c, const OffLayout& layout, double out[3]) {
  const double w = layout.homogeneous ? c[3] : 1.0;
  for (int i = 0; i < 3; ++i) out[i] = c[i] / w;
  return std::isfinite(w) && w != 0;
}

void add_off_vertex(RawMesh& raw, const double* c, const OffLayout& layout) {
  double p[3];
  Vec3 q;
  if (!off_point(c, layout, p) || !(to_float(p[0], q.x) && to_float(p[1], q.y) && to_float(p[2], q.z))) {
    ++raw.problems.non_finite_vertices;
    raw.add_vertex({}, true);
  } else {
    raw.add_vertex({p[0], p[1], p[2]}, q, false);
  }
}

// Texture coordinates per corner from those per vertex (STOFF); zero at a corner out of range.
void off_corner_texcoords(RawMesh& raw, const std::vector<std::array<float, 2>>& vertex_texcoords) {
  const auto vertex_count = static_cast<std::int64_t>(vertex_texcoords.size());
  raw.corner_texcoords.reserve(raw.corners.size());
  for (const std::int64_t v : raw.corners)
    raw.corner_texcoords.push_back(v >= 0 && v < vertex_count ? vertex_texcoords[static_cast<std::size_t>(v)] : std::array<float, 2>{});
}

// 32-bit words of a binary OFF body, in one byte order.
class OffWords {
 public:
  OffWords(std::string_view bytes, bool swap) : bytes_(bytes), swap_(swap) {}
  bool next(std::uint32_t& value) {
    if (bytes_.size() - pos_ < 4) return false;
    std::memcpy(&value, bytes_.data() + pos_, 4);
    if (swap_) value = __builtin_bswap32(value);
    pos_ += 4;
    return true;
  }
  float next_float() {
    std::uint32_t bits = 0;
    next(bits);
    return std::bit_cast<float>(bits);
  }
  bool skip(std::uint64_t words) {
    if (words > remaining()) return false;
    pos_ += static_cast<std::size_t>(words) * 4;
    return true;
  }
  std::size_t remaining() const { return (bytes_.size() - pos_) / 4; }

 private:
  std::string_view bytes_;
  bool swap_;
  std::size_t pos_ = 0;
};

// Binary OFF (Geomview's layout), after the header line: the dimension (nOFF) and the vertex, face
// and edge counts as 32-bit integers; per vertex its coordinates, normal (N), RGBA colour (C) and
// texture coordinates (ST) as floats; per face its corner count, the indices, a colour count and
// that many floats. Big-endian as Geomview writes it; a file whose counts fit the file only in the
// other byte order (OpenMesh writes the machine's) is read in that order. The counts must fit the
// bytes after them before anything is allocated.
RawMesh read_off_binary(const std::string& path, std::string_view text, const OffLayout& layout, bool dimension_given) {
  std::size_t body_start = text.size();
  {
    Lines lines(text);
    std::string_view line;
    std::vector<std::string_view> tokens;
    while (lines.next(line)) {
      split(strip_comment(line), tokens);
      if (!tokens.empty()) {
        body_start = std::min(lines.position(), text.size());
        break;
      }
    }
  }
  const std::string_view body = text.substr(body_start);
  const std::size_t vertex_words = layout.coordinates() + (layout.normals ? 3 : 0) + (layout.colors ? 4 : 0) + (layout.texcoords ? 2 : 0);
  struct Counts {
    std::uint32_t dimension = 3, vertices = 0, faces = 0, edges = 0;
  };
  const auto read_counts = [&](OffWords& in, Counts& c) {
    return (!dimension_given || in.next(c.dimension)) && in.next(c.vertices) && in.next(c.faces) && in.next(c.edges);
  };
  // Every face takes at least two words (its corner and colour counts).
  const auto fits = [&](bool swap) {
    OffWords in(body, swap);
    Counts c;
    return read_counts(in, c) && std::uint64_t{c.vertices} * vertex_words + std::uint64_t{c.faces} * 2 <= in.remaining();
  };
  bool swap = std::endian::native == std::endian::little;
  if (!fits(swap) && fits(!swap)) swap = !swap;
  OffWords in(body, swap);
  Counts counts;
  if (!read_counts(in, counts)) refuse(path, "truncated binary OFF: no vertex, face and edge counts after the header");
  if (counts.dimension != 3) refuse(path, fmt::format("nOFF of dimension {}: only 3-dimensional meshes are read", counts.dimension));
  if (std::uint64_t{counts.vertices} * vertex_words + std::uint64_t{counts.faces} * 2 > in.remaining())
    refuse(path, fmt::format("binary OFF header declares {} and {}, more than the {} after it can hold", plural(counts.vertices, "vertex", "vertices"),
                             plural(counts.faces, "face", "faces"), plural(in.remaining() * 4, "byte", "bytes")));
  RawMesh raw;
  raw.positions.reserve(counts.vertices);
  std::vector<std::array<float, 2>> vertex_texcoords;
  for (std::uint32_t i = 0; i < counts.vertices; ++i) {
    double c[4] = {0, 0, 0, 1};
    for (std::size_t k = 0; k < layout.coordinates(); ++k) c[k] = in.next_float();
    add_off_vertex(raw, c, layout);
    if (layout.normals) {
      const float x = in.next_float(), y = in.next_float(), z = in.next_float();
      raw.normals.push_back({x, y, z});
      raw.has_normal.push_back(1);
    }
    if (layout.colors) in.skip(4);
    if (layout.texcoords) {
      const float u = in.next_float(), v = in.next_float();
      vertex_texcoords.push_back({u, v});
    }
  }
  for (std::uint32_t f = 0; f < counts.faces; ++f) {
    const auto truncated = [&] { refuse(path, fmt::format("truncated binary OFF: the file ends in face {} of {}", f + 1, counts.faces)); };
    std::uint32_t n = 0, colors = 0, index = 0;
    if (!in.next(n) || n > in.remaining()) truncated();
    for (std::uint32_t c = 0; c < n; ++c) {
      in.next(index);
      raw.corners.push_back(static_cast<std::int32_t>(index));
    }
    if (!in.next(colors) || !in.skip(colors)) truncated();
    raw.end_face();
  }
  if (layout.texcoords) off_corner_texcoords(raw, vertex_texcoords);
  return raw;
}

RawMesh read_off(const std::string& path, std::string_view text) {
  OffLines lines(text);
  std::vector<std::string_view> tokens;
  if (!lines.next(tokens)) refuse(path, "empty file (no OFF header)");
  OffLayout layout;
  std::string_view key = tokens[0];
  if (key.starts_with("ST")) key.remove_prefix(2), layout.texcoords = true;
  if (key.starts_with("C")) key.remove_prefix(1), layout.colors = true;
  if (key.starts_with("N")) key.remove_prefix(1), layout.normals = true;
  if (key.starts_with("4")) key.remove_prefix(1), layout.homogeneous = true;
  const bool dimension_given = key.starts_with("n");
  if (dimension_given) key.remove_prefix(1);
  if (key != "OFF") refuse(path, "not an OFF file (its first word is not OFF)");
  std::vector<std::string_view> rest(tokens.begin() + 1, tokens.end());
  if (!rest.empty() && rest[0] == "BINARY") return read_off_binary(path, text, layout, dimension_given);
  if (dimension_given) {
    if (rest.empty() && !lines.next(rest)) refuse(path, "truncated nOFF: no dimension after the header");
    std::int64_t dimension = 0;
    if (!parse_integer(rest[0], dimension) || dimension != 3)
      refuse(path, fmt::format("nOFF of dimension '{}': only 3-dimensional meshes are read", rest[0]));
    rest.erase(rest.begin());
  }
  std::vector<std::string_view>& counts = rest;
  if (counts.empty() && !lines.next(counts)) refuse(path, "truncated OFF: no vertex and face counts after the header");
  std::int64_t vertex_count = 0, face_count = 0;
  if (counts.size() < 2 || !parse_integer(counts[0], vertex_count) || !parse_integer(counts[1], face_count) || vertex_count < 0 ||
      face_count < 0)
    refuse(path, "the OFF header has no vertex and face counts");
  const auto nv = static_cast<std::size_t>(vertex_count), nf = static_cast<std::size_t>(face_count);
  const auto truncated = [&](std::size_t vertices, std::size_t faces) {
    refuse(path, fmt::format("truncated OFF: the header declares {} and {}, the file ends after {} and {}", plural(nv, "vertex", "vertices"),
                             plural(nf, "face", "faces"), plural(vertices, "vertex", "vertices"), plural(faces, "face", "faces")));
  };
  RawMesh raw;
  const std::size_t reserve_limit = text.size() / 4;  // no header count allocates beyond what the file can hold
  raw.positions.reserve(std::min(nv, reserve_limit));
  std::vector<std::array<float, 2>> vertex_texcoords;
  if (layout.normals) {
    raw.normals.reserve(std::min(nv, reserve_limit));
    raw.has_normal.reserve(std::min(nv, reserve_limit));
  }
  const std::size_t dims = layout.coordinates();
  const std::size_t needed = dims + (layout.normals ? 3 : 0) + (layout.texcoords ? 2 : 0);
  for (std::size_t i = 0; i < nv; ++i) {
    if (!lines.next(tokens)) truncated(i, 0);
    double c[4] = {0, 0, 0, 1};
    bool readable = tokens.size() >= needed;
    for (std::size_t k = 0; readable && k < dims; ++k) readable = parse_number(tokens[k], c[k]);
    if (!readable) {
      ++raw.problems.unreadable_vertices;
      raw.add_vertex({}, true);
    } else {
      add_off_vertex(raw, c, layout);
    }
    if (layout.normals) {
      raw.normals.push_back(vec_tokens(tokens, dims));
      raw.has_normal.push_back(tokens.size() >= dims + 3 ? 1 : 0);
    }
    if (layout.texcoords) {
      const Vec3 t = tokens.size() >= needed ? vec_tokens(tokens, tokens.size() - 2) : Vec3{};
      vertex_texcoords.push_back({t.x, t.y});
    }
  }
  for (std::size_t f = 0; f < nf; ++f) {
    if (!lines.next(tokens)) truncated(nv, f);
    std::int64_t n = 0;
    if (!parse_integer(tokens[0], n) || n < 0) {
      raw.corners.push_back(kBad);  // an unreadable face record
    } else if (tokens.size() < static_cast<std::size_t>(n) + 1) {
      if (!lines.more()) truncated(nv, f);  // cut inside its last face
      raw.corners.push_back(kBad);
    } else {
      for (std::size_t c = 1; c <= static_cast<std::size_t>(n); ++c) {
        std::int64_t index = 0;
        raw.corners.push_back(parse_integer(tokens[c], index) ? index : kBad);
      }
    }
    raw.end_face();
  }
  if (layout.texcoords) off_corner_texcoords(raw, vertex_texcoords);
  return raw;
}

// ---------------------------------------------------------------------------------------------- PLY

constexpr std::size_t kPlyHeaderLimit = std::size_t{1} << 20;  // a sane PLY header is a few hundred bytes

RawMesh read_ply(const std::string& path, std::string_view text) {
  const PlyHeader header = parse_ply_header(path, text, "mesh");
  const PlyFormat format = header.format;
  const std::vector<PlyElement>& elements = header.elements;
  const std::string_view body_text = header.body;
  const auto vertex_element = std::find_if(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex_element == elements.end()) refuse(path, "PLY file has no vertex element");
  if (vertex_element->count > std::numeric_limits<std::uint32_t>::max()) refuse(path, "PLY file has more than 2^32 vertices");

  RawMesh raw;
  PlyBody body(body_text, format);
  std::vector<std::array<float, 2>> vertex_texcoords;
  bool any_vertex_texcoords = false, any_face_texcoords = false;
  std::vector<std::array<float, 2>> face_texcoords;  // per corner from face texcoord lists
  std::vector<double> values;
  std::vector<PlyBody::Result> results;
  std::vector<double> list;
  std::vector<std::int64_t> strip;
  for (const PlyElement& e : elements) {
    const bool is_vertex = &e == &*vertex_element, is_face = e.name == "face", is_strips = e.name == "tristrips";
    int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1, u = -1, v = -1, indices = -1, texcoord = -1;
    if (is_vertex) {
      x = e.find("x"), y = e.find("y"), z = e.find("z"), nx = e.find("nx"), ny = e.find("ny"), nz = e.find("nz");
      for (const auto& [su, sv] : {std::pair{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}})
        if (u < 0 && e.find(su) >= 0 && e.find(sv) >= 0) u = e.find(su), v = e.find(sv);
      if (x < 0 || y < 0 || z < 0) refuse(path, "PLY vertex element has no x, y and z properties");
      // Any float axis loses detail far out (float easting and northing beside a double height).
      for (const int p : {x, y, z})
        raw.float_coordinates = raw.float_coordinates || (format != PlyFormat::Ascii && e.properties[static_cast<std::size_t>(p)].type == PlyType::F32);
      raw.positions.reserve(e.count);
      raw.bad_vertex.reserve(e.count);
      if (nx >= 0 && ny >= 0 && nz >= 0) {
        raw.normals.reserve(e.count);
        raw.has_normal.assign(e.count, 1);
      }
      any_vertex_texcoords = u >= 0;
    } else if (is_face || is_strips) {
      indices = e.find("vertex_indices");
      if (indices < 0 && is_face) indices = e.find("vertex_index");
      if (indices >= 0 && !e.properties[static_cast<std::size_t>(indices)].list) indices = -1;
      if (is_face) texcoord = e.find("texcoord");
      if (texcoord >= 0 && !e.properties[static_cast<std::size_t>(texcoord)].list) texcoord = -1;
      any_face_texcoords |= texcoord >= 0;
    }
    values.assign(e.properties.size(), 0.0);
    results.assign(e.properties.size(), PlyBody::Ok);
    for (std::uint64_t r = 0; r < e.count; ++r) {
      const auto truncated = [&] { refuse(path, fmt::format("truncated PLY: the file ends in {} record {} of {}", e.name, r + 1, e.count)); };
      std::size_t corners_before = raw.corners.size();
      std::array<float, 2> no_texcoord{};
      std::vector<std::array<float, 2>> record_texcoords;
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const PlyProperty& p = e.properties[k];
        if (!p.list) {
          results[k] = body.next(p.type, values[k]);
          if (results[k] == PlyBody::End) truncated();
          continue;
        }
        std::uint64_t n = 0;
        const PlyBody::Result counted = body.next_count(p.count_type, p.type, n);
        if (counted == PlyBody::End) truncated();
        if (counted == PlyBody::Malformed) refuse(path, fmt::format("PLY {} record {} has a list length that is not a count", e.name, r + 1));
        list.resize(n);
        bool list_readable = true;
        for (std::uint64_t i = 0; i < n; ++i) {
          const PlyBody::Result got = body.next(p.type, list[i]);
          if (got == PlyBody::End) truncated();
          if (got == PlyBody::Malformed) list[i] = NAN, list_readable = false;
        }
        const auto as_index = [](double d) {
          return std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 9e15 ? static_cast<std::int64_t>(d) : kBad;
        };
        if (static_cast<int>(k) == indices && is_face) {
          for (const double d : list) raw.corners.push_back(as_index(d));
        } else if (static_cast<int>(k) == indices && is_strips) {
          strip.clear();
          for (const double d : list) strip.push_back(as_index(d) == kBad && d != -1.0 ? kNone : as_index(d));
        } else if (static_cast<int>(k) == texcoord && list_readable) {
          for (std::uint64_t i = 0; i + 1 < n; i += 2) record_texcoords.push_back({static_cast<float>(list[i]), static_cast<float>(list[i + 1])});
        }
      }
      if (body.end_record() == PlyBody::Malformed)
        refuse(path, fmt::format("PLY {} record {}: its line holds more or fewer values than its properties", e.name, r + 1));
      if (is_vertex) {
        bool readable = results[static_cast<std::size_t>(x)] == PlyBody::Ok && results[static_cast<std::size_t>(y)] == PlyBody::Ok &&
                        results[static_cast<std::size_t>(z)] == PlyBody::Ok;
        Vec3 p;
        if (!readable) {
          ++raw.problems.unreadable_vertices;
          raw.add_vertex({}, true);
        } else if (!(to_float(values[static_cast<std::size_t>(x)], p.x) && to_float(values[static_cast<std::size_t>(y)], p.y) &&
                     to_float(values[static_cast<std::size_t>(z)], p.z))) {
          ++raw.problems.non_finite_vertices;
          raw.add_vertex({}, true);
        } else {
          raw.add_vertex({values[static_cast<std::size_t>(x)], values[static_cast<std::size_t>(y)], values[static_cast<std::size_t>(z)]}, p,
                         false);
        }
        if (!raw.has_normal.empty())
          raw.normals.push_back({static_cast<float>(values[static_cast<std::size_t>(nx)]), static_cast<float>(values[static_cast<std::size_t>(ny)]),
                                 static_cast<float>(values[static_cast<std::size_t>(nz)])});
        if (u >= 0)
          vertex_texcoords.push_back({static_cast<float>(values[static_cast<std::size_t>(u)]), static_cast<float>(values[static_cast<std::size_t>(v)])});
      } else if (is_face && indices >= 0) {
        const std::size_t n = raw.corners.size() - corners_before;
        for (std::size_t i = 0; i < n; ++i) face_texcoords.push_back(record_texcoords.size() == n ? record_texcoords[i] : no_texcoord);
        raw.end_face();
      } else if (is_strips && indices >= 0) {
        // A strip: triangle k of a run (after a -1 restart) has corners k, k+1, k+2, its winding
        // swapped on odd k so that every triangle faces the same way. Triangles with a repeated
        // corner join strips on purpose and are left out.
        std::size_t start = 0;
        for (std::size_t i = 0; i < strip.size(); ++i) {
          if (strip[i] == -1) {
            start = i + 1;
            continue;
          }
          if (i < start + 2) continue;
          std::int64_t a = strip[i - 2], b = strip[i - 1];
          const std::int64_t c = strip[i];
          if ((i - start) % 2 == 1) std::swap(a, b);
          if (a != kNone && b != kNone && c != kNone && (a == b || b == c || a == c)) continue;
          for (const std::int64_t corner : {a, b, c}) {
            raw.corners.push_back(corner == kNone ? kBad : corner);
            face_texcoords.push_back(no_texcoord);
          }
          raw.end_face();
        }
      }
    }
  }
  if (any_face_texcoords) {
    raw.corner_texcoords = std::move(face_texcoords);
  } else if (any_vertex_texcoords) {
    raw.corner_texcoords.reserve(raw.corners.size());
    for (const std::int64_t c : raw.corners)
      raw.corner_texcoords.push_back(c >= 0 && c < static_cast<std::int64_t>(vertex_texcoords.size()) ? vertex_texcoords[static_cast<std::size_t>(c)]
                                                                                                       : std::array<float, 2>{});
  }
  return raw;
}

// ---------------------------------------------------------------------------------------------- STL

// STL lists each triangle's corners by position; equal positions are one vertex (as OpenMesh's
// reader merges them), non-finite ones each their own bad vertex. Equal as read (in double), not as
// floats: an ASCII STL far out, merged by float position, lost its detail before a mesh could be
// read about its centre (a small sphere far out became a handful of vertices).
class StlVertices {
 public:
  explicit StlVertices(RawMesh& raw) : raw_(raw) {}
  void corner(const double c[3], bool readable) {
    Vec3 p;
    if (!readable) {
      ++raw_.problems.unreadable_vertices;
    } else if (!(to_float(c[0], p.x) && to_float(c[1], p.y) && to_float(c[2], p.z))) {
      ++raw_.problems.non_finite_vertices;
    } else {
      // +0 and -0 are one position.
      const Key key{std::bit_cast<std::uint64_t>(c[0] + 0.0), std::bit_cast<std::uint64_t>(c[1] + 0.0), std::bit_cast<std::uint64_t>(c[2] + 0.0)};
      const auto [it, added] = index_.try_emplace(key, raw_.positions.size());
      if (added) raw_.add_vertex({c[0], c[1], c[2]}, p, false);
      raw_.corners.push_back(static_cast<std::int64_t>(it->second));
      return;
    }
    raw_.corners.push_back(static_cast<std::int64_t>(raw_.positions.size()));
    raw_.add_vertex({}, true);
  }

 private:
  struct Key {
    std::uint64_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return std::hash<std::uint64_t>{}(k.x ^ (k.y * 0x9E3779B97F4A7C15ull) ^ (k.z * 0xC2B2AE3D27D4EB4Full));
    }
  };
  RawMesh& raw_;
  std::unordered_map<Key, std::size_t, Hash> index_;
};

RawMesh read_stl(const std::string& path, std::string_view text) {
  RawMesh raw;
  StlVertices vertices(raw);
  // A binary STL's 80-byte header may start with anything, so the byte-order mark is skipped for the text form only.
  const std::string_view ascii = text.starts_with(kUtf8Bom) ? text.substr(kUtf8Bom.size()) : text;
  const std::size_t first = std::min(ascii.find_first_not_of(" \t\r\n"), ascii.size());
  const bool ascii_start = is_keyword(ascii.substr(first, 5), "solid");
  if (text.size() >= 84) {
    std::uint32_t triangles = 0;
    std::memcpy(&triangles, text.data() + 80, 4);
    if constexpr (std::endian::native == std::endian::big) triangles = __builtin_bswap32(triangles);
    if (84 + 50 * std::uint64_t{triangles} == text.size()) {
      raw.float_coordinates = true;
      for (std::uint32_t t = 0; t < triangles; ++t) {
        const char* record = text.data() + 84 + 50 * std::size_t{t};
        for (int corner = 0; corner < 3; ++corner) {
          double c[3];
          for (int i = 0; i < 3; ++i) {
            std::uint32_t bits = 0;
            std::memcpy(&bits, record + 12 + 12 * corner + 4 * i, 4);
            if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
            c[i] = std::bit_cast<float>(bits);
          }
          vertices.corner(c, true);
        }
        raw.end_face();
      }
      return raw;
    }
    if (!ascii_start)
      refuse(path, fmt::format("binary STL of {} bytes, but its header declares {} triangles ({} bytes)", text.size(), triangles,
                               84 + 50 * std::uint64_t{triangles}));
  }
  if (!ascii_start) refuse(path, "not an STL file (neither 'solid' text nor a binary triangle count)");
  std::vector<std::string_view> tokens;
  split(ascii, tokens);
  bool in_facet = false;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    if (is_keyword(tokens[i], "facet")) {
      in_facet = true;
    } else if (is_keyword(tokens[i], "vertex") && in_facet) {
      double c[3] = {0, 0, 0};
      bool readable = i + 3 < tokens.size();
      for (int k = 0; readable && k < 3; ++k) readable = parse_number(tokens[i + 1 + static_cast<std::size_t>(k)], c[k]);
      vertices.corner(c, readable);
      i += 3;
    } else if (is_keyword(tokens[i], "endfacet") && in_facet) {
      in_facet = false;
      raw.end_face();
    }
  }
  if (in_facet) refuse(path, fmt::format("truncated STL: the file ends inside facet {}", raw.face_count() + 1));
  return raw;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) refuse(path, "not readable");
  std::string text;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) refuse(path, "not readable");
  text.resize(static_cast<std::size_t>(size));
  in.seekg(0, std::ios::beg);
  in.read(text.data(), size);
  if (!in) refuse(path, "read failed");
  return text;
}

}  // namespace

bool ply_type(std::string_view name, PlyType& type) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::I8},   {"int8", PlyType::I8},     {"uchar", PlyType::U8},   {"uint8", PlyType::U8},
      {"short", PlyType::I16}, {"int16", PlyType::I16},   {"ushort", PlyType::U16}, {"uint16", PlyType::U16},
      {"int", PlyType::I32},   {"int32", PlyType::I32},   {"uint", PlyType::U32},   {"uint32", PlyType::U32},
      {"float", PlyType::F32}, {"float32", PlyType::F32}, {"double", PlyType::F64}, {"float64", PlyType::F64}};
  for (const auto& [n, t] : names)
    if (name == n) {
      type = t;
      return true;
    }
  return false;
}

std::size_t size_of(PlyType t) {
  switch (t) {
    case PlyType::I8:
    case PlyType::U8: return 1;
    case PlyType::I16:
    case PlyType::U16: return 2;
    case PlyType::I32:
    case PlyType::U32:
    case PlyType::F32: return 4;
    case PlyType::F64: return 8;
  }
  return 1;
}

PlyBody::Result PlyBody::next(PlyType type, double& value) {
  if (format_ == PlyFormat::Ascii) {
    while (pos_ < body_.size() && is_space(body_[pos_])) ++pos_;
    if (pos_ >= body_.size()) return End;
    const std::size_t begin = pos_;
    while (pos_ < body_.size() && !is_space(body_[pos_])) ++pos_;
    return parse_number(body_.substr(begin, pos_ - begin), value) ? Ok : Malformed;
  }
  const std::size_t size = size_of(type);
  if (body_.size() - pos_ < size) return End;
  unsigned char bytes[8];
  std::memcpy(bytes, body_.data() + pos_, size);
  pos_ += size;
  if ((format_ == PlyFormat::BinaryBig) != (std::endian::native == std::endian::big)) std::reverse(bytes, bytes + size);
  value = decode(type, bytes);
  return Ok;
}

PlyBody::Result PlyBody::end_record() {
  if (format_ != PlyFormat::Ascii) return Ok;
  while (pos_ < body_.size() && body_[pos_] != '\n' && is_space(body_[pos_])) ++pos_;
  if (pos_ >= body_.size()) return Ok;
  if (body_[pos_] != '\n') return Malformed;
  ++pos_;
  return Ok;
}

PlyBody::Result PlyBody::next_count(PlyType count_type, PlyType type, std::uint64_t& count) {
  double value = 0;
  const Result counted = next(count_type, value);
  if (counted != Ok) return counted;
  if (!(value >= 0) || value != std::floor(value)) return Malformed;
  // Compared as a double first: a float or double count may be beyond any integer.
  if (value > static_cast<double>(remaining() / (binary() ? size_of(type) : 2) + 1)) return End;
  count = static_cast<std::uint64_t>(value);
  return Ok;
}

PlyBody::Result PlyBody::skip_list(PlyType count_type, PlyType type) {
  std::uint64_t n = 0;
  if (const Result counted = next_count(count_type, type, n); counted != Ok) return counted;
  double value = 0;
  for (; n > 0; --n)
    if (next(type, value) == End) return End;
  return Ok;
}

PlyHeader parse_ply_header(const std::string& path, std::string_view text, const char* what) {
  const std::string prefix = fmt::format("cannot read {} {}", what, path);
  // The header: must end with end_header within the limit (OpenMesh's reader hangs without one).
  Lines lines(text);
  std::string_view line;
  if (!lines.next(line) || line.substr(0, line.find_last_not_of(" \t") + 1) != "ply") refuse_ply(prefix, "not a PLY file (no 'ply' first line)");
  std::vector<std::string> header;
  bool ended = false;
  while (lines.position() <= kPlyHeaderLimit && lines.next(line)) {
    std::vector<std::string_view> tokens;
    split(line, tokens);
    if (tokens.size() == 1 && tokens[0] == "end_header") {
      ended = true;
      break;
    }
    header.emplace_back(line);
  }
  if (!ended)
    refuse_ply(prefix, text.size() > kPlyHeaderLimit ? "PLY header has no end_header in its first MiB" : "PLY header has no end_header");
  const std::string_view body_text = text.substr(std::min(lines.position(), text.size()));
  PlyFormat format = PlyFormat::Ascii;
  bool has_format = false;
  std::vector<PlyElement> elements;
  std::vector<std::string_view> tokens;
  for (const std::string& h : header) {
    split(h, tokens);
    if (tokens.empty() || tokens[0] == "comment" || tokens[0] == "obj_info") continue;
    if (tokens[0] == "format" && tokens.size() >= 2) {
      has_format = true;
      if (tokens[1] == "ascii")
        format = PlyFormat::Ascii;
      else if (tokens[1] == "binary_little_endian")
        format = PlyFormat::BinaryLittle;
      else if (tokens[1] == "binary_big_endian")
        format = PlyFormat::BinaryBig;
      else
        refuse_ply(prefix, fmt::format("unknown PLY format '{}'", tokens[1]));
    } else if (tokens[0] == "element" && tokens.size() == 3) {
      PlyElement e;
      e.name = tokens[1];
      const auto [end, ec] = std::from_chars(tokens[2].data(), tokens[2].data() + tokens[2].size(), e.count);
      if (ec != std::errc() || end != tokens[2].data() + tokens[2].size())
        refuse_ply(prefix, fmt::format("PLY element {} has count '{}', not a number", e.name, tokens[2]));
      elements.push_back(std::move(e));
    } else if (tokens[0] == "property" && !elements.empty()) {
      PlyProperty p;
      bool ok = false;
      if (tokens.size() == 5 && tokens[1] == "list") {
        p.list = true;
        ok = ply_type(tokens[2], p.count_type) && ply_type(tokens[3], p.type);
        p.name = tokens[4];
      } else if (tokens.size() == 3) {
        ok = ply_type(tokens[1], p.type);
        p.name = tokens[2];
      }
      if (!ok) refuse_ply(prefix, fmt::format("PLY header line '{}' is not a property of a known type", h));
      elements.back().properties.push_back(std::move(p));
    } else {
      refuse_ply(prefix, fmt::format("PLY header line '{}' is not understood", h));
    }
  }
  if (!has_format) refuse_ply(prefix, "PLY header has no format line");
  // Every record takes at least a byte per scalar (binary) or a value and a separator (ASCII), so a
  // header claiming more records than that is refused before anything is allocated.
  for (const PlyElement& e : elements) {
    std::uint64_t least = 0;
    for (const PlyProperty& p : e.properties) least += format == PlyFormat::Ascii ? 2 : size_of(p.list ? p.count_type : p.type);
    least = std::max<std::uint64_t>(least, 1);
    if (e.count > (body_text.size() + 1) / least)
      refuse_ply(prefix, fmt::format("PLY header declares {} {} records, more than the {} after end_header can hold", e.count, e.name,
                               plural(body_text.size(), "byte", "bytes")));
  }
  return {format, std::move(elements), body_text};
}

bool parse_number(std::string_view token, double& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') token.remove_prefix(1);
  if (token.empty()) return false;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (end != token.data() + token.size()) return false;
  if (ec == std::errc::result_out_of_range) {
    // Beyond double range: strtod's ±HUGE_VAL (inf) or 0 for what is too small.
    const std::string copy(token);
    value = std::strtod(copy.c_str(), nullptr);
    return true;
  }
  return ec == std::errc();
}

RawMesh read_mesh_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) refuse(path, "it is a directory");
  if (!std::filesystem::is_regular_file(path, ec)) refuse(path, "no such file");
  if (!known_mesh_extension(lower_extension(path))) refuse(path, "not an OBJ, PLY, OFF or STL file (by its extension)");
  return parse_mesh_file(path, read_file(path));
}

RawMesh parse_mesh_file(const std::string& path, std::string_view text) {
  const std::string ext = lower_extension(path);
  if (!known_mesh_extension(ext)) refuse(path, "not an OBJ, PLY, OFF or STL file (by its extension)");
  if (ext == ".stl") return read_stl(path, text);
  // Before, an OBJ's mark made its first vertex unreadable: every later index pointed one vertex off.
  if (text.starts_with(kUtf8Bom)) text.remove_prefix(kUtf8Bom.size());
  if (ext == ".obj") return read_obj(path, text);
  if (ext == ".off") return read_off(path, text);
  return read_ply(path, text);
}

}  // namespace splatcl::mesh_io
