#include "splats/reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <tuple>

#include "core/parallel.hpp"
#include "splats/fit_device.hpp"

namespace splatcl::splats::reference {

// The size rule, sort key, colour test and hull test: splats::device, one source with the kernel.

static_assert(static_cast<int>(Stop::None) == STOP_NONE && static_cast<int>(Stop::Geometry) == STOP_GEOMETRY &&
                  static_cast<int>(Stop::Color) == STOP_COLOR,
              "Stop has the values of kernels/splat_fit.h");

namespace {

Vec3 canonical_sign(Vec3 a) {
  float m = a.x;
  if (std::fabs(a.y) > std::fabs(m)) m = a.y;
  if (std::fabs(a.z) > std::fabs(m)) m = a.z;
  return m < 0.0f ? Vec3{-a.x, -a.y, -a.z} : a;
}

Vec3 scaled(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }

Frame frame_of(const Samples& samples, const Neighborhoods& nb, std::size_t i, float crease_cos) {
  const std::uint32_t k = nb.k;
  const Vec3 p0 = xyz(samples.positions[i]);
  const float di = nb.kth_distance[i];
  const float scale = di > 0.0f ? 1.0f / di : 1.0f;
  const std::uint32_t* row = nb.indices.data() + i * k;
  const Vec4 n0 = samples.normals[i];
  const auto same_side = [&](std::uint32_t r) {
    const Vec4 nr = samples.normals[row[r]];
    return device::splat_same_side_of_crease(n0.x, n0.y, n0.z, nr.x, nr.y, nr.z, crease_cos);
  };
  std::uint32_t taken = 0;
  for (std::uint32_t r = 0; r < k; ++r) taken += same_side(r) ? 1 : 0;
  const bool take_all = taken < 2 || taken == k;
  const auto in_frame = [&](std::uint32_t r) { return take_all || same_side(r); };
  float mx = 0.0f, my = 0.0f, mz = 0.0f;
  for (std::uint32_t r = 0; r < k; ++r) {
    if (!in_frame(r)) continue;
    const Vec3 w = scaled(xyz(samples.positions[row[r]]) - p0, scale);
    mx += w.x, my += w.y, mz += w.z;
  }
  const float inv = 1.0f / static_cast<float>((take_all ? k : taken) + 1);
  mx *= inv, my *= inv, mz *= inv;
  float a[3][3];
  {
    float xx = mx * mx, xy = mx * my, xz = mx * mz, yy = my * my, yz = my * mz, zz = mz * mz;
    for (std::uint32_t r = 0; r < k; ++r) {
      if (!in_frame(r)) continue;
      const Vec3 w = scaled(xyz(samples.positions[row[r]]) - p0, scale);
      const float x = w.x - mx, y = w.y - my, z = w.z - mz;
      xx += x * x, xy += x * y, xz += x * z, yy += y * y, yz += y * z, zz += z * z;
    }
    a[0][0] = xx * inv, a[0][1] = xy * inv, a[0][2] = xz * inv;
    a[1][0] = xy * inv, a[1][1] = yy * inv, a[1][2] = yz * inv;
    a[2][0] = xz * inv, a[2][1] = yz * inv, a[2][2] = zz * inv;
  }
  float e[3][3] = {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  for (int sweep = 0; sweep < 10; ++sweep) {
    if (a[0][1] == 0.0f && a[0][2] == 0.0f && a[1][2] == 0.0f) break;
    for (int pair = 0; pair < 3; ++pair) {
      const int p = pair == 2 ? 1 : 0, q = pair == 0 ? 1 : 2;
      const float apq = a[p][q];
      if (apq == 0.0f) continue;
      const float theta = (a[q][q] - a[p][p]) / (2.0f * apq);
      float t = 1.0f / (std::fabs(theta) + std::sqrt(theta * theta + 1.0f));
      if (theta < 0.0f) t = -t;
      const float c = 1.0f / std::sqrt(t * t + 1.0f), s = t * c;
      for (int r = 0; r < 3; ++r) {
        const float arp = a[r][p], arq = a[r][q];
        a[r][p] = c * arp - s * arq;
        a[r][q] = s * arp + c * arq;
      }
      for (int r = 0; r < 3; ++r) {
        const float apr = a[p][r], aqr = a[q][r];
        a[p][r] = c * apr - s * aqr;
        a[q][r] = s * apr + c * aqr;
      }
      for (int r = 0; r < 3; ++r) {
        const float erp = e[r][p], erq = e[r][q];
        e[r][p] = c * erp - s * erq;
        e[r][q] = s * erp + c * erq;
      }
    }
  }
  int order[3] = {0, 1, 2};
  for (int x = 1; x < 3; ++x)
    for (int y = x; y > 0 && a[order[y]][order[y]] > a[order[y - 1]][order[y - 1]]; --y) std::swap(order[y], order[y - 1]);
  Vec3 u = canonical_sign({e[0][order[0]], e[1][order[0]], e[2][order[0]]});
  Vec3 v = canonical_sign({e[0][order[1]], e[1][order[1]], e[2][order[1]]});
  Vec3 n = cross(u, v);
  Vec3 m = xyz(samples.normals[i]);
  for (std::uint32_t r = 0; r < k; ++r) {
    if (!in_frame(r)) continue;
    const Vec3 w = xyz(samples.positions[row[r]]) - p0;
    const float d = std::sqrt(dot(w, w));
    const float weight = std::exp(-3.0f * d * scale);
    const Vec3 nj = xyz(samples.normals[row[r]]);
    m = m + Vec3{nj.x * weight, nj.y * weight, nj.z * weight};
  }
  {
    float fu[3] = {u.x, u.y, u.z}, fv[3] = {v.x, v.y, v.z}, fn[3] = {n.x, n.y, n.z};
    device::splat_frame_facing(fu, fv, fn, n0.x, n0.y, n0.z, crease_cos);
    u = {fu[0], fu[1], fu[2]}, v = {fv[0], fv[1], fv[2]}, n = {fn[0], fn[1], fn[2]};
  }
  if (dot(m, n) < 0.0f) u = scaled(u, -1.0f), v = scaled(v, -1.0f), n = scaled(n, -1.0f);
  return {to_vec4(u), to_vec4(v), to_vec4(n)};
}

float size_rule(float e1, float e2, Stop stop, bool at_accepted) {
  return device::splat_size_rule(e1, e2, static_cast<int>(stop), at_accepted);
}

struct Scratch {
  std::vector<std::uint32_t> seen_by;  // sample -> item that saw it last (+1)
  std::vector<std::pair<float, std::uint32_t>> ring;
  std::vector<std::uint32_t> next;
};

}  // namespace

bool color_similar(Rgba8 a, Rgba8 b, int tolerance) {
  return device::splat_color_similar(a.r, a.g, a.b, b.r, b.g, b.b, tolerance);
}

void mark_hull_points(const Samples& samples, Vec3 c, Vec3 fu, Vec3 fv, std::vector<std::uint32_t>& q) {
  const std::size_t qn = q.size();
  if (qn <= 3) return;
  // (x, y, local index) sorted lexicographically, as the kernel's sort_points.
  std::vector<std::tuple<float, float, std::uint32_t>> points(qn);
  float lo_x = INFINITY, hi_x = -INFINITY, lo_y = INFINITY, hi_y = -INFINITY;
  for (std::size_t r = 0; r < qn; ++r) {
    const Vec3 w = xyz(samples.positions[q[r]]) - c;
    const float x = dot(fu, w), y = dot(fv, w);
    points[r] = {x, y, static_cast<std::uint32_t>(r)};
    lo_x = std::fmin(lo_x, x), hi_x = std::fmax(hi_x, x), lo_y = std::fmin(lo_y, y), hi_y = std::fmax(hi_y, y);
  }
  std::sort(points.begin(), points.end());
  std::vector<float> xs(qn), ys(qn);
  std::vector<std::uint32_t> order(qn), hull(2 * qn);
  for (std::size_t r = 0; r < qn; ++r) std::tie(xs[r], ys[r], order[r]) = points[r];
  device::splat_mark_hull(xs.data(), ys.data(), order.data(), static_cast<std::uint32_t>(qn),
                          std::fmax(hi_x - lo_x, hi_y - lo_y), hull.data(), q.data(), kOnHullBit);
}

namespace {

// Grows splat i; returns Q with kOnHullBit on hull points.
std::vector<std::uint32_t> grow_one(const Samples& samples, const Neighborhoods& nb, const Frame& f,
                                    const FitOptions& options, std::uint32_t i, Scratch& scratch, SplatShape& out,
                                    Vec4& clip) {
  const std::uint32_t k = nb.k;
  auto seen_insert = [&](std::uint32_t j) {
    if (scratch.seen_by[j] == i + 1) return false;
    scratch.seen_by[j] = i + 1;
    return true;
  };
  const Vec3 p0 = xyz(samples.positions[i]);
  const Vec4 n0 = samples.normals[i];
  const float crease_cos = crease_cosine(options.crease_degrees);
  const Rgba8 c0 = samples.colors[i];
  const Vec3 fu = xyz(f.u), fv = xyz(f.v), fn = xyz(f.n);
  const float two_eps = 2.0f * options.eps;
  float hmin = 0.0f, hmax = 0.0f;
  std::vector<std::uint32_t> q{i};
  seen_insert(i);
  auto& ring = scratch.ring;
  auto& next = scratch.next;
  ring.clear(), next.clear();
  for (std::uint32_t r = 0; r < k; ++r) {
    const std::uint32_t j = nb.indices[std::size_t{i} * k + r];
    if (seen_insert(j)) ring.emplace_back(0.0f, j);
  }
  float extent1[2] = {0.0f, 1.0f}, extent2[2] = {-1.0f, -1.0f};
  Stop stop[2] = {Stop::None, Stop::None};
  float b = 0.0f;
  float clip_x = 0.0f, clip_y = 0.0f;  // sum of the unit in-plane directions to the skipped violators
  std::vector<std::uint32_t> rejected;
  std::size_t pos = 0;
  bool full = false;  // Q reached options.max_covered: both phases end as if no violator was met
  for (int ellipse = 0; ellipse < 2 && !full; ++ellipse) {
    if (ellipse) {
      b = options.retest_violator ? extent1[0] : size_rule(extent1[0], extent2[0], stop[0], options.size_at_accepted);
      const std::size_t from = stop[0] != Stop::None ? (options.retest_violator ? pos : pos + 1) : ring.size();
      ring.erase(ring.begin(), ring.begin() + static_cast<std::ptrdiff_t>(from));
      for (const std::uint32_t j : next) ring.emplace_back(0.0f, j);
      next.clear();
    }
    for (;;) {
      for (auto& [key, j] : ring) {
        const Vec3 w = xyz(samples.positions[j]) - p0;
        key = device::splat_growth_key(ellipse != 0, dot(fu, w), dot(fv, w), b);
      }
      std::sort(ring.begin(), ring.end());
      bool stopped = false;
      for (pos = 0; pos < ring.size(); ++pos) {
        const auto [key, j] = ring[pos];
        if (ellipse && key < 1.0f) continue;
        const Vec3 w = xyz(samples.positions[j]) - p0;
        const float h = dot(fn, w);
        const Vec4 nj = samples.normals[j];
        if (device::splat_other_sheet(n0.x, n0.y, n0.z, nj.x, nj.y, nj.z, h, crease_cos)) continue;
        const float lo = std::fmin(hmin, h), hi = std::fmax(hmax, h);
        const Stop violation = !color_similar(samples.colors[j], c0, options.color_tolerance) ? Stop::Color
                               : hi - lo > two_eps                                             ? Stop::Geometry
                                                                                               : Stop::None;
        if (violation != Stop::None) {
          if (options.clip) {
            const float wx = dot(fu, w), wy = dot(fv, w);
            const float len = std::sqrt(wx * wx + wy * wy);
            if (len > 0.0f && (rejected.empty() || wx * clip_x + wy * clip_y > 0.0f)) {
              clip_x += wx / len, clip_y += wy / len;
              rejected.push_back(j);
              continue;
            }
          }
          stop[ellipse] = violation, extent2[ellipse] = key, stopped = true;
          break;
        }
        if (q.size() == options.max_covered) {
          full = true;
          break;
        }
        hmin = lo, hmax = hi;
        q.push_back(j);
        extent1[ellipse] = std::fmax(extent1[ellipse], key);
        const std::uint32_t* row = nb.indices.data() + std::size_t{j} * k;
        for (std::uint32_t r = 0; r < k; ++r)
          if (seen_insert(row[r])) next.push_back(row[r]);
      }
      if (stopped || full || next.empty()) break;
      ring.clear();
      for (const std::uint32_t j : next) ring.emplace_back(0.0f, j);
      next.clear();
    }
    if (!ellipse && stop[0] == Stop::None) ring.clear(), next.clear();
  }

  const float minor = size_rule(extent1[0], extent2[0], stop[0], options.size_at_accepted);
  const float ratio = options.literal_lambda
                          ? size_rule(extent1[1], extent2[1], stop[1], options.size_at_accepted)
                          : size_rule(std::sqrt(extent1[1]), extent2[1] >= 0.0f ? std::sqrt(extent2[1]) : -1.0f, stop[1], options.size_at_accepted);
  const float major = ratio * minor;
  const float mid = 0.5f * (hmin + hmax);
  const Vec3 c{p0.x + fn.x * mid, p0.y + fn.y * mid, p0.z + fn.z * mid};
  out.center = {c.x, c.y, c.z, static_cast<float>(stop[0])};
  out.normal = {fn.x, fn.y, fn.z, static_cast<float>(stop[1])};
  out.major = {fu.x * major, fu.y * major, fu.z * major, major};
  out.minor = {fv.x * minor, fv.y * minor, fv.z * minor, minor};
  clip = {0.0f, 0.0f, INFINITY, 0.0f};
  const float clip_len = std::sqrt(clip_x * clip_x + clip_y * clip_y);
  if (!rejected.empty() && clip_len > 0.0f) {
    const float dx = clip_x / clip_len, dy = clip_y / clip_len;
    auto reach = [&](std::uint32_t m) {
      const Vec3 w = xyz(samples.positions[m]) - c;
      return dx * dot(fu, w) + dy * dot(fv, w);
    };
    float accepted_reach = -INFINITY, rejected_reach = INFINITY;
    for (const std::uint32_t m : q) accepted_reach = std::fmax(accepted_reach, reach(m));
    for (const std::uint32_t m : rejected) rejected_reach = std::fmin(rejected_reach, reach(m));
    const float offset = rejected_reach > accepted_reach ? accepted_reach + 0.5f * (rejected_reach - accepted_reach) : accepted_reach;
    clip = {dx, dy, offset, 0.0f};
  }

  mark_hull_points(samples, c, fu, fv, q);
  return q;
}

}  // namespace

std::vector<Frame> fit_frames(const Samples& samples, const Neighborhoods& neighbors, float crease_degrees) {
  std::vector<Frame> frames(samples.size());
  const float cosine = crease_cosine(crease_degrees);
  parallel_for(samples.size(), 256, [&](std::size_t i, std::size_t) { frames[i] = frame_of(samples, neighbors, i, cosine); });
  return frames;
}

FitResult grow_splats(const Samples& samples, const Neighborhoods& neighbors, const std::vector<Frame>& frames,
                      const FitOptions& options) {
  validate(options);
  const std::size_t n = samples.size();
  FitResult result;
  result.frames = frames;
  result.splats.resize(n);
  result.clips.resize(n);
  std::vector<std::vector<std::uint32_t>> sets(n);
  std::vector<Scratch> scratch(worker_count(n, 64));
  parallel_for(n, 64, [&](std::size_t i, std::size_t worker) {
    Scratch& s = scratch[worker];
    if (s.seen_by.size() != n) s.seen_by.assign(n, 0);
    sets[i] = grow_one(samples, neighbors, frames[i], options, static_cast<std::uint32_t>(i), s, result.splats[i],
                       result.clips[i]);
  });
  set_rows(sets, result);
  return result;
}

FitResult fit_splats(const Samples& samples, const Neighborhoods& neighbors, const FitOptions& options) {
  return grow_splats(samples, neighbors, fit_frames(samples, neighbors, options.crease_degrees), options);
}

}  // namespace splatcl::splats::reference
