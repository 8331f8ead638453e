#pragma once
// The scene as its camera sees it, ray cast on the host: per pixel the nearest surface of the
// scene's meshes and floor at the scene's time, as view-space depth and normal. The G-buffer of
// `splatcl cluster` (no GPU needed) and of the cluster stage's tests and benchmark.
#include <cstdint>
#include <vector>

#include "core/scene.hpp"

namespace splatcl {

// View-space z of a pixel where no surface is hit (the cluster stage's background depth).
inline constexpr float kNoSurfaceViewZ = 0.0f;

// Per pixel, row 0 = bottom: view-space z of the nearest hit in [near, far] (kNoSurfaceViewZ on a
// miss) and the view-space unit normal facing the camera ((0,0,0) on a miss).
struct DepthFrame {
  std::uint32_t width = 0, height = 0;
  std::vector<float> view_z;
  std::vector<Vec3> normals;
};

// Ray casts `scene` at scene.time: every mesh object under its fit and placement, and the floor
// square. Normals are the hit triangle's own (flat shading of the facets). An object given as a
// splat file has no mesh to cast: Error naming it. Runs on at most `threads` threads of
// parallel_for (0 = every usable CPU); the result does not depend on the thread count.
DepthFrame ray_cast(const Scene& scene, std::uint32_t width, std::uint32_t height, unsigned threads = 0);

}  // namespace splatcl
