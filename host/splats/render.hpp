#pragma once
// A small offscreen picture of a splat set (until the GL presenter exists): orthographic view,
// every splat drawn as its ellipse with a depth test and Lambert shading, in its own colour or in a
// per-splat random colour that shows the individual splats. Written through OpenImageIO.
#include <string>
#include <vector>

#include "splats/splat_file.hpp"

namespace splatcl::splats {

struct RenderOptions {
  int width = 800, height = 800;
  Vec3 view{0.35f, 0.25f, 1.0f};  // direction from the model towards the viewer
  Vec3 up{0, 1, 0};
  bool random_colors = true;
};

void render_splats(const std::string& path, const std::vector<SplatRecord>& splats, const RenderOptions& options);

}  // namespace splatcl::splats
