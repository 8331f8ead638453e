#pragma once
// The one 3-vector of the host code (splats, CSM, cluster stage). Plain floats, operations
// written out term by term (no fused multiply-add) so the kernels, which do the same, round
// identically. The presenter uses GLM instead.
#include <cmath>

namespace splatcl {

struct Vec3 {
  float x = 0, y = 0, z = 0;
  friend bool operator==(Vec3 a, Vec3 b) = default;
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(float s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline Vec3 operator*(Vec3 a, float s) { return s * a; }
inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
// Unit vector along a; the zero vector stays zero (instead of becoming NaN).
inline Vec3 normalized(Vec3 a) {
  const float l = length(a);
  return l > 0 ? (1.0f / l) * a : Vec3{};
}
inline bool finite(Vec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

}  // namespace splatcl
