#include "splats/render.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/image.hpp"
#include "math/dvec3.hpp"
#include "runtime/error.hpp"

namespace splatcl::splats {

void render_splats(const std::string& path, const std::vector<SplatRecord>& splats, const RenderOptions& options) {
  const int w = options.width, h = options.height;
  if (w <= 0 || h <= 0) throw Error("render size must be positive");
  const float half_w = 0.5f * static_cast<float>(w), half_h = 0.5f * static_cast<float>(h);
  const Vec3 back = normalized(options.view);  // camera looks along -back
  const Vec3 right = normalized(cross(options.up, back));
  const Vec3 up = cross(back, right);
  Box box;
  for (const auto& s : splats) box.add({dot(s.center, right), dot(s.center, up), dot(s.center, back)});
  std::vector<float> rgb(static_cast<std::size_t>(w) * h * 3, 1.0f);
  if (box.empty()) return write_image_rgb(path, w, h, rgb);
  const float span = std::max(box.hi.x - box.lo.x, box.hi.y - box.lo.y) * 1.05f;
  const float scale = static_cast<float>(std::min(w, h)) / span;
  const float cx = 0.5f * (box.lo.x + box.hi.x), cy = 0.5f * (box.lo.y + box.hi.y);
  std::vector<float> depth(static_cast<std::size_t>(w) * h, -std::numeric_limits<float>::infinity());
  const Vec3 light = normalized(back + 0.5f * up + 0.3f * right);
  for (std::size_t i = 0; i < splats.size(); ++i) {
    const SplatRecord& s = splats[i];
    const auto a = static_cast<float>(length(DVec3(s.major))), b = static_cast<float>(length(DVec3(s.minor)));
    const Vec3 n = normalized(s.normal);
    const float facing = dot(n, back);
    if (!(a > 0 && b > 0) || std::fabs(facing) < 1e-3f) continue;
    const Vec3 u = to_float(normalized(DVec3(s.major))), v = to_float(normalized(DVec3(s.minor)));
    const Vec3 c{dot(s.center, right), dot(s.center, up), dot(s.center, back)};
    const int x0 = static_cast<int>(std::floor((c.x - a - cx) * scale + half_w)), x1 = static_cast<int>(std::ceil((c.x + a - cx) * scale + half_w));
    const int y0 = static_cast<int>(std::floor((c.y - a - cy) * scale + half_h)), y1 = static_cast<int>(std::ceil((c.y + a - cy) * scale + half_h));
    float color[3] = {s.color.r / 255.0f, s.color.g / 255.0f, s.color.b / 255.0f};
    if (options.random_colors) {
      std::uint32_t hash = static_cast<std::uint32_t>(i) * 2654435761u;
      for (float& ch : color) ch = 0.35f + 0.65f * static_cast<float>((hash >>= 8) & 0xFF) / 255.0f;
    }
    const float shade = 0.3f + 0.7f * std::fabs(dot(n, light));
    for (int y = std::max(y0, 0); y <= std::min(y1, h - 1); ++y) {
      for (int x = std::max(x0, 0); x <= std::min(x1, w - 1); ++x) {
        // Pixel ray (along -back) meets the splat plane; keep it when inside the ellipse.
        const float px = (static_cast<float>(x) + 0.5f - half_w) / scale + cx, py = (static_cast<float>(y) + 0.5f - half_h) / scale + cy;
        const Vec3 on_screen = px * right + py * up + c.z * back;
        const float t = dot(n, s.center - on_screen) / facing;
        const Vec3 hit = on_screen + t * back;
        const Vec3 r = hit - s.center;
        const float ru = dot(r, u) / a, rv = dot(r, v) / b;
        if (ru * ru + rv * rv > 1.0f) continue;
        if (ru * a * s.clip_x + rv * b * s.clip_y > s.clip_offset) continue;  // cut away by the clip line
        const float z = dot(hit, back);
        const std::size_t p = static_cast<std::size_t>(y) * w + x;
        if (z <= depth[p]) continue;
        depth[p] = z;
        for (int ch = 0; ch < 3; ++ch) rgb[3 * p + ch] = color[ch] * shade;
      }
    }
  }
  write_image_rgb(path, w, h, rgb);
}

}  // namespace splatcl::splats
