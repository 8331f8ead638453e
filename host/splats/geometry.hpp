#pragma once
// Small vector types shared by the splat stage. Vec4 and Rgba8 match OpenCL's float4 and uchar4
// layouts, so sample and splat arrays upload to the device without repacking.
#include <cmath>
#include <cstdint>

namespace splatcl::splats {

struct Vec3 {
  float x = 0, y = 0, z = 0;
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(float s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
// Written out term by term (no fused multiply-add) so the kernels, which do the same, round identically.
inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalized(Vec3 a) {
  const float l = length(a);
  return l > 0 ? (1.0f / l) * a : Vec3{};
}
inline bool finite(Vec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

struct alignas(16) Vec4 {
  float x = 0, y = 0, z = 0, w = 0;
};
inline Vec4 to_vec4(Vec3 a) { return {a.x, a.y, a.z, 0.0f}; }
inline Vec3 xyz(const Vec4& a) { return {a.x, a.y, a.z}; }

struct Rgba8 {
  std::uint8_t r = 128, g = 128, b = 128, a = 255;
};
inline bool operator==(Rgba8 p, Rgba8 q) { return p.r == q.r && p.g == q.g && p.b == q.b && p.a == q.a; }

// Axis-aligned bounding box.
struct Box {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  void add(Vec3 p) {
    lo = {std::fmin(lo.x, p.x), std::fmin(lo.y, p.y), std::fmin(lo.z, p.z)};
    hi = {std::fmax(hi.x, p.x), std::fmax(hi.y, p.y), std::fmax(hi.z, p.z)};
  }
  bool empty() const { return lo.x > hi.x; }
  float diagonal() const { return empty() ? 0.0f : length(hi - lo); }
};

}  // namespace splatcl::splats
