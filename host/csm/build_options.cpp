#include "csm/build_options.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "csm/sphere_grid.hpp"
#include "runtime/error.hpp"

namespace splatcl::csm {

static_assert(kMaxMaps == 16777216, "the help texts of maps and batch state the limit");

const std::vector<ParameterInfo>& csm_parameters() {
  static const std::vector<ParameterInfo> list{
      {"maps", "Number of maps N, 1..16777216: G^2 for uniform/regular, 2T^2 for ao", false, false, true},
      {"res", "Map resolution M (M x M pixels), 1..8192", false, false, true},
      {"dist", "Direction grid: uniform, regular (G x G) or ao (the AO thesis's T x 2T)"},
      {"order", "Map order: zigzag-h, zigzag-v, linear-h, linear-v (h = theta fastest), hilbert, morton (extension)"},
      {"pole", "Object axis of the sphere's pole: y, z, x, or y180, z180, x180 (poles swapped). On the uniform grid the maps "
               "lie farthest apart around the pole (the 32 maps of the first row lie 14 degrees from it at 1024 maps and answer every "
               "direction within 20): put it on an axis that light and AO directions seldom follow (the presenter takes, per object, the axis farthest from up and the key lights)"},
      {"single_hit", "z2 of single-surface pixels: sphere-exit (the ray's exit from the bounding sphere), exact (z2 = z1), thin (z2 = z1 on every pixel, also behind a second surface: for an open mesh that encloses air, a bowl or a roof, at the cost of compression), or auto: exact for a mesh with a border or a non-manifold edge (a sheet, a scan with holes), sphere-exit for a closed one"},
      {"encoding", "File encoding: plain (float depth + u32 end, the thesis's layout) or compact (16-bit codes, exactly lossless)"},
      {"capture", "Capture method: raster (two-layer depth buffer) or raycast (SAH BVH); same depths up to rounding and "
                  "triangle-edge pixels; recorded in the .csm"},
      {"batch", "Maps captured per batch, 0..16777216 (0: about 8 M samples); memory only, the file is the same", false, false, true},
      {"hit_eps", "Hits closer than this x the bounding sphere's diameter count as one surface (shared edges), 1e-7..1e-2 "
                  "(default 1e-5): a part thinner than that reads as one surface, so its back face is lost and what lies "
                  "under it reads as lit; lower it for thin parts (a 1 mm pane in a 100 m model: below 5e-6)",
       false, false, true},
  };
  return list;
}

bool is_csm_parameter(const std::string& name) {
  const std::string key = parameter_key(name);
  const auto& list = csm_parameters();
  return std::any_of(list.begin(), list.end(), [&](const ParameterInfo& p) { return key == p.key; });
}

void set_parameter(CsmParameters& p, const std::string& name, const nlohmann::json& value) {
  const std::string key = parameter_key(name);
  if (key == "maps") {
    p.maps = static_cast<std::uint32_t>(integer_parameter(name, value, 1, kMaxMaps));
  } else if (key == "res") {
    p.res = static_cast<std::uint32_t>(integer_parameter(name, value, 1, 8192));
  } else if (key == "dist") {
    p.dist = string_parameter(name, value);
  } else if (key == "order") {
    p.order = string_parameter(name, value);
  } else if (key == "pole") {
    p.pole = string_parameter(name, value);
  } else if (key == "single_hit") {
    p.single_hit = string_parameter(name, value);
  } else if (key == "encoding") {
    p.encoding = string_parameter(name, value);
  } else if (key == "capture") {
    p.capture = string_parameter(name, value);
  } else if (key == "batch") {
    p.batch = static_cast<std::uint32_t>(integer_parameter(name, value, 0, kMaxMaps));
  } else if (key == "hit_eps") {
    const auto v = static_cast<float>(number_parameter(name, value));  // compared as the float it is stored as
    if (!(v >= kMinHitEpsilon && v <= kMaxHitEpsilon))
      throw Error(fmt::format("'{}' must be in [{:g}, {:g}], got {}", name, kMinHitEpsilon, kMaxHitEpsilon, shown_value(value)));
    p.hit_eps = v;
  } else {
    throw Error(fmt::format("unknown CSM parameter '{}'", name));
  }
}

void validate(const CsmParameters& p, Spelling spelling) {
  auto in_key = [spelling](const char* key, auto&& check) {
    try {
      check();
    } catch (const Error& e) {
      throw Error(fmt::format("{}: {}", spelled(key, spelling), e.what()));
    }
  };
  if (p.res < 1 || p.res > 8192) throw Error(fmt::format("{} must be an integer from 1 to 8192, got {}", spelled("res", spelling), p.res));
  in_key("dist", [&] { parse_distribution(p.dist); });
  in_key("order", [&] { parse_order(p.order); });
  in_key("pole", [&] { parse_pole_axis(p.pole); });
  in_key("single_hit", [&] { parse_single_hit(p.single_hit); });
  in_key("encoding", [&] { parse_encoding(p.encoding); });
  in_key("capture", [&] { parse_capture_method(p.capture); });
  // The grid's shape only: building its tables for 2^24 maps takes a second per model of a manifest.
  in_key("maps", [&] { grid_shape(parse_distribution(p.dist), parse_order(p.order), p.maps); });
}

nlohmann::json to_json(const CsmParameters& p) {
  nlohmann::json json = {{"maps", p.maps},   {"res", p.res},   {"dist", p.dist},         {"order", p.order},
                         {"pole", p.pole},   {"single_hit", p.single_hit}, {"capture", p.capture}, {"encoding", p.encoding}};
  // Only when not the default, so that records of earlier runs keep their parameters checksum.
  if (p.hit_eps != kDefaultHitEpsilon) json["hit_eps"] = p.hit_eps;
  return json;
}

BuildOptions to_build_options(const CsmParameters& p) {
  validate(p);
  BuildOptions options;
  options.maps = p.maps;
  options.resolution = p.res;
  options.distribution = parse_distribution(p.dist);
  options.order = parse_order(p.order);
  options.pole = parse_pole_axis(p.pole);
  options.single_hit = parse_single_hit(p.single_hit);
  options.capture = parse_capture_method(p.capture);
  options.batch_maps = p.batch;
  options.hit_epsilon = p.hit_eps;
  return options;
}

Encoding file_encoding(const CsmParameters& p) { return parse_encoding(p.encoding); }

}  // namespace splatcl::csm
