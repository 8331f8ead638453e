#pragma once
// The quality settings a frame depends on, as enums. A scene's Quality keeps them as the text of the
// scene file (the viewer and the tests change it between frames); render() parses it once at the
// start of each frame, so no pass, light-list stage or lighting worker compares strings.
#include "csm/visibility.hpp"
#include "core/scene.hpp"

namespace splatcl::present {

enum class RenderMode { Splats, Points };               // quality.mode: "splats", "points"
enum class ShadingMethod { Clustered, Tiled, Brute };   // quality.shading: "clustered", "tiled", "brute"
enum class ShadowMode { Splat, Pixel, Off };            // quality.shadows: "splat", "pixel", "off"

struct FrameSettings {
  RenderMode mode = RenderMode::Splats;
  ShadingMethod shading = ShadingMethod::Clustered;
  ShadowMode shadows = ShadowMode::Splat;
  csm::Filter filter = csm::Filter::March;  // quality.filter (csm::parse_filter)
  // Error naming the setting and its values for text outside its set.
  static FrameSettings parse(const Quality& quality);
};

RenderMode parse_render_mode(const std::string& text);
ShadingMethod parse_shading_method(const std::string& text);
ShadowMode parse_shadow_mode(const std::string& text);

}  // namespace splatcl::present
