#include "core/scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>

#include "io/json_keys.hpp"
#include "io/text_file.hpp"
#include "runtime/embedded.hpp"
#include "runtime/error.hpp"

namespace splatcl {
namespace {

using nlohmann::json;

// Field readers: a missing field keeps the default; a present one of the wrong shape throws
// Error naming it.
struct Reader {
  std::string source;  // the scene file, and the object where one is being read
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw Error(fmt::format("{}: '{}' {}", source, field, what));
  }
  // Numbers are finite as floats (json_float): 1e39 became inf, which failed far from here with
  // another cause ("not invertible", "non-finite centre") or drew nothing.
  float number(const json& j, const std::string& field, float fallback) const {
    if (!j.contains(field)) return fallback;
    float v = 0;
    if (!json_float(j[field], v)) fail(field, "must be a finite number (within float range, |x| < 3.4e38)");
    return v;
  }
  float positive(const json& j, const std::string& field, float fallback) const {
    const float v = number(j, field, fallback);
    if (!(v > 0)) fail(field, "must be positive");
    return v;
  }
  // A size or scale factor the assets are built at: within what their float geometry holds (the
  // coherent shadow maps take bounding spheres of radius 1e-18..1e18). Beyond, the error named the
  // mesh's bounding sphere, not the field that caused it.
  float extent(const json& j, const std::string& field, float fallback) const {
    const float v = positive(j, field, fallback);
    if (!(v >= kMinSceneExtent && v <= kMaxSceneExtent))
      fail(field, fmt::format("must be in [{:g}, {:g}], not {:g}", kMinSceneExtent, kMaxSceneExtent, v));
    return v;
  }
  // A light's place: every coordinate within ±kMaxSceneExtent, so that the square of a distance
  // between it and the scene stays finite in float (beyond 1.8e19 it was inf, and a light that
  // covered the scene shaded it black; a helper's audit of cluster).
  glm::vec3 place(const json& j, const std::string& field, glm::vec3 fallback) const {
    const glm::vec3 v = vec3(j, field, fallback);
    for (int i = 0; i < 3; ++i)
      if (!(std::abs(v[i]) <= kMaxSceneExtent))
        fail(field, fmt::format("coordinates must be within ±{:g}, not {:g}", kMaxSceneExtent, v[i]));
    return v;
  }
  std::uint32_t count(const json& j, const std::string& field, std::uint32_t fallback, std::uint32_t lo,
                      std::uint32_t hi) const {
    if (!j.contains(field)) return fallback;
    if (!j[field].is_number_integer() || j[field].get<long long>() < lo || j[field].get<long long>() > hi)
      fail(field, fmt::format("must be an integer in [{}, {}]", lo, hi));
    return j[field].get<std::uint32_t>();
  }
  glm::vec3 vec3(const json& j, const std::string& field, glm::vec3 fallback) const {
    if (!j.contains(field)) return fallback;
    const json& v = j[field];
    glm::vec3 out;
    if (v.is_number() && json_float(v, out.x)) return glm::vec3(out.x);  // one number for all three
    if (!v.is_array() || v.size() != 3 || !json_float(v[0], out.x) || !json_float(v[1], out.y) || !json_float(v[2], out.z))
      fail(field, "must be an array of 3 finite numbers (within float range)");
    return out;
  }
  // A colour or radiance: every channel finite and >= 0, and with `most` > 0 at most that (an
  // albedo reflects at most all the light).
  glm::vec3 color(const json& j, const std::string& field, glm::vec3 fallback, float most = 0) const {
    const glm::vec3 c = vec3(j, field, fallback);
    for (int i = 0; i < 3; ++i)
      if (!(std::isfinite(c[i]) && c[i] >= 0 && (most <= 0 || c[i] <= most)))
        fail(field, most > 0 ? fmt::format("must have every channel in [0, {}]", most) : std::string("must have no negative channel"));
    return c;
  }
  float non_negative(const json& j, const std::string& field, float fallback, const std::string& meaning) const {
    const float v = number(j, field, fallback);
    if (!(v >= 0)) fail(field, fmt::format("must not be negative ({})", meaning));
    return v;
  }
  std::array<float, 2> range(const json& j, const std::string& field, std::array<float, 2> fallback) const {
    if (!j.contains(field)) return fallback;
    const json& v = j[field];
    float lo = 0, hi = 0;
    if (v.is_number() && json_float(v, lo)) return {lo, lo};
    if (!v.is_array() || v.size() != 2 || !json_float(v[0], lo) || !json_float(v[1], hi) || lo > hi)
      fail(field, "must be [min, max] (finite numbers within float range)");
    return {lo, hi};
  }
  std::string text(const json& j, const std::string& field, const std::string& fallback,
                   std::initializer_list<const char*> allowed = {}) const {
    if (!j.contains(field)) return fallback;
    if (!j[field].is_string()) fail(field, "must be a string");
    const std::string value = j[field].get<std::string>();
    if (allowed.size() == 0) return value;
    std::string list;
    for (const char* a : allowed) {
      if (value == a) return value;
      list += (list.empty() ? "" : ", ") + std::string(a);
    }
    fail(field, fmt::format("is '{}', not one of: {}", value, list));
  }
  bool flag(const json& j, const std::string& field, bool fallback) const {
    if (!j.contains(field)) return fallback;
    if (!j[field].is_boolean()) fail(field, "must be true or false");
    return j[field].get<bool>();
  }
  const json& object(const json& j, const std::string& field) const {
    if (!j[field].is_object()) fail(field, "must be an object");
    return j[field];
  }
  // Every key of the object `j` (the scene part `where`) must be one of `known`: a typo such as
  // "colour" or "positon" is an error naming it, not a silent default.
  void known_keys(const json& j, const std::string& where, std::initializer_list<const char*> known) const {
    if (const auto key = unknown_key(j, known)) fail(*key, fmt::format("is not a key of {} (known: {})", where, key_list(known)));
  }
};

Light read_light(const Reader& list_reader, const json& j, const std::string& where) {
  if (!j.is_object()) list_reader.fail("lights", "entries must be objects");
  list_reader.known_keys(j, where, {"position", "radius", "color", "size"});
  const Reader r{fmt::format("{}: {}", list_reader.source, where)};
  Light light;
  if (!j.contains("position")) r.fail("position", "is missing (a light needs a position)");
  light.position = r.place(j, "position", light.position);
  light.radius = r.extent(j, "radius", light.radius);
  light.color = r.color(j, "color", light.color);
  light.size = r.number(j, "size", light.size);
  if (!(light.size >= 0 && light.size <= kMaxSceneExtent)) r.fail("size", fmt::format("must be in [0, {:g}]", kMaxSceneExtent));
  return light;
}

MeshSpec read_mesh(const Reader& r, const json& j) {
  MeshSpec spec;
  if (j.is_string()) {
    spec.path = j.get<std::string>();
    if (spec.path.empty()) r.fail("mesh", "must not be an empty file name");
    return spec;
  }
  if (!j.is_object()) r.fail("mesh", "must be a file name or an object");
  r.known_keys(j, "mesh", {"procedural", "radius", "tube", "size", "segments", "rings"});
  spec.procedural = r.text(j, "procedural", "", {"sphere", "torus", "box"});
  if (spec.procedural.empty()) r.fail("mesh", "needs \"procedural\": sphere, torus or box (or give a file name)");
  spec.radius = r.positive(j, "radius", spec.radius);
  spec.tube = r.positive(j, "tube", spec.tube);
  spec.size = r.vec3(j, "size", spec.size);
  if (!(spec.size.x > 0 && spec.size.y > 0 && spec.size.z > 0)) r.fail("size", "must be positive");
  spec.segments = r.count(j, "segments", spec.segments, 3, 1024);
  spec.rings = r.count(j, "rings", spec.rings, 1, 1024);
  return spec;
}

// The quality settings that shape an object's assets (the scene's, or an object's overrides).
void read_asset_quality(const Reader& r, const json& q, Quality& Q) {
  Q.sampling = r.text(q, "sampling", Q.sampling);
  if (Q.sampling.empty()) r.fail("sampling", "must not be empty (auto, vertices, grid:N or spacing:D)");
  Q.splat_bound = r.text(q, "splat_bound", Q.splat_bound, {"thesis", "two-sided"});
  Q.eps_diagonal = r.positive(q, "eps_diagonal", Q.eps_diagonal);
  Q.crease_angle = r.positive(q, "crease_angle", Q.crease_angle);
  if (Q.crease_angle > 180) r.fail("crease_angle", fmt::format("must be in (0, 180] degrees, got {}", Q.crease_angle));
  Q.csm_maps = r.count(q, "csm_maps", Q.csm_maps, 16, 65536);
  // The presenter's CSMs use the build's default uniform distribution: its maps lie on a G x G grid.
  const auto grid = static_cast<std::uint32_t>(std::lround(std::sqrt(static_cast<double>(Q.csm_maps))));
  if (grid * grid != Q.csm_maps)
    r.fail("csm_maps", fmt::format("{} is not a perfect square (the maps lie on a uniform G x G grid, e.g. 1024 or 4096)", Q.csm_maps));
  Q.csm_resolution = r.count(q, "csm_resolution", Q.csm_resolution, 8, 1024);
  Q.csm_single_hit = r.text(q, "csm_single_hit", Q.csm_single_hit, {"auto", "sphere-exit", "exact", "thin"});
  Q.surface_clip = r.number(q, "surface_clip", Q.surface_clip);
  if (!(Q.surface_clip >= 0 && Q.surface_clip <= 0.1f))
    r.fail("surface_clip", fmt::format("must be in [0, 0.1] (a share of the mesh's diagonal; 0 = drawn as built), got {}", Q.surface_clip));
}

ObjectSpec read_object(const Reader& scene_reader, const json& j, std::size_t index) {
  if (!j.is_object()) scene_reader.fail("objects", "entries must be objects");
  scene_reader.known_keys(j, fmt::format("objects[{}]", index),
                          {"name", "mesh", "color", "color_field", "texture", "color_tolerance", "position", "rotation_degrees", "scale",
                           "occluder", "two_sided", "animation", "splats", "fit", "quality"});
  ObjectSpec o;
  o.name = scene_reader.text(j, "name", fmt::format("object {}", index));
  if (o.name.empty()) scene_reader.fail("name", fmt::format("of objects[{}] must not be empty", index));
  // Errors in the object name it: a scene of several objects may share every field name.
  const Reader r{object_where(scene_reader.source, index, o.name)};
  if (j.contains("mesh") == j.contains("splats"))
    r.fail("mesh", fmt::format("{}: give either \"mesh\" (a file or a procedural shape) or \"splats\" (a splat PLY)",
                               j.contains("mesh") ? "and \"splats\" are both given" : "is missing"));
  if (j.contains("mesh")) {
    o.mesh = read_mesh(r, j["mesh"]);
  } else {
    o.mesh.splat_path = r.text(j, "splats", "");
    if (o.mesh.splat_path.empty()) r.fail("splats", "must be a file name (a splatcl splat PLY or a 3D Gaussian Splatting PLY)");
  }
  if (j.contains("fit")) {
    const json& f = r.object(j, "fit");
    r.known_keys(f, "fit", {"size", "on_floor"});
    if (f.contains("size")) o.fit.size = r.extent(f, "size", 1.0f);
    o.fit.on_floor = r.flag(f, "on_floor", o.fit.on_floor);
    if (!o.fit.enabled())  // {} or {"on_floor": false}
      r.fail("fit", "does nothing: give \"size\" (the largest extent it scales to), \"on_floor\": true, or both");
  }
  if (j.contains("quality")) {
    // Only what shapes the object's own assets; the frame's settings stay the scene's.
    const json& q = r.object(j, "quality");
    r.known_keys(q, fmt::format("objects[{}].quality", index),
                 {"sampling", "splat_bound", "eps_diagonal", "crease_angle", "csm_maps", "csm_resolution", "csm_single_hit", "surface_clip"});
    Quality read;
    read_asset_quality(r, q, read);
    AssetQualityOverrides& over = o.quality;
    if (q.contains("sampling")) over.sampling = read.sampling;
    if (q.contains("splat_bound")) over.splat_bound = read.splat_bound;
    if (q.contains("eps_diagonal")) over.eps_diagonal = read.eps_diagonal;
    if (q.contains("crease_angle")) over.crease_angle = read.crease_angle;
    if (q.contains("csm_maps")) over.csm_maps = read.csm_maps;
    if (q.contains("csm_resolution")) over.csm_resolution = read.csm_resolution;
    if (q.contains("csm_single_hit")) over.csm_single_hit = read.csm_single_hit;
    if (q.contains("surface_clip")) over.surface_clip = read.surface_clip;
    if (!o.mesh.splat_path.empty() && (over.sampling || over.splat_bound || over.eps_diagonal || over.crease_angle || over.surface_clip))
      r.fail("quality", "of a splat file: its splats are used as they are (only csm_maps, csm_resolution and csm_single_hit apply)");
  }
  if (!o.mesh.splat_path.empty() && (j.contains("color_field") || j.contains("texture") || j.contains("color_tolerance")))
    r.fail("color_field", "of a splat file: it brings its own colours (\"color\": \"splats\" uses them)");
  if (j.contains("color") && j["color"].is_string()) {
    if (j["color"].get<std::string>() != "splats") r.fail("color", "must be an RGB array, a number or \"splats\"");
    o.splat_colors = true;
    o.color_field = r.text(j, "color_field", o.color_field, {"grey", "soft", "hard", "rainbow"});
    o.texture = r.text(j, "texture", o.texture);
    o.color_tolerance = r.count(j, "color_tolerance", o.color_tolerance, 0, 255);
  } else {
    o.color = r.color(j, "color", o.color, 1.0f);
    if (j.contains("color_field") || j.contains("texture") || j.contains("color_tolerance")) r.fail("color_field", "needs \"color\": \"splats\"");
  }
  if (!o.mesh.splat_path.empty() && !j.contains("color")) o.splat_colors = true;  // a splat file's own colours
  o.position = r.vec3(j, "position", o.position);
  o.rotation_degrees = r.vec3(j, "rotation_degrees", o.rotation_degrees);
  // Angles within 100 turns and rates within 100 turns a second: 1e30 degrees (or degrees per
  // second) turned the object at random (float radians); a few turns are fine.
  const auto check_turns = [&](const char* field, glm::vec3 values, bool per_second) {
    for (int axis = 0; axis < 3; ++axis)
      if (std::abs(values[axis]) > kMaxSceneDegrees)
        r.fail(field, fmt::format("{:g} is beyond 100 turns{} (degrees{} in -{:g}..{:g})", values[axis], per_second ? " a second" : "",
                                  per_second ? " per second" : "", kMaxSceneDegrees, kMaxSceneDegrees));
  };
  check_turns("rotation_degrees", o.rotation_degrees, false);
  o.scale = r.extent(j, "scale", o.scale);
  o.occluder = r.flag(j, "occluder", o.occluder);
  if (j.contains("two_sided")) o.two_sided = r.flag(j, "two_sided", false);
  if (j.contains("animation")) {
    const json& a = r.object(j, "animation");
    r.known_keys(a, "animation", {"spin_degrees_per_second", "orbit"});
    o.animation.spin_degrees_per_second = r.vec3(a, "spin_degrees_per_second", o.animation.spin_degrees_per_second);
    check_turns("spin_degrees_per_second", o.animation.spin_degrees_per_second, true);
    if (a.contains("orbit")) {
      const json& orbit = r.object(a, "orbit");
      r.known_keys(orbit, "animation.orbit", {"center", "radius", "degrees_per_second", "phase_degrees"});
      o.animation.orbit_center = r.vec3(orbit, "center", o.animation.orbit_center);
      o.animation.orbit_radius = r.positive(orbit, "radius", 1.0f);
      o.animation.orbit_degrees_per_second = r.number(orbit, "degrees_per_second", 30.0f);
      check_turns("degrees_per_second", glm::vec3(o.animation.orbit_degrees_per_second), true);
      o.animation.orbit_phase_degrees = r.number(orbit, "phase_degrees", 0.0f);
      check_turns("phase_degrees", glm::vec3(o.animation.orbit_phase_degrees), false);
    }
  }
  return o;
}

// Rotations about x, then y, then z (degrees), as the scene's "rotation_degrees".
glm::mat4 rotation_matrix(glm::vec3 degrees) {
  const glm::vec3 angles = glm::radians(degrees);
  glm::mat4 m = glm::rotate(glm::mat4(1.0f), angles.z, {0, 0, 1});
  m = glm::rotate(m, angles.y, {0, 1, 0});
  return glm::rotate(m, angles.x, {1, 0, 0});
}

}  // namespace

