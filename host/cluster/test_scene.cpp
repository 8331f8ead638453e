#include "cluster/test_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/parallel.hpp"
#include "io/json_keys.hpp"
#include "runtime/error.hpp"

namespace splatcl::cluster {
namespace {

// SplitMix64: small, fast, and the same sequence on every platform (unlike std distributions).
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [lo, hi).
  float uniform(float lo, float hi) { return lo + (hi - lo) * static_cast<float>(next() >> 40) * 0x1.0p-24f; }
  std::uint64_t below(std::uint64_t n) { return next() % n; }
  Vec3 in_unit_ball() {
    for (;;) {
      const Vec3 v{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
      if (dot(v, v) <= 1.0f) return v;
    }
  }

 private:
  std::uint64_t state_;
};

constexpr float kMiss = std::numeric_limits<float>::infinity();

struct Hit {
  float t = kMiss;
  Vec3 normal;
};

// Nearest t in [t_min, t_max] along origin + t·dir (dir not normalised).
void hit_floor(float floor_y, Vec3 origin, Vec3 dir, float t_min, Hit& best) {
  if (dir.y == 0.0f) return;
  const float t = (floor_y - origin.y) / dir.y;
  if (t >= t_min && t < best.t) best = {t, {0, 1, 0}};
}

void hit_sphere(const Sphere& s, Vec3 origin, Vec3 dir, float t_min, Hit& best) {
  const Vec3 oc = origin - s.center;
  const float a = dot(dir, dir), b = dot(oc, dir), c = dot(oc, oc) - s.radius * s.radius;
  const float disc = b * b - a * c;
  if (disc < 0.0f) return;
  const float root = std::sqrt(disc);
  for (const float t : {(-b - root) / a, (-b + root) / a}) {
    if (t >= t_min && t < best.t) {
      best = {t, normalized(origin + dir * t - s.center)};
      return;
    }
  }
}

void hit_box(const Box& box, Vec3 origin, Vec3 dir, float t_min, Hit& best) {
  const float o[3] = {origin.x, origin.y, origin.z}, d[3] = {dir.x, dir.y, dir.z};
  const float lo[3] = {box.min.x, box.min.y, box.min.z}, hi[3] = {box.max.x, box.max.y, box.max.z};
  float t_enter = -kMiss, t_exit = kMiss;
  int enter_axis = 0, exit_axis = 0;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0f) {
      if (o[a] < lo[a] || o[a] > hi[a]) return;
      continue;
    }
    float t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_enter) t_enter = t0, enter_axis = a;
    if (t1 < t_exit) t_exit = t1, exit_axis = a;
  }
  if (t_enter > t_exit) return;
  const auto axis_normal = [](int axis) {
    return axis == 0 ? Vec3{1, 0, 0} : axis == 1 ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
  };
  if (t_enter >= t_min && t_enter < best.t) {
    best = {t_enter, axis_normal(enter_axis)};
  } else if (t_enter < t_min && t_exit >= t_min && t_exit < best.t) {
    best = {t_exit, axis_normal(exit_axis)};
  }
}

nlohmann::json vec_json(Vec3 v) { return nlohmann::json::array({v.x, v.y, v.z}); }

// Errors of the scene reader: "scene: " and the field's path.
const JsonFields kScene{"scene: "};

}  // namespace

Scene random_scene(std::uint64_t seed, const RandomSceneOptions& options) {
  Random random(seed);
  const float e = options.extent;
  Scene scene;
  scene.floor_y = 0.0f;
  for (std::uint32_t i = 0; i < options.spheres; ++i) {
    const float radius = random.uniform(0.03f, 0.15f) * e;
    const Vec3 center{random.uniform(-e, e), radius + random.uniform(0, 0.2f) * e, random.uniform(-e, e)};
    scene.objects.push_back(Sphere{center, radius});
  }
  for (std::uint32_t i = 0; i < options.boxes; ++i) {
    const Vec3 size{random.uniform(0.05f, 0.3f) * e, random.uniform(0.05f, 0.4f) * e, random.uniform(0.05f, 0.3f) * e};
    const Vec3 corner{random.uniform(-e, e), 0.0f, random.uniform(-e, e)};
    scene.objects.push_back(Box{corner, corner + size});
  }
  const float angle = random.uniform(0.0f, 2.0f * std::numbers::pi_v<float>);
  const float distance = random.uniform(1.2f, 1.8f) * e;
  scene.camera.eye = {distance * std::cos(angle), random.uniform(0.2f, 0.6f) * e, distance * std::sin(angle)};
  scene.camera.target = {0, 0, 0};
  scene.camera.near_plane = 0.1f;
  scene.camera.far_plane = 10.0f * e;
  scene.lights = options.lights;
  return scene;
}

