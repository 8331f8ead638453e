#pragma once
// The .csm file: one coherent shadow map, described in docs/formats.md. A 256-byte header (magic,
// version, encoding, parameters, sphere, distribution, order, pole frame, object transform,
// section sizes, FNV-1a checksum, capture method) and three sections. Plain encoding: the thesis's layout, per-pixel
// offsets u32[M²+1], depths f32[S], inclusive end indices u32[S]. Compact encoding (exactly
// lossless, beyond the theses): 16-bit depth codes chosen inside each segment's interval, run
// lengths as LEB128 varints, and the float depths of the few segments no code fits.
// Written atomically; read with one read and validated completely before use.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "csm/capture.hpp"
#include "csm/compress.hpp"
#include "csm/raster_capture.hpp"
#include "csm/sphere_grid.hpp"

namespace splatcl::csm {

enum class Encoding : std::uint32_t { Plain = 0, Compact = 1 };
const char* to_string(Encoding value);
Encoding parse_encoding(const std::string& text);

struct CsmInfo {
  std::uint32_t resolution = 0, maps = 0;
  Distribution distribution = Distribution::Uniform;
  Order order = Order::ZigzagH;
  PoleAxis pole = PoleAxis::Y;
  SingleHit single_hit = SingleHit::SphereExit;
  float hit_epsilon = kDefaultHitEpsilon;
  // How the maps were captured: verify recaptures with the same method (the two differ at
  // triangle-edge pixels).
  CaptureMethod capture = kDefaultCaptureMethod;
  Sphere sphere;
  // Row-major 4×4 transform from the model file's coordinates to the object space the maps were
  // taken in; identity when the model was used as loaded.
  std::array<float, 16> object_transform{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::uint32_t triangles = 0;  // triangles the capture used
  std::string source;           // model file name, at most 39 bytes kept
};

struct Csm {
  CsmInfo info;
  std::vector<std::uint32_t> offsets{0};  // pixel p: segments [offsets[p], offsets[p + 1])
  std::vector<float> depth;               // stored depth per segment
  std::vector<std::uint32_t> end;         // inclusive end index in the map sequence

  std::size_t pixels() const { return offsets.size() - 1; }
  std::size_t segments() const { return end.size(); }
  // The stored depth of (pixel, map at sequence position i): binary search for the first end >= i.
  float lookup(std::size_t pixel, std::uint32_t sequence) const;
};

// Plain depths from fresh segments (segment_depth of each interval).
Csm make_csm(const CsmInfo& info, const Segments& segments);

// File bytes in the given encoding. Compact encoding chooses codes inside the segments' intervals
// when `intervals` is given; without it (a CSM read from a file) a code must reproduce the stored
// depth exactly, else the float is kept.
std::string encode_csm(const Csm& csm, Encoding encoding, const Segments* intervals = nullptr);
void write_csm(const std::string& path, const Csm& csm, Encoding encoding, const Segments* intervals = nullptr);

// Reads and validates everything (sizes, enums, checksum, monotone offsets and end indices, every
// pixel's list ending at map N − 1); throws Error naming the file and the first problem.
Csm read_csm(const std::string& path, Encoding* encoding = nullptr, std::size_t* file_bytes = nullptr);
// The same for bytes already in memory; `name` appears in errors.
Csm decode_csm(const std::string& bytes, const std::string& name, Encoding* encoding = nullptr);

inline constexpr std::size_t kCsmHeaderBytes = 256;
// Version 2 added the capture method (offset 212); other versions are refused.
inline constexpr std::uint32_t kCsmVersion = 2;

}  // namespace splatcl::csm