std::string object_where(const std::string& source, std::size_t index, const std::string& name) {
  return fmt::format("{}: objects[{}] '{}'", source, index, name);
}

std::string object_where(const Scene& scene, std::size_t index) { return object_where(scene.source, index, scene.objects[index].name); }

Quality object_quality(const Quality& scene_quality, const ObjectSpec& object) {
  Quality q = scene_quality;
  const AssetQualityOverrides& over = object.quality;
  q.sampling = over.sampling.value_or(q.sampling);
  q.splat_bound = over.splat_bound.value_or(q.splat_bound);
  q.eps_diagonal = over.eps_diagonal.value_or(q.eps_diagonal);
  q.crease_angle = over.crease_angle.value_or(q.crease_angle);
  q.csm_maps = over.csm_maps.value_or(q.csm_maps);
  q.csm_resolution = over.csm_resolution.value_or(q.csm_resolution);
  q.csm_single_hit = over.csm_single_hit.value_or(q.csm_single_hit);
  q.surface_clip = over.surface_clip.value_or(q.surface_clip);
  return q;
}

// base + rate · time degrees, reduced to (−360, 360) in double: at a late time the float product
// had few bits below a turn, and the object jumped instead of turning.
namespace {
float turned_degrees(float base, float rate, float time) {
  return static_cast<float>(std::fmod(static_cast<double>(base) + static_cast<double>(rate) * static_cast<double>(time), 360.0));
}
}  // namespace

