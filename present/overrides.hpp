#pragma once
// What `splatcl render` and `splatcl view` take from their command lines on top of the scene.
#include <optional>
#include <string>
#include <utility>

#include "core/scene.hpp"

namespace splatcl::present {

// "WIDTHxHEIGHT" with both in 1..8192; Error naming `what` otherwise.
std::pair<int, int> parse_frame_size(const std::string& text, const char* what);

// Command-line overrides of the quality settings; empty strings keep the scene's value. Error
// names the option for a value outside its set.
struct Overrides {
  std::string shading, mode, shadows;
  std::string filter;  // CSM shadow test (csm::parse_filter)
  // Unset keeps the scene's value; a given value out of range (negative, NaN) is an error.
  std::optional<long long> lights;  // generated light count
  std::optional<double> lod;        // LOD error threshold in pixels
  std::optional<double> specular;   // Blinn-Phong strength, 0 = off
};
void apply_overrides(Scene& scene, const Overrides& overrides);

}  // namespace splatcl::present
