#include "present/assets.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <optional>

#include "csm/build.hpp"
#include "csm/splat_lighting.hpp"
#include "io/checksum.hpp"
#include "io/output_files.hpp"
#include "io/atomic_file.hpp"
#include "io/text_file.hpp"
#include "math/dvec3.hpp"
#include "present/cache_blob.hpp"
#include "runtime/error.hpp"
#include "runtime/profiling.hpp"
#include "splats/pipeline.hpp"
#include "splats/pipeline_options.hpp"
#include "splats/sampling.hpp"
#include "splats/gaussian_file.hpp"

namespace splatcl::present {
namespace {

// The sphere grid's pole of an object's CSM: the first object axis of x, z, y whose world direction
// at time 0 keeps its pole cap clear of up and of the key lights as the object sees them, else the
// one that keeps them farthest. A query is answered by the map of the grid cell its direction falls
// in; the uniform grid's first row of maps lies 14° from the pole at 1024 maps and answers every
// direction within 20° of it (the cap), against about 6° at the equator, and the rows just outside
// the cap are tall: so 1.5 times the cap is kept clear. With the pole on y (the thesis's and `csm
// build`'s default) an overhead key light's shadow was drawn as from 14-20° further over, and with
// it on x a low light along x's. Outside the cap where a direction falls within its cell decides
// its error, so x stays where it clears (a helper's scene: 41 pixels inside a ball's umbra lit with
// the pole on x, 201 with it on z, the axis farthest from the light).
csm::PoleAxis scene_pole(const ObjectSpec& object, const Scene& scene, std::uint32_t maps) {
  const glm::mat3 turn(object.placement(0.0f));
  std::vector<glm::vec3> kept_clear{{0.0f, 1.0f, 0.0f}};
  for (const Light& light : scene.key_lights)
    if (glm::length(light.position - object.position) > 0.0f) kept_clear.push_back(glm::normalize(light.position - object.position));
  const double clear = 1.5 * std::acos(1.0 - 2.0 / std::sqrt(static_cast<double>(maps)));  // radians
  const std::pair<csm::PoleAxis, int> axes[] = {{csm::PoleAxis::X, 0}, {csm::PoleAxis::Z, 2}, {csm::PoleAxis::Y, 1}};
  csm::PoleAxis best = csm::PoleAxis::X;
  double best_angle = -1.0;
  for (const auto& [pole, column] : axes) {
    const glm::vec3 axis = glm::normalize(turn[column]);
    double nearest = std::numbers::pi / 2;  // the smallest angle between ±axis and a kept direction
    for (const glm::vec3& d : kept_clear) nearest = std::min(nearest, std::acos(std::min(1.0, std::abs(double{glm::dot(axis, d)}))));
    if (nearest > clear) return pole;
    if (nearest > best_angle) best = pole, best_angle = nearest;
  }
  return best;
}

template <class T>
std::string_view bytes_of(const std::vector<T>& values) {
  return {reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)};
}

// Reads a cache entry with `read` when the file exists; false when it does not or cannot be read
// (truncated, corrupted, written by an older version): the caller rebuilds and overwrites it
// rather than failing the render.
template <class Read>
bool read_cached(const std::string& path, const Read& read) {
  if (!std::filesystem::exists(path)) return false;
  try {
    read();
    return true;
  } catch (const Error&) {
    return false;
  }
}

// The drawn splats' fit (splats::clip_to_surface over the splats and their gap splats: the drawn
// splats and their second clip lines), so that a cached load does not fit again (about 190 ms of
// the default scene's setup, as much for the scans scene).
constexpr CacheMagic kDrawnMagic = {'S', 'P', 'L', 'D', 'R', 'A', 'W', 'N'};
constexpr std::uint32_t kDrawnVersion = 1;  // counts: drawn splats

void write_drawn_fit(const std::string& path, const std::vector<splats::SplatRecord>& drawn,
                     const std::vector<splats::ClipLine>& second_clips) {
  std::string body;
  put_array(body, drawn);
  put_array(body, second_clips);
  write_cache_blob(path, kDrawnMagic, kDrawnVersion, {static_cast<std::uint32_t>(drawn.size())}, body);
}

// Error unless the file holds the fit of `count` splats.
void read_drawn_fit(const std::string& path, std::size_t count, std::vector<splats::SplatRecord>& drawn,
                    std::vector<splats::ClipLine>& second_clips) {
  CacheBlob blob = read_cache_blob(path, kDrawnMagic, kDrawnVersion, 1, "drawn splat fit");
  if (blob.counts[0] != count) throw Error(fmt::format("{}: the fit of {} splats, the object has {}", path, blob.counts[0], count));
  blob.take(drawn, count);
  blob.take(second_clips, count);
  blob.expect_consumed();
}

// The Phong splats' normal fields of a mesh object (splats::fit_normal_fields over the drawn
// splats and over the LOD tree's nodes): 19 nearest-surface queries per splat and node, about
// 100 ms of the default scene's setup.
constexpr CacheMagic kFieldsMagic = {'S', 'P', 'L', 'F', 'I', 'E', 'L', 'D'};
constexpr std::uint32_t kFieldsVersion = 1;  // counts: drawn splats, tree nodes

void write_normal_fields(const std::string& path, const std::vector<splats::NormalField>& splat_fields,
                         const std::vector<splats::NormalField>& node_fields) {
  std::string body;
  put_array(body, splat_fields);
  put_array(body, node_fields);
  write_cache_blob(path, kFieldsMagic, kFieldsVersion,
                   {static_cast<std::uint32_t>(splat_fields.size()), static_cast<std::uint32_t>(node_fields.size())}, body);
}

// Error unless the file holds the fields of `splats` drawn splats and `nodes` tree nodes.
void read_normal_fields(const std::string& path, std::size_t splats, std::size_t nodes, std::vector<splats::NormalField>& splat_fields,
                        std::vector<splats::NormalField>& node_fields) {
  CacheBlob blob = read_cache_blob(path, kFieldsMagic, kFieldsVersion, 2, "normal fields");
  if (blob.counts[0] != splats || blob.counts[1] != nodes)
    throw Error(fmt::format("{}: the fields of {} splats and {} nodes, the object has {} and {}", path, blob.counts[0], blob.counts[1],
                            splats, nodes));
  blob.take(splat_fields, splats);
  blob.take(node_fields, nodes);
  blob.expect_consumed();
}

}  // namespace

