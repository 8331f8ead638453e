#include "cli/scene_options.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

#include "io/json_keys.hpp"
#include "runtime/error.hpp"

namespace splatcl::cli {

splatcl::Scene SceneOptions::load() const {
  // The asset cache before any work: a --cache naming a file failed at the first object, after the
  // scene, the device and the GL context were set up, blamed on that object.
  const std::string dir = cache_dir();
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (!std::filesystem::is_directory(dir))
    throw Error(fmt::format("{} {}: cannot be the asset cache: {}", cache.empty() ? "asset cache" : "--cache", dir,
                            error ? error.message() : std::string("not a directory")));
  splatcl::Scene s = scene.empty() ? splatcl::default_scene() : splatcl::load_scene(scene);
  present::apply_overrides(s, overrides);
  return s;
}

std::string SceneOptions::cache_dir() const { return cache.empty() ? present::default_cache_dir() : cache; }

present::AssetProgress asset_progress(ProgressLine& line, const std::string& command) {
  return [&line, command](const std::string& what, bool finished) {
    if (!finished) return line.show("building " + what);
    line.clear();
    std::fprintf(stderr, "%s: built %s\n", command.c_str(), what.c_str());
  };
}

void print_mesh_warnings(const present::Presenter& presenter) {
  for (const std::string& line : presenter.mesh_warnings()) std::fprintf(stderr, "splatcl: warning: %s\n", printable(line).c_str());
}

void add_scene_options(CLI::App& app, SceneOptions& o) {
  app.add_option("scene", o.scene, "Scene JSON (default: the embedded data/presenter-scene.json)");
  app.add_option("--shading", o.overrides.shading, "clustered, tiled or brute (default: the scene's)");
  app.add_option("--mode", o.overrides.mode, "splats (three-pass Gaussian splatting) or points (low quality)");
  app.add_option("--shadows", o.overrides.shadows, "Key-light shadows: splat, pixel or off");
  app.add_option("--filter", o.overrides.filter,
                 "Key-light shadow test: none (1 texel), same-map (4x4 PCF), cross-map (2x2 PCF in 4 maps) or march (the true light ray "
                 "through 4 maps: shadow edges in place, hard per light sample) (default: the scene's quality.filter, march)");
  app.add_option("--lights", o.overrides.lights, "Number of generated point lights (default: the scene's)");
  app.add_option("--lod", o.overrides.lod,
                 "Level of detail: screen-space error threshold in pixels, 0 = off (default: the scene's quality.lod_error)");
  app.add_option("--specular", o.overrides.specular,
                 "Blinn-Phong highlight strength in [0, 100], 0 = Lambert only (default: the scene's quality.specular, 0)");
  app.add_option("--cache", o.cache, "Asset cache directory (default: $SPLATCL_CACHE, else ~/.cache/splatcl)");
  add_device_option(app, o.device);
}

}  // namespace splatcl::cli
