#pragma once
// The presenter's GL passes, each with its program and the uniform locations it sets, looked up
// once when the program is linked:
//   VisibilityPass: splat depth only, pushed back by ε (the splat-mode pass 1)
//   AccumulationPass: Gaussian-weighted attribute sums of the splats within ε of the front into
//     the G-buffer (pass 2)
//   PointPass: the low-quality mode's one pass, a square point per splat with weight 1
//   ShadingPass: the final shading and debug views, one program per ShadeVariant
//   ResolvePass: silhouette anti-aliasing of the final image
//   MeshMaskPass: the objects' triangle meshes, for the coverage test
// A pass sets the GL state it needs and draws; the presenter's render() orders them.
#include <array>
#include <cstdint>
#include <map>
#include <vector>

#include <glm/glm.hpp>

#include "present/gbuffer.hpp"
#include "present/gl_objects.hpp"
#include "present/shaders/layout.h"

namespace splatcl::present {

// What the splat passes share in a frame.
struct SplatFrame {
  glm::mat4 view{1.0f}, proj{1.0f};
  glm::vec3 eye{0.0f};
  float scale = 1.0f;    // k: multiplies every splat's axes
  int ambient = 0;       // the per-splat ambient term (splat_head.glsl): 0 sky × AO, 1 sky, 2 the AO itself
  const glm::vec3* sh = nullptr;  // 9 irradiance SH coefficients of the sky
  // How much farther a two-sided object's back copies are drawn than their splats lie, in both splat
  // passes (splat.vert.glsl): where front and back copies meet at a fold, the front side wins.
  float back_offset = 0.0f;
};

// One object's draw: its placement and a run of splat instances (static and lighting rows).
struct SplatDraw {
  glm::mat4 model{1.0f};
  std::size_t first = 0, count = 0;
  float lod = 0.0f;  // LOD error per model unit of eye distance; 0 = off
  // A two-sided object's: the offset from each splat to its mirrored copy (its normal field turned,
  // lit as the back side). The draw covers the front splats only, and the vertex shader takes the
  // copy's rows where the front faces away: one primitive per splat instead of two, one of them
  // culled (llvmpipe pays per primitive). 0 = one-sided.
  std::size_t mirror = 0;
  // The scene object drawn, for the object target (GBuffer): GBuffer::kNoObject for the floor.
  std::uint32_t object = GBuffer::kNoObject;
};

class SplatPass {
 protected:
  explicit SplatPass(gl::Program program);
  // Uses the program and sets the frame's uniforms.
  void begin(const SplatFrame& frame) const;
  // Draws each run: 3 vertices per splat (one triangle around its ellipse), or 1 as points.
  void draw(const std::vector<SplatDraw>& draws, bool points) const;
  const gl::Program& program() const { return program_; }

 private:
  gl::Program program_;
  GLint model_, view_, proj_, eye_, scale_, lod_, mirror_, back_offset_, ambient_, sh_, object_;
};

class VisibilityPass : SplatPass {
 public:
  VisibilityPass();
  // `object_ids`: also the object target (GBuffer::write_object_ids).
  void run(const GBuffer& gbuffer, const SplatFrame& frame, const std::vector<SplatDraw>& draws, float depth_offset,
           bool object_ids) const;

 private:
  GLint depth_offset_;
};

class AccumulationPass : SplatPass {
 public:
  AccumulationPass();
  // Into the G-buffer, depth tested against the visibility pass's; `footprints` colours each
  // splat by its index.
  void run(const GBuffer& gbuffer, const SplatFrame& frame, const std::vector<SplatDraw>& draws, float beta,
           bool footprints) const;

 private:
  GLint beta_, footprints_;
};

class PointPass : SplatPass {
 public:
  PointPass();
  // Into the bound G-buffer with its depth test.
  void run(const SplatFrame& frame, const std::vector<SplatDraw>& draws, int viewport_height, bool footprints) const;

