#pragma once
// The cluster stage's inputs from a scene (core/scene.hpp): the window depth a GL depth buffer of
// a ray-cast frame holds, and the scene's point lights in view space.
#include <vector>

#include "cluster/types.hpp"
#include "core/camera.hpp"
#include "core/scene.hpp"
#include "core/scene_ray_cast.hpp"

namespace splatcl::cluster {

// The frame's depth as reversed window depth under the camera's projection (1 at the near plane, 0
// at the far one and for background: the presenter's depth buffer).
std::vector<float> window_depth(const DepthFrame& frame, const Camera& camera);

// World-space lights as the cluster stage takes them: centres in the view space of `view`.
std::vector<PointLight> view_lights(const std::vector<Light>& lights, const ViewFrame& view);

}  // namespace splatcl::cluster