glm::mat4 ObjectSpec::placement(float time) const {
  glm::vec3 centre = position;
  if (animation.orbit_radius > 0) {
    const float angle = glm::radians(turned_degrees(animation.orbit_phase_degrees, animation.orbit_degrees_per_second, time));
    centre = animation.orbit_center +
             glm::vec3(animation.orbit_radius * std::cos(angle), position.y - animation.orbit_center.y,
                       animation.orbit_radius * std::sin(angle));
  }
  const glm::vec3 turned(turned_degrees(rotation_degrees.x, animation.spin_degrees_per_second.x, time),
                         turned_degrees(rotation_degrees.y, animation.spin_degrees_per_second.y, time),
                         turned_degrees(rotation_degrees.z, animation.spin_degrees_per_second.z, time));
  const glm::mat4 m = glm::translate(glm::mat4(1.0f), centre) * rotation_matrix(turned);
  return glm::scale(m, glm::vec3(scale));
}

std::vector<Light> generate_lights(const GeneratedLights& spec, const FloorSpec& floor) {
  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float extent = spec.extent > 0 ? spec.extent : 0.5f * floor.size;
  std::vector<Light> lights(spec.count);
  for (Light& light : lights) {
    light.position = {(2 * unit(rng) - 1) * extent, floor.y + spec.height_min + unit(rng) * (spec.height_max - spec.height_min),
                      (2 * unit(rng) - 1) * extent};
    light.radius = spec.radius_min + unit(rng) * (spec.radius_max - spec.radius_min);
    // A saturated hue: one channel full, one zero, one random.
    const float h = unit(rng) * 6.0f, f = h - std::floor(h);
    const glm::vec3 hues[6] = {{1, f, 0}, {1 - f, 1, 0}, {0, 1, f}, {0, 1 - f, 1}, {f, 0, 1}, {1, 0, 1 - f}};
    light.color = spec.intensity * hues[static_cast<int>(h) % 6];
  }
  return lights;
}

