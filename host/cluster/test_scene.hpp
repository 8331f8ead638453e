#pragma once
// Test input for the cluster stage without a GPU: scenes of a floor plane, spheres and boxes
// (random from a seed, or from JSON), a pinhole camera (core/camera.hpp), a multithreaded host ray caster producing
// view-space depth and normals, and point lights placed around the visible geometry.
//
// JSON form (all lengths in world units):
//   { "floor":   {"y": 0},                                          optional
//     "objects": [ {"type": "sphere", "center": [x,y,z], "radius": r},
//                  {"type": "box", "min": [x,y,z], "max": [x,y,z]} ],
//     "camera":  {"eye": [..], "target": [..], "up": [0,1,0], "fov_y_degrees": 60, "near": 0.1, "far": 100},
//     "lights":  {"count": N, "radius": [min, max], "seed": S}       random, around the visible geometry
//             or [ {"position": [x,y,z], "radius": r, "color": [r,g,b]} ] }   explicit, world space
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "cluster/layout.hpp"
#include "core/camera.hpp"
#include "cluster/types.hpp"

namespace splatcl::cluster {

struct Sphere {
  Vec3 center;
  float radius = 1;
  friend bool operator==(const Sphere&, const Sphere&) = default;
};
struct Box {
  Vec3 min, max;
  friend bool operator==(const Box&, const Box&) = default;
};
using SceneObject = std::variant<Sphere, Box>;

// Lights placed at random around the visible geometry of the rendered frame (view space).
struct RandomLights {
  std::uint32_t count = 0;
  float radius_min = 0.5f;
  float radius_max = 2.0f;
  std::uint64_t seed = 1;
  friend bool operator==(const RandomLights&, const RandomLights&) = default;
};
// A light given in world space.
struct SceneLight {
  Vec3 position;
  float radius = 1;
  Vec3 color{1, 1, 1};
  friend bool operator==(const SceneLight&, const SceneLight&) = default;
};

struct Scene {
  std::optional<float> floor_y;
  std::vector<SceneObject> objects;
  Camera camera;
  std::variant<RandomLights, std::vector<SceneLight>> lights;
  friend bool operator==(const Scene&, const Scene&) = default;
};

struct RandomSceneOptions {
  std::uint32_t spheres = 12;
  std::uint32_t boxes = 8;
  float extent = 10.0f;  // objects stand on the floor within [−extent, extent] in x and z
  RandomLights lights{256, 0.5f, 2.0f, 1};
};
// Deterministic for a given seed: floor at y = 0, objects, a camera looking at the scene from a
// seed-chosen direction (near 0.1, far 10·extent), and the given light spec.
Scene random_scene(std::uint64_t seed, const RandomSceneOptions& options = {});

// Per pixel, row 0 = bottom: view-space z of the nearest hit in [near, far] (kBackgroundViewZ on a
// miss) and the view-space unit normal facing the camera ((0,0,0) on a miss).
struct DepthFrame {
  std::uint32_t width = 0, height = 0;
  std::vector<float> view_z;
  std::vector<Vec3> normals;
};
// Ray casts the scene on at most `threads` threads of parallel_for (0 = every usable CPU).
DepthFrame ray_cast(const Scene& scene, std::uint32_t width, std::uint32_t height, unsigned threads = 0);

// The scene's lights in view space: explicit lights transformed; random lights placed around
// visible pixels of `frame` (uniformly in the frustum when nothing is visible).
std::vector<PointLight> view_lights(const Scene& scene, const DepthFrame& frame);

// The frame's depth as OpenGL window depth under the camera's projection (1 for background).
std::vector<float> window_depth(const DepthFrame& frame, const Camera& camera);

// JSON conversion (nlohmann ADL). from_json throws Error naming the offending field.
void to_json(nlohmann::json& json, const Scene& scene);
void from_json(const nlohmann::json& json, Scene& scene);
// Parses JSON text; errors name `source` (a file name or "default scene").
Scene parse_scene(std::string_view text, const std::string& source);

}  // namespace splatcl::cluster
