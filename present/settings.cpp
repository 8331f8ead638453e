#include "present/settings.hpp"

#include <array>
#include <string_view>
#include <utility>

#include "runtime/error.hpp"

namespace splatcl::present {
namespace {

template <class E, std::size_t N>
E parse_one(const std::string& text, const char* setting, const std::array<std::pair<std::string_view, E>, N>& names) {
  std::string listed;
  for (const auto& [name, value] : names) {
    if (text == name) return value;
    listed += (listed.empty() ? "" : ", ") + std::string(name);
  }
  throw Error("quality." + std::string(setting) + " '" + text + "' is not one of " + listed);
}

}  // namespace

RenderMode parse_render_mode(const std::string& text) {
  return parse_one<RenderMode, 2>(text, "mode", {{{"splats", RenderMode::Splats}, {"points", RenderMode::Points}}});
}

ShadingMethod parse_shading_method(const std::string& text) {
  return parse_one<ShadingMethod, 3>(
      text, "shading",
      {{{"clustered", ShadingMethod::Clustered}, {"tiled", ShadingMethod::Tiled}, {"brute", ShadingMethod::Brute}}});
}

ShadowMode parse_shadow_mode(const std::string& text) {
  return parse_one<ShadowMode, 3>(
      text, "shadows", {{{"splat", ShadowMode::Splat}, {"pixel", ShadowMode::Pixel}, {"off", ShadowMode::Off}}});
}

FrameSettings FrameSettings::parse(const Quality& quality) {
  FrameSettings s;
  s.mode = parse_render_mode(quality.mode);
  s.shading = parse_shading_method(quality.shading);
  s.shadows = parse_shadow_mode(quality.shadows);
  s.filter = csm::parse_filter(quality.filter);
  return s;
}

}  // namespace splatcl::present
