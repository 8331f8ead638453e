#include "splats/splat_file.hpp"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <cstring>
#include <string_view>

#include "io/atomic_file.hpp"
#include "io/binary.hpp"
#include "io/checksum.hpp"
#include "io/text_file.hpp"
#include "math/dvec3.hpp"
#include "runtime/error.hpp"

namespace splatcl::splats {
namespace {

constexpr const char* kProperties[] = {"x", "y", "z", "nx", "ny", "nz", "ux", "uy", "uz", "vx", "vy", "vz", "major", "minor"};
constexpr const char* kClipProperties[] = {"clip_x", "clip_y", "clip_offset"};

// Comment values are single tokens on one header line: a space, '%' and control characters in a
// path are written %XX (a newline in a model's file name split the line, and the file was no PLY).
std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte <= 0x20 || byte == 0x7F || c == '%')
      out += fmt::format("%{:02X}", byte);
    else
      out += c;
  }
  return out;
}
std::string unescape(const std::string& text) {
  const auto hex = [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; };
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() && hex(text[i + 1]) && hex(text[i + 2])) {
      out += static_cast<char>(std::stoi(text.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

// The property lines of a splat file, clipped or not.
std::string property_lines(bool clipped) {
  std::string lines;
  for (int p = 0; p < 6; ++p) lines += fmt::format("property float {}\n", kProperties[p]);
  lines += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  for (int p = 6; p < 14; ++p) lines += fmt::format("property float {}\n", kProperties[p]);
  if (clipped)
    for (const char* name : kClipProperties) lines += fmt::format("property float {}\n", name);
  return lines;
}

// The whole header as written; `checksum` is 16 hex digits.
std::string header_text(const SplatFileInfo& info, std::size_t count, const std::string& checksum) {
  std::string header = "ply\nformat binary_little_endian 1.0\n";
  header += fmt::format("comment splatcl_version {}\n", kSplatFileVersion);
  header += fmt::format("comment splatcl_model {}\n", escape(info.model));
  header += fmt::format("comment splatcl_sampling {}\n", info.sampling);
  header += fmt::format("comment splatcl_eps {:.9g}\n", info.eps);
  header += fmt::format("comment splatcl_k {}\n", info.k);
  header += fmt::format("comment splatcl_color_tolerance {}\n", info.color_tolerance);
  header += fmt::format("comment splatcl_color_source {}\n", escape(info.color_source));
  // fmt's shortest form that reads back as the same double.
  header += fmt::format("comment splatcl_origin {} {} {}\n", info.origin.x, info.origin.y, info.origin.z);
  header += "comment splatcl_checksum " + checksum + "\n";
  header += fmt::format("element vertex {}\n", count);
  header += property_lines(info.clipped);
  header += "end_header\n";
  return header;
}

constexpr const char* kZeroChecksum = "0000000000000000";

// FNV-1a 64 of the whole file with the checksum's 16 hex digits read as zeros: header and body.
std::uint64_t file_checksum(std::string_view header_with_zeros, std::string_view body) {
  return fnv1a64(body, fnv1a64(header_with_zeros));
}

}  // namespace

bool clip_cuts(const SplatRecord& s) {
  if (!(s.clip_offset < INFINITY)) return false;
  const double a = std::hypot(double{s.major.x}, double{s.major.y}, double{s.major.z}) * s.clip_x;
  const double b = std::hypot(double{s.minor.x}, double{s.minor.y}, double{s.minor.z}) * s.clip_y;
  return s.clip_offset < std::hypot(a, b);
}

void write_splat_file(const std::string& path, const std::vector<SplatRecord>& splats, const SplatFileInfo& info) {
  std::string body;
  for (const SplatRecord& s : splats) {
    // The lengths in double: the float squares overflow beyond 1.8e19 and underflow below 1e-19 (a
    // mesh at 1e20 stored major = inf for a finite axis vector).
    const float values[] = {s.center.x, s.center.y, s.center.z, s.normal.x, s.normal.y, s.normal.z, s.major.x, s.major.y, s.major.z,
                            s.minor.x,  s.minor.y,  s.minor.z,  static_cast<float>(length(DVec3(s.major))),
                            static_cast<float>(length(DVec3(s.minor)))};
    for (int p = 0; p < 6; ++p) append_bytes(body, values[p]);
    append_bytes(body, s.color.r), append_bytes(body, s.color.g), append_bytes(body, s.color.b);
    for (int p = 6; p < 14; ++p) append_bytes(body, values[p]);
    if (info.clipped) append_bytes(body, s.clip_x), append_bytes(body, s.clip_y), append_bytes(body, s.clip_offset);
  }
  const std::string zeros = header_text(info, splats.size(), kZeroChecksum);
  write_file_atomically(path, header_text(info, splats.size(), checksum_hex(file_checksum(zeros, body))) + body);
}

bool parse_origin_line(std::string_view text, DVec3& origin) {
  constexpr std::string_view prefix = "comment splatcl_origin ";
  if (!text.starts_with(prefix)) return false;
  double xyz[3] = {NAN, NAN, NAN};
  const char* at = text.data() + prefix.size();
  const char* const stop = text.data() + text.size();
  for (int axis = 0; axis < 3; ++axis) {
    if (axis > 0 && !(at < stop && *at++ == ' ')) return false;
    const auto [ptr, ec] = std::from_chars(at, stop, xyz[axis]);
    if (ec != std::errc() || !std::isfinite(xyz[axis])) return false;
    at = ptr;
  }
  if (at != stop) return false;
  origin = {xyz[0], xyz[1], xyz[2]};
  return true;
}

bool is_splatcl_splat_file(const std::string& bytes) {
  // In the header only: a large 3DGS file has no such line, and its body need not be searched.
  const std::string_view text(bytes);
  return text.substr(0, text.find("end_header")).find("\ncomment splatcl_version ") != std::string_view::npos;
}

SplatFile read_splat_file(const std::string& path) { return decode_splat_file(read_text_file(path, "splat file"), path); }

SplatFile decode_splat_file(const std::string& data, const std::string& path) {
  const auto fail = [&](const std::string& why) { return Error("splat file " + path + ": " + why); };
  const std::size_t end = data.find("end_header\n");
  if (data.rfind("ply\n", 0) != 0 || end == std::string::npos) throw fail("not a PLY file");
  std::vector<std::string> lines;
  for (std::size_t at = 0; at < end + 11;) {
    const std::size_t eol = data.find('\n', at);
    lines.push_back(data.substr(at, eol - at));
    at = eol + 1;
  }
  // Every line is checked against what write_splat_file writes, in order: the format, the version,
  // the parameters, the checksum, the count, each property's type and name, end_header.
  std::size_t line = 1;
  const auto next = [&]() -> const std::string& {
    if (line >= lines.size()) throw fail("header ends early");
    return lines[line++];
  };
  const auto comment = [&](const char* key) {
    const std::string& text = next();
    const std::string prefix = std::string("comment ") + key + " ";
    if (text.rfind(prefix, 0) != 0 || text.find(' ', prefix.size()) != std::string::npos)
      throw fail(fmt::format("header line {} is '{}', not 'comment {} VALUE'", line, text, key));
    return text.substr(prefix.size());
  };
  const auto number = [&](const char* key, auto& value) {
    const std::string text = comment(key);
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || ptr != text.data() + text.size()) throw fail(fmt::format("{} '{}' is not a number", key, text));
  };
  if (next() != "format binary_little_endian 1.0") throw fail("not binary little-endian PLY 1.0");
  if (!is_splatcl_splat_file(data))
    throw fail("not a splatcl splat file (no 'comment splatcl_version' in its header): a 3D Gaussian splatting PLY, such as splats "
               "--format 3dgs writes, keeps no eps or clip lines (a scene reads one as an object; verify the file splats writes by "
               "default)");
  int version = 0;
  {
    const std::string text = comment("splatcl_version");
    if (text == std::to_string(kSplatFileVersion))
      version = kSplatFileVersion;
    else if (text == std::to_string(kOldestReadSplatFileVersion))
      version = kOldestReadSplatFileVersion;
    else
      throw fail(fmt::format("not a splatcl splat file of version {} to {} (it has version {}; rebuild it with splatcl splats)",
                             kOldestReadSplatFileVersion, kSplatFileVersion, text));
  }
  SplatFile file;
  file.info.model = unescape(comment("splatcl_model"));
  file.info.sampling = comment("splatcl_sampling");
  number("splatcl_eps", file.info.eps);
  long long k = 0;
  number("splatcl_k", k);
  number("splatcl_color_tolerance", file.info.color_tolerance);
  file.info.color_source = unescape(comment("splatcl_color_source"));
  if (version >= 4) {
    const std::string& text = next();
    if (!parse_origin_line(text, file.info.origin))
      throw fail(fmt::format("header line {} is '{}', not 'comment splatcl_origin X Y Z' (three finite numbers)", line, text));
  }
  const std::size_t checksum_line = line;
  const std::string checksum = comment("splatcl_checksum");
  if (!(std::isfinite(file.info.eps) && file.info.eps > 0)) throw fail(fmt::format("eps {} is not positive", file.info.eps));
  if (k < 1 || k > 1024) throw fail(fmt::format("k {} is not in 1..1024", k));
  file.info.k = static_cast<unsigned>(k);
  if (file.info.color_tolerance < 0 || file.info.color_tolerance > 255)
    throw fail(fmt::format("colour tolerance {} is not in 0..255", file.info.color_tolerance));
  std::size_t count = 0;
  {
    const std::string& text = next();
    const std::string prefix = "element vertex ";
    const bool element = text.rfind(prefix, 0) == 0;
    const char* digits = text.data() + (element ? prefix.size() : 0);
    const auto [ptr, ec] = std::from_chars(digits, text.data() + text.size(), count);
    if (!element || ec != std::errc() || ptr != text.data() + text.size())
      throw fail(fmt::format("header line {} is '{}', not 'element vertex COUNT'", line, text));
  }
  std::string properties;
  for (; line + 1 < lines.size(); ++line) properties += lines[line] + "\n";
  file.info.clipped = properties == property_lines(true);
  if (!file.info.clipped && properties != property_lines(false))
    throw fail("the properties are not those of a splat file (x y z nx ny nz red green blue ux uy uz vx vy vz major minor [clip_x clip_y clip_offset], all float but the uchar colours)");
  const std::size_t record = 14 * sizeof(float) + 3 + (file.info.clipped ? 3 * sizeof(float) : 0);
  const std::string_view body = std::string_view(data).substr(end + 11);
  if (count > body.size() / record || body.size() != count * record)
    throw fail(fmt::format("truncated or oversized: {} bytes for {} splats of {} bytes", body.size(), count, record));
  std::string header = data.substr(0, end + 11);
  std::size_t checksum_at = 0;
  for (std::size_t l = 0; l < checksum_line; ++l) checksum_at += lines[l].size() + 1;
  checksum_at += std::string("comment splatcl_checksum ").size();
  if (checksum.size() != 16) throw fail("checksum '" + checksum + "' is not 16 hex digits");
  header.replace(checksum_at, 16, kZeroChecksum);
  if (checksum != checksum_hex(file_checksum(header, body))) throw fail("checksum mismatch (corrupted header or body)");
  file.splats.resize(count);
  const char* p = body.data();
  auto take = [&p](auto& value) {
    std::memcpy(&value, p, sizeof(value));
    p += sizeof(value);
  };
  const auto finite3 = [](const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  for (std::size_t i = 0; i < count; ++i) {
    SplatRecord& s = file.splats[i];
    float lengths[2];
    take(s.center.x), take(s.center.y), take(s.center.z), take(s.normal.x), take(s.normal.y), take(s.normal.z);
    take(s.color.r), take(s.color.g), take(s.color.b);
    take(s.major.x), take(s.major.y), take(s.major.z), take(s.minor.x), take(s.minor.y), take(s.minor.z);
    take(lengths[0]), take(lengths[1]);
    if (file.info.clipped) take(s.clip_x), take(s.clip_y), take(s.clip_offset);
    const auto bad = [&](const std::string& why) { return fail(fmt::format("splat {}: {}", i, why)); };
    if (!finite3(s.center)) throw bad("non-finite centre");
    if (!finite3(s.normal) || std::abs(length(s.normal) - 1.0f) > 1e-2f) throw bad("the normal is not a finite unit vector");
    if (!finite3(s.major) || !finite3(s.minor)) throw bad("non-finite semi-axis");
    for (int a = 0; a < 2; ++a) {
      const double expected = length(DVec3(a == 0 ? s.major : s.minor));
      if (!(lengths[a] >= 0) || !std::isfinite(lengths[a]) || std::abs(lengths[a] - expected) > 1e-4 * expected + std::numeric_limits<float>::denorm_min())
        throw bad(fmt::format("{} axis length {} is not the length {} of its vector", a == 0 ? "major" : "minor", lengths[a],
                              static_cast<float>(expected)));
    }
    if (file.info.clipped && (!std::isfinite(s.clip_x) || !std::isfinite(s.clip_y) || std::isnan(s.clip_offset) || s.clip_offset == -INFINITY))
      throw bad("bad clip line");
  }
  return file;
}

}  // namespace splatcl::splats
