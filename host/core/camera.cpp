#include "core/camera.hpp"

#include <cmath>
#include <numbers>

#include "math/dvec3.hpp"
#include "runtime/error.hpp"

namespace splatcl {
namespace {

nlohmann::json vec_json(Vec3 v) { return nlohmann::json::array({v.x, v.y, v.z}); }

}  // namespace

Vec3 ViewFrame::point_to_view(Vec3 world) const {
  const Vec3 d = world - eye;
  return {dot(d, right), dot(d, up), dot(d, back)};
}

Vec3 ViewFrame::direction_to_world(Vec3 view) const { return right * view.x + up * view.y + back * view.z; }

ViewFrame view_frame(const Camera& camera) {
  const Vec3 forward = camera.target - camera.eye;
  if (length(forward) == 0.0f) throw Error("camera eye and target coincide");
  ViewFrame frame;
  frame.eye = camera.eye;
  frame.back = normalized(forward) * -1.0f;
  // The up vector's direction only: a short one ([0, 1e-7, 0]) read as parallel to the view.
  const Vec3 right = cross(to_float(normalized(DVec3(camera.up))), frame.back);
  if (!(length(right) > 1e-6f)) throw Error("camera up vector is parallel to the view direction (or zero)");
  frame.right = normalized(right);
  frame.up = cross(frame.back, frame.right);
  return frame;
}

Camera camera_from_json(const nlohmann::json& json, const JsonFields& fields, const std::string& path) {
  if (!json.is_object()) fields.fail(path + " must be an object");
  fields.known_keys(json, path, {"eye", "target", "up", "fov_y_degrees", "near", "far"});
  Camera c;
  c.eye = fields.vec3(fields.field(json, "eye", path), path + ".eye");
  c.target = fields.vec3(fields.field(json, "target", path), path + ".target");
  if (json.contains("up")) {
    // Kept as its direction: glm::lookAt works in float, where a short one ([0, 1e-25, 0]) made NaN.
    c.up = to_float(normalized(DVec3(fields.vec3(json["up"], path + ".up"))));
  } else if (const Vec3 view = to_float(normalized(DVec3(c.target) - DVec3(c.eye))); std::fabs(view.y) > 0.9999f) {
    // Looking straight down (or up) the default +y is the view direction: image up is -z instead
    // (a top view was refused until an "up" was written by hand).
    c.up = {0, 0, -1};
  }
  c.fov_y = fields.number_or(json, "fov_y_degrees", 60.0f, path) * std::numbers::pi_v<float> / 180.0f;
  c.near_plane = fields.number_or(json, "near", c.near_plane, path);
  c.far_plane = fields.number_or(json, "far", c.far_plane, path);
  if (!(c.fov_y > 0 && c.fov_y < std::numbers::pi_v<float>)) fields.fail(path + ".fov_y_degrees must be in (0, 180)");
  if (!(c.near_plane > 0 && c.far_plane > c.near_plane)) fields.fail(path + " needs 0 < near < far");
  try {
    view_frame(c);  // eye and target apart, up not along the view
  } catch (const Error& e) {
    fields.fail(e.what());
  }
  return c;
}

nlohmann::json camera_to_json(const Camera& c) {
  return {{"eye", vec_json(c.eye)},
          {"target", vec_json(c.target)},
          {"up", vec_json(c.up)},
          {"fov_y_degrees", c.fov_y * 180.0f / std::numbers::pi_v<float>},
          {"near", c.near_plane},
          {"far", c.far_plane}};
}

}  // namespace splatcl