Scene parse_scene(std::string_view text, const std::string& source, const std::string& directory) {
  json j;
  try {
    j = parse_json_once_per_key<json>(text, source);
  } catch (const json::exception& e) {
    throw Error(fmt::format("{}: not valid JSON ({})", source, e.what()));
  }
  if (!j.is_object()) throw Error(source + ": the scene must be a JSON object");
  const Reader r{source};
  r.known_keys(j, "the scene", {"objects", "floor", "lights", "key_lights", "camera", "sky", "quality", "time"});
  Scene scene;
  scene.source = source;
  scene.directory = directory;
  if (!j.contains("objects") || !j["objects"].is_array()) r.fail("objects", "must be an array");
  for (std::size_t i = 0; i < j["objects"].size(); ++i) {
    scene.objects.push_back(read_object(r, j["objects"][i], i));
    // Names pick objects in the viewer and name them in errors, figures and the asset cache's progress.
    for (std::size_t k = 0; k < i; ++k)
      if (scene.objects[k].name == scene.objects[i].name)
        r.fail("name", fmt::format("'{}' is used by objects[{}] and objects[{}]: object names must differ", scene.objects[i].name, k, i));
  }
  if (j.contains("floor")) {
    if (j["floor"].is_boolean()) {
      scene.floor.enabled = j["floor"].get<bool>();
    } else {
      r.object(j, "floor");
      const json& f = j["floor"];
      r.known_keys(f, "floor", {"y", "size", "color", "splats_per_side"});
      const Reader fr{source + ": floor"};
      scene.floor.y = fr.number(f, "y", scene.floor.y);
      scene.floor.size = fr.positive(f, "size", scene.floor.size);
      scene.floor.color = fr.color(f, "color", scene.floor.color, 1.0f);
      scene.floor.splats_per_side = fr.count(f, "splats_per_side", scene.floor.splats_per_side, 2, 2048);
    }
  }
  if (j.contains("lights")) {
    const json& l = j["lights"];
    if (l.is_array()) {
      if (l.size() > kMaxSceneLights) r.fail("lights", fmt::format("lists {} lights, more than the limit of {}", l.size(), kMaxSceneLights));
      for (std::size_t i = 0; i < l.size(); ++i) scene.lights.push_back(read_light(r, l[i], fmt::format("lights[{}]", i)));
    } else if (l.is_object()) {
      r.known_keys(l, "lights", {"count", "radius", "height", "extent", "intensity", "seed"});
      const Reader lr{source + ": lights"};
      GeneratedLights& g = scene.generated;
      g.count = lr.count(l, "count", g.count, 0, kMaxSceneLights);
      const auto radius = lr.range(l, "radius", {g.radius_min, g.radius_max});
      const auto height = lr.range(l, "height", {g.height_min, g.height_max});
      if (!(radius[0] >= kMinSceneExtent && radius[1] <= kMaxSceneExtent))
        lr.fail("radius", fmt::format("must be within [{:g}, {:g}]", kMinSceneExtent, kMaxSceneExtent));
      if (!(height[0] >= 0)) lr.fail("height", "must not be negative (heights above the floor)");
      if (!(height[1] <= kMaxSceneExtent)) lr.fail("height", fmt::format("must be at most {:g}", kMaxSceneExtent));
      g.radius_min = radius[0], g.radius_max = radius[1], g.height_min = height[0], g.height_max = height[1];
      g.extent = lr.non_negative(l, "extent", g.extent, "half the side of the lights' square; 0 = half the floor's");
      if (!(g.extent <= kMaxSceneExtent)) lr.fail("extent", fmt::format("must be at most {:g}", kMaxSceneExtent));
      g.intensity = lr.positive(l, "intensity", g.intensity);
      g.seed = lr.count(l, "seed", static_cast<std::uint32_t>(g.seed), 0, UINT32_MAX);
    } else {
      r.fail("lights", "must be an array of lights or {\"count\": N, ...}");
    }
  }
  if (j.contains("key_lights")) {
    if (!j["key_lights"].is_array()) r.fail("key_lights", "must be an array");
    for (std::size_t i = 0; i < j["key_lights"].size(); ++i)
      scene.key_lights.push_back(read_light(r, j["key_lights"][i], fmt::format("key_lights[{}]", i)));
  }
  if (j.contains("camera")) scene.camera = camera_from_json(j["camera"], JsonFields{source + ": "});
  if (j.contains("sky")) {
    const json& s = r.object(j, "sky");
    r.known_keys(s, "sky", {"zenith", "horizon", "ground"});
    scene.sky.zenith = r.color(s, "zenith", scene.sky.zenith);
    scene.sky.horizon = r.color(s, "horizon", scene.sky.horizon);
    scene.sky.ground = r.color(s, "ground", scene.sky.ground);
  }
  if (j.contains("quality")) {
    const json& q = r.object(j, "quality");
    r.known_keys(q, "quality",
                 {"sampling", "splat_bound", "eps_diagonal", "crease_angle", "csm_maps", "csm_resolution", "csm_single_hit", "ao_samples", "ao_bias", "shadow_lift", "splat_scale", "surface_clip", "antialias", "depth_offset",
                  "gaussian", "mode", "shading", "tile", "shadows", "filter", "shadow_samples", "ambient_occlusion", "pixel_ao", "floor_pixels", "lod_error",
                  "lod_leaf", "specular", "shininess"});
    Quality& Q = scene.quality;
    read_asset_quality(r, q, Q);
    Q.ao_samples = r.count(q, "ao_samples", Q.ao_samples, 1, 256);
    Q.ao_bias = r.non_negative(q, "ao_bias", Q.ao_bias, "a depth bias in texels of each occluder's CSM");
    if (!(Q.ao_bias <= kMaxSceneAoBias)) r.fail("ao_bias", fmt::format("must be in [0, {:g}] texels, not {:g}", kMaxSceneAoBias, Q.ao_bias));
    Q.shadow_lift = r.non_negative(q, "shadow_lift", Q.shadow_lift, "a lift off the surface in world units");
    if (!(Q.shadow_lift <= kMaxSceneExtent)) r.fail("shadow_lift", fmt::format("must be at most {:g} world units", kMaxSceneExtent));
    Q.shadow_lift_auto = !q.contains("shadow_lift");
    Q.splat_scale = r.number(q, "splat_scale", Q.splat_scale);
    if (!(Q.splat_scale >= kMinSplatScale && Q.splat_scale <= kMaxSplatScale))  // the gap covering grows with k
      r.fail("splat_scale", fmt::format("must be in [{:g}, {:g}], not {:g}", kMinSplatScale, kMaxSplatScale, Q.splat_scale));
    Q.antialias = r.non_negative(q, "antialias", Q.antialias, "0 = off");
    // A jump relative to the farther depth is below 1, so above 1 only coverage would mark outlines.
    if (!(Q.antialias <= 1)) r.fail("antialias", fmt::format("must be in [0, 1] (a relative depth jump; 0 = off), not {:g}", Q.antialias));
    Q.depth_offset = r.non_negative(q, "depth_offset", Q.depth_offset, "the visibility pass's ε behind the nearest splat");
    if (!(Q.depth_offset <= kMaxSceneExtent)) r.fail("depth_offset", fmt::format("must be at most {:g} world units", kMaxSceneExtent));
    Q.depth_offset_auto = !q.contains("depth_offset");
    Q.gaussian = r.positive(q, "gaussian", Q.gaussian);
    Q.mode = r.text(q, "mode", Q.mode, {"splats", "points"});
    Q.shading = r.text(q, "shading", Q.shading, {"clustered", "tiled", "brute"});
    Q.tile = r.count(q, "tile", Q.tile, 4, 256);
    Q.shadows = r.text(q, "shadows", Q.shadows, {"splat", "pixel", "off"});
    Q.filter = r.text(q, "filter", Q.filter, {"none", "same-map", "cross-map", "march"});
    Q.shadow_samples = r.count(q, "shadow_samples", Q.shadow_samples, 1, 64);
    Q.ambient_occlusion = r.flag(q, "ambient_occlusion", Q.ambient_occlusion);
    Q.pixel_ao = r.flag(q, "pixel_ao", Q.pixel_ao);
    Q.floor_pixels = r.flag(q, "floor_pixels", Q.floor_pixels);
    Q.lod_error = r.number(q, "lod_error", Q.lod_error);
    if (Q.lod_error < 0) r.fail("lod_error", "must not be negative (0 = off)");
    Q.lod_leaf = r.count(q, "lod_leaf", Q.lod_leaf, 2, 4096);
    Q.specular = r.number(q, "specular", Q.specular);
    if (!(Q.specular >= 0 && Q.specular <= kMaxSpecular)) r.fail("specular", fmt::format("must be in [0, {}] (0 = off)", kMaxSpecular));
    Q.shininess = r.positive(q, "shininess", Q.shininess);
  }
  scene.time = r.number(j, "time", 0.0f);
  const auto generated = generate_lights(scene.generated, scene.floor);
  scene.lights.insert(scene.lights.end(), generated.begin(), generated.end());
  return scene;
}

