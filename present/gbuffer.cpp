#include "present/gbuffer.hpp"

#include <algorithm>
#include <cstddef>

#include <glm/glm.hpp>

#include "present/shaders/layout.h"

namespace splatcl::present {
namespace {

std::vector<float> drop_alpha(const std::vector<float>& rgba) {
  std::vector<float> rgb(rgba.size() / 4 * 3);
  for (std::size_t i = 0; i < rgba.size() / 4; ++i)
    for (int c = 0; c < 3; ++c) rgb[3 * i + static_cast<std::size_t>(c)] = rgba[4 * i + static_cast<std::size_t>(c)];
  return rgb;
}

}  // namespace

GBuffer::GBuffer(int width, int height)
    : width_(width),
      height_(height),
      depth_(gl::make_texture(GL_DEPTH_COMPONENT32F, width, height)),
      object_(gl::make_texture(GL_R32UI, width, height)) {
  static_assert(kObjectAttachment == kTargets, "the object target follows the accumulation targets");
  for (gl::Texture& t : accum_) t = gl::make_texture(GL_RGBA32F, width, height);
  visibility_fbo_ = gl::make_framebuffer({object_.get()}, depth_.get(), "splat visibility");
  write_object_ids(false);
  accum_fbo_ = gl::make_framebuffer({accum_[0].get(), accum_[1].get(), accum_[2].get(), accum_[3].get(), object_.get()},
                                    depth_.get(), "splat accumulation");
}

void GBuffer::bind_and_clear(int targets, bool object_ids) const {
  GLenum buffers[kTargets + 1] = {GL_NONE, GL_NONE, GL_NONE, GL_NONE, GL_NONE};
  for (int b = 0; b < targets; ++b) buffers[b] = static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + b);
  if (object_ids) buffers[kObjectAttachment] = GL_COLOR_ATTACHMENT0 + kObjectAttachment;
  glNamedFramebufferDrawBuffers(accum_fbo_.get(), object_ids ? kTargets + 1 : targets, buffers);
  glBindFramebuffer(GL_FRAMEBUFFER, accum_fbo_.get());
  const float zero[4] = {0, 0, 0, 0};
  const float farthest = 0.0f;  // reversed depth: far is 0
  for (GLint b = 0; b < targets; ++b) glClearBufferfv(GL_COLOR, b, zero);
  if (object_ids) {
    const GLuint none[4] = {kNoObject, 0, 0, 0};
    glClearBufferuiv(GL_COLOR, kObjectAttachment, none);
  }
  glDepthMask(GL_TRUE);
  glClearBufferfv(GL_DEPTH, 0, &farthest);
}

void GBuffer::write_object_ids(bool on) const {
  glNamedFramebufferDrawBuffer(visibility_fbo_.get(), on ? GL_COLOR_ATTACHMENT0 : GL_NONE);
  if (!on) return;
  const GLuint none[4] = {kNoObject, 0, 0, 0};
  glClearNamedFramebufferuiv(visibility_fbo_.get(), GL_COLOR, 0, none);
}

std::vector<std::uint32_t> GBuffer::read_object_ids() const {
  std::vector<std::uint32_t> ids(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_));
  glNamedFramebufferReadBuffer(visibility_fbo_.get(), GL_COLOR_ATTACHMENT0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, visibility_fbo_.get());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RED_INTEGER, GL_UNSIGNED_INT, ids.data());
  return ids;
}

std::vector<float> GBuffer::read_channel(int target) const {
  std::vector<float> values(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, accum_fbo_.get());
  glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(target));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RED, GL_FLOAT, values.data());
  return values;
}

