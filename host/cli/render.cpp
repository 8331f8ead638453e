// splatcl render: the presenter offscreen (EGL, no X server): renders K frames of a scene, writes
// the last one as PNG/EXR and prints per-stage timings and frames per second.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "io/json_keys.hpp"
#include "cli/progress.hpp"
#include "cli/scene_figures.hpp"
#include "cli/scene_options.hpp"
#include "io/atomic_file.hpp"
#include "io/image.hpp"
#include "io/output_files.hpp"
#include "present/context.hpp"
#include "present/presenter.hpp"
#include "runtime/error.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::cli {
namespace {

struct RenderOptions {
  SceneOptions scene;
  std::string output, size = "640x480", view = "final", json;
  unsigned frames = 1;
  bool pixel_ao = false;
  bool floor_splats = false;
  bool wall_passes = false;
  bool serial_lighting = false;
  std::optional<double> time;  // unset: the scene's "time"
  double dt = 1.0 / 30.0;
};

int run_render(const RenderOptions& o) {
  const auto [width, height] = present::parse_frame_size(o.size, "--size");
  const present::DebugView view = present::parse_debug_view(o.view);
  if (o.frames == 0) throw Error("--frames 0: not a whole number 1 or more");
  check_output_extension(o.output, "-o", {".png", ".exr"}, "the image");
  // Outputs writable before any work; staged and committed together at the end.
  check_output_file(o.output, "-o");
  check_output_file(o.json, "--json");
  // The asset cache too: --json P --cache P made the folder P, built every asset, then failed to write P.
  check_distinct_outputs({{"-o", o.output}, {"--json", o.json}, {"--cache", o.scene.cache_dir()}});
  // Within float range: the frames' times are floats (--time 1e39 failed as "a placement is not invertible").
  if (!(std::isfinite(static_cast<float>(o.dt)) && o.dt >= 0))
    throw Error(fmt::format("--dt {} is not a time step in seconds (finite within float range, not negative)", o.dt));
  if (o.time && !std::isfinite(static_cast<float>(*o.time)))
    throw Error(fmt::format("--time {} is not a scene time in seconds (finite within float range)", *o.time));
  const splatcl::Scene scene = o.scene.load();
  check_outputs_spare_inputs({{"-o", o.output}, {"--json", o.json}}, scene_input_files(scene));  // --json scene.json replaced the scene
  auto runtime = Runtime::create(o.scene.device.device);
  auto context = present::GlContext::offscreen();
  ProgressLine progress("render");
  Stopwatch setup;
  present::Presenter presenter(scene, *runtime, width, height, o.scene.cache_dir(), asset_progress(progress, "render"));
  // Linear radiance is written only for an .exr image: a PNG needs the tone-mapped target alone.
  const bool exr = output_extension(o.output) == ".exr";
  presenter.hdr_output = exr;
  progress.clear();
  print_mesh_warnings(presenter);
  presenter.debug_view = view;
  presenter.pixel_ao = presenter.pixel_ao || o.pixel_ao;
  presenter.floor_per_pixel = presenter.floor_per_pixel && !o.floor_splats;
  presenter.wall_clock_passes = o.wall_passes;
  presenter.overlap_lighting = !o.serial_lighting;
  const double setup_ms = setup.elapsed_ms();

  const double start = o.time ? *o.time : scene.time;
  std::map<std::string, std::pair<double, unsigned>> sums;  // per stage: total ms, frames seen
  std::vector<std::string> order;
  double frame_total = 0;
  unsigned measured = 0;
  present::FrameStats last;
  for (unsigned f = 0; f < o.frames; ++f) {
    progress.show(fmt::format("frame {}/{}", f + 1, o.frames));
    last = presenter.render(static_cast<float>(start + f * o.dt));
    // The first frame compiles kernels and shaders; it is left out when there are others.
    if (f == 0 && o.frames > 1) continue;
    ++measured;
    frame_total += last.frame_ms;
    for (const auto& s : last.stages) {
      if (!sums.count(s.name)) order.push_back(s.name);
      sums[s.name].first += s.ms;
      sums[s.name].second += 1;
    }
  }
  progress.clear();

  fmt::print("device     {} | {}\n", runtime->info().name, context->renderer());
  fmt::print("scene      {}: {} objects, {} splats{}, {} lights ({} shading, {} mode), {}x{}\n", scene.source,
             scene.objects.size(), last.splats,
             scene.quality.lod_error > 0 ? fmt::format(" drawn (LOD {} px)", scene.quality.lod_error) : "",
             scene.lights.size(), scene.quality.shading, scene.quality.mode, width, height);
  fmt::print("setup      {:.0f} ms (assets, shaders, buffers)\n", setup_ms);
  std::string objects;
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    objects += fmt::format("{}{} {} splats{}{}", i ? ", " : "", scene.objects[i].name, presenter.object_splats(i).second,
                           presenter.two_sided(i) ? " (two-sided)" : "", presenter.assets(i).splats_cached ? "" : " (built)");
  if (!objects.empty()) fmt::print("objects    {}\n", objects);
  fmt::print("clusters   {} with {} light indices (last frame)\n", last.clusters, last.light_indices);
  fmt::print("stages     mean ms per frame over {} frame(s){}\n", measured, o.frames > 1 ? " after the first" : "");
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& name : order) {
    const auto [total, count] = sums[name];
    // Stages that run only on some frames (the AO update) are averaged over all measured frames.
    const double mean = total / measured;
    fmt::print("  {:28s} {:8.2f}{}\n", name, mean, count < measured ? fmt::format("  (on {} of {} frames)", count, measured) : "");
    stages[name] = mean;
  }
  const double frame_ms = frame_total / measured;
  fmt::print("frame      {:.2f} ms = {:.1f} fps\n", frame_ms, 1000.0 / frame_ms);
  StagedOutputs outputs;
  if (!o.json.empty()) outputs.stage(o.json);
  if (!o.output.empty()) {
    outputs.stage(o.output);
    const std::vector<float> rgb = exr ? presenter.read_hdr_rgb() : presenter.read_display_rgb();
    outputs.write(o.output, [&](const std::string& path) { write_image_rgb(path, width, height, rgb); });
  }
  if (!o.json.empty()) {
    const nlohmann::json summary = {{"scene", scene.source},         {"width", width},
                                    {"height", height},              {"lights", scene.lights.size()},
                                    {"splats", last.splats},         {"shading", scene.quality.shading},
                                    {"lod_error", scene.quality.lod_error},
                                    {"mode", scene.quality.mode},    {"frames_measured", measured},
                                    {"gl_pass_clock", o.wall_passes ? "wall" : "timer queries"},
                                    {"frame_ms", frame_ms},          {"fps", 1000.0 / frame_ms},
                                    {"stages_ms", stages},           {"device", runtime->info().name},
                                    {"renderer", context->renderer()},
                                    {"clusters", last.clusters},     {"light_indices", last.light_indices},
                                    // The figures of splatcl view's panel: its modes and toggles, and each object's.
                                    {"settings", settings_json(presenter.scene(), presenter.debug_view, presenter.ambient_occlusion, presenter.pixel_ao,
                                                                 presenter.floor_per_pixel)},
                                    {"objects", to_json(object_figures(presenter, scene))}};
    outputs.write(o.json, [&](const std::string& path) { write_file_atomically(path, json_text(summary) + "\n"); });
  }
  outputs.commit();
  if (!o.output.empty()) fmt::print("image      {}\n", o.output);
  return 0;
}

}  // namespace

