#pragma once
// GLSL 4.50 sources of the presenter's passes (present/shaders.cpp), kept as raw string literals so
// the binary needs no source tree.
#include <string>

namespace splatcl::present::shaders {

extern const std::string kSplatVisibilityVertex;  // the same without the lighting rows (pass 1)
extern const std::string kSplatVertex;        // a triangle around each splat's ellipse (HQ passes)
extern const char* const kSplatVisibility;    // pass 1: ellipse test, depth pushed back by ε
extern const std::string kSplatAccumulate;    // pass 2: Gaussian-weighted attribute sums = G-buffer
extern const std::string kPointVertex;        // low-quality mode: one square point per splat
extern const std::string kPointFragment;      //   writes the G-buffer with weight 1
extern const char* const kFullscreenVertex;   // one triangle covering the viewport
extern const std::string kShade;              // final shading and debug views: HDR and tone-mapped 8-bit
extern const char* const kMeshVertex;         // triangle mesh, for the coverage test
extern const char* const kMeshFragment;

}  // namespace splatcl::present::shaders
