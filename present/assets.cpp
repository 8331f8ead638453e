#include "present/assets.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>

#include "csm/build.hpp"
#include "io/checksum.hpp"
#include "runtime/error.hpp"
#include "runtime/profiling.hpp"
#include "splats/pipeline.hpp"

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
  const std::string splat_parameters = fmt::format("splats v1 sampling={} eps_diagonal={:.9g}", q.sampling, q.eps_diagonal);
  const std::string csm_parameters = fmt::format("csm v1 maps={} resolution={}", q.csm_maps, q.csm_resolution);
  assets.key = asset_key(assets.mesh, splat_parameters + "|" + csm_parameters);
  std::error_code ec;
  std::filesystem::create_directories(cache_dir, ec);
  if (ec) throw Error(fmt::format("cannot create the asset cache {}: {}", cache_dir, ec.message()));
  const std::string splat_path = fmt::format("{}/{}.splats.ply", cache_dir, asset_key(assets.mesh, splat_parameters));
  const std::string csm_path = fmt::format("{}/{}.csm", cache_dir, asset_key(assets.mesh, csm_parameters));

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
    splats::PipelineOptions options;
    options.sampling = splats::parse_sampling(q.sampling);
    options.fit.eps = q.eps_diagonal * assets.mesh.bounds().diagonal();
    splats::ColorSource colors;
    colors.bounds = assets.mesh.bounds();
    const splats::SplatRun run = splats::generate_splats(assets.mesh, colors, options, &runtime);
    assets.splats = run.records();
    const splats::SplatFileInfo info{assets.mesh.source, splats::to_string(options.sampling), options.fit.eps,
                                     run.neighbors.k, 255, "grey", false};
    splats::write_splat_file(splat_path, assets.splats, info);
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
    assets.csm = std::move(built.csm);
  }
  assets.build_ms = clock.elapsed_ms();
  return assets;
}

}  // namespace splatcl::present
