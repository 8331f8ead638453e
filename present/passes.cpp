#include "present/passes.hpp"

#include <fmt/format.h>

#include <glm/gtc/type_ptr.hpp>

#include "present/shaders.hpp"

namespace splatcl::present {

SplatPass::SplatPass(gl::Program program)
    : program_(std::move(program)),
      model_(program_.uniform("u_model")),
      view_(program_.uniform("u_view")),
      proj_(program_.uniform("u_proj")),
      eye_(program_.uniform("u_eye")),
      scale_(program_.uniform("u_scale")),
      lod_(program_.uniform("u_lod")),
      mirror_(program_.uniform("u_mirror")),
      back_offset_(program_.uniform("u_back_offset")),
      ambient_(program_.uniform("u_ambient")),
      sh_(program_.uniform("u_sh")),
      object_(program_.uniform("u_object")) {}

void SplatPass::begin(const SplatFrame& frame) const {
  program_.use();
  glUniformMatrix4fv(view_, 1, GL_FALSE, glm::value_ptr(frame.view));
  glUniformMatrix4fv(proj_, 1, GL_FALSE, glm::value_ptr(frame.proj));
  glUniform3fv(eye_, 1, glm::value_ptr(frame.eye));
  glUniform1f(scale_, frame.scale);
  glUniform1i(ambient_, frame.ambient);
  glUniform1f(back_offset_, frame.back_offset);
  glUniform3fv(sh_, 9, glm::value_ptr(frame.sh[0]));
}

void SplatPass::draw(const std::vector<SplatDraw>& draws, bool points) const {
  for (const SplatDraw& d : draws) {
    glUniformMatrix4fv(model_, 1, GL_FALSE, glm::value_ptr(d.model));
    glUniform1f(lod_, d.lod);
    glUniform1ui(mirror_, static_cast<GLuint>(d.mirror));
    if (object_ >= 0) glUniform1ui(object_, d.object);
    if (points)
      glDrawArrays(GL_POINTS, static_cast<GLint>(d.first), static_cast<GLsizei>(d.count));
    else
      glDrawArrays(GL_TRIANGLES, static_cast<GLint>(3 * d.first), static_cast<GLsizei>(3 * d.count));
  }
}

VisibilityPass::VisibilityPass()
    : SplatPass(gl::Program(shaders::source("splat.vert.glsl", "#define VISIBILITY_PASS 1\n"),
                            shaders::source("splat_visibility.frag.glsl"), "splat visibility")),
      depth_offset_(program().uniform("u_depth_offset")) {}

void VisibilityPass::run(const GBuffer& gbuffer, const SplatFrame& frame, const std::vector<SplatDraw>& draws,
                         float depth_offset, bool object_ids) const {
  gbuffer.write_object_ids(object_ids);
  glBindFramebuffer(GL_FRAMEBUFFER, gbuffer.visibility_framebuffer());
  if (!object_ids) glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glEnable(GL_CLIP_DISTANCE0);  // the un-pushed near plane (splat.vert.glsl)
  begin(frame);
  glUniform1f(depth_offset_, depth_offset);
  draw(draws, false);
  glDisable(GL_CLIP_DISTANCE0);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

AccumulationPass::AccumulationPass()
    : SplatPass(gl::Program(shaders::source("splat.vert.glsl"), shaders::source("splat_accumulate.frag.glsl"),
                            "splat accumulation")),
      beta_(program().uniform("u_beta")),
      footprints_(program().uniform("u_footprints")) {}

void AccumulationPass::run(const GBuffer& gbuffer, const SplatFrame& frame, const std::vector<SplatDraw>& draws,
                           float beta, bool footprints) const {
  glBindFramebuffer(GL_FRAMEBUFFER, gbuffer.accumulation_framebuffer());
  glDepthMask(GL_FALSE);
  glDepthFunc(GL_GEQUAL);  // reversed depth: nearer is greater
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);
  glEnable(GL_CLIP_DISTANCE0);  // the near plane as the visibility pass cuts it (splat.vert.glsl)
  begin(frame);
  glUniform1f(beta_, beta);
  glUniform1i(footprints_, footprints ? 1 : 0);
  draw(draws, false);
  glDisable(GL_CLIP_DISTANCE0);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
}

PointPass::PointPass()
    : SplatPass(gl::Program(shaders::source("point.vert.glsl"), shaders::source("point.frag.glsl"), "points")),
      viewport_height_(program().uniform("u_viewport_height")),
      footprints_(program().uniform("u_footprints")) {}

void PointPass::run(const SplatFrame& frame, const std::vector<SplatDraw>& draws, int viewport_height,
                    bool footprints) const {
  glEnable(GL_PROGRAM_POINT_SIZE);
  begin(frame);
  glUniform1f(viewport_height_, static_cast<float>(viewport_height));
  glUniform1i(footprints_, footprints ? 1 : 0);
  draw(draws, true);
}

std::uint32_t ShadeVariant::key() const {
  return static_cast<std::uint32_t>(debug) | (brute_force ? 1u : 0u) << 3 | (pixel_shadows ? 1u : 0u) << 4 |
         (pixel_ao ? 1u : 0u) << 5 | (hdr_output ? 1u : 0u) << 6 | (specular ? 1u : 0u) << 7 |
         static_cast<std::uint32_t>(key_count) << 8 | (floor_ao ? 1u : 0u) << 11 | (floor_shadows ? 1u : 0u) << 12;
}

namespace {
std::string shade_defines(const ShadeVariant& v) {
  return fmt::format(
      "#define DEBUG_VIEW {}\n#define BRUTE_FORCE {}\n#define PIXEL_SHADOWS {}\n"
      "#define PIXEL_AO {}\n#define HDR_OUTPUT {}\n#define KEY_COUNT {}\n#define SPECULAR {}\n#define FLOOR_AO {}\n"
      "#define FLOOR_SHADOWS {}\n",
      v.debug, v.brute_force ? 1 : 0, v.pixel_shadows ? 1 : 0, v.pixel_ao ? 1 : 0, v.hdr_output ? 1 : 0, v.key_count,
      v.specular ? 1 : 0, v.floor_ao ? 1 : 0, v.floor_shadows ? 1 : 0);
}
}  // namespace

ShadingPass::Program::Program(const ShadeVariant& variant)
    : program(shaders::source("fullscreen.vert.glsl"), shaders::source("shade.frag.glsl", shade_defines(variant)),
              "shading"),
      view(program.uniform("u_view")),
      tan_half(program.uniform("u_tan_half")),
      viewport(program.uniform("u_viewport")),
      light_count(program.uniform("u_light_count")),
      sh(program.uniform("u_sh")),
      heat_max(program.uniform("u_heat_max")),
      specular(program.uniform("u_specular")),
      shininess(program.uniform("u_shininess")),
      floor_plane(program.uniform("u_floor_plane")),
      floor_tolerance(program.uniform("u_floor_tolerance")) {
  for (int k = 0; k < MAX_KEY_LIGHTS; ++k) {
    key_center[k] = program.uniform(fmt::format("u_key_center[{}]", k).c_str());
    key_color[k] = program.uniform(fmt::format("u_key_color[{}]", k).c_str());
  }
}

const ShadingPass::Program& ShadingPass::program(const ShadeVariant& variant) {
  const auto found = programs_.find(variant.key());
  if (found != programs_.end()) return found->second;
  return programs_.emplace(variant.key(), Program(variant)).first->second;
}

void ShadingPass::run(GLuint framebuffer, const GBuffer& gbuffer, const PixelInputs& pixel, const ShadeVariant& variant,
                      const ShadeFrame& frame) {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  const Program& p = program(variant);
  p.program.use();
  GLuint textures[SHADING_UNITS] = {};
  textures[UNIT_WEIGHT_ALBEDO] = gbuffer.texture(GBuffer::WeightAlbedo);
  textures[UNIT_Z_NORMAL] = gbuffer.texture(GBuffer::ZNormal);
  textures[UNIT_SHADOW_AMBIENT] = gbuffer.texture(GBuffer::ShadowAmbient);
  textures[UNIT_SHADOWS] = gbuffer.texture(GBuffer::Shadows);
  textures[UNIT_PIXEL_LIST] = pixel.light_list.get();
  textures[UNIT_PIXEL_SHADOW] = pixel.shadow.get();
  textures[UNIT_PIXEL_AO] = pixel.ao.get();
  textures[UNIT_FLOOR_AO] = pixel.floor_ao.get();
  textures[UNIT_FLOOR_SHADOW] = pixel.floor_shadow.get();
  textures[UNIT_LIGHT_ROWS] = frame.light_rows;
  textures[UNIT_LIST_OFFSETS] = frame.list_offsets;
  textures[UNIT_LIST_COUNTS] = frame.list_counts;
  textures[UNIT_LIST_INDICES] = frame.list_indices;
  glBindTextures(0, SHADING_UNITS, textures);
  glUniformMatrix4fv(p.view, 1, GL_FALSE, glm::value_ptr(frame.view));
  glUniform2f(p.tan_half, frame.tan_half.x, frame.tan_half.y);
  glUniform2f(p.viewport, frame.viewport.x, frame.viewport.y);
  glUniform1i(p.light_count, frame.light_count);
  for (int k = 0; k < variant.key_count; ++k) {
    glUniform4fv(p.key_center[k], 1, glm::value_ptr(frame.key_center[k]));
    glUniform3fv(p.key_color[k], 1, glm::value_ptr(frame.key_color[k]));
  }
  glUniform3fv(p.sh, 9, glm::value_ptr(frame.sh[0]));
  glUniform1f(p.heat_max, frame.heat_max);
  glUniform1f(p.specular, frame.specular);
  glUniform1f(p.shininess, frame.shininess);
  glUniform4fv(p.floor_plane, 1, glm::value_ptr(frame.floor_plane));
  glUniform1f(p.floor_tolerance, frame.floor_tolerance);
  glDrawArrays(GL_TRIANGLES, 0, 3);
}

ResolvePass::ResolvePass()
    : program_(shaders::source("resolve.vert.glsl"), shaders::source("resolve.frag.glsl"), "silhouette resolve"),
      depth_jump_(program_.uniform("u_depth_jump")),
      viewport_(program_.uniform("u_viewport")),
      rectangles_(gl::make_buffer()) {}

void ResolvePass::run(GLuint framebuffer, GLuint display_framebuffer, GLuint display, const GBuffer& gbuffer, float depth_jump,
                      const std::vector<std::array<std::int32_t, 4>>& rectangles) {
  glBlitNamedFramebuffer(display_framebuffer, framebuffer, 0, 0, gbuffer.width(), gbuffer.height(), 0, 0, gbuffer.width(),
                         gbuffer.height(), GL_COLOR_BUFFER_BIT, GL_NEAREST);
  if (rectangles.empty()) return;
  glNamedBufferData(rectangles_.get(), static_cast<GLsizeiptr>(rectangles.size() * sizeof(rectangles[0])), rectangles.data(),
                    GL_STREAM_DRAW);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_RESOLVE_TILES, rectangles_.get());
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  program_.use();
  glBindTextureUnit(UNIT_WEIGHT_ALBEDO, gbuffer.texture(GBuffer::WeightAlbedo));
  glBindTextureUnit(UNIT_Z_NORMAL, gbuffer.texture(GBuffer::ZNormal));
  glBindTextureUnit(UNIT_DISPLAY, display);
  glUniform1f(depth_jump_, depth_jump);
  glUniform2f(viewport_, static_cast<float>(gbuffer.width()), static_cast<float>(gbuffer.height()));
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(6 * rectangles.size()));
}