std::string default_cache_dir() {
  if (const char* dir = std::getenv("SPLATCL_CACHE"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/splatcl";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/splatcl";
  return ".splatcl-cache";
}

std::string asset_key(const Mesh& mesh, const std::string& parameters) {
  std::uint64_t h = fnv1a64(bytes_of(mesh.vertices));
  h = fnv1a64(bytes_of(mesh.face_offsets), h);
  h = fnv1a64(bytes_of(mesh.corners), h);
  return checksum_hex(fnv1a64(parameters, h));
}

SplatObjectFile read_splat_object(const std::string& path) {
  const std::string bytes = read_text_file(path, "splat file");
  SplatObjectFile file;
  file.checksum = checksum_hex(fnv1a64(bytes));
  if (splats::is_splatcl_splat_file(bytes)) {
    splats::SplatFile decoded = splats::decode_splat_file(bytes, path);
    file.splats = std::move(decoded.splats);
    file.origin = decoded.info.origin;
  } else {
    file.splats = splats::decode_gaussian_file(bytes, path);
    file.origin = splats::gaussian_file_origin(bytes, path);
  }
  return file;
}

Mesh splat_disc_mesh(const std::vector<splats::SplatRecord>& splats, const std::string& what) {
  std::vector<Vec3> vertices;
  std::vector<std::vector<std::uint32_t>> faces;
  vertices.reserve(6 * splats.size());
  faces.reserve(splats.size());
  for (const splats::SplatRecord& s : splats) {
    // In double: a splat file at 1e-11 scale squares to below float range and read as "no splat
    // has an area" (a helper's audit), while such a mesh renders.
    if (!(length(cross(DVec3(s.major), DVec3(s.minor))) > 0)) continue;
    const auto first = static_cast<std::uint32_t>(vertices.size());
    for (int k = 0; k < 6; ++k) {
      const float angle = static_cast<float>(k) * std::numbers::pi_v<float> / 3.0f;
      vertices.push_back(s.center + std::cos(angle) * s.major + std::sin(angle) * s.minor);
    }
    // Wound so that the hexagon's normal is the splat's: the CSM capture is two-sided, the mesh's
    // normals are what a viewer of the mesh would see.
    const bool flip = dot(cross(s.major, s.minor), s.normal) < 0;
    faces.push_back(flip ? std::vector<std::uint32_t>{first + 5, first + 4, first + 3, first + 2, first + 1, first}
                         : std::vector<std::uint32_t>{first, first + 1, first + 2, first + 3, first + 4, first + 5});
  }
  if (faces.empty()) throw Error(fmt::format("{}: no splat has an area", what));
  return make_mesh(vertices, faces, what + " (splat discs)");
}

namespace {

// Applies a fit to splats: the same scale and offset as the mesh's vertices.
void fit_splats(std::vector<splats::SplatRecord>& splats, const FitTransform& t) {
  for (splats::SplatRecord& s : splats) {
    s.center = t.apply(s.center);
    s.major = t.scale * s.major;
    s.minor = t.scale * s.minor;
  }
}

std::string seconds(double ms) { return fmt::format("{:.1f} s", ms / 1000.0); }

}  // namespace

std::string far_placement_check(const ObjectSpec& object, const Mesh& mesh) {
  // Bounds of where the object's points go at any time, per axis (floats step by the largest
  // |coordinate|; the centre's length overstated it by up to √3, a step too coarse): its centre (or
  // orbit) plus its extent, any rotation of a point within √3 × its mesh's reach. An orbit's
  // centre is orbit_center + (r cos, position.y − orbit_center.y, r sin): position's x and z play
  // no part (ObjectSpec::placement), its y is position.y.
  const Animation& orbit = object.animation;
  const double r = orbit.orbit_radius;
  const double centre = r > 0 ? std::max({std::abs(double{orbit.orbit_center.x}) + r, std::abs(double{object.position.y}),
                                          std::abs(double{orbit.orbit_center.z}) + r})
                              : std::max({std::abs(double{object.position.x}), std::abs(double{object.position.y}),
                                          std::abs(double{object.position.z})});
  const double reach = centre + std::sqrt(3.0) * object.scale * mesh.bounds().reach();
  const FloatStep far = float_step(reach, object.scale * mesh.bounds().exact_diagonal());
  if (!far.coarse()) return {};
  const std::string text = fmt::format("placed where coordinates reach {:.7g}, where {}: the presenter draws, lights and "
                                       "shadows it in float world coordinates",
                                       reach, far.clause("its", "size"));
  if (far.share > kFarPlacementShare)
    throw Error(text + ", which breaks it up; move the scene (objects, lights, camera) nearer the origin");
  return text + "; move the scene nearer the origin";
}

std::string stray_splats_warning(const std::vector<splats::SplatRecord>& splats) {
  constexpr std::size_t kFewest = 100;  // fewer splats have no "rest" to stray from
  constexpr double kStrayFactor = 10;
  if (splats.size() < kFewest) return {};
  // The central 98 % of the centres per axis, and the discs' whole box.
  DVec3 lo, hi, full_lo(INFINITY, INFINITY, INFINITY), full_hi(-INFINITY, -INFINITY, -INFINITY);
  std::vector<double> values(splats.size());
  for (int axis = 0; axis < 3; ++axis) {
    for (std::size_t i = 0; i < splats.size(); ++i) values[i] = (&splats[i].center.x)[axis];
    const auto at = [&](double q) {
      const auto k = static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1));
      std::nth_element(values.begin(), values.begin() + k, values.end());
      return values[static_cast<std::size_t>(k)];
    };
    (&lo.x)[axis] = at(0.01), (&hi.x)[axis] = at(0.99);
  }
  std::vector<double> reach(splats.size());
  for (std::size_t i = 0; i < splats.size(); ++i) {
    const DVec3 c(splats[i].center);
    reach[i] = length(DVec3(splats[i].major));
    full_lo = {std::min(full_lo.x, c.x - reach[i]), std::min(full_lo.y, c.y - reach[i]), std::min(full_lo.z, c.z - reach[i])};
    full_hi = {std::max(full_hi.x, c.x + reach[i]), std::max(full_hi.y, c.y + reach[i]), std::max(full_hi.z, c.z + reach[i])};
  }
  const double central = length(hi - lo), whole = length(full_hi - full_lo);
  if (!(central > 0) || !(whole > kStrayFactor * central)) return {};
  std::size_t stray = 0;
  for (std::size_t i = 0; i < splats.size(); ++i) {
    const DVec3 c(splats[i].center);
    const double outside = std::max({0.0, lo.x - c.x, c.x - hi.x, lo.y - c.y, c.y - hi.y, lo.z - c.z, c.z - hi.z});
    stray += outside + reach[i] > central;
  }
  return fmt::format("{} of {} splats reach far outside the rest (the box the fit scales is {:.3g}x the extent of the central "
                     "98 %): stray Gaussians of a capture? The object is fitted by that box; crop them from the file",
                     stray, splats.size(), whole / central);
}