DepthFrame ray_cast(const Scene& scene, std::uint32_t width, std::uint32_t height, unsigned threads) {
  if (width == 0 || height == 0) throw Error("ray_cast: frame size must be at least 1x1");
  const ViewFrame frame = view_frame(scene.camera);
  const float tan_y = std::tan(0.5f * scene.camera.fov_y);
  const float tan_x = tan_y * static_cast<float>(width) / static_cast<float>(height);
  const float near_plane = scene.camera.near_plane, far_plane = scene.camera.far_plane;

  DepthFrame result;
  result.width = width;
  result.height = height;
  result.view_z.assign(std::size_t{width} * height, kBackgroundViewZ);
  result.normals.assign(std::size_t{width} * height, Vec3{});

  const auto cast_row = [&](std::uint32_t y) {
    for (std::uint32_t x = 0; x < width; ++x) {
      const float ndc_x = (static_cast<float>(x) + 0.5f) * 2.0f / static_cast<float>(width) - 1.0f;
      const float ndc_y = (static_cast<float>(y) + 0.5f) * 2.0f / static_cast<float>(height) - 1.0f;
      // View-space direction with unit forward component: t along it is the view distance.
      const Vec3 dir = frame.direction_to_world({ndc_x * tan_x, ndc_y * tan_y, -1.0f});
      Hit best;
      if (scene.floor_y) hit_floor(*scene.floor_y, frame.eye, dir, near_plane, best);
      for (const auto& object : scene.objects) {
        if (const auto* sphere = std::get_if<Sphere>(&object)) {
          hit_sphere(*sphere, frame.eye, dir, near_plane, best);
        } else {
          hit_box(std::get<Box>(object), frame.eye, dir, near_plane, best);
        }
      }
      if (best.t > far_plane) continue;
      Vec3 normal = best.normal;
      if (dot(normal, dir) > 0.0f) normal = normal * -1.0f;
      const std::size_t p = std::size_t{y} * width + x;
      result.view_z[p] = -best.t;
      result.normals[p] = {dot(normal, frame.right), dot(normal, frame.up), dot(normal, frame.back)};
    }
  };
  parallel_for(height, 1, [&](std::size_t y, std::size_t) { cast_row(static_cast<std::uint32_t>(y)); }, threads);
  return result;
}

std::vector<PointLight> view_lights(const Scene& scene, const DepthFrame& frame) {
  std::vector<PointLight> lights;
  if (const auto* explicit_lights = std::get_if<std::vector<SceneLight>>(&scene.lights)) {
    const ViewFrame view = view_frame(scene.camera);
    for (const auto& light : *explicit_lights)
      lights.push_back({view.point_to_view(light.position), light.radius, light.color});
    return lights;
  }
  const auto& spec = std::get<RandomLights>(scene.lights);
  if (!(spec.radius_min >= 0 && spec.radius_max >= spec.radius_min))
    throw Error("random lights need 0 <= radius min <= radius max");
  const ClusterLayout layout = ClusterLayout::make(cluster_config(scene.camera, frame.width, frame.height));
  std::vector<std::uint32_t> visible;
  for (std::uint32_t p = 0; p < frame.view_z.size(); ++p)
    if (pixel_distance(layout, frame.view_z[p], DepthFormat::ViewZ)) visible.push_back(p);
  Random random(spec.seed);
  for (std::uint32_t i = 0; i < spec.count; ++i) {
    PointLight light;
    light.radius = random.uniform(spec.radius_min, spec.radius_max);
    light.color = {random.uniform(0, 1), random.uniform(0, 1), random.uniform(0, 1)};
    if (visible.empty()) {
      const auto p = static_cast<std::uint32_t>(random.below(frame.view_z.size()));
      const float distance = random.uniform(layout.config.near_plane, layout.config.far_plane);
      light.center = pixel_view_position(layout, p % frame.width, p / frame.width, distance);
    } else {
      const std::uint32_t p = visible[random.below(visible.size())];
      const Vec3 surface = pixel_view_position(layout, p % frame.width, p / frame.width, -frame.view_z[p]);
      light.center = surface + random.in_unit_ball() * light.radius;
    }
    lights.push_back(light);
  }
  return lights;
}

std::vector<float> window_depth(const DepthFrame& frame, const Camera& camera) {
  std::vector<float> depth(frame.view_z.size());
  for (std::size_t p = 0; p < depth.size(); ++p) {
    const float z = frame.view_z[p];
    depth[p] = (-z >= camera.near_plane && -z <= camera.far_plane)
                   ? window_depth_from_view_z(z, camera.near_plane, camera.far_plane)
                   : 1.0f;
  }
  return depth;
}

void to_json(nlohmann::json& json, const Scene& scene) {
  json = nlohmann::json::object();
  if (scene.floor_y) json["floor"] = {{"y", *scene.floor_y}};
  json["objects"] = nlohmann::json::array();
  for (const auto& object : scene.objects) {
    if (const auto* sphere = std::get_if<Sphere>(&object)) {
      json["objects"].push_back({{"type", "sphere"}, {"center", vec_json(sphere->center)}, {"radius", sphere->radius}});
    } else {
      const Box& box = std::get<Box>(object);
      json["objects"].push_back({{"type", "box"}, {"min", vec_json(box.min)}, {"max", vec_json(box.max)}});
    }
  }
  json["camera"] = camera_to_json(scene.camera);
  if (const auto* random = std::get_if<RandomLights>(&scene.lights)) {
    json["lights"] = {{"count", random->count},
                      {"radius", {random->radius_min, random->radius_max}},
                      {"seed", random->seed}};
  } else {
    json["lights"] = nlohmann::json::array();
    for (const auto& light : std::get<std::vector<SceneLight>>(scene.lights))
      json["lights"].push_back(
          {{"position", vec_json(light.position)}, {"radius", light.radius}, {"color", vec_json(light.color)}});
  }
}

