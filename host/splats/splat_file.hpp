#pragma once
// The splat file: binary little-endian PLY, one "vertex" per splat with x y z, nx ny nz, red green
// blue (what point-cloud viewers read) and the splat's semi-axis vectors ux uy uz (major) and
// vx vy vz (minor) with their lengths major and minor. Clipped splats add clip_x clip_y (unit
// direction in the (u, v) frame) and clip_offset (distance of the clip line from the centre along
// it; no clip when clip_offset is +inf). Header comments carry the format version, the generating
// parameters (for `splatcl splats verify`) and an FNV-1a checksum of the whole file. The reader
// checks every header line against what the writer writes (property types, names and order
// included), the checksum, and each splat: finite centre, unit normal, finite semi-axes whose
// stored lengths are their lengths, a valid clip line.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry.hpp"
#include "math/dvec3.hpp"

namespace splatcl::splats {

struct SplatRecord {
  Vec3 center, normal, major, minor;  // major, minor: semi-axis vectors
  Rgba8 color;
  float clip_x = 0, clip_y = 0, clip_offset = INFINITY;
};

// Whether the splat's clip line cuts its ellipse as written (scale 1): the line's offset lies within
// the ellipse's reach along the line's normal, √((a·clip_x)² + (b·clip_y)²). A line beyond it keeps
// the whole splat at scale 1 but may cut it drawn larger (the presenter's splat scale k).
bool clip_cuts(const SplatRecord& s);

struct SplatFileInfo {
  std::string model;     // source mesh as given
  std::string sampling;  // "vertices" or "grid:N"
  float eps = 0;
  unsigned k = 0;
  int color_tolerance = 255;
  std::string color_source;  // "grey", "soft", "hard" or "texture:FILE"
  bool clipped = false;
  // The positions are relative to it: a splat's place in the model's coordinates is origin + center
  // (in double). Zero unless the model's coordinates were too coarse as floats for its size
  // or its eps (splats::recentre_test): a part at 1e5 keeps its detail.
  DVec3 origin{0, 0, 0};
};

// Version 4 adds `comment splatcl_origin X Y Z` after the colour source. Version 3 files (no origin
// line, origin zero) are still read. Version 3: the checksum (FNV-1a 64, io/checksum.hpp) covers the
// header too, its own 16 digits read as zeros; version 2 covered the body only, version 1 used a
// mistyped offset basis.
inline constexpr int kSplatFileVersion = 4;
inline constexpr int kOldestReadSplatFileVersion = 3;
// Whether a PLY's header says it is splatcl's splat file (its `comment splatcl_version` line);
// any other PLY is read as a 3D Gaussian splatting file where one may be (a scene's splat object).
bool is_splatcl_splat_file(const std::string& bytes);

// Reads a header line `comment splatcl_origin X Y Z` (three finite numbers, single spaces) into
// `origin`; false, leaving it, for any other line. Splat files and splatcl's 3DGS export carry it.
bool parse_origin_line(std::string_view text, DVec3& origin);

void write_splat_file(const std::string& path, const std::vector<SplatRecord>& splats, const SplatFileInfo& info);

struct SplatFile {
  SplatFileInfo info;
  std::vector<SplatRecord> splats;
};
// Throws Error naming the file (and the splat) for anything that is not a complete, uncorrupted
// splat file of the current version.
SplatFile read_splat_file(const std::string& path);
// The same for a file's bytes already in memory; `name` appears in errors.
SplatFile decode_splat_file(const std::string& bytes, const std::string& name);

}  // namespace splatcl::splats
