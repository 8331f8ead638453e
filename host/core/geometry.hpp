#pragma once
// Small vector types shared by the stages (Vec3 is the one of math/vec3.hpp). Vec4 and Rgba8
// match OpenCL's float4 and uchar4 layouts, so sample and splat arrays upload to the device
// without repacking.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "math/vec3.hpp"

namespace splatcl {


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
  // In double: a float |hi − lo|² overflows for extents above ~1e19 and underflows below ~1e-19;
  // a diagonal near the float limit (1.7e38) is finite only in double.
  double exact_diagonal() const {
    if (empty()) return 0.0;
    const double x = double{hi.x} - lo.x, y = double{hi.y} - lo.y, z = double{hi.z} - lo.z;
    return std::sqrt(x * x + y * y + z * z);
  }
  float diagonal() const { return static_cast<float>(exact_diagonal()); }
  // The largest |coordinate| of the box: floats there step by 2^-24 of it.
  double reach() const {
    if (empty()) return 0.0;
    return std::max({std::fabs(double{lo.x}), std::fabs(double{lo.y}), std::fabs(double{lo.z}), std::fabs(double{hi.x}),
                     std::fabs(double{hi.y}), std::fabs(double{hi.z})});
  }
};

}  // namespace splatcl