std::vector<std::uint8_t> GBuffer::read_coverage() const {
  const std::vector<float> weight = read_channel(WeightAlbedo);
  std::vector<std::uint8_t> mask(weight.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = weight[i] > 0.0f ? 1 : 0;
  return mask;
}

std::vector<float> GBuffer::read_view_z() const {
  // Σw·z / Σw, the division the shading does; 0 where no splat covers the pixel.
  std::vector<float> z = read_channel(ZNormal);
  const std::vector<float> weight = read_channel(WeightAlbedo);
  for (std::size_t i = 0; i < z.size(); ++i) z[i] = weight[i] > 0.0f ? z[i] / weight[i] : 0.0f;
  return z;
}

std::vector<float> GBuffer::read_normals() const {
  const auto z_normal = gl::read_rgba(accum_fbo_.get(), GL_COLOR_ATTACHMENT0 + ZNormal, width_, height_);
  std::vector<float> normals(z_normal.size() / 4 * 3, 0.0f);
  for (std::size_t i = 0; i < normals.size() / 3; ++i) {
    const glm::vec3 sum(z_normal[4 * i + 1], z_normal[4 * i + 2], z_normal[4 * i + 3]);
    if (glm::dot(sum, sum) <= 0.0f) continue;
    const glm::vec3 n = glm::normalize(sum);
    std::copy(&n.x, &n.x + 3, normals.begin() + static_cast<std::ptrdiff_t>(3 * i));
  }
  return normals;
}

ShadingTargets::ShadingTargets(int width, int height)
    : width_(width),
      height_(height),
      hdr_(gl::make_texture(GL_RGBA32F, width, height)),
      display_(gl::make_texture(GL_RGBA8, width, height)),
      resolved_(gl::make_texture(GL_RGBA8, width, height)),
      hdr_fbo_(gl::make_framebuffer({hdr_.get(), display_.get()}, 0, "shading")),
      display_fbo_(gl::make_framebuffer({display_.get()}, 0, "display")),
      resolved_fbo_(gl::make_framebuffer({resolved_.get()}, 0, "resolved display")) {}

std::vector<float> ShadingTargets::read_display_rgb() const {
  return drop_alpha(gl::read_rgba(display_framebuffer(), GL_COLOR_ATTACHMENT0, width_, height_));
}

std::vector<float> ShadingTargets::read_hdr_rgb() const {
  return drop_alpha(gl::read_rgba(hdr_fbo_.get(), GL_COLOR_ATTACHMENT0, width_, height_));
}

PixelInputs::PixelInputs(int width, int height)
    : light_list(gl::make_texture(GL_R32UI, width, height)),
      shadow(gl::make_texture(GL_RGBA32F, width, height)),
      ao(gl::make_texture(GL_RGBA32F, width, height)),
      lattice_columns((width + FLOOR_LATTICE_STEP - 1) / FLOOR_LATTICE_STEP),
      lattice_rows((height + FLOOR_LATTICE_STEP - 1) / FLOOR_LATTICE_STEP),
      floor_ao(gl::make_texture(GL_RGBA32F, lattice_columns, lattice_rows, GL_LINEAR)),
      floor_shadow(gl::make_texture(GL_RGBA32F, lattice_columns, lattice_rows, GL_LINEAR)) {}

MeshMaskTarget::MeshMaskTarget(int width, int height)
    : width_(width),
      height_(height),
      color_(gl::make_texture(GL_R32F, width, height)),
      depth_(gl::make_texture(GL_DEPTH_COMPONENT32F, width, height)),
      fbo_(gl::make_framebuffer({color_.get()}, depth_.get(), "mesh mask")) {}

std::vector<std::uint8_t> MeshMaskTarget::read_mask() const {
  const auto rgba = gl::read_rgba(fbo_.get(), GL_COLOR_ATTACHMENT0, width_, height_);
  std::vector<std::uint8_t> mask(rgba.size() / 4);
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = rgba[4 * i] > 0.0f ? 1 : 0;
  return mask;
}

std::vector<float> MeshMaskTarget::read_view_z() const {
  const auto rgba = gl::read_rgba(fbo_.get(), GL_COLOR_ATTACHMENT0, width_, height_);
  std::vector<float> z(rgba.size() / 4);
  for (std::size_t i = 0; i < z.size(); ++i) z[i] = -rgba[4 * i];
  return z;
}

}  // namespace splatcl::present
