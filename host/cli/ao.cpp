// splatcl ao: ambient occlusion for the vertices of a receiver mesh under placed occluders, each a
// .csm with its own placement (instances may share one file), written as a vertex-coloured PLY.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "cli/commands.hpp"
#include "cli/model_input.hpp"
#include "cli/progress.hpp"
#include "csm/ao.hpp"
#include "csm/ao_receivers.hpp"
#include "csm/query_reach.hpp"
#include "io/output_files.hpp"
#include "runtime/error.hpp"
#include "runtime/profiling.hpp"

namespace splatcl::cli {
namespace {

using namespace splatcl::csm;

struct AoCommand {
  DeviceOptions device;
  std::string receiver, output, pattern = "hammersley-scrambled";
  std::vector<std::string> occluders, transforms;
  ReceiverAoOptions options;
  float lift_texels = kDefaultLiftTexels;
  bool reference = false, keep_winding = false;
};

int run_ao(const AoCommand& c) {
  if (c.receiver.empty()) throw Error("ao: a RECEIVER_MESH is required (see splatcl ao --help)");
  if (c.output.empty()) throw Error("ao: an output file is required (-o OUT.ply)");
  if (c.occluders.empty()) throw Error("ao: at least one --occluder FILE.csm is required");
  if (!c.transforms.empty() && c.transforms.size() != c.occluders.size())
    throw Error(fmt::format("ao: {} --occluder-transform for {} --occluder (give one per occluder, or none)", c.transforms.size(),
                            c.occluders.size()));
  ReceiverAoOptions options = c.options;
  options.pattern_set = parse_pattern_set(c.pattern);
  if (options.samples == 0 || options.samples > kMaxSamples)
    throw Error(fmt::format("ao: --samples {} is not a direction count in 1..{}", options.samples, kMaxSamples));
  // Progress after every ~16M direction tests: at --samples 4096 a batch of 65,536 vertices took
  // about 40 s with no movement.
  options.batch = std::clamp<std::size_t>((std::size_t{1} << 24) / options.samples, 256, std::size_t{1} << 16);
  if (options.patterns == 0 || options.patterns > kMaxPatterns)
    throw Error(fmt::format("ao: --patterns {} is not a pattern count in 1..{}", options.patterns, kMaxPatterns));
  // 1e39 reads as the float inf: say what was wrong with what was typed.
  if (const std::string problem = bias_error(options.bias); !problem.empty()) throw Error("ao: " + problem);
  if (!(c.lift_texels >= 0 && c.lift_texels <= kMaxLiftTexels))
    throw Error(fmt::format("ao: --lift {} is not a texel count in 0..{}", c.lift_texels, kMaxLiftTexels));
  check_output_file(c.output, "-o");
  std::vector<std::pair<std::string, std::string>> inputs{{"receiver", c.receiver}};
  for (const std::string& occluder : c.occluders) inputs.emplace_back("occluder", occluder);
  check_outputs_spare_inputs({{"-o", c.output}}, inputs);
  check_output_extension(c.output, "-o", {".ply"}, "a vertex-coloured PLY");
  std::vector<Instance> instances;
  for (std::size_t k = 0; k < c.transforms.size(); ++k) instances.push_back({0, parse_placement(c.transforms[k])});
  instances.resize(c.occluders.size());
  ProgressLine progress("ao");
  // One copy of each distinct file, shared by its instances.
  std::map<std::string, std::uint32_t> index_of;
  std::vector<std::unique_ptr<Csm>> csms;
  for (std::size_t k = 0; k < c.occluders.size(); ++k) {
    auto [it, fresh] = index_of.emplace(c.occluders[k], static_cast<std::uint32_t>(csms.size()));
    if (fresh) {
      progress.show("reading " + c.occluders[k]);
      csms.push_back(std::make_unique<Csm>(read_csm(c.occluders[k])));
    }
    instances[k].occluder = it->second;
  }
  const Mesh receiver = load_model(c.receiver, progress, c.keep_winding ? Winding::AsGiven : Winding::Orient);
  // The placements are applied in float, as the receiver's vertices are read: far from the origin
  // for an occluder's size they move it (1e6 + 0.6 became 1000000.625), so say so as for a mesh.
  for (std::size_t k = 0; k < instances.size(); ++k) {
    const MovedReach placed = moved_reach(csms[instances[k].occluder]->info, instances[k].placement, 0.0f);
    const double reach = std::max({std::abs(placed.centre.x), std::abs(placed.centre.y), std::abs(placed.centre.z)}) + placed.radius;
    if (const FloatStep far = float_step(reach, 2.0 * placed.radius); far.coarse())
      queue_warning(fmt::format("--occluder {} ({})", k + 1, c.occluders[k]),
                    fmt::format("placed where {}: its placement is rounded to that; place the scene nearer the origin",
                                far.clause("its", "bounding diameter")));
  }
  std::vector<const Csm*> views;
  for (const auto& csm : csms) views.push_back(csm.get());
  const VisibilityScene scene(views, instances);
  options.lift = receiver_lifts(receiver, views, instances, c.lift_texels);
  std::shared_ptr<Runtime> runtime;
  if (!c.reference) runtime = Runtime::create(c.device.device);
  Stopwatch clock;
  const std::vector<Vec4> ao = receiver_ambient_occlusion(receiver, scene, options, runtime.get(), [&](std::size_t done, std::size_t total) {
    progress.show(fmt::format("{}/{} vertices", done, total));
  });
  const double ms = clock.elapsed_ms();
  progress.show("writing " + c.output);
  write_ao_ply(c.output, receiver, ao);
  progress.clear();
  double sum = 0;
  float lo = 1, hi = 0;
  for (const Vec4& v : ao) {
    sum += v.w;
    lo = std::min(lo, v.w);
    hi = std::max(hi, v.w);
  }
  const double samples = static_cast<double>(ao.size()) * options.samples * static_cast<double>(instances.size());
  fmt::print("receivers  {} vertices of {}; {} occluder instance(s) of {} CSM file(s){}\n", ao.size(), c.receiver, instances.size(),
             csms.size(), options.ground ? "; ground plane on" : "");
  const std::string lifted =
      options.lift.own_instance == kNoInstance
          ? std::string("receivers not lifted (none of the occluders: only an occluder's own surface is lifted off its maps)")
          : fmt::format("receivers lifted {:g} texels of their own occluder, --occluder {} ({:g}), for its maps only", c.lift_texels,
                        options.lift.own_instance + 1, options.lift.lifts.front());
  fmt::print("sampling   {} directions per vertex, pattern set {} ({} patterns, seed {}), bias {:g}, {}\n", options.samples,
             to_string(options.pattern_set), options.patterns, options.seed, options.bias, lifted);
  fmt::print("ao         mean {:.4f}, min {:.4f}, max {:.4f} (1 = unoccluded)\n", sum / static_cast<double>(ao.size()), lo, hi);
  fmt::print("time       {:.1f} ms wall on {}, kernel build and uploads included ({:.2f} M direction tests/s at most: "
             "instances after a blocking one are skipped)\n",
             ms,
             runtime ? runtime->info().name : std::string("the native reference"), samples / ms / 1e3);
  fmt::print("wrote      {}\n", c.output);
  return 0;
}

}  // namespace

Action register_ao(CLI::App& app) {
  auto* sub = app.add_subcommand("ao", "Ambient occlusion (AO thesis) for the vertices of a receiver mesh under occluders given as .csm "
                                       "files; writes a vertex-coloured PLY with the AO value and bent normal per vertex");
  auto c = std::make_shared<AoCommand>();
  add_device_option(*sub, c->device);
  sub->add_option("receiver", c->receiver, "Receiver mesh (OBJ, PLY, OFF, STL): AO is computed at its vertices");
  sub->add_option("--occluder", c->occluders, "An occluder's .csm file (repeatable; repeat a file for several instances of it)");
  sub->add_option("--occluder-transform", c->transforms,
                  "Placement of the matching --occluder in the receiver's space: tx,ty,tz or tx,ty,tz,rx,ry,rz (degrees in -36000..36000, about x "
                  "then y then z) or 16 numbers (row-major 4x4); one per --occluder, in order, or none (identity)");
  sub->add_option("-o,--output", c->output, "Output PLY file");
  sub->add_option("--pattern", c->pattern,
                  "Sampling pattern set: mc, stratified, lhs, halton, hammersley-cp, hammersley-scrambled (long names "
                  "monte-carlo, latin-hypercube, halton-cp also accepted)")
      ->capture_default_str();
  sub->add_option("--samples", c->options.samples, fmt::format("Directions per vertex, 1..{} (a perfect square for stratified)", kMaxSamples))
      ->capture_default_str()
      ->type_name("COUNT");
  sub->add_option("--patterns", c->options.patterns, fmt::format("Precomputed patterns each vertex picks one of, 1..{}", kMaxPatterns))->capture_default_str();
  sub->add_option("--seed", c->options.seed, "Seed of the patterns and of each vertex's pattern choice")->capture_default_str();
  sub->add_flag("--ground-plane", c->options.ground, "Directions below the horizon (world y < 0) count as occluded (the thesis's floor test); the AO is then the lit share of the others times (1 + n.y) / 2");
  sub->add_option("--bias", c->options.bias, "Shadow offset in texels of each occluder's CSM, 0..1000 (occluded when the stored depth g < depth - bias/M, depth in units of the bounding diameter)")->capture_default_str();
  sub->add_option("--lift", c->lift_texels,
                  "Receivers lifted along their normal off their own surface by this many texels, 0..1000. A receiver that is one of "
                  "the occluders (its CSM built from this mesh, placed where it lies) is lifted by texels of that occluder, for its "
                  "maps only; any other receiver is not lifted (no CSM holds its surface: lifted, a floor under a box resting on it "
                  "went into the box). 0: on the surface, as the thesis; an open mesh's own surface then shadowed itself: a flat "
                  "sheet got AO 0.74 instead of 1")
      ->capture_default_str();
  sub->add_flag("--reference", c->reference, "Use the native C++ reference instead of the OpenCL kernel");
  sub->add_flag("--keep-winding", c->keep_winding,
                "Take the receiver's faces as wound in the file: its vertex normals, and so the AO hemispheres, follow them (by "
                "default the faces are turned so that neighbours agree and closed parts face outward: an inside-out receiver "
                "otherwise got AO near 0)");
  return [c]() { return run_ao(*c); };
}

}  // namespace splatcl::cli