Scene load_scene(const std::string& path) {
  const auto directory = std::filesystem::path(path).parent_path().string();
  return parse_scene(read_text_file(path, "scene"), path, directory);
}

const char* default_scene_name() { return "default scene (data/presenter-scene.json)"; }

Scene default_scene() { return parse_scene(embedded_data().at("presenter-scene.json"), default_scene_name(), "."); }

std::string scene_path(const std::string& path, const std::string& directory) {
  const std::filesystem::path p(path);
  return p.is_absolute() || directory.empty() ? p.string() : (std::filesystem::path(directory) / p).string();
}

std::vector<std::pair<std::string, std::string>> scene_input_files(const Scene& scene) {
  std::vector<std::pair<std::string, std::string>> files;
  if (scene.source != default_scene_name()) files.emplace_back("scene", scene.source);
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const ObjectSpec& object = scene.objects[i];
    const std::string where = object_where(scene, i);
    for (const auto& [what, path] : {std::pair{"mesh", &object.mesh.path}, {"splat file", &object.mesh.splat_path}, {"texture", &object.texture}})
      if (!path->empty()) files.emplace_back(std::string(what) + " (" + where + ")", scene_path(*path, scene.directory));
  }
  return files;
}

FitTransform fit_transform(const std::vector<Vec3>& points, const MeshFit& fit, glm::vec3 rotation_degrees,
                           const std::string& what) {
  FitTransform t;
  if (!fit.enabled()) return t;
  Box box;
  for (const Vec3& p : points) box.add(p);
  const glm::vec3 lo(box.lo.x, box.lo.y, box.lo.z), hi(box.hi.x, box.hi.y, box.hi.z);
  const float largest = box.empty() ? 0.0f : std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  if (!(largest > 0) || !std::isfinite(largest)) throw Error(fmt::format("{}: cannot fit: its bounding box has no extent", what));
  t.scale = fit.size > 0 ? fit.size / largest : 1.0f;
  t.offset = -t.scale * 0.5f * (lo + hi);
  if (fit.on_floor) {
    // The lowest point of the rotated, centred points, moved to the origin's height: the shift is
    // along the rotated frame's vertical, so it is R⁻¹ (0, −lowest, 0) in model space.
    const glm::mat3 rotation(rotation_matrix(rotation_degrees));
    float lowest = INFINITY;
    for (const Vec3& p : points) lowest = std::min(lowest, (rotation * t.apply(glm::vec3(p.x, p.y, p.z))).y);
    t.offset += glm::transpose(rotation) * glm::vec3(0.0f, -lowest, 0.0f);
  }
  return t;
}

