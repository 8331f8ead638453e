#include "cluster/scene_input.hpp"

#include <algorithm>
#include <cfloat>

#include "cluster/layout.hpp"

namespace splatcl::cluster {

static_assert(kNoSurfaceViewZ == kBackgroundViewZ, "a ray-cast miss must read as the cluster stage's background");

std::vector<float> window_depth(const DepthFrame& frame, const Camera& camera) {
  std::vector<float> depth(frame.view_z.size());
  for (std::size_t p = 0; p < depth.size(); ++p) {
    const float z = frame.view_z[p];
    // A surface on the far plane keeps a depth above the clear value 0 (background): FLT_MIN, which
    // reads back as the far plane while near/far is far above FLT_MIN (far/near below about 1e30;
    // beyond, as a nearer distance), and it was background with --window-depth, covered with view z.
    depth[p] = (-z >= camera.near_plane && -z <= camera.far_plane)
                   ? std::max(window_depth_from_view_z(z, camera.near_plane, camera.far_plane), FLT_MIN)
                   : 0.0f;
  }
  return depth;
}

std::vector<PointLight> view_lights(const std::vector<Light>& lights, const ViewFrame& view) {
  std::vector<PointLight> result(lights.size());
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const Light& l = lights[i];
    result[i] = {view.point_to_view({l.position.x, l.position.y, l.position.z}), l.radius, {l.color.x, l.color.y, l.color.z}};
  }
  return result;
}

}  // namespace splatcl::cluster
