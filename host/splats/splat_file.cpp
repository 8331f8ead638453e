#include "splats/splat_file.hpp"

#include <fmt/format.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "io/atomic_file.hpp"
#include "io/binary.hpp"
#include "io/checksum.hpp"
#include "runtime/error.hpp"

namespace splatcl::splats {
namespace {

constexpr const char* kProperties[] = {"x", "y", "z", "nx", "ny", "nz", "ux", "uy", "uz", "vx", "vy", "vz", "major", "minor"};
constexpr const char* kClipProperties[] = {"clip_x", "clip_y", "clip_offset"};

// Comment values are single tokens; spaces in a path become %20.
std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text) c == ' ' ? out += "%20" : out += c;
  return out;
}
std::string unescape(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text.compare(i, 3, "%20") == 0) {
      out += ' ';
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

}  // namespace

void write_splat_file(const std::string& path, const std::vector<SplatRecord>& splats, const SplatFileInfo& info) {
  std::string body;
  for (const SplatRecord& s : splats) {
    const float values[] = {s.center.x, s.center.y, s.center.z, s.normal.x, s.normal.y, s.normal.z, s.major.x,
                            s.major.y,  s.major.z,  s.minor.x,  s.minor.y,  s.minor.z,  length(s.major), length(s.minor)};
    for (int p = 0; p < 6; ++p) append_bytes(body, values[p]);
    append_bytes(body, s.color.r), append_bytes(body, s.color.g), append_bytes(body, s.color.b);
    for (int p = 6; p < 14; ++p) append_bytes(body, values[p]);
    if (info.clipped) append_bytes(body, s.clip_x), append_bytes(body, s.clip_y), append_bytes(body, s.clip_offset);
  }
  std::string header = "ply\nformat binary_little_endian 1.0\n";
  header += fmt::format("comment splatcl_version {}\n", kSplatFileVersion);
  header += fmt::format("comment splatcl_model {}\n", escape(info.model));
  header += fmt::format("comment splatcl_sampling {}\n", info.sampling);
  header += fmt::format("comment splatcl_eps {:.9g}\n", info.eps);
  header += fmt::format("comment splatcl_k {}\n", info.k);
  header += fmt::format("comment splatcl_color_tolerance {}\n", info.color_tolerance);
  header += fmt::format("comment splatcl_color_source {}\n", escape(info.color_source));
  header += "comment splatcl_checksum " + checksum_hex(fnv1a64(body)) + "\n";
  header += fmt::format("element vertex {}\n", splats.size());
  for (int p = 0; p < 6; ++p) header += fmt::format("property float {}\n", kProperties[p]);
  header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  for (int p = 6; p < 14; ++p) header += fmt::format("property float {}\n", kProperties[p]);
  if (info.clipped)
    for (const char* name : kClipProperties) header += fmt::format("property float {}\n", name);
  header += "end_header\n";
  write_file_atomically(path, header + body);
}

SplatFile read_splat_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read splat file " + path + ": no such file or not readable");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto fail = [&](const std::string& why) { return Error("splat file " + path + ": " + why); };
  const std::size_t end = data.find("end_header\n");
  if (data.rfind("ply\n", 0) != 0 || end == std::string::npos) throw fail("not a PLY file");
  std::istringstream header(data.substr(0, end));
  SplatFile file;
  std::string line, checksum;
  int version = 0;
  std::size_t count = 0;
  bool have_count = false;
  std::vector<std::string> properties;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string word, key, value;
    words >> word;
    if (word == "format" && line != "format binary_little_endian 1.0") throw fail("not binary little-endian");
    if (word == "element") {
      words >> key >> count;
      if (key != "vertex" || !words) throw fail("unexpected element '" + line + "'");
      have_count = true;
    }
    if (word == "property") {
      std::string type;
      words >> type >> key;
      properties.push_back(key);
    }
    if (word != "comment") continue;
    words >> key >> value;
    if (key == "splatcl_version") version = std::atoi(value.c_str());
    if (key == "splatcl_model") file.info.model = unescape(value);
    if (key == "splatcl_sampling") file.info.sampling = value;
    if (key == "splatcl_eps") file.info.eps = std::strtof(value.c_str(), nullptr);
    if (key == "splatcl_k") file.info.k = static_cast<unsigned>(std::atoi(value.c_str()));
    if (key == "splatcl_color_tolerance") file.info.color_tolerance = std::atoi(value.c_str());
    if (key == "splatcl_color_source") file.info.color_source = unescape(value);
    if (key == "splatcl_checksum") checksum = value;
  }
  if (version != kSplatFileVersion) throw fail(fmt::format("not a splatcl splat file of version {}", kSplatFileVersion));
  if (!have_count) throw fail("no vertex element");
  file.info.clipped = properties.size() == 20;
  if (properties.size() != 17 && properties.size() != 20) throw fail("unexpected property list");
  const std::size_t record = 14 * sizeof(float) + 3 + (file.info.clipped ? 3 * sizeof(float) : 0);
  const std::string body = data.substr(end + 11);
  if (body.size() != count * record)
    throw fail(fmt::format("truncated or oversized: {} bytes for {} splats of {} bytes", body.size(), count, record));
  if (checksum != checksum_hex(fnv1a64(body))) throw fail("checksum mismatch (corrupted)");
  file.splats.resize(count);
  const char* p = body.data();
  auto take = [&p](auto& value) {
    std::memcpy(&value, p, sizeof(value));
    p += sizeof(value);
  };
  for (SplatRecord& s : file.splats) {
    float lengths[2];
    take(s.center.x), take(s.center.y), take(s.center.z), take(s.normal.x), take(s.normal.y), take(s.normal.z);
    take(s.color.r), take(s.color.g), take(s.color.b);
    take(s.major.x), take(s.major.y), take(s.major.z), take(s.minor.x), take(s.minor.y), take(s.minor.z);
    take(lengths[0]), take(lengths[1]);
    if (file.info.clipped) take(s.clip_x), take(s.clip_y), take(s.clip_offset);
  }
  return file;
}

}  // namespace splatcl::splats
