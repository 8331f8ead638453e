#include "present/assets.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>

#include "csm/build.hpp"
#include "io/checksum.hpp"
#include "runtime/error.hpp"
#include "runtime/profiling.hpp"
#include "splats/pipeline.hpp"
#include "splats/pipeline_options.hpp"

namespace splatcl::present {
namespace {

template <class T>
std::string_view bytes_of(const std::vector<T>& values) {
  return {reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)};
}

}  // namespace

std::string default_cache_dir() {
  if (const char* dir = std::getenv("SPLATCL_CACHE"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/splatcl";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/splatcl";
  return ".splatcl-cache";
}

std::string asset_key(const splats::Mesh& mesh, const std::string& parameters) {
  std::uint64_t h = fnv1a64(bytes_of(mesh.vertices));
  h = fnv1a64(bytes_of(mesh.face_offsets), h);
  h = fnv1a64(bytes_of(mesh.corners), h);
  return checksum_hex(fnv1a64(parameters, h));
}

ObjectAssets load_object_assets(const ObjectSpec& object, const Scene& scene, const std::string& cache_dir,
                                Runtime& runtime, const AssetProgress& progress) {
  const Quality& q = scene.quality;
  const Stopwatch clock;
  ObjectAssets assets;
  assets.mesh = make_object_mesh(object.mesh, scene.directory);
  // Colour sources enter the key only when used, so grey objects keep their cache entries.
  std::string splat_parameters = fmt::format("splats v1 sampling={} eps_diagonal={:.9g}", q.sampling, q.eps_diagonal);
  if (q.splat_bound != "thesis") splat_parameters += " bound=" + q.splat_bound;
  std::string texture_path;
  if (object.splat_colors) {
    if (!object.texture.empty()) {
      const std::filesystem::path t(object.texture);
      texture_path = t.is_absolute() || scene.directory.empty() ? t.string() : (std::filesystem::path(scene.directory) / t).string();
      splat_parameters += fmt::format(" texture={}", checksum_of_file(texture_path));
    } else {
      splat_parameters += " field=" + object.color_field;
    }
    if (object.color_tolerance < 255) splat_parameters += fmt::format(" tolerance={}", object.color_tolerance);
  }
  const LodOptions lod_options{q.lod_leaf, 32, 0.1f};
  const std::string tree_parameters = fmt::format("{}|tree v1 leaf={} grid={} overlap={:.9g}", splat_parameters,
                                                  lod_options.leaf_splats, lod_options.grid, lod_options.overlap);
  const std::string csm_parameters = fmt::format("csm v1 maps={} resolution={}", q.csm_maps, q.csm_resolution);
  assets.key = asset_key(assets.mesh, splat_parameters + "|" + csm_parameters);
  std::error_code ec;
  std::filesystem::create_directories(cache_dir, ec);
  if (ec) throw Error(fmt::format("cannot create the asset cache {}: {}", cache_dir, ec.message()));
  const std::string splat_path = fmt::format("{}/{}.splats.ply", cache_dir, asset_key(assets.mesh, splat_parameters));
  const std::string csm_path = fmt::format("{}/{}.csm", cache_dir, asset_key(assets.mesh, csm_parameters));
  const std::string tree_path = fmt::format("{}/{}.spt", cache_dir, asset_key(assets.mesh, tree_parameters));

  // A cache entry that cannot be read (truncated, corrupted, written by an older version) is
  // rebuilt and overwritten rather than failing the render.
  if (std::filesystem::exists(splat_path)) {
    try {
      assets.splats = splats::read_splat_file(splat_path).splats;
      assets.splats_cached = true;
    } catch (const Error&) {
    }
  }
  if (!assets.splats_cached) {
    if (progress) progress(fmt::format("{}: splats", object.name));
    // The scene's quality settings and colour source as the splat stage's shared parameter list.
    splats::SplatParameters params;
    params.samples = q.sampling;
    params.eps_diag = q.eps_diagonal;
    params.thesis_only = q.splat_bound == "thesis";
    if (object.splat_colors) {
      params.color_tol = static_cast<int>(object.color_tolerance);
      if (!texture_path.empty())
        params.texture = texture_path;
      else
        params.color_field = object.color_field;
    }
    const splats::SplatSetup setup = splats::splat_setup(params, assets.mesh, fmt::format("{}: {}", scene.source, object.name));
    const splats::SplatRun run = splats::generate_splats(assets.mesh, setup.colors, setup.options, &runtime);
    assets.splats = run.records();
    splats::write_splat_file(splat_path, assets.splats, splats::splat_file_info(setup, run, assets.mesh.source));
  }
  if (assets.splats_cached && std::filesystem::exists(tree_path)) {
    try {
      assets.tree = read_splat_tree(tree_path, static_cast<std::uint32_t>(assets.splats.size()));
      assets.tree_cached = true;
    } catch (const Error&) {
    }
  }
  if (!assets.tree_cached) {
    if (progress) progress(fmt::format("{}: LOD tree", object.name));
    assets.tree = build_splat_tree(assets.splats, lod_options);
    write_splat_tree(tree_path, assets.tree);
  }
  if (std::filesystem::exists(csm_path)) {
    try {
      assets.csm = csm::read_csm(csm_path);
      assets.csm_cached = true;
    } catch (const Error&) {
    }
  }
  if (!assets.csm_cached) {
    if (progress) progress(fmt::format("{}: coherent shadow map", object.name));
    csm::BuildOptions options;
    options.maps = q.csm_maps;
    options.resolution = q.csm_resolution;
    csm::BuildResult built = csm::build_csm(assets.mesh, options, &runtime);
    csm::write_csm(csm_path, built.csm, csm::Encoding::Compact, &built.segments);
    // Read back what was cached: the compact encoding stores other (equally lossless) depths than
    // the build's midpoints, and a first render must see the same shadows as every later one.
    assets.csm = csm::read_csm(csm_path);
  }
  assets.build_ms = clock.elapsed_ms();
  return assets;
}

}  // namespace splatcl::present