 private:
  GLint viewport_height_, footprints_;
};

// The compile-time modes of the final shading shader (shade.frag.glsl).
struct ShadeVariant {
  int debug = 0;  // DebugView, footprints drawn as albedo
  bool brute_force = false, pixel_shadows = false, pixel_ao = false, hdr_output = true, specular = false;
  // The floor's pixels take AO / key-light shadows from the floor's lattice (PixelInputs).
  bool floor_ao = false, floor_shadows = false;
  int key_count = 0;
  std::uint32_t key() const;
};

// What the shading reads besides the G-buffer and the pixel inputs.
struct ShadeFrame {
  glm::mat4 view{1.0f};
  glm::vec2 tan_half{0.0f}, viewport{0.0f};
  int light_count = 0;
  glm::vec4 key_center[MAX_KEY_LIGHTS] = {};  // view space, 1/r² in w
  glm::vec3 key_color[MAX_KEY_LIGHTS] = {};
  const glm::vec3* sh = nullptr;
  float heat_max = 1, specular = 0, shininess = 32;
  // The floor's plane in view space (n·p + w = height above it) and how far off it a pixel may lie
  // and still be the floor (the variant's floor_ao / floor_shadows).
  glm::vec4 floor_plane{0.0f};
  float floor_tolerance = 0;
  // Buffer textures over the point lights' rows (RGBA32F, two texels per light) and the light
  // lists' offsets, counts and indices (R32UI): on llvmpipe a texel fetch gathers across the pixels
  // of a vector, where a storage-buffer load with a per-pixel index is a loop over them (the
  // shading took 15–17 ms against 18–21 at 640×480 with 1,024 lights, 62–82 against 116–122 with 16,384).
  GLuint light_rows = 0, list_offsets = 0, list_counts = 0, list_indices = 0;
};

class ShadingPass {
 public:
  // One full-screen triangle into `framebuffer`, reading the G-buffer, the pixel inputs and the
  // frame's buffer textures; the variant's program is compiled on first use.
  void run(GLuint framebuffer, const GBuffer& gbuffer, const PixelInputs& pixel, const ShadeVariant& variant,
           const ShadeFrame& frame);

 private:
  struct Program {
    explicit Program(const ShadeVariant& variant);
    gl::Program program;
    GLint view, tan_half, viewport, light_count, sh, heat_max, specular, shininess, floor_plane, floor_tolerance;
    GLint key_center[MAX_KEY_LIGHTS], key_color[MAX_KEY_LIGHTS];
  };
  const Program& program(const ShadeVariant& variant);
  std::map<std::uint32_t, Program> programs_;
};

// Silhouette anti-aliasing (resolve.frag.glsl): the display image filtered across object outlines
// (coverage or depth edges of the G-buffer) into `framebuffer`.
class ResolvePass {
 public:
  ResolvePass();
  // `display` copied to `framebuffer`, then the filter run over `rectangles` (pixels x0, y0, x1,
  // y1; see outline_rectangles), which must hold every outline pixel.
  void run(GLuint framebuffer, GLuint display_framebuffer, GLuint display, const GBuffer& gbuffer, float depth_jump,
           const std::vector<std::array<std::int32_t, 4>>& rectangles);

 private:
  gl::Program program_;
  GLint depth_jump_, viewport_;
  gl::Buffer rectangles_;
};

// The screen tiles (kResolveTile pixels square) that hold a pixel the resolve may take as an
// outline, merged into runs along each row of tiles: from the view z the cluster stage reads back
// (0 where no splat covers a pixel), a coverage change or a depth jump over 0.9 × `depth_jump`
// (float rounding between this and the shader's own division stays far below the 10 %). Pixels
// outside them are ones whose 4-neighbours are all sky or all one surface: the filter leaves them
// as they are (sky pixels average identical colours).
constexpr int kResolveTile = 16;
std::vector<std::array<std::int32_t, 4>> outline_rectangles(const std::vector<float>& view_z, int width, int height,
                                                            float depth_jump);

class MeshMaskPass {
 public:
  MeshMaskPass();
  // Draws each (vertex array, vertex count) with its model matrix into the bound framebuffer.
  void run(const glm::mat4& view, const glm::mat4& proj, const std::vector<glm::mat4>& models,
           const std::vector<GLuint>& vertex_arrays, const std::vector<GLsizei>& vertices) const;

 private:
  gl::Program program_;
  GLint model_, view_, proj_;
};

}  // namespace splatcl::present
