#pragma once
// The pinhole camera of every stage that renders a view (the cluster stage's test frames, the
// presenter), its orthonormal frame, and its JSON form:
//   {"eye": [x,y,z], "target": [x,y,z], "up": [0,1,0], "fov_y_degrees": 60, "near": 0.1, "far": 100}
// with eye and target required.
#include <nlohmann/json.hpp>

#include "io/json_keys.hpp"
#include "math/vec3.hpp"

namespace splatcl {

struct Camera {
  Vec3 eye{0, 4, 12};
  Vec3 target{0, 0, 0};
  Vec3 up{0, 1, 0};
  float fov_y = 1.04719755f;  // radians (JSON: degrees)
  float near_plane = 0.1f;
  float far_plane = 100.0f;
  friend bool operator==(const Camera&, const Camera&) = default;
};

// Orthonormal camera frame: view space has the camera at the origin looking down −z, +y up.
struct ViewFrame {
  Vec3 eye, right, up, back;
  Vec3 point_to_view(Vec3 world) const;
  Vec3 direction_to_world(Vec3 view) const;
};
// Throws Error for a camera whose eye equals its target or whose up is parallel to the view direction.
ViewFrame view_frame(const Camera& camera);

// The camera of a JSON object at `path` ("camera"); errors through `fields`, naming the field. A
// camera without a frame (eye at the target, up along the view) is an error too.
Camera camera_from_json(const nlohmann::json& json, const JsonFields& fields, const std::string& path = "camera");
nlohmann::json camera_to_json(const Camera& camera);

}  // namespace splatcl