void check_scene_settings(const Scene& scene) {
  if (scene.key_lights.size() > csm::SplatLighting::kMaxKeyLights)
    throw Error(fmt::format("{}: 'key_lights' lists {} lights, at most {}", scene.source, scene.key_lights.size(),
                            csm::SplatLighting::kMaxKeyLights));
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (!scene.objects[i].mesh.splat_path.empty()) continue;  // a splat file is drawn as it is
    try {
      splats::parse_sampling(object_quality(scene.quality, scene.objects[i]).sampling);
    } catch (const Error& e) {
      throw Error(fmt::format("{}: 'sampling': {}", object_where(scene, i), e.what()));
    }
  }
}

ObjectAssets load_object_assets(const ObjectSpec& object, const Scene& scene, const std::string& cache_dir,
                                Runtime& runtime, const AssetProgress& progress) {
  const Quality q = object_quality(scene.quality, object);
  const Stopwatch clock;
  const auto report = [&](const std::string& what, bool finished = false) {
    if (progress) progress(fmt::format("{}: {}", object.name, what), finished);
  };
  ObjectAssets assets;
  std::string splat_parameters;
  std::string texture_path;
  const bool splat_file = !object.mesh.splat_path.empty();
  if (splat_file) {
    const std::string path = scene_path(object.mesh.splat_path, scene.directory);
    report("reading " + path);
    SplatObjectFile file = read_splat_object(path);
    assets.splats = std::move(file.splats);
    // Without a fit the splats go where the model's coordinates put them: the origin their file
    // records added (a fit places them by their box, where it cancels, and keeps their detail).
    if (!object.fit.enabled() && (file.origin.x != 0 || file.origin.y != 0 || file.origin.z != 0))
      for (splats::SplatRecord& s : assets.splats) {
        const DVec3 placed = file.origin + DVec3(s.center);
        if (!(std::max({std::fabs(placed.x), std::fabs(placed.y), std::fabs(placed.z)}) <= std::numeric_limits<float>::max()))
          throw Error(fmt::format("{}: its splats placed at its splatcl_origin ({}, {}, {}) leave float range; give the object a fit", path,
                                  file.origin.x, file.origin.y, file.origin.z));
        s.center = to_float(placed);
      }
    assets.mesh = splat_disc_mesh(assets.splats, path);
    if (object.fit.enabled()) {
      // One stray Gaussian far out (common in trained captures) sets the fitted box, and the object
      // shrank to nothing without a word.
      assets.fit_warning = stray_splats_warning(assets.splats);
      // Affine, so the fitted splats' discs are the discs' corners fitted.
      const FitTransform t = fit_transform(assets.mesh.vertices, object.fit, object.rotation_degrees, path);
      fit_splats(assets.splats, t);
      t.apply_to(assets.mesh.vertices);
    }
    assets.splats_cached = true;  // nothing to build
    splat_parameters = "splat file " + file.checksum;
  } else {
    report("loading the mesh");
    assets.mesh = make_fitted_mesh(object, scene.directory);
    // Colour sources enter the key only when used, so grey objects keep their cache entries.
    splat_parameters = fmt::format("splats v{} sampling={} eps_diagonal={:.9g}", splats::kSplatMethodVersion, q.sampling, q.eps_diagonal);
    if (q.splat_bound != "thesis") splat_parameters += " bound=" + q.splat_bound;
    if (q.crease_angle < 180) splat_parameters += fmt::format(" crease={:.9g}", q.crease_angle);
    if (object.splat_colors) {
      if (!object.texture.empty()) {
        texture_path = scene_path(object.texture, scene.directory);
        splat_parameters += fmt::format(" texture={}", checksum_of_file(texture_path));
      } else {
        splat_parameters += " field=" + object.color_field;
      }
      if (object.color_tolerance < 255) splat_parameters += fmt::format(" tolerance={}", object.color_tolerance);
    }
  }
  assets.placement_warning = far_placement_check(object, assets.mesh);  // before any building
  // The drawn splats' fit (its gap splats are cached, and the LOD tree is built over them too).
  const bool fit_drawn = !splat_file && q.surface_clip > 0;
  const std::string gap_parameters =
      fit_drawn ? fmt::format("{}|drawn gaps v3 surface_clip={:.9g} scale={:.9g}", splat_parameters, q.surface_clip, q.splat_scale)
                : splat_parameters;
  const LodOptions tree_options{q.lod_leaf, 32, 0.1f};
  const std::string tree_parameters = fmt::format("{}|tree v1 leaf={} grid={} overlap={:.9g}", gap_parameters,
                                                  tree_options.leaf_splats, tree_options.grid, tree_options.overlap);
  // The build's rule for single-surface pixels (quality.csm_single_hit, auto resolved by
  // resolve_single_hit): named in the key unless it is sphere-exit, so that an open mesh's maps
  // cached with sphere-exit were built again and a closed mesh's keep their keys.
  const csm::SingleHit single_hit = csm::resolve_single_hit(csm::parse_single_hit(q.csm_single_hit), assets.mesh);
  const csm::PoleAxis pole = scene_pole(object, scene, q.csm_maps);
  const std::string csm_parameters = fmt::format("csm v2 pole={} maps={} resolution={}{}", csm::to_string(pole), q.csm_maps, q.csm_resolution,
                                                 single_hit == csm::SingleHit::SphereExit ? "" : fmt::format(" single_hit={}", csm::to_string(single_hit)));
  assets.key = asset_key(assets.mesh, splat_parameters + "|" + csm_parameters);
  std::error_code ec;
  std::filesystem::create_directories(cache_dir, ec);
  if (ec) throw Error(fmt::format("cannot create the asset cache {}: {}", cache_dir, ec.message()));
  const std::string splat_path = fmt::format("{}/{}.splats.ply", cache_dir, asset_key(assets.mesh, splat_parameters));
  const std::string csm_path = fmt::format("{}/{}.csm", cache_dir, asset_key(assets.mesh, csm_parameters));
  const std::string tree_path = fmt::format("{}/{}.spt", cache_dir, asset_key(assets.mesh, tree_parameters));
  const std::string gap_path = fmt::format("{}/{}.gaps.ply", cache_dir, asset_key(assets.mesh, gap_parameters));
  // Like "drawn gaps", raise "drawn fit" whenever splats::clip_to_surface changes.
  const std::string drawn_path = fmt::format("{}/{}.drawn", cache_dir, asset_key(assets.mesh, gap_parameters + "|drawn fit v1"));

  // What is not cached is built and then written there: a cache the user cannot write failed only
  // after the build (a helper's audit: 24 s into a bunny). Probed once, at the first miss, so a
  // read-only cache that holds every asset still serves.
  bool cache_probed = false;
  const auto before_building = [&] {
    if (!cache_probed) check_writable_directory(cache_dir, "the asset cache");
    cache_probed = true;
  };
  if (!splat_file) assets.splats_cached = read_cached(splat_path, [&] { assets.splats = splats::read_splat_file(splat_path).splats; });
  if (!assets.splats_cached) {
    before_building();
    const Stopwatch step;
    report("splats");
    // The scene's quality settings and colour source as the splat stage's shared parameter list.
    splats::SplatParameters params;
    params.samples = q.sampling;
    params.eps_diag = q.eps_diagonal;
    params.thesis_only = q.splat_bound == "thesis";
    params.crease_angle = q.crease_angle;
    if (object.splat_colors) {
      params.color_tol = static_cast<int>(object.color_tolerance);
      if (!texture_path.empty())
        params.texture = texture_path;
      else
        params.color_field = object.color_field;
    }
    const splats::SplatSetup setup = splats::splat_setup(params, assets.mesh, assets.mesh.source);
    const splats::SplatRun run =
        splats::generate_splats(assets.mesh, setup.colors, setup.options, &runtime, [&](const std::string& phase) { report("splats: " + phase); });
    assets.splats = run.records();
    splats::write_splat_file(splat_path, assets.splats, splats::splat_file_info(setup, run, assets.mesh.source));
    report(fmt::format("{} splats from {} faces in {}", assets.splats.size(), assets.mesh.face_count(), seconds(step.elapsed_ms())), true);
  }
  assets.drawn = assets.splats;
  assets.second_clips.assign(assets.drawn.size(), splats::ClipLine{});
  // The mesh as the fit and the normal fields query it, built on first use: not at all when both
  // come from the cache.
  std::optional<splats::Surface> surface;
  const auto mesh_surface = [&]() -> const splats::Surface& {
    if (!surface) surface.emplace(assets.mesh);
    return *surface;
  };
  if (fit_drawn) {
    const double tolerance = q.surface_clip * assets.mesh.bounds().diagonal();
    std::vector<splats::SplatRecord> gaps;
    if (assets.splats_cached) assets.gaps_cached = read_cached(gap_path, [&] { gaps = splats::read_splat_file(gap_path).splats; });
    if (assets.gaps_cached)
      assets.drawn_cached = read_cached(drawn_path, [&] {
        read_drawn_fit(drawn_path, assets.splats.size() + gaps.size(), assets.drawn, assets.second_clips);
      });
    if (!assets.drawn_cached) {
      before_building();
      splats::clip_to_surface(mesh_surface(), assets.drawn, tolerance, q.splat_scale, assets.second_clips);
    }
    if (!assets.gaps_cached) {
      before_building();
      const Stopwatch step;
      report("gap splats of the splats as drawn");
      splats::SurfaceFitStats stats;
      gaps = splats::cover_drawn_gaps(mesh_surface(), assets.drawn, assets.second_clips, tolerance, q.splat_scale, stats);
      splats::SplatFileInfo info;  // what the reader checks; the cache key holds the parameters
      info.model = assets.mesh.source;
      info.sampling = "gaps";
      info.eps = static_cast<float>(tolerance);
      info.k = 1;
      info.color_source = "nearest splat";
      splats::write_splat_file(gap_path, gaps, info);
      report(fmt::format("{} gap splats of the splats as drawn in {}", gaps.size(), seconds(step.elapsed_ms())), true);
    }
    assets.gap_splats = gaps.size();
    assets.splats.insert(assets.splats.end(), gaps.begin(), gaps.end());
    if (!assets.drawn_cached) {
      // Drawn like the others: cut at a sharp edge they overhang at the splat scale.
      std::vector<splats::ClipLine> gap_corners;
      splats::clip_to_surface(mesh_surface(), gaps, tolerance, q.splat_scale, gap_corners);
      assets.drawn.insert(assets.drawn.end(), gaps.begin(), gaps.end());
      assets.second_clips.insert(assets.second_clips.end(), gap_corners.begin(), gap_corners.end());
      write_drawn_fit(drawn_path, assets.drawn, assets.second_clips);
    }
  }
  if (assets.splats_cached && (!fit_drawn || assets.gaps_cached))
    assets.tree_cached =
        read_cached(tree_path, [&] { assets.tree = read_splat_tree(tree_path, static_cast<std::uint32_t>(assets.splats.size())); });
  if (!assets.tree_cached) {
    before_building();
    const Stopwatch step;
    report("LOD tree");
    assets.tree = build_splat_tree(assets.splats, tree_options);
    write_splat_tree(tree_path, assets.tree);
    report(fmt::format("LOD tree of {} splats in {}", assets.splats.size(), seconds(step.elapsed_ms())), true);
  }
  // Phong splats: each splat's normal field from the mesh's smooth normals. A splat file has no
  // surface but its own discs: its splats are drawn as they are, their fields from their neighbours.
  if (splat_file) {
    assets.normal_fields = splats::fit_normal_fields_from_splats(assets.drawn, q.crease_angle);
    assets.node_fields = splats::fit_normal_fields_from_splats(assets.tree.nodes, assets.drawn, q.crease_angle);
  } else {
    // Raise "fields v1" whenever splats::fit_normal_fields changes.
    const std::string fields_path = fmt::format("{}/{}.fields", cache_dir,
                                                asset_key(assets.mesh, fmt::format("{}|fields v1 crease={:.9g}", tree_parameters, q.crease_angle)));
    if (assets.tree_cached && (!fit_drawn || assets.drawn_cached))
      assets.fields_cached = read_cached(fields_path, [&] {
        read_normal_fields(fields_path, assets.drawn.size(), assets.tree.nodes.size(), assets.normal_fields, assets.node_fields);
      });
    if (!assets.fields_cached) {
      before_building();
      assets.normal_fields = splats::fit_normal_fields(assets.mesh, mesh_surface(), assets.drawn, assets.second_clips, q.crease_angle);
      assets.node_fields = splats::fit_normal_fields(assets.mesh, mesh_surface(), assets.tree.nodes, {}, q.crease_angle);
      write_normal_fields(fields_path, assets.normal_fields, assets.node_fields);
    }
  }
  assets.csm_cached = read_cached(csm_path, [&] { assets.csm = csm::read_csm(csm_path); });
  // Parts thinner than the hit epsilon of a closed mesh: the build says, and its answer is cached
  // beside the CSM (empty: none); a cached CSM without one has its mesh sampled here (a BVH and
  // 16,384 rays: 0.1-0.2 s on a 100k-face scan).
  const std::string thin_remedy = "give the object \"quality\": {\"csm_single_hit\": \"exact\"}, or thicken the part";
  const std::string thin_path = csm_path + ".thin1";  // raise the number when csm::thin_part_warning changes
  constexpr std::string_view kThinHeader = "splatcl thin-part warning 1\n";  // then the warning, empty for none
  const auto read_thin = [&] {
    const std::string text = read_text_file(thin_path, "cached thin-part warning");
    if (!text.starts_with(kThinHeader) || text.find('\n', kThinHeader.size()) != std::string::npos)
      throw Error(thin_path + ": not a cached thin-part warning");
    assets.thin_part_warning = text.substr(kThinHeader.size());
  };
  const auto write_thin = [&] { write_file_atomically(thin_path, std::string(kThinHeader) + assets.thin_part_warning); };
  if (assets.csm_cached && !read_cached(thin_path, read_thin)) {
    if (csm::resolve_single_hit(single_hit, assets.mesh) == csm::SingleHit::SphereExit)
      assets.thin_part_warning = csm::thin_part_warning(
          csm::CaptureScene(assets.mesh, csm::bounding_sphere(assets.mesh), q.csm_resolution, single_hit), assets.mesh, thin_remedy);
    write_thin();
  }
  if (!assets.csm_cached) {
    before_building();
    const Stopwatch step;
    report("coherent shadow map");
    csm::BuildOptions options;
    options.maps = q.csm_maps;
    options.resolution = q.csm_resolution;
    options.single_hit = single_hit;
    options.pole = pole;
    options.thin_part_remedy = thin_remedy;
    csm::BuildResult built = csm::build_csm(assets.mesh, options, &runtime, [&](std::uint32_t done, std::uint32_t total) {
      report(fmt::format("coherent shadow map {}/{}", done, total));
    });
    assets.thin_part_warning = built.thin_part_warning;
    write_thin();
    csm::write_csm(csm_path, built.csm, csm::Encoding::Compact, &built.segments);
    // Read back what was cached: the compact encoding stores other (equally lossless) depths than
    // the build's midpoints, and a first render must see the same shadows as every later one.
    assets.csm = csm::read_csm(csm_path);
    report(fmt::format("coherent shadow map of {} maps of {}² in {}", q.csm_maps, q.csm_resolution, seconds(step.elapsed_ms())), true);
  }
  assets.build_ms = clock.elapsed_ms();
  return assets;
}

}  // namespace splatcl::present
