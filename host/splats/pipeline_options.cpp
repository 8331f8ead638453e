#include "splats/pipeline_options.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "runtime/error.hpp"

namespace splatcl::splats {

const std::vector<ParameterInfo>& splat_parameters() {
  static const std::string max_covered_help =
      fmt::format("Growth cap: a splat stops growing when it covers this many samples (keeps flat regions linear), 4..{}; with "
                  "thesis_only the default is {} / samples, at least {} (bounds the accepted sets' memory)",
                  kMaxCoveredLimit, kCoveredBudget, kMinBudgetCap);
  static const std::vector<ParameterInfo> list{
      {"eps", "Geometric tolerance epsilon, absolute in model units (0: eps_diag times the bounding-box diagonal); one larger than the diagonal is capped at it", false, false, true},
      {"eps_diag", "Epsilon as a fraction of the bounding-box diagonal when eps is 0", false, false, true},
      {"color_tol", "Colour tolerance phi per RGB channel, 0..255 (255 ignores colour)", false, false, true},
      {"color_field", "Sample colours without a texture: grey, soft (red to white gradient), hard (3-D checker of flat colours) or "
                      "rainbow (cells of continuous hue bands with hard edges between cells)"},
      {"texture", "Texture image applied through the mesh's texture coordinates (nearest texel)", false, true},
      {"samples", "auto (vertices plus, on every face, grid points at a spacing of 0.5*sqrt(eps*diagonal), coarsened to fit "
                  "max_samples), vertices, grid:N (the thesis: spacing shortest-edge / N) or spacing:D (absolute spacing D)"},
      {"max_samples", "Sample budget: a sampling estimated to exceed it is refused before any work (auto coarsens instead), 1000..2147483647", false, false, true},
      {"max_covered", max_covered_help.c_str(), false, false, true},
      {"thesis_only", "Only the thesis's method: its size corrections, no surface bound on splat size, no gap filling, growth "
                      "capped only by memory (see max_covered; the two-sided bound is then not guaranteed)", true},
      {"crease_angle", "Crease angle in degrees, (0, 180]: where faces meet at more than it (a sharp edge), the samples beside the "
                       "edge keep their face's normal and a splat's frame takes only the neighbours on its side, so the splats lie in "
                       "the faces instead of bevelling the edge; 180 is the thesis's frames (the default with thesis_only)", false, false, true},
      {"k", "Neighbourhood size, 1..1024", false, false, true},
      {"rounds", "Optimisation rounds (relaxation + removal), 0..1000", false, false, true},
      {"literal_lambda", "Read lambda in the size corrections literally instead of as the axis ratio sqrt(lambda)", true},
      {"retest_violator", "Ellipse phase with b = d1, re-testing the circle phase's violator", true},
      {"clip", "Clipped splats (thesis ch. 4): skip violators on one side and cut the splat there with a line", true},
      {"keep_winding", "Take the faces as wound in the file (an inside-out mesh then gets splats facing into it) instead of turning "
                       "them so that neighbours agree and closed parts face outward", true},
  };
  return list;
}

bool is_splat_parameter(const std::string& name) {
  const std::string key = parameter_key(name);
  const auto& list = splat_parameters();
  return std::any_of(list.begin(), list.end(), [&](const ParameterInfo& p) { return key == p.key; });
}

void set_parameter(SplatParameters& p, const std::string& name, const nlohmann::json& value) {
  const std::string key = parameter_key(name);
  if (key == "eps") {
    p.eps = number_parameter(name, value);
    // Float range here, not only when a mesh resolves it: a batch manifest's "eps": 1e39 passed the
    // manifest's check and then failed every model.
    if (!(p.eps >= 0 && p.eps <= std::numeric_limits<float>::max()))
      throw Error(fmt::format("'{}' must be >= 0 (0: use eps_diag) and within float range (< 3.4e38), got {}", name, shown_value(value)));
  } else if (key == "eps_diag") {
    p.eps_diag = number_parameter(name, value);
    if (!(p.eps_diag > 0 && std::isfinite(p.eps_diag))) throw Error(fmt::format("'{}' must be positive, got {}", name, shown_value(value)));
  } else if (key == "crease_angle") {
    const double degrees = number_parameter(name, value);
    if (!(degrees > 0 && degrees <= 180)) throw Error(fmt::format("'{}' must be in (0, 180] degrees, got {}", name, shown_value(value)));
    p.crease_angle = degrees;
  } else if (key == "k") {
    p.k = static_cast<unsigned>(integer_parameter(name, value, 1, 1024));
  } else if (key == "samples") {
    p.samples = string_parameter(name, value);
  } else if (key == "max_samples") {
    p.max_samples = static_cast<std::size_t>(integer_parameter(name, value, 1000, 2147483647));
  } else if (key == "max_covered") {
    p.max_covered = static_cast<unsigned>(integer_parameter(name, value, 4, kMaxCoveredLimit));
  } else if (key == "thesis_only") {
    p.thesis_only = bool_parameter(name, value);
  } else if (key == "color_tol") {
    p.color_tol = static_cast<int>(integer_parameter(name, value, 0, 255));
  } else if (key == "color_field") {
    p.color_field = string_parameter(name, value);
  } else if (key == "texture") {
    p.texture = string_parameter(name, value);
  } else if (key == "rounds") {
    p.rounds = static_cast<unsigned>(integer_parameter(name, value, 0, 1000));
  } else if (key == "clip") {
    p.clip = bool_parameter(name, value);
  } else if (key == "literal_lambda") {
    p.literal_lambda = bool_parameter(name, value);
  } else if (key == "retest_violator") {
    p.retest_violator = bool_parameter(name, value);
  } else if (key == "keep_winding") {
    p.keep_winding = bool_parameter(name, value);
  } else {
    throw Error(fmt::format("unknown splat parameter '{}'", name));
  }
}

Winding winding(const SplatParameters& p) { return p.keep_winding ? Winding::AsGiven : Winding::Orient; }

double crease_angle(const SplatParameters& p) { return p.crease_angle.value_or(p.thesis_only ? 180.0 : kDefaultCreaseAngle); }

void validate(const SplatParameters& p, Spelling spelling) {
  auto in_key = [spelling](const char* key, auto&& check) {
    try {
      check();
    } catch (const Error& e) {
      throw Error(fmt::format("{}: {}", spelled(key, spelling), e.what()));
    }
  };
  in_key("samples", [&] { parse_sampling(p.samples); });
  in_key("color_field", [&] { parse_color_field(p.color_field); });
}

nlohmann::json to_json(const SplatParameters& p) {
  return {{"eps", p.eps},
          {"eps_diag", p.eps_diag},
          {"k", p.k},
          {"samples", p.samples},
          {"max_samples", p.max_samples},
          // null: the thesis's cap from the sets' budget (budget_growth_cap), which differs from any fixed
          // value, so that batch does not reuse splats built with another cap.
          {"max_covered", p.max_covered ? nlohmann::json(*p.max_covered)
                          : p.thesis_only ? nlohmann::json(nullptr)
                                          : nlohmann::json(kDefaultMaxCovered)},
          {"thesis_only", p.thesis_only},
          {"crease_angle", crease_angle(p)},
          {"color_tol", p.color_tol},
          {"color_field", p.color_field},
          {"texture", p.texture},
          {"rounds", p.rounds},
          {"clip", p.clip},
          {"literal_lambda", p.literal_lambda},
          {"retest_violator", p.retest_violator},
          {"keep_winding", p.keep_winding}};
}

SplatSetup splat_setup(const SplatParameters& p, const Mesh& mesh, const std::string& model) {
  validate(p);
  SplatSetup setup;
  PipelineOptions& options = setup.options;
  options.sampling = parse_sampling(p.samples);
  options.k = p.k;
  options.rounds = p.rounds;
  options.fit.color_tolerance = p.color_tol;
  options.fit.literal_lambda = p.literal_lambda;
  options.fit.retest_violator = p.retest_violator;
  options.fit.clip = p.clip;
  options.fit.crease_degrees = static_cast<float>(crease_angle(p));
  options.sampling.crease_degrees = options.fit.crease_degrees;
  options.sampling.max_samples = p.max_samples;
  options.fit.max_covered = p.max_covered.value_or(p.thesis_only ? kMaxCoveredLimit : kDefaultMaxCovered);
  options.covered_budget = p.thesis_only && !p.max_covered ? kCoveredBudget : 0;
  options.surface_bound = !p.thesis_only;
  options.fit.size_at_accepted = !p.thesis_only;
  setup.diagonal = mesh.bounds().diagonal();
  setup.origin = mesh.origin;
  setup.requested_eps = p.eps > 0 ? p.eps : p.eps_diag * setup.diagonal;
  setup.eps_capped = setup.requested_eps > setup.diagonal && setup.diagonal > 0;
  options.fit.eps = static_cast<float>(setup.eps_capped ? setup.diagonal : setup.requested_eps);
  if (!(options.fit.eps > 0 && std::isfinite(options.fit.eps))) {
    if (p.eps > 0)
      throw Error(fmt::format("{}: eps {} is beyond float range (the splats are floats: give an eps between {:.3g} and {:.3g})", model,
                              p.eps, std::numeric_limits<float>::min(), std::numeric_limits<float>::max()));
    if (const std::string collapsed = float_step_warning(mesh); !setup.diagonal && !collapsed.empty())
      throw Error(fmt::format("{}: the mesh has zero extent: {}", model, collapsed));
    throw Error(fmt::format("{}: eps resolves to {} (eps_diag {} x bounding-box diagonal {}); the mesh has no extent or one "
                            "beyond float range, or eps underflows: pass --eps",
                            model, options.fit.eps, p.eps_diag, setup.diagonal));
  }
  setup.colors.bounds = mesh.bounds();
  setup.colors.field = parse_color_field(p.color_field);
  setup.color_description = to_string(setup.colors.field);
  if (!p.texture.empty()) {
    setup.colors.texture = load_texture(p.texture);  // a missing or unreadable image is named first
    if (!mesh.has_texcoords()) throw Error(model + " has no texture coordinates for the texture " + p.texture);
    setup.color_description = "texture:" + p.texture;
  }
  return setup;
}

RecentreTest recentre_test(const SplatParameters& p) {
  return [p](double reach, double diagonal) {
    if (coarse_for_floats(reach, diagonal)) return true;
    // By eps only where the surface bound holds the splats to it (not thesis_only), and where the
    // centre would lower the rounding: a mesh within twice its diagonal of the origin gains nothing
    // (a unit cube at [0, 1] was moved by half a unit and its warning blamed the float step).
    const double eps = std::min(p.eps > 0 ? p.eps : p.eps_diag * diagonal, diagonal);  // capped as splat_setup caps it
    return !p.thesis_only && reach > 2 * diagonal && float_rounding(reach, diagonal) > kRecentreRounding * eps;
  };
}

std::string recentred_warning(const Mesh& mesh) {
  const DVec3& o = mesh.origin;
  if (o.x == 0 && o.y == 0 && o.z == 0) return {};
  const double reach = mesh.file_reach();
  // The origin to 12 digits here; the header holds it exactly.
  return fmt::format("coordinates reach {:.7g}, where {}: {}read about the centre of its bounding box ({:.12g}, {:.12g}, "
                     "{:.12g}) instead; the splats hold positions relative to it (add it to place them; the splat file records it "
                     "exactly as splatcl_origin)",
                     reach, float_step(reach, mesh.file_diagonal()).clause("the mesh's", "diagonal"),
                     mesh.float_file ? "the file stores its coordinates as floats, so detail finer than that step was lost in the file "
                                       "itself; "
                                     : "",
                     o.x, o.y, o.z);
}

SplatFileInfo splat_file_info(const SplatSetup& setup, const SplatRun& run, const std::string& model) {
  const PipelineOptions& o = setup.options;
  return {model, to_string(o.sampling), o.fit.eps, run.neighbors.k, o.fit.color_tolerance, setup.color_description, o.fit.clip, setup.origin};
}

nlohmann::json splat_statistics(const SplatRun& run, const SplatSetup& setup, const std::string& model, const std::string& output) {
  nlohmann::json stats = run_statistics(run, setup.options);
  stats["model"] = model;
  stats["bbox_diagonal"] = setup.diagonal;
  stats["color_source"] = setup.color_description;
  stats["output"] = output;
  stats["origin"] = {setup.origin.x, setup.origin.y, setup.origin.z};
  if (setup.eps_capped) stats["eps_requested"] = setup.requested_eps;  // "eps" holds the diagonal it was capped at
  return stats;
}

}  // namespace splatcl::splats
