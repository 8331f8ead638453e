#pragma once
// The splat stage's build parameters, one list for `splatcl splats` (options --NAME) and
// `splatcl batch` (manifest keys NAME): their defaults, parsing and validation, and their
// translation into the pipeline's options and colour source for one mesh.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/parameters.hpp"
#include "splats/pipeline.hpp"

namespace splatcl::splats {

struct SplatParameters {
  double eps = 0;                    // absolute ε in model units; 0: eps_diag × bounding-box diagonal
  double eps_diag = 0.001;
  unsigned k = 10;                   // neighbourhood size
  std::string samples = "auto";      // or "vertices", "grid:N", "spacing:D"
  std::size_t max_samples = kDefaultMaxSamples;
  // Growth cap (samples per splat); unset: kDefaultMaxCovered, or with thesis_only the share of
  // kCoveredBudget per sample (budget_growth_cap).
  std::optional<unsigned> max_covered;
  bool thesis_only = false;          // the thesis's method alone: no surface bound, no gap filling, growth capped by memory only
  int color_tol = 255;               // φ per channel; 255 ignores colour
  std::string color_field = "grey";  // colours without a texture
  std::string texture;               // image through the mesh's texture coordinates; empty: none
  unsigned rounds = 5;               // optimisation rounds
  bool clip = false, literal_lambda = false, retest_violator = false;
  // The faces as wound in the file; by default they are turned so that neighbours agree and closed
  // parts face outward (core/mesh.hpp, Winding::Orient), as the presenter's scenes are.
  bool keep_winding = false;
  // Crease angle in degrees (FitOptions::crease_degrees); unset: kDefaultCreaseAngle, or 180 (the
  // thesis's frames) with thesis_only.
  std::optional<double> crease_angle;
};

inline constexpr double kDefaultCreaseAngle = 60;
// cos(kDefaultCreaseAngle): a triangle within this of a splat's plane faces it (the surface bound's
// facing rule, surface_fit.cpp, and verify's flipped count, surface_check.cpp).
inline constexpr double kFacingCos = 0.5;
static_assert(kDefaultCreaseAngle == 60, "kFacingCos is cos(kDefaultCreaseAngle)");
inline constexpr unsigned kDefaultMaxCovered = 128;
// How the model's faces are loaded for these parameters.
Winding winding(const SplatParameters& params);
// The crease angle the parameters resolve to.
double crease_angle(const SplatParameters& params);

// Every parameter, in the order of `splatcl splats --help`.
const std::vector<ParameterInfo>& splat_parameters();
// Whether `name` (any spelling, see parameter_key) is one of them.
bool is_splat_parameter(const std::string& name);
// Sets the parameter `name` from a JSON value or text. Throws Error naming it as given for an
// unknown name or a value out of range.
void set_parameter(SplatParameters& params, const std::string& name, const nlohmann::json& value);
// Checks what set_parameter cannot check alone (the sampling spec, the colour field name).
// Errors name the parameter as `spelling` does.
void validate(const SplatParameters& params, Spelling spelling = Spelling::Key);
// Every parameter by key: a run's record, and what its parameters checksum is computed from.
nlohmann::json to_json(const SplatParameters& params);

// What the parameters make of one mesh: ε resolved against its bounding-box diagonal, the colour
// source (the texture loaded), and the names the splat file and statistics record.
struct SplatSetup {
  PipelineOptions options;
  ColorSource colors;
  std::string color_description;  // "grey", "soft", ..., or "texture:FILE"
  double diagonal = 0;
  // The eps asked for (eps, or eps_diag x the diagonal). options.fit.eps is it, or the diagonal when
  // it is larger: no point of the mesh lies farther than that from another, so the bound is as
  // loose as it gets, and a box fitted at eps 3 x its diagonal came out with holes (0.02 % of its
  // surface uncovered by a splat facing its way), refused by the check (a helper's audit).
  double requested_eps = 0;
  bool eps_capped = false;
  DVec3 origin{0, 0, 0};  // the mesh's (Mesh::origin): the splat file records it
};
// Throws Error for invalid parameters, a texture that cannot be read, or a textured run on a mesh
// without texture coordinates (naming `model`).
SplatSetup splat_setup(const SplatParameters& params, const Mesh& mesh, const std::string& model);
// Where splats and batch read a model about the centre of its box (load_mesh_recentred), recording
// that origin in the splat file: where floats are coarse for its size (coarse_for_floats), or, for
// the surface bound (not thesis_only) and a mesh more than twice its diagonal from the origin, where
// writing the splats as floats would move them by more than kRecentreRounding of the eps these
// parameters resolve to for its diagonal (a fine eps on a mesh far out was refused, "translate the
// mesh nearer the origin").
inline constexpr double kRecentreRounding = 0.25;
RecentreTest recentre_test(const SplatParameters& params);
// The warning for a mesh read about the centre of its box (Mesh::origin not zero; splats and batch
// read so where the file's coordinates are too coarse as floats for its size): where they reach,
// and that the splats hold positions relative to the origin the splat file records. Empty for a
// zero origin.
std::string recentred_warning(const Mesh& mesh);
SplatFileInfo splat_file_info(const SplatSetup& setup, const SplatRun& run, const std::string& model);
// run_statistics plus the model, its diagonal, the colour source and the output file's name.
nlohmann::json splat_statistics(const SplatRun& run, const SplatSetup& setup, const std::string& model, const std::string& output);

}  // namespace splatcl::splats