std::vector<std::array<std::int32_t, 4>> outline_rectangles(const std::vector<float>& view_z, int width, int height,
                                                            float depth_jump) {
  const auto w = static_cast<std::size_t>(width), h = static_cast<std::size_t>(height);
  const std::size_t columns = (w + kResolveTile - 1) / kResolveTile, rows = (h + kResolveTile - 1) / kResolveTile;
  std::vector<char> marked(columns * rows, 0);
  const float jump = 0.9f * depth_jump;
  // A pair of 4-neighbours p, q that the shader may take as an outline marks both pixels' tiles.
  const auto outline = [&](float a, float b) {
    if ((a == 0.0f) != (b == 0.0f)) return true;
    return a != 0.0f && std::abs(a - b) > jump * std::max(-a, -b);
  };
  const auto mark = [&](std::size_t x, std::size_t y) { marked[y / kResolveTile * columns + x / kResolveTile] = 1; };
  for (std::size_t y = 0; y < h; ++y)
    for (std::size_t x = 0; x < w; ++x) {
      const float a = view_z[y * w + x];
      if (x + 1 < w && outline(a, view_z[y * w + x + 1])) mark(x, y), mark(x + 1, y);
      if (y + 1 < h && outline(a, view_z[(y + 1) * w + x])) mark(x, y), mark(x, y + 1);
    }
  std::vector<std::array<std::int32_t, 4>> rectangles;
  for (std::size_t ty = 0; ty < rows; ++ty)
    for (std::size_t tx = 0; tx < columns; ++tx) {
      if (!marked[ty * columns + tx]) continue;
      const std::size_t begin = tx;
      while (tx + 1 < columns && marked[ty * columns + tx + 1]) ++tx;
      rectangles.push_back({static_cast<std::int32_t>(begin * kResolveTile), static_cast<std::int32_t>(ty * kResolveTile),
                            static_cast<std::int32_t>(std::min(w, (tx + 1) * kResolveTile)),
                            static_cast<std::int32_t>(std::min(h, (ty + 1) * kResolveTile))});
    }
  return rectangles;
}

MeshMaskPass::MeshMaskPass()
    : program_(shaders::source("mesh.vert.glsl"), shaders::source("mesh.frag.glsl"), "mesh"),
      model_(program_.uniform("u_model")),
      view_(program_.uniform("u_view")),
      proj_(program_.uniform("u_proj")) {}

void MeshMaskPass::run(const glm::mat4& view, const glm::mat4& proj, const std::vector<glm::mat4>& models,
                       const std::vector<GLuint>& vertex_arrays, const std::vector<GLsizei>& vertices) const {
  program_.use();
  glUniformMatrix4fv(view_, 1, GL_FALSE, glm::value_ptr(view));
  glUniformMatrix4fv(proj_, 1, GL_FALSE, glm::value_ptr(proj));
  for (std::size_t i = 0; i < models.size(); ++i) {
    glUniformMatrix4fv(model_, 1, GL_FALSE, glm::value_ptr(models[i]));
    glBindVertexArray(vertex_arrays[i]);
    glDrawArrays(GL_TRIANGLES, 0, vertices[i]);
  }
}

}  // namespace splatcl::present
