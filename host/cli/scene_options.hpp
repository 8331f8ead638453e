#pragma once
// The scene options `splatcl render` and `splatcl view` share: the scene file, the quality
// overrides, the asset cache and the OpenCL device, registered once and resolved into a Scene.
#include <string>

#include <CLI/CLI.hpp>

#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "present/assets.hpp"
#include "present/overrides.hpp"
#include "present/presenter.hpp"

namespace splatcl::cli {

struct SceneOptions {
  std::string scene;  // empty: the embedded default scene
  std::string cache;  // empty: present::default_cache_dir()
  present::Overrides overrides;
  DeviceOptions device;

  // The scene file, or the default scene, with the overrides applied.
  splatcl::Scene load() const;
  std::string cache_dir() const;
};

// Asset-building progress of `command`: the current step on the progress line (on a terminal), and
// one line on stderr per built step with what it made and its time (always, so a log shows where a
// first run's minutes went).
present::AssetProgress asset_progress(ProgressLine& line, const std::string& command);

// The mesh problems the presenter found and repaired while loading (Presenter::mesh_warnings), on
// stderr as "splatcl: warning: ..." lines.
void print_mesh_warnings(const present::Presenter& presenter);

// Adds the positional scene, --shading, --mode, --shadows, --filter, --lights, --lod, --cache and --device.
void add_scene_options(CLI::App& app, SceneOptions& options);

}  // namespace splatcl::cli
