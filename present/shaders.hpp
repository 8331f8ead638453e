#pragma once
// GLSL 4.50 sources of the presenter's passes (present/shaders.cpp), kept as raw string literals so
// the binary needs no source tree.
namespace splatcl::present::shaders {

extern const char* const kSplatVertex;        // instanced quad over each splat's ellipse (HQ passes)
extern const char* const kSplatVisibility;    // pass 1: ellipse test, depth pushed back by ε
extern const char* const kSplatAccumulate;    // pass 2: Gaussian-weighted attribute sums
extern const char* const kPointVertex;        // low-quality mode: one square point per splat
extern const char* const kPointFragment;      //   writes the G-buffer directly
extern const char* const kFullscreenVertex;   // one triangle covering the viewport
extern const char* const kNormalize;          // pass 3: sums / weight → G-buffer
extern const char* const kShade;              // final shading and debug views: HDR and tone-mapped 8-bit
extern const char* const kMeshVertex;         // triangle mesh, for the coverage test
extern const char* const kMeshFragment;

}  // namespace splatcl::present::shaders