Action register_render(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* sub = app.add_subcommand("render", "Render a presenter scene offscreen (no display needed): splat passes, "
                                               "clustered shading, CSM shadows and AO; prints per-stage timings and fps");
  add_scene_options(*sub, o->scene);
  sub->add_option("-o,--output", o->output, "Write the last frame: .png (tone mapped) or .exr (linear radiance)");
  sub->add_option("--frames", o->frames, "Frames to render; timings leave out the first when there are more")->capture_default_str()->type_name("COUNT");
  sub->add_option("--size", o->size, "Frame size WIDTHxHEIGHT")->capture_default_str();
  sub->add_option("--time", o->time, "Scene time of the first frame in seconds (default: the scene's \"time\")");
  sub->add_option("--dt", o->dt, "Scene time between frames in seconds")->capture_default_str();
  sub->add_flag("--pixel-ao", o->pixel_ao, "Ambient occlusion per pixel (quality mode) instead of per splat");
  sub->add_flag("--floor-splats", o->floor_splats,
                "The floor's shadows and AO per floor splat (faster, stepped at its splat spacing) instead of per pixel (quality.floor_pixels)");
  sub->add_option("--view", o->view, "final, albedo, normals, ao, clusters (lights per cluster), shadows, depth, footprints")
      ->capture_default_str();
  sub->add_option("--json", o->json, "Write the timings as JSON");
  sub->add_flag("--wall-passes", o->wall_passes,
                "Time each GL pass by wall clock between glFinish calls (serialises the frame) instead of timer queries");
  sub->add_flag("--serial-lighting", o->serial_lighting,
                "Run the CL lighting on this thread (the per-splat lighting of moved occluders after the visibility pass, the floor's lattice after the depth readback) instead of on a worker beside the splat passes (for comparison)");
  return [o] { return run_render(*o); };
}

}  // namespace splatcl::cli
