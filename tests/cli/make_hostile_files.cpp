// make_hostile_files DIR [GOOD.csm]: files that are wrong in one way each but carry a checksum that
// matches (recomputed by the format's rule, docs/formats.md), so only the reader's own checks can
// refuse them: splat files DIR/hostile-NAME.ply for each NAME below (and
// DIR/hostile-good.ply, which is valid); given a .csm, DIR/hostile-NAME.csm made from it.
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "io/checksum.hpp"
#include "csm/csm_file.hpp"
#include "splats/splat_file.hpp"

namespace {

using namespace splatcl;
using namespace splatcl::splats;

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// The file with its checksum recomputed.
std::string resealed(std::string file) {
  const std::string key = "comment splatcl_checksum ";
  const std::size_t at = file.find(key) + key.size();
  const std::size_t end = file.find("end_header\n") + 11;
  file.replace(at, 16, std::string(16, '0'));
  const std::uint64_t hash = fnv1a64(std::string_view(file).substr(end), fnv1a64(std::string_view(file).substr(0, end)));
  file.replace(at, 16, checksum_hex(hash));
  return file;
}

std::string replaced(std::string file, const std::string& from, const std::string& to) {
  file.replace(file.find(from), from.size(), to);
  return file;
}

// The file with the float at `byte_offset` in splat 0's record set to `value`.
std::string with_float(std::string file, std::size_t byte_offset, float value) {
  const std::size_t body = file.find("end_header\n") + 11;
  std::memcpy(file.data() + body + byte_offset, &value, sizeof value);
  return file;
}

// A .csm with `count` floats at `offset` of its header replaced, resealed: FNV-1a 64 of the header
// with its checksum (bytes 204..211) zeroed, then of the payload.
std::string csm_with_floats(std::string file, std::size_t offset, std::size_t count, float value) {
  for (std::size_t k = 0; k < count; ++k) std::memcpy(file.data() + offset + 4 * k, &value, sizeof value);
  std::memset(file.data() + 204, 0, 8);
  const std::uint64_t hash = fnv1a64(std::string_view(file).substr(csm::kCsmHeaderBytes), fnv1a64(std::string_view(file).substr(0, csm::kCsmHeaderBytes)));
  std::memcpy(file.data() + 204, &hash, sizeof hash);
  return file;
}

void write_csm_variants(const std::string& dir, const std::string& good) {
  const std::string file = read(good);
  // Bytes 72..107: the pole frame (3 x 3 floats); 108..171: the object transform (row-major 4 x 4).
  std::ofstream(dir + "/hostile-zero-pole-frame.csm", std::ios::binary) << csm_with_floats(file, 72, 9, 0.0f);
  std::ofstream(dir + "/hostile-nan-pole-frame.csm", std::ios::binary) << csm_with_floats(file, 72, 1, std::numeric_limits<float>::quiet_NaN());
  std::ofstream(dir + "/hostile-singular-transform.csm", std::ios::binary) << csm_with_floats(file, 108, 11, 0.0f);  // t[0..10]: the 3 x 3 part zero
  std::ofstream(dir + "/hostile-projective-transform.csm", std::ios::binary) << csm_with_floats(file, 108 + 4 * 12, 1, 0.5f);
  // A valid transform: model file x + 1 = object x (t[3], the x translation), for a model shifted by -1 in x.
  std::ofstream(dir + "/hostile-translated.csm", std::ios::binary) << csm_with_floats(file, 108 + 4 * 3, 1, 1.0f);
  // Bytes 20, 24, 28: the map count and the grid's rows and columns. A count of 46340² (the grid would
  // take gigabytes) with the checksum left as it was: refused by the checksum before any allocation.
  std::string huge = file;
  const std::uint32_t maps = 46340u * 46340u, side = 46340u;
  std::memcpy(huge.data() + 20, &maps, 4), std::memcpy(huge.data() + 24, &side, 4), std::memcpy(huge.data() + 28, &side, 4);
  std::ofstream(dir + "/hostile-huge-map-count.csm", std::ios::binary) << huge;
  // The same count resealed: refused by the map-count limit before the grid is sized.
  std::ofstream(dir + "/hostile-resealed-huge-map-count.csm", std::ios::binary) << csm_with_floats(huge, 72, 0, 0.0f);
  // 257 maps resealed: not a square, refused as the file's count, not as an option.
  std::string odd = file;
  const std::uint32_t odd_maps = 257;
  std::memcpy(odd.data() + 20, &odd_maps, 4);
  std::ofstream(dir + "/hostile-odd-map-count.csm", std::ios::binary) << csm_with_floats(odd, 72, 0, 0.0f);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 && argc != 3) {
    std::fprintf(stderr, "usage: make_hostile_files DIR [GOOD.csm]\n");
    return 2;
  }
  const std::string dir = argv[1];
  try {
    // A 5 x 5 grid of circles of radius 0.145 covering the unit square, none leaving it by more than eps 0.05.
    std::vector<SplatRecord> splats(25);
    for (int i = 0; i < 25; ++i) {
      splats[i].center = {0.1f + 0.2f * static_cast<float>(i % 5), 0.1f + 0.2f * static_cast<float>(i / 5), 0};
      splats[i].normal = {0, 0, 1};
      splats[i].major = {0.145f, 0, 0};
      splats[i].minor = {0, 0.145f, 0};
    }
    const std::string good = dir + "/hostile-good.ply";
    write_splat_file(good, splats, SplatFileInfo{"verify-plane.obj", "vertices", 0.05f, 10, 255, "grey", false});
    const std::string file = read(good);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    // Byte offsets in a record: x y z nx ny nz (0..23), red green blue (24..26), ux uy uz vx vy vz (27..50), major minor (51..58).
    const std::vector<std::pair<std::string, std::string>> variants = {
        {"double-x", resealed(replaced(file, "property float x\n", "property double x\n"))},
        {"swapped-xy", resealed(replaced(file, "property float x\nproperty float y\n", "property float y\nproperty float x\n"))},
        {"negative-k", resealed(replaced(file, "comment splatcl_k 10\n", "comment splatcl_k -3\n"))},
        {"nan-normal", resealed(with_float(file, 12, nan))},
        {"nan-axis", resealed(with_float(file, 27, nan))},
        {"negative-axis", resealed(with_float(file, 51, -0.4f))},
        // Not resealed: a flipped bit in the header that the old body-only checksum let through.
        {"floqt", replaced(file, "property float x\n", "property floqt x\n")},
        {"eps-flip", replaced(file, "comment splatcl_eps 0.0500000007\n", "comment splatcl_eps 0.0500000407\n")},
    };
    for (const auto& [name, contents] : variants) std::ofstream(dir + "/hostile-" + name + ".ply", std::ios::binary) << contents;
    if (argc == 3) write_csm_variants(dir, argv[2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_hostile_files: %s\n", e.what());
    return 1;
  }
  return 0;
}
