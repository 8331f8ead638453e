#pragma once
// The presenter's render targets, each a class that owns its textures and framebuffers.
//   GBuffer: the splat passes' depth, the four accumulation targets, which are the G-buffer the
//     shading reads (Σw-weighted sums; the shading divides by Σw itself, so no normalisation pass
//     writes a second set of full-screen targets). Σw and Σw·z lead their targets, so the light-list
//     stage reads them back as single channels.
//   ShadingTargets: the linear radiance (HDR), the tone-mapped display image and its silhouette
//     resolve.
//   PixelInputs: what the host computes per pixel for the shading: the light list index, and in the
//     quality modes the key-light visibility and the AO with bent normal.
//   MeshMaskTarget: the objects' triangle meshes rasterised for the coverage test.
#include <cstdint>
#include <vector>

#include "present/gl_objects.hpp"

namespace splatcl::present {

class GBuffer {
 public:
  // The accumulation targets (colour attachments 0-3) and what each holds.
  enum Target : int {
    WeightAlbedo = 0,   // Σw, Σw·albedo
    ZNormal = 1,        // Σw·z_view, Σw·n (world)
    ShadowAmbient = 2,  // Σw·visibility of key light 0, Σw·ambient
    Shadows = 3,        // Σw·visibility of key lights 1-3 (drawn with 2+ key lights)
    kTargets = 4
  };
  // The object target's value where no scene object is drawn (background, the floor).
  static constexpr std::uint32_t kNoObject = 0xFFFFFFFFu;
  // The object target: per pixel the scene object of the nearest splat (R32UI), written by the
  // visibility pass, or by the point pass as colour attachment kObjectAttachment of the
  // accumulation framebuffer, only when a frame asks for it.
  static constexpr int kObjectAttachment = 4;
  GBuffer(int width, int height);
  int width() const { return width_; }
  int height() const { return height_; }

  GLuint visibility_framebuffer() const { return visibility_fbo_.get(); }   // depth only
  GLuint accumulation_framebuffer() const { return accum_fbo_.get(); }     // targets and depth
  GLuint texture(int target) const { return accum_[target].get(); }
  // Binds the accumulation framebuffer drawing `targets` (3, or 4 with 2+ key lights), clears
  // them to 0 and the depth to 0 (reversed depth: far).
  // With `object_ids` (the point pass) the object target too, cleared to kNoObject.
  void bind_and_clear(int targets, bool object_ids = false) const;
  // Whether the visibility pass writes the object target, which it clears to kNoObject; off, the
  // pass writes depth alone.
  void write_object_ids(bool on) const;

  // Readbacks, row 0 = bottom.
  std::vector<float> read_channel(int target) const;  // red channel of a target
  std::vector<std::uint8_t> read_coverage() const;    // 1 where Σw > 0
  std::vector<float> read_view_z() const;             // Σw·z / Σw, 0 where uncovered
  std::vector<float> read_normals() const;            // normalised Σw·n, 0 where uncovered
  std::vector<std::uint32_t> read_object_ids() const;  // the object target

 private:
  int width_, height_;
  gl::Texture depth_, accum_[kTargets], object_;
  gl::Framebuffer visibility_fbo_, accum_fbo_;
};

class ShadingTargets {
 public:
  ShadingTargets(int width, int height);
  // The shading's framebuffer: HDR (attachment 0) and display (1), or the display alone.
  GLuint framebuffer(bool hdr) const { return hdr ? hdr_fbo_.get() : display_fbo_.get(); }
  // The silhouette resolve reads the shading's display image and writes the resolved one; after
  // a frame with `resolved` set, the resolved image is the one shown and read back.
  GLuint shaded_display() const { return display_.get(); }
  GLuint shaded_framebuffer() const { return display_fbo_.get(); }
  GLuint resolved_framebuffer() const { return resolved_fbo_.get(); }
  bool resolved = false;
  GLuint display_framebuffer() const { return resolved ? resolved_fbo_.get() : display_fbo_.get(); }
  std::vector<float> read_display_rgb() const;
  std::vector<float> read_hdr_rgb() const;

 private:
  int width_, height_;
  gl::Texture hdr_, display_, resolved_;
  gl::Framebuffer hdr_fbo_, display_fbo_, resolved_fbo_;
};

struct PixelInputs {
  PixelInputs(int width, int height);
  gl::Texture light_list;  // R32UI: index of the pixel's light list, kNoCluster for none
  gl::Texture shadow;      // RGBA32F: key-light visibility 0-3 (per-pixel shadows)
  gl::Texture ao;          // RGBA32F: bent normal, AO (per-pixel AO)
  // The floor's lighting lattice (FLOOR_LATTICE_STEP pixels apart, lattice_columns × lattice_rows
  // nodes, bilinear filtering), RGBA32F: bent normal and AO; key-light visibility 0-3. Nodes off
  // the floor hold their floor neighbours' mean, or a large negative value where none is.
  int lattice_columns, lattice_rows;
  gl::Texture floor_ao, floor_shadow;
};

class MeshMaskTarget {
 public:
  MeshMaskTarget(int width, int height);
  GLuint framebuffer() const { return fbo_.get(); }
  std::vector<std::uint8_t> read_mask() const;  // 1 where a triangle covers the pixel
  std::vector<float> read_view_z() const;       // view z of the nearest triangle, 0 where none

 private:
  int width_, height_;
  gl::Texture color_, depth_;
  gl::Framebuffer fbo_;
};

}  // namespace splatcl::present
