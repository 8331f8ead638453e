#pragma once
// A double 3-vector for geometric checks that must not inherit float rounding (distances to the
// mesh surface, ellipse points far from the origin). The float Vec3 stays the type of the kernels.
#include <cmath>

#include "math/vec3.hpp"

namespace splatcl {

struct DVec3 {
  double x = 0, y = 0, z = 0;
  DVec3() = default;
  DVec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  explicit DVec3(Vec3 a) : x(a.x), y(a.y), z(a.z) {}
};

inline DVec3 operator+(DVec3 a, DVec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline DVec3 operator-(DVec3 a, DVec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline DVec3 operator*(double s, DVec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(DVec3 a, DVec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline DVec3 cross(DVec3 a, DVec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double length(DVec3 a) { return std::sqrt(dot(a, a)); }
inline DVec3 normalized(DVec3 a) {
  const double l = length(a);
  return l > 0 ? (1.0 / l) * a : DVec3{};
}
// A unit vector perpendicular to the unit vector n (crossed with the axis n is least along).
inline DVec3 any_perpendicular(DVec3 n) {
  const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
  const DVec3 axis = ax <= ay && ax <= az ? DVec3{1, 0, 0} : ay <= az ? DVec3{0, 1, 0} : DVec3{0, 0, 1};
  return normalized(cross(n, axis));
}
inline Vec3 to_float(DVec3 a) { return {static_cast<float>(a.x), static_cast<float>(a.y), static_cast<float>(a.z)}; }

}  // namespace splatcl
