// splatcl cluster: the clustered-shading back end on a scene's depth buffer — ray cast on the host
// (core/scene_ray_cast.hpp), keys, compaction, bounds, light assignment — with a summary, images and
// a JSON summary.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "io/json_keys.hpp"
#include "cli/progress.hpp"
#include "cluster/cluster.hpp"
#include "cluster/shading.hpp"
#include "cluster/scene_input.hpp"
#include "core/scene.hpp"
#include "io/in_flight.hpp"
#include "present/assets.hpp"
#include "core/scene_ray_cast.hpp"
#include "io/atomic_file.hpp"
#include "io/image.hpp"
#include "io/output_files.hpp"
#include "runtime/error.hpp"

namespace splatcl::cli {
namespace {

using namespace splatcl::cluster;

struct ClusterOptions {
  DeviceOptions device;
  std::string scene_path;
  std::string output_dir;
  std::string size = "1920x1080";
  std::string tile = "32x32";
  std::string compaction = "tile-sort";
  std::string assignment = "bvh";
  std::string shape = "auto";
  bool normal_bits = false;
  bool window_depth = false;
  std::optional<long long> light_count;
};

// Frame and tile sides: each in 1..kMaxSide, the frame at most kMaxPixels (8K UHD fits), refused
// before anything is allocated (docs/reliability.md).
constexpr long long kMaxSide = 16384;
constexpr long long kMaxPixels = 1ll << 25;

std::pair<std::uint32_t, std::uint32_t> parse_dimensions(const std::string& text, const char* what) {
  long long a = 0, b = 0;
  char x = 0;
  std::istringstream in(text);
  if (!(in >> a >> x >> b) || (x != 'x' && x != 'X') || !in.eof() || a < 1 || b < 1 || a > kMaxSide || b > kMaxSide)
    throw Error(fmt::format("{} '{}' is not WIDTHxHEIGHT with sides in 1..{}", what, text, kMaxSide));
  if (a * b > kMaxPixels) throw Error(fmt::format("{} '{}' has {} pixels, more than the limit of {}", what, text, a * b, kMaxPixels));
  return {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b)};
}

// Checked as render checks it (present/assets.hpp), though the cluster stage uses neither part.
Scene load_cluster_scene(const std::string& path) {
  Scene scene = path.empty() ? default_scene() : load_scene(path);
  present::check_scene_settings(scene);
  return scene;
}

// Random colour per cluster index, so neighbouring clusters are told apart in the image.
std::vector<float> cluster_image(const ClusterList& clusters) {
  std::vector<float> rgb(clusters.pixel_cluster.size() * 3, 0.0f);
  for (std::size_t p = 0; p < clusters.pixel_cluster.size(); ++p) {
    const std::uint32_t c = clusters.pixel_cluster[p];
    if (c == kNoCluster) continue;
    std::uint32_t h = c * 2654435761u;
    for (int k = 0; k < 3; ++k, h >>= 8) rgb[3 * p + k] = 0.25f + 0.75f * static_cast<float>(h & 0xFF) / 255.0f;
  }
  return rgb;
}

int run_cluster(const ClusterOptions& o) {
  const auto [width, height] = parse_dimensions(o.size, "--size");
  const auto [tile_w, tile_h] = parse_dimensions(o.tile, "--tile");
  const Compaction compaction = parse_compaction(o.compaction);
  const Assignment assignment = parse_assignment(o.assignment);
  Scene scene = load_cluster_scene(o.scene_path);
  if (o.light_count) {
    if (*o.light_count < 0 || *o.light_count > kMaxSceneLights)
      throw Error(fmt::format("--lights {} is not a light count in [0, {}]", *o.light_count, kMaxSceneLights));
    set_generated_light_count(scene, static_cast<std::uint32_t>(*o.light_count));
  }
  // The four outputs writable before any work; staged and committed together at the end.
  const std::vector<std::string> output_names = {"lights-per-cluster.png", "clusters.png", "shaded.png", "summary.json"};
  // The folders -o makes, removed again (where still empty) when the run fails: a refused run
  // (a frame whose keys need more than 32 bits, a full disk) left the empty folder behind.
  // A signal removes them too (io/in_flight.hpp): a SIGTERM left the empty folder.
  struct MadeFolders {
    std::vector<std::filesystem::path> paths;  // outermost first
    std::vector<int> slots;
    bool keep = false;
    ~MadeFolders() {
      std::error_code ignored;
      for (auto it = paths.rbegin(); !keep && it != paths.rend(); ++it) std::filesystem::remove(*it, ignored);
      for (const int slot : slots) unregister_in_flight(slot);
    }
  } made;
  if (!o.output_dir.empty()) {
    std::error_code ec;
    for (std::filesystem::path p = std::filesystem::absolute(o.output_dir, ec); !ec && p.has_relative_path() && !std::filesystem::exists(p, ec);
         p = p.parent_path())
      made.paths.insert(made.paths.begin(), p);
    for (const std::filesystem::path& p : made.paths) made.slots.push_back(register_in_flight_folder(p.string()));
    std::filesystem::create_directories(o.output_dir, ec);
    if (ec) throw Error("cannot create -o directory " + o.output_dir + ": " + ec.message());
    std::vector<std::pair<std::string, std::string>> outputs;
    for (const auto& name : output_names) outputs.emplace_back("-o", (std::filesystem::path(o.output_dir) / name).string());
    for (const auto& [option, path] : outputs) check_output_file(path, option);
    check_outputs_spare_inputs(outputs, scene_input_files(scene));
  }

  auto runtime = Runtime::create(o.device.device);
  const ClusterConfig config = cluster_config(scene.camera, width, height, tile_w, tile_h, o.normal_bits);
  Stopwatch cast_clock;
  const DepthFrame frame = ray_cast(scene, width, height);
  const std::vector<PointLight> lights = view_lights(scene.lights, view_frame(scene.camera));
  const double cast_ms = cast_clock.elapsed_ms();

  ClusterPipeline pipeline(*runtime, config, parse_shape(o.shape));
  const ClusterLayout& layout = pipeline.layout();
  if (o.window_depth) {
    pipeline.upload_depth(window_depth(frame, scene.camera), DepthFormat::Window);
  } else {
    pipeline.upload_depth(frame.view_z, DepthFormat::ViewZ);
  }
  if (o.normal_bits) pipeline.upload_normals(frame.normals);
  pipeline.upload_lights(lights);
  // First pass builds the kernels; the timed second pass is the steady state a renderer sees.
  for (int pass = 0; pass < 2; ++pass) {
    pipeline.compute_keys();
    pipeline.compact(compaction);
    pipeline.compute_bounds();
    pipeline.assign_lights(assignment);
    pipeline.finish();
  }
  std::vector<std::pair<std::string, double>> stage_ms;
  auto timed = [&](const char* name, auto&& stage) {
    Stopwatch clock;
    stage();
    pipeline.finish();
    stage_ms.emplace_back(name, clock.elapsed_ms());
  };
  timed("keys", [&] { pipeline.compute_keys(); });
  timed("compaction", [&] { pipeline.compact(compaction); });
  timed("bounds", [&] { pipeline.compute_bounds(); });
  timed("light assignment", [&] { pipeline.assign_lights(assignment); });

  const ClusterList clusters = pipeline.download_clusters();
  const LightLists lists = pipeline.download_light_lists();
  std::size_t covered = 0;
  std::uint64_t light_evaluations = 0;
  std::vector<std::uint32_t> per_pixel(layout.pixel_count(), 0);
  for (std::size_t p = 0; p < per_pixel.size(); ++p) {
    const std::uint32_t c = clusters.pixel_cluster[p];
    if (c == kNoCluster) continue;
    ++covered;
    per_pixel[p] = lists.counts[c];
    light_evaluations += lists.counts[c];
  }
  const std::uint32_t max_per_cluster = lists.counts.empty() ? 0 : *std::max_element(lists.counts.begin(), lists.counts.end());

  // Clustered shading must equal shading with every light: same formula, same summation order.
  const Vec3 albedo{0.8f, 0.8f, 0.8f};
  const auto shaded = shade_clustered(layout, frame.view_z, frame.normals, lights, clusters, lists, albedo);
  ProgressLine progress("cluster");
  const auto reference = shade_brute_force(layout, frame.view_z, frame.normals, lights, albedo, [&](std::size_t done, std::size_t rows) {
    progress.show(fmt::format("checking against brute-force shading with {} lights: {} of {} rows", lights.size(), done, rows));
  });
  progress.clear();
  float max_difference = 0.0f;
  // Bitwise-equal values (inf included) differ by 0; a NaN on either side, or infinities of
  // opposite signs, count as an infinite difference (std::max dropped the NaN of inf − inf).
  for (std::size_t i = 0; i < shaded.size(); ++i) {
    if (shaded[i] == reference[i]) continue;
    const float d = std::abs(shaded[i] - reference[i]);
    max_difference = std::isnan(d) ? INFINITY : std::max(max_difference, d);
  }

  fmt::print("scene      {}, {} objects at time {:g}\n", scene.source, scene.objects.size(), scene.time);
  fmt::print("device     {} ({} shape)\n", runtime->info().name, to_string(pipeline.shape() == Shape::Auto ? runtime->resolve(Shape::Auto) : pipeline.shape()));
  fmt::print("frame      {}x{}, {} covered pixels ({:.1f}%), ray cast in {:.1f} ms\n", width, height, covered,
             100.0 * static_cast<double>(covered) / static_cast<double>(layout.pixel_count()), cast_ms);
  fmt::print("grid       {}x{} tiles of {}x{}, {} depth slices (q = {:.5f}), {}-bit keys{}\n", layout.tiles_x, layout.tiles_y,
             tile_w, tile_h, layout.slice_count, layout.q, layout.key_bits, o.normal_bits ? " with normal-cone bits" : "");
  fmt::print("clusters   {} occupied ({:.2f}% of the grid), {}\n", pipeline.cluster_count(),
             100.0 * pipeline.cluster_count() / (static_cast<double>(layout.tile_count) * layout.slice_count * (o.normal_bits ? kNormalCells : 1)),
             to_string(compaction));
  fmt::print("lights     {}, {} list entries ({}), {:.3g} per cluster on average, {} at most, {:.3g} per covered pixel\n",
             lights.size(), pipeline.light_index_count(), to_string(assignment),
             pipeline.cluster_count() ? static_cast<double>(pipeline.light_index_count()) / pipeline.cluster_count() : 0.0,
             max_per_cluster, covered ? static_cast<double>(light_evaluations) / static_cast<double>(covered) : 0.0);
  std::string timing = "time      ";
  for (const auto& [name, ms] : stage_ms) timing += fmt::format(" {} {:.2f} ms,", name, ms);
  timing.pop_back();
  fmt::print("{}\n", timing);
  fmt::print("check      clustered vs brute-force shading: max difference {:g} over {} lights\n", max_difference, lights.size());
  // A failed check is a failed run: none of its outputs are written (they were, with exit 1).
  if (max_difference != 0.0f) throw Error(fmt::format("clustered shading differs from brute-force shading by {:g}", max_difference));

  if (!o.output_dir.empty()) {
    const std::filesystem::path dir(o.output_dir);
    std::vector<float> heat(layout.pixel_count() * 3, 0.0f);
    for (std::size_t p = 0; p < per_pixel.size(); ++p) {
      if (clusters.pixel_cluster[p] == kNoCluster) continue;
      const auto color = heat_color(max_per_cluster ? static_cast<float>(per_pixel[p]) / static_cast<float>(max_per_cluster) : 0.0f);
      std::copy(color.begin(), color.end(), heat.begin() + static_cast<std::ptrdiff_t>(3 * p));
    }
    const int w = static_cast<int>(width), h = static_cast<int>(height);
    StagedOutputs outputs;
    for (const auto& name : output_names) outputs.stage((dir / name).string());
    const auto image = [&](const std::string& name, const std::vector<float>& rgb) {
      outputs.write((dir / name).string(), [&](const std::string& path) { write_image_rgb(path, w, h, rgb); });
    };
    image("lights-per-cluster.png", heat);
    image("clusters.png", cluster_image(clusters));
    // Many lights overlap: Reinhard tone mapping c / (1 + c) keeps the picture out of saturation.
    std::vector<float> tone_mapped(shaded.size());
    std::transform(shaded.begin(), shaded.end(), tone_mapped.begin(), [](float c) { return c / (1.0f + c); });
    image("shaded.png", tone_mapped);
    nlohmann::json summary = {
        {"scene", scene.source},
        {"device", runtime->info().name},
        {"width", width}, {"height", height}, {"tile", {tile_w, tile_h}},
        {"tiles", {layout.tiles_x, layout.tiles_y}}, {"slices", layout.slice_count}, {"key_bits", layout.key_bits},
        {"normal_bits", o.normal_bits}, {"compaction", to_string(compaction)}, {"assignment", to_string(assignment)},
        {"covered_pixels", covered}, {"clusters", pipeline.cluster_count()}, {"lights", lights.size()},
        {"light_list_entries", pipeline.light_index_count()}, {"max_lights_per_cluster", max_per_cluster},
        {"shading_max_difference_vs_brute_force", max_difference}};
    for (const auto& [name, ms] : stage_ms) summary["stage_ms"][name] = ms;
    outputs.write((dir / "summary.json").string(), [&](const std::string& path) { write_file_atomically(path, json_text(summary) + "\n"); });
    outputs.commit();
    made.keep = true;
    fmt::print("wrote      {}/{{lights-per-cluster.png, clusters.png, shaded.png, summary.json}}\n", o.output_dir);
  }
  return 0;
}

}  // namespace

