#include "splats/gaussian_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "io/atomic_file.hpp"
#include "io/binary.hpp"
#include "math/dvec3.hpp"
#include "runtime/error.hpp"
#include "core/mesh_readers.hpp"

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

std::size_t write_gaussian_file(const std::string& path, const std::vector<SplatRecord>& splats, const DVec3& origin) {
  std::string header = "ply\nformat binary_little_endian 1.0\n";
  header += fmt::format("comment splatcl 3dgs export: sigma = {:g} semi-axis, normal sigma = {:g} minor sigma, alpha {:g}, "
                        "SH degree 0, clip lines dropped\n",
                        kGaussianSigmaPerSemiAxis, kGaussianNormalSigma, kGaussianAlpha);
  if (origin.x != 0 || origin.y != 0 || origin.z != 0)
    header += fmt::format("comment splatcl_origin {} {} {}\n", origin.x, origin.y, origin.z);
  header += fmt::format("element vertex {}\n", splats.size());
  for (const std::string& name : gaussian_properties()) header += "property float " + name + "\n";
  header += "end_header\n";
  std::string out = header;
  out.reserve(header.size() + splats.size() * gaussian_properties().size() * sizeof(float));
  std::size_t clipped = 0;
  for (const SplatRecord& s : splats) {
    if (clip_cuts(s)) ++clipped;
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

DVec3 gaussian_file_origin(const std::string& bytes, const std::string& name) {
  const std::string_view header = std::string_view(bytes).substr(0, bytes.find("end_header"));
  DVec3 origin{0, 0, 0};
  for (std::size_t at = 0; at < header.size();) {
    const std::size_t eol = std::min(header.find('\n', at), header.size());
    std::string_view line = header.substr(at, eol - at);
    if (line.ends_with('\r')) line.remove_suffix(1);
    if (line.starts_with("comment splatcl_origin") && !parse_origin_line(line, origin))
      throw Error(fmt::format("cannot read 3D Gaussian Splatting file {}: header line '{}' is not 'comment splatcl_origin X Y Z' "
                              "(three finite numbers)",
                              name, line));
    at = eol + 1;
  }
  return origin;
}

std::vector<SplatRecord> decode_gaussian_file(const std::string& bytes, const std::string& name) {
  const std::string what = "3D Gaussian Splatting file";
  const mesh_io::PlyHeader header = mesh_io::parse_ply_header(name, bytes, what.c_str());
  const auto fail = [&](const std::string& why) { return Error(fmt::format("cannot read {} {}: {}", what, name, why)); };
  const auto vertices = std::find_if(header.elements.begin(), header.elements.end(), [](const auto& e) { return e.name == "vertex"; });
  if (vertices == header.elements.end()) throw fail("no vertex element");
  const auto index = [&](const char* property, bool required) {
    const int i = vertices->find(property);
    if (i < 0 && required) throw fail(fmt::format("the vertex element has no '{}' property", property));
    if (i >= 0 && vertices->properties[static_cast<std::size_t>(i)].list) throw fail(fmt::format("'{}' is a list, not a number", property));
    return i;
  };
  const int x = index("x", true), y = index("y", true), z = index("z", true);
  const int scale[3] = {index("scale_0", true), index("scale_1", true), index("scale_2", true)};
  const int rot[4] = {index("rot_0", true), index("rot_1", true), index("rot_2", true), index("rot_3", true)};
  const int dc[3] = {index("f_dc_0", false), index("f_dc_1", false), index("f_dc_2", false)};
  const int normal[3] = {index("nx", false), index("ny", false), index("nz", false)};
  const int opacity = index("opacity", false);
  for (const auto& e : header.elements)
    if (&e != &*vertices && e.count > 0) throw fail(fmt::format("element '{}' after or beside the Gaussians is not understood", e.name));

  mesh_io::PlyBody body(header.body, header.format);
  std::vector<double> v(vertices->properties.size());
  std::vector<SplatRecord> splats;
  splats.reserve(vertices->count);
  for (std::uint64_t r = 0; r < vertices->count; ++r) {
    for (std::size_t k = 0; k < v.size(); ++k) {
      const mesh_io::PlyProperty& p = vertices->properties[k];
      // A list property is none of the used ones (index() refused those): skipped whole.
      const auto result = p.list ? body.skip_list(p.count_type, p.type) : body.next(p.type, v[k]);
      if (result == mesh_io::PlyBody::End) throw fail(fmt::format("truncated: the file ends in Gaussian {} of {}", r + 1, vertices->count));
      if (result == mesh_io::PlyBody::Malformed && p.list) throw fail(fmt::format("Gaussian {}: the list '{}' has a length that is not a count", r + 1, p.name));
      if (result == mesh_io::PlyBody::Malformed) throw fail(fmt::format("Gaussian {}: '{}' is not a number", r + 1, p.name));
    }
    if (body.end_record() == mesh_io::PlyBody::Malformed)
      throw fail(fmt::format("Gaussian {}: its line holds more or fewer values than the vertex element's {} properties", r + 1, v.size()));
    const auto at = [&](int i) { return v[static_cast<std::size_t>(i)]; };
    // NaN in the colour, opacity or normal was taken silently (a NaN opacity kept the Gaussian, a
    // NaN colour rounded to whatever lround gives).
    for (const int i : {dc[0], dc[1], dc[2], opacity, normal[0], normal[1], normal[2]})
      if (i >= 0 && std::isnan(at(i)))
        throw fail(fmt::format("Gaussian {}: '{}' is not a number", r + 1, vertices->properties[static_cast<std::size_t>(i)].name));
    // An infinite normal component picked the facing side at random (dark specks on a face).
    for (const int i : {normal[0], normal[1], normal[2]})
      if (i >= 0 && !std::isfinite(at(i)))
        throw fail(fmt::format("Gaussian {}: '{}' is not finite", r + 1, vertices->properties[static_cast<std::size_t>(i)].name));
    if (opacity >= 0 && 1.0 / (1.0 + std::exp(-at(opacity))) < kGaussianMinReadAlpha) continue;
    double q[4] = {at(rot[0]), at(rot[1]), at(rot[2]), at(rot[3])};
    const double q_len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(q_len > 1e-30) || !std::isfinite(q_len)) throw fail(fmt::format("Gaussian {}: its rotation quaternion is zero or not finite", r + 1));
    for (double& c : q) c /= q_len;
    const double w = q[0], qx = q[1], qy = q[2], qz = q[3];
    // The rotation's columns: the Gaussian's local x, y, z axes.
    const DVec3 axes[3] = {{1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + w * qz), 2 * (qx * qz - w * qy)},
                           {2 * (qx * qy - w * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + w * qx)},
                           {2 * (qx * qz + w * qy), 2 * (qy * qz - w * qx), 1 - 2 * (qx * qx + qy * qy)}};
    double sigma[3];
    for (int c = 0; c < 3; ++c) {
      sigma[c] = std::exp(at(scale[c]));
      if (!std::isfinite(sigma[c])) throw fail(fmt::format("Gaussian {}: scale_{} is not finite", r + 1, c));
    }
    int order[3] = {0, 1, 2};  // by σ, largest first; ties keep the file's order
    std::stable_sort(order, order + 3, [&](int a, int b) { return sigma[a] > sigma[b]; });
    DVec3 n = axes[order[2]];
    if (normal[0] >= 0 && normal[1] >= 0 && normal[2] >= 0 && dot(n, DVec3{at(normal[0]), at(normal[1]), at(normal[2])}) < 0) n = -1.0 * n;
    SplatRecord s;
    s.center = {static_cast<float>(at(x)), static_cast<float>(at(y)), static_cast<float>(at(z))};
    if (!finite(s.center)) throw fail(fmt::format("Gaussian {}: its centre is not finite", r + 1));
    const DVec3 major = (sigma[order[0]] / kGaussianSigmaPerSemiAxis) * axes[order[0]];
    const DVec3 minor = (sigma[order[1]] / kGaussianSigmaPerSemiAxis) * axes[order[1]];
    s.normal = {static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)};
    s.major = {static_cast<float>(major.x), static_cast<float>(major.y), static_cast<float>(major.z)};
    s.minor = {static_cast<float>(minor.x), static_cast<float>(minor.y), static_cast<float>(minor.z)};
    if (!finite(s.major) || !finite(s.minor))  // exp(scale) finite as a double, beyond float range
      throw fail(fmt::format("Gaussian {}: its scale makes an axis beyond float range", r + 1));
    if (dc[0] >= 0 && dc[1] >= 0 && dc[2] >= 0) {
      std::uint8_t rgb[3];
      for (int c = 0; c < 3; ++c) rgb[c] = static_cast<std::uint8_t>(std::lround(std::clamp(255.0 * (0.5 + kShC0 * at(dc[c])), 0.0, 255.0)));
      s.color = {rgb[0], rgb[1], rgb[2], 255};
    }
    splats.push_back(s);
  }
  if (splats.empty()) throw fail(vertices->count == 0 ? "it has no Gaussians" : "every Gaussian is fainter than the opacity kept on reading");
  return splats;
}

}  // namespace splatcl::splats