Mesh make_fitted_mesh(const ObjectSpec& object, const std::string& directory) {
  // Fitted, a mesh is placed by its bounds alone: read it about their centre, in double.
  Mesh mesh = object.fit.enabled() && !object.mesh.path.empty()
                  ? load_mesh_recentred(scene_path(object.mesh.path, directory), Winding::Orient)
                  : make_object_mesh(object.mesh, directory);
  const FitTransform t = fit_transform(mesh.vertices, object.fit, object.rotation_degrees, mesh.source);
  if (object.fit.enabled()) t.apply_to(mesh.vertices);
  return mesh;
}

Mesh make_object_mesh(const MeshSpec& spec, const std::string& directory) {
  if (!spec.splat_path.empty()) throw Error(fmt::format("{}: a splat file, not a mesh", spec.splat_path));
  if (!spec.path.empty()) return load_mesh(scene_path(spec.path, directory), Winding::Orient);
  std::vector<Vec3> v;
  std::vector<std::vector<std::uint32_t>> f;
  const float pi = std::numbers::pi_v<float>;
  const std::uint32_t n = spec.segments, m = spec.rings;
  if (spec.procedural == "sphere") {
    v.push_back({0, spec.radius, 0});
    for (std::uint32_t i = 1; i < m; ++i) {
      const float theta = pi * static_cast<float>(i) / static_cast<float>(m);
      for (std::uint32_t k = 0; k < n; ++k) {
        const float phi = 2 * pi * static_cast<float>(k) / static_cast<float>(n);
        v.push_back({spec.radius * std::sin(theta) * std::cos(phi), spec.radius * std::cos(theta),
                     -spec.radius * std::sin(theta) * std::sin(phi)});
      }
    }
    v.push_back({0, -spec.radius, 0});
    const auto ring = [&](std::uint32_t i, std::uint32_t k) { return 1 + (i - 1) * n + k % n; };
    const std::uint32_t bottom = static_cast<std::uint32_t>(v.size() - 1);
    for (std::uint32_t k = 0; k < n; ++k) {
      f.push_back({0, ring(1, k), ring(1, k + 1)});
      for (std::uint32_t i = 1; i + 1 < m; ++i) f.push_back({ring(i, k), ring(i + 1, k), ring(i + 1, k + 1), ring(i, k + 1)});
      f.push_back({ring(m - 1, k), bottom, ring(m - 1, k + 1)});
    }
  } else if (spec.procedural == "torus") {
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t k = 0; k < m; ++k) {
        const float a = 2 * pi * static_cast<float>(i) / static_cast<float>(n);
        const float b = 2 * pi * static_cast<float>(k) / static_cast<float>(m);
        const float r = spec.radius + spec.tube * std::cos(b);
        v.push_back({r * std::cos(a), spec.tube * std::sin(b), -r * std::sin(a)});
      }
    const auto at = [&](std::uint32_t i, std::uint32_t k) { return (i % n) * m + k % m; };
    for (std::uint32_t i = 0; i < n; ++i)
      for (std::uint32_t k = 0; k < m; ++k) f.push_back({at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1)});
  } else {
    // Box with m × m quads per face, centred on the origin, outward winding.
    const glm::vec3 h = 0.5f * spec.size;
    const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int axis = 0; axis < 3; ++axis)
      for (int sign = -1; sign <= 1; sign += 2) {
        const glm::vec3 normal = static_cast<float>(sign) * axes[axis];
        const glm::vec3 s = axes[(axis + 1) % 3], t = axes[(axis + 2) % 3];
        const glm::vec3 su = sign > 0 ? s : t, tu = sign > 0 ? t : s;  // (su × tu) = normal
        const auto base = static_cast<std::uint32_t>(v.size());
        for (std::uint32_t i = 0; i <= m; ++i)
          for (std::uint32_t k = 0; k <= m; ++k) {
            const float a = 2.0f * static_cast<float>(i) / static_cast<float>(m) - 1.0f;
            const float b = 2.0f * static_cast<float>(k) / static_cast<float>(m) - 1.0f;
            const glm::vec3 p = h * (normal + a * su + b * tu);
            v.push_back({p.x, p.y, p.z});
          }
        for (std::uint32_t i = 0; i < m; ++i)
          for (std::uint32_t k = 0; k < m; ++k) {
            const auto at = [&](std::uint32_t a, std::uint32_t b) { return base + a * (m + 1) + b; };
            f.push_back({at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1)});
          }
      }
    // Shared edge vertices are duplicated per face; merge them so the mesh is closed. The tolerance
    // follows the box's size: an absolute 1e-6 merged every corner of a box smaller than that.
    const float merge = 1e-6f * std::max({h.x, h.y, h.z});
    std::vector<Vec3> unique;
    std::vector<std::uint32_t> remap(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      std::size_t j = 0;
      for (; j < unique.size(); ++j)
        if (std::abs(unique[j].x - v[i].x) <= merge && std::abs(unique[j].y - v[i].y) <= merge &&
            std::abs(unique[j].z - v[i].z) <= merge)
          break;
      if (j == unique.size()) unique.push_back(v[i]);
      remap[i] = static_cast<std::uint32_t>(j);
    }
    for (auto& face : f)
      for (auto& corner : face) corner = remap[corner];
    v = std::move(unique);
  }
  return make_mesh(v, f, fmt::format("procedural {}", spec.procedural));
}

void set_generated_light_count(Scene& scene, std::uint32_t count) {
  const std::size_t listed = scene.lights.size() - scene.generated.count;
  // The limit holds for the lights together: 2 listed and 2^20 generated were taken.
  if (listed + count > kMaxSceneLights)
    throw Error(fmt::format("{} generated lights and the scene's {} listed ones make {}, more than the limit of {} lights", count, listed,
                            listed + count, kMaxSceneLights));
  scene.lights.resize(listed);
  scene.generated.count = count;
  const auto generated = generate_lights(scene.generated, scene.floor);
  scene.lights.insert(scene.lights.end(), generated.begin(), generated.end());
}

}  // namespace splatcl