void from_json(const nlohmann::json& json, Scene& scene) {
  if (!json.is_object()) kScene.fail("the top level must be an object");
  kScene.known_keys(json, "the scene", {"floor", "objects", "camera", "lights"});
  Scene result;
  if (json.contains("floor") && !json["floor"].is_null()) {
    kScene.known_keys(json["floor"], "floor", {"y"});
    result.floor_y = kScene.number(kScene.field(json["floor"], "y", "floor"), "floor.y");
  }

  if (json.contains("objects")) {
    const auto& objects = json["objects"];
    if (!objects.is_array()) kScene.fail("objects must be an array");
    for (std::size_t i = 0; i < objects.size(); ++i) {
      const std::string path = "objects[" + std::to_string(i) + "]";
      const auto& type = kScene.field(objects[i], "type", path);
      const std::string name = type.is_string() ? type.get<std::string>() : "";
      if (name == "sphere") {
        kScene.known_keys(objects[i], path, {"type", "center", "radius"});
        Sphere sphere{kScene.vec3(kScene.field(objects[i], "center", path), path + ".center"),
                      kScene.number(kScene.field(objects[i], "radius", path), path + ".radius")};
        if (!(sphere.radius > 0)) kScene.fail(path + ".radius must be positive");
        result.objects.push_back(sphere);
      } else if (name == "box") {
        kScene.known_keys(objects[i], path, {"type", "min", "max"});
        Box box{kScene.vec3(kScene.field(objects[i], "min", path), path + ".min"), kScene.vec3(kScene.field(objects[i], "max", path), path + ".max")};
        if (!(box.min.x <= box.max.x && box.min.y <= box.max.y && box.min.z <= box.max.z))
          kScene.fail(path + ".min must not exceed .max");
        result.objects.push_back(box);
      } else {
        kScene.fail(path + ".type must be \"sphere\" or \"box\"");
      }
    }
  }

  result.camera = camera_from_json(kScene.field(json, "camera", "the scene"), kScene);

  if (json.contains("lights")) {
    const auto& lights = json["lights"];
    if (lights.is_array()) {
      if (lights.size() > kMaxSceneLights)
        kScene.fail("lights lists " + std::to_string(lights.size()) + " lights, more than the limit of " + std::to_string(kMaxSceneLights));
      std::vector<SceneLight> list;
      for (std::size_t i = 0; i < lights.size(); ++i) {
        const std::string path = "lights[" + std::to_string(i) + "]";
        kScene.known_keys(lights[i], path, {"position", "radius", "color"});
        SceneLight light;
        light.position = kScene.vec3(kScene.field(lights[i], "position", path), path + ".position");
        light.radius = kScene.number(kScene.field(lights[i], "radius", path), path + ".radius");
        if (!(light.radius >= 0)) kScene.fail(path + ".radius must not be negative");
        if (lights[i].contains("color")) light.color = kScene.vec3(lights[i]["color"], path + ".color");
        list.push_back(light);
      }
      result.lights = std::move(list);
    } else if (lights.is_object()) {
      kScene.known_keys(lights, "lights", {"count", "radius", "seed"});
      RandomLights random;
      const auto& count = kScene.field(lights, "count", "lights");
      if (!count.is_number_unsigned()) kScene.fail("lights.count must be a non-negative integer");
      if (count.get<std::uint64_t>() > kMaxSceneLights)
        kScene.fail("lights.count " + std::to_string(count.get<std::uint64_t>()) + " is above the limit of " + std::to_string(kMaxSceneLights));
      random.count = count.get<std::uint32_t>();
      if (lights.contains("radius")) {
        const auto& radius = lights["radius"];
        if (!radius.is_array() || radius.size() != 2) kScene.fail("lights.radius must be [min, max]");
        random.radius_min = kScene.number(radius[0], "lights.radius[0]");
        random.radius_max = kScene.number(radius[1], "lights.radius[1]");
        if (!(random.radius_min >= 0 && random.radius_max >= random.radius_min))
          kScene.fail("lights.radius must satisfy 0 <= min <= max");
      }
      if (lights.contains("seed")) {
        if (!lights["seed"].is_number_unsigned()) kScene.fail("lights.seed must be a non-negative integer");
        random.seed = lights["seed"].get<std::uint64_t>();
      }
      result.lights = random;
    } else {
      kScene.fail("lights must be an object {count, radius, seed} or an array of lights");
    }
  }
  scene = std::move(result);
}

Scene parse_scene(std::string_view text, const std::string& source) {
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(source + ": invalid JSON: " + e.what());
  }
  try {
    return json.get<Scene>();
  } catch (const Error& e) {
    throw Error(source + ": " + e.what());
  }
}

}  // namespace splatcl::cluster