Action register_cluster(CLI::App& app) {
  auto* sub = app.add_subcommand("cluster",
                                 "Clustered shading back end on a scene: ray-cast depth, cluster keys, compaction, "
                                 "bounds and light assignment on the OpenCL device; prints a summary");
  auto o = std::make_shared<ClusterOptions>();
  add_device_option(*sub, o->device);
  sub->add_option("scene", o->scene_path, "Scene JSON, as render and view read it (schema in docs/presenter.md; its meshes and floor are ray cast, splat-file objects are refused); default: the embedded data/presenter-scene.json");
  sub->add_option("-o,--output", o->output_dir, "Directory for lights-per-cluster.png, clusters.png, shaded.png and summary.json (created if missing)")
      ->check([](const std::string& value) { return value.empty() ? std::string("empty: name a directory") : std::string(); });
  sub->add_option("--size", o->size, "Frame size WIDTHxHEIGHT")->capture_default_str();
  sub->add_option("--tile", o->tile, "Tile size WIDTHxHEIGHT in pixels")->capture_default_str();
  sub->add_option("--compaction", o->compaction, "global-sort, tile-sort (the thesis's per-tile sort) or bitmask")->capture_default_str();
  sub->add_option("--assignment", o->assignment, "Light assignment: brute or bvh")->capture_default_str();
  sub->add_option("--shape", o->shape, "Kernel shape: auto (by device type), cpu or gpu")->capture_default_str();
  sub->add_option("--lights", o->light_count, "Number of generated lights (replaces the scene's generated lights; listed lights stay)");
  sub->add_flag("--normal-bits", o->normal_bits, "Add the normal-cone bits to the key (Olsson et al. 2012 extension)");
  sub->add_flag("--window-depth", o->window_depth, "Feed the kernels reversed window depth (1 at the near plane, 0 at the far one, as the presenter's depth buffer) instead of view-space z");
  return [o] { return run_cluster(*o); };
}

}  // namespace splatcl::cli
