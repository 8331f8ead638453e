#include "present/overrides.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <initializer_list>

#include "csm/visibility.hpp"
#include "runtime/error.hpp"

namespace splatcl::present {

std::pair<int, int> parse_frame_size(const std::string& text, const char* what) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 1 || h < 1 ||
      w > 8192 || h > 8192)
    throw Error(fmt::format("{} '{}' is not WIDTHxHEIGHT with sides in 1..8192", what, text));
  return {w, h};
}

void apply_overrides(Scene& scene, const Overrides& o) {
  const auto pick = [](const std::string& value, const char* option, std::initializer_list<const char*> allowed,
                       std::string& target) {
    if (value.empty()) return;
    std::string list;
    for (const char* a : allowed) {
      if (value == a) {
        target = value;
        return;
      }
      list += (list.empty() ? "" : ", ") + std::string(a);
    }
    throw Error(fmt::format("{} '{}' is not one of: {}", option, value, list));
  };
  pick(o.shading, "--shading", {"clustered", "tiled", "brute"}, scene.quality.shading);
  pick(o.mode, "--mode", {"splats", "points"}, scene.quality.mode);
  pick(o.shadows, "--shadows", {"splat", "pixel", "off"}, scene.quality.shadows);
  if (!o.filter.empty()) {
    try {
      csm::parse_filter(o.filter);
    } catch (const Error& e) {
      throw Error(fmt::format("--filter: {}", e.what()));
    }
    scene.quality.filter = o.filter;
  }
  if (o.lod) {
    if (!(*o.lod >= 0 && *o.lod <= 1000)) throw Error(fmt::format("--lod {} is not a pixel error in [0, 1000]", *o.lod));
    scene.quality.lod_error = static_cast<float>(*o.lod);
  }
  if (o.specular) {
    if (!(*o.specular >= 0 && *o.specular <= kMaxSpecular))
      throw Error(fmt::format("--specular {} is not a highlight strength in [0, {}]", *o.specular, kMaxSpecular));
    scene.quality.specular = static_cast<float>(*o.specular);
  }
  if (o.lights) {
    if (*o.lights < 0 || *o.lights > kMaxSceneLights)
      throw Error(fmt::format("--lights {} is not a light count in [0, {}]", *o.lights, kMaxSceneLights));
    set_generated_light_count(scene, static_cast<std::uint32_t>(*o.lights));
  }
}

}  // namespace splatcl::present
