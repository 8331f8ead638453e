#include "splats/gaussian_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "io/atomic_file.hpp"
#include "io/binary.hpp"
#include "math/dvec3.hpp"

namespace splatcl::splats {
namespace {

// a / |a| into `a`, or false when a is zero or not finite.
bool normalize(DVec3& a) {
  const double len = length(a);
  if (!(len > 1e-30) || !std::isfinite(len)) return false;
  a = (1.0 / len) * a;
  return true;
}

}  // namespace

const std::vector<std::string>& gaussian_properties() {
  static const std::vector<std::string> names = {"x",       "y",       "z",       "nx",      "ny",    "nz",
                                                 "f_dc_0",  "f_dc_1",  "f_dc_2",  "opacity", "scale_0", "scale_1",
                                                 "scale_2", "rot_0",   "rot_1",   "rot_2",   "rot_3"};
  return names;
}

void rotation_quaternion(const double c0[3], const double c1[3], const double c2[3], double q[4]) {
  // m[row][column]
  const double m[3][3] = {{c0[0], c1[0], c2[0]}, {c0[1], c1[1], c2[1]}, {c0[2], c1[2], c2[2]}};
  const double trace = m[0][0] + m[1][1] + m[2][2];
  double w, x, y, z;
  // Shepperd: divide by the largest of 4w², 4x², 4y², 4z², never by a small one.
  if (trace >= m[0][0] && trace >= m[1][1] && trace >= m[2][2]) {
    const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 + trace));  // 4w
    w = s / 4, x = (m[2][1] - m[1][2]) / s, y = (m[0][2] - m[2][0]) / s, z = (m[1][0] - m[0][1]) / s;
  } else if (m[0][0] >= m[1][1] && m[0][0] >= m[2][2]) {
    const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 + m[0][0] - m[1][1] - m[2][2]));  // 4x
    w = (m[2][1] - m[1][2]) / s, x = s / 4, y = (m[0][1] + m[1][0]) / s, z = (m[0][2] + m[2][0]) / s;
  } else if (m[1][1] >= m[2][2]) {
    const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 - m[0][0] + m[1][1] - m[2][2]));  // 4y
    w = (m[0][2] - m[2][0]) / s, x = (m[0][1] + m[1][0]) / s, y = s / 4, z = (m[1][2] + m[2][1]) / s;
  } else {
    const double s = 2.0 * std::sqrt(std::max(0.0, 1.0 - m[0][0] - m[1][1] + m[2][2]));  // 4z
    w = (m[1][0] - m[0][1]) / s, x = (m[0][2] + m[2][0]) / s, y = (m[1][2] + m[2][1]) / s, z = s / 4;
  }
  const double len = std::sqrt(w * w + x * x + y * y + z * z);
  const double sign = w < 0 ? -1.0 : 1.0;  // q and −q are the same rotation; keep w ≥ 0
  q[0] = sign * w / len, q[1] = sign * x / len, q[2] = sign * y / len, q[3] = sign * z / len;
}

Gaussian to_gaussian(const SplatRecord& s) {
  // The splat's frame, made exactly orthonormal and right-handed: n, u ⟂ n, v = n × u.
  DVec3 n(s.normal);
  if (!normalize(n)) {
    n = cross(DVec3(s.major), DVec3(s.minor));
    if (!normalize(n)) n = {0, 0, 1};
  }
  const DVec3 major(s.major);
  DVec3 u = major - dot(major, n) * n;
  if (!normalize(u)) {
    const DVec3 minor(s.minor);
    DVec3 v = minor - dot(minor, n) * n;
    u = normalize(v) ? cross(v, n) : any_perpendicular(n);
  }
  const DVec3 v = cross(n, u);
  const double c0[3] = {u.x, u.y, u.z}, c1[3] = {v.x, v.y, v.z}, c2[3] = {n.x, n.y, n.z};
  double q[4];
  rotation_quaternion(c0, c1, c2, q);

  const double sigma_u = std::max(kGaussianSigmaPerSemiAxis * length(major), kGaussianMinSigma);
  const double sigma_v = std::max(kGaussianSigmaPerSemiAxis * length(DVec3(s.minor)), kGaussianMinSigma);
  const double sigma_n = std::max(kGaussianNormalSigma * sigma_v, kGaussianMinSigma);

  Gaussian g{};
  g.position[0] = s.center.x, g.position[1] = s.center.y, g.position[2] = s.center.z;
  g.normal[0] = static_cast<float>(n.x), g.normal[1] = static_cast<float>(n.y), g.normal[2] = static_cast<float>(n.z);
  const std::uint8_t rgb[3] = {s.color.r, s.color.g, s.color.b};
  for (int c = 0; c < 3; ++c) g.f_dc[c] = static_cast<float>((rgb[c] / 255.0 - 0.5) / kShC0);
  g.opacity = static_cast<float>(std::log(kGaussianAlpha / (1.0 - kGaussianAlpha)));
  g.scale[0] = static_cast<float>(std::log(sigma_u));
  g.scale[1] = static_cast<float>(std::log(sigma_v));
  g.scale[2] = static_cast<float>(std::log(sigma_n));
  for (int c = 0; c < 4; ++c) g.rotation[c] = static_cast<float>(q[c]);
  return g;
}

std::size_t write_gaussian_file(const std::string& path, const std::vector<SplatRecord>& splats) {
  std::string header = "ply\nformat binary_little_endian 1.0\n";
  header += fmt::format("comment splatcl 3dgs export: sigma = {:g} semi-axis, normal sigma = {:g} minor sigma, alpha {:g}, "
                        "SH degree 0, clip lines dropped\n",
                        kGaussianSigmaPerSemiAxis, kGaussianNormalSigma, kGaussianAlpha);
  header += fmt::format("element vertex {}\n", splats.size());
  for (const std::string& name : gaussian_properties()) header += "property float " + name + "\n";
  header += "end_header\n";
  std::string out = header;
  out.reserve(header.size() + splats.size() * gaussian_properties().size() * sizeof(float));
  std::size_t clipped = 0;
  for (const SplatRecord& s : splats) {
    if (std::isfinite(s.clip_offset)) ++clipped;
    const Gaussian g = to_gaussian(s);
    for (const float v : g.position) append_bytes(out, v);
    for (const float v : g.normal) append_bytes(out, v);
    for (const float v : g.f_dc) append_bytes(out, v);
    append_bytes(out, g.opacity);
    for (const float v : g.scale) append_bytes(out, v);
    for (const float v : g.rotation) append_bytes(out, v);
  }
  write_file_atomically(path, out);
  return clipped;
}

}  // namespace splatcl::splats
