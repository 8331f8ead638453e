#pragma once
// One frame of the presenter:
//   CL, when an occluder moved, on a worker thread beside the visibility pass: per-splat ambient
//       occlusion and bent normal from every occluder's CSM (csm::AmbientOcclusion) and per-splat
//       key-light visibility (csm::VisibilityQueries, PCF)
//   GL: splat visibility pass (depth pushed back by ε) → Gaussian-weighted accumulation into the
//       G-buffer (or one point pass in the low-quality mode)
//   readback of Σw and Σw·z (the view-space depth)
//   CL: cluster keys → compaction → bounds → light assignment (cluster::ClusterPipeline); or tile
//       lists on the host (tiled baseline); or nothing (brute-force baseline)
//   upload of the lights and lists → GL final shading (division by Σw, Lambert with the corrected
//   falloff, shadowed key lights, per-splat SH sky with the bent normal × AO) → tone mapping →
//   silhouette resolve (anti-aliasing across object outlines, final view only).
// Every stage is timed: GL passes with timer queries (or wall clocks, wall_clock_passes), CL
// stages and transfers with wall clocks.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "present/assets.hpp"
#include "core/scene.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::present {

enum class DebugView : int { Final = 0, Albedo, Normals, AmbientOcclusion, LightsPerCluster, Shadows, Depth, Footprints };
const char* to_string(DebugView view);
DebugView parse_debug_view(const std::string& text);  // final, albedo, normals, ao, clusters, shadows, depth, footprints

struct StageTime {
  std::string name;
  double ms = 0;
};
struct FrameStats {
  std::vector<StageTime> stages;
  double frame_ms = 0;
  std::uint32_t clusters = 0, light_indices = 0, splats = 0;
  std::uint32_t heat_max = 0;  // lights in the fullest list: the top of the lights-per-cluster heat map
  bool ao_updated = false;
  std::uint32_t lighting_receivers = 0;  // splats whose AO and shadows the last update recomputed
  // Floor lattice nodes on the floor this frame, and those whose AO and shadows were recomputed.
  std::uint32_t floor_nodes = 0, floor_receivers = 0;
};

struct FrameSettings;  // present/settings.hpp
struct SplatDraw;      // present/passes.hpp

// A length the scene does not give (the visibility ε, Quality::depth_offset_auto; the shadow lift,
// shadow_lift_auto): its default `length`, lowered to kAutoLengthShare of the smallest object's
// diagonal at its scale (the fit is in its mesh), or raised to kAutoLengthShareLarge of it. The
// default scene's smallest, the box, keeps 0.02; a scene scaled by 0.01 gets 0.0002, as its objects
// need (an ε of 0.02 showed the floor through their lower halves, a lift of 0.02 carried the
// floor's receivers out of their shadows); a scene scaled by 10⁴ gets 194 (an ε of 0.02 let the
// splats of one surface hide each other: 629 of 19,200 pixels changed in the normals view).
float auto_scene_length(float length, const Scene& scene, const std::vector<ObjectAssets>& assets);

class Presenter {
 public:
  // Needs a current GL 4.5 context. Builds or loads every object's assets (progress per object).
  Presenter(Scene scene, Runtime& runtime, int width, int height, const std::string& cache_dir,
            const AssetProgress& progress = {});
  ~Presenter();
  Presenter(const Presenter&) = delete;
  Presenter& operator=(const Presenter&) = delete;

  Scene& scene() { return scene_; }
  int width() const { return width_; }
  int height() const { return height_; }
  void resize(int width, int height);

  DebugView debug_view = DebugView::Final;
  bool ambient_occlusion = true;  // AO and bent normal in the ambient term
  bool pixel_ao = false;          // AO per G-buffer pixel (quality mode) instead of per splat
  // The floor's pixels get their AO and key-light shadows per pixel (the objects' stay per splat),
  // so the floor's shading does not step at its splat spacing; off, the floor splats' values.
  bool floor_per_pixel = true;
  // When occluders move, recompute only the splats whose AO or shadow queries may reach a moved
  // occluder (before or after its move) and the moved objects' own splats; the result equals a full
  // recomputation exactly. Off: every splat each time (cross-map PCF always does that:
  // csm::cone_reach_texels). The same for the floor's pixel lattice: with the camera still, its
  // nodes keep their visibility through the occluders that did not move.
  bool incremental_lighting = true;
  // The shading also writes linear radiance (read_hdr_rgb); off, only the tone-mapped image.
  bool hdr_output = true;
  // GL passes timed by wall clock between glFinish calls instead of timer queries (serialises the
  // frame; on llvmpipe only this splits the time between passes and the depth readback's wait).
  bool wall_clock_passes = false;
  // The per-splat lighting of moved occluders and the floor's lattice (CL) run on a worker thread
  // beside the splat passes; off, on this thread (after the visibility pass, after the depth
  // readback). Same rows either way. Not for a first update, the points mode's lighting, or while
  // wall_clock_passes is on.
  bool overlap_lighting = true;
  // The silhouette resolve filters only the screen tiles that may hold an outline (found on the
  // host from the read-back view z) and copies the rest; off, it runs over every pixel. Same image.
  bool resolve_outline_tiles = true;

  // Renders the scene at `time` into the presenter's framebuffers.
  FrameStats render(float time);
  // Results of the last render(), row 0 = bottom.
  std::vector<float> read_display_rgb() const;  // tone-mapped, [0, 1]
  std::vector<float> read_hdr_rgb() const;      // linear radiance before tone mapping
  std::vector<std::uint8_t> read_coverage() const;  // 1 where a splat covers the pixel
  std::vector<float> read_view_z() const;           // view-space z, 0 where no splat covers the pixel
  std::vector<float> read_normals() const;          // world normal xyz per pixel, 0 where uncovered
  // Rasterises the objects' triangle meshes at `time` with the same camera: 1 where covered.
  std::vector<std::uint8_t> render_mesh_mask(float time);
  // The view z of the last render_mesh_mask's nearest triangles, 0 where none covers the pixel.
  std::vector<float> read_mesh_view_z() const;
  // The display framebuffer (for blitting into a window).
  unsigned display_framebuffer() const;

  // Per-splat (bent normal xyz, AO) of the last update, in splat order: objects in scene order,
  // then the floor. object_splats(i) gives object i's range; the floor is the last range.
  const std::vector<glm::vec4>& splat_ao() const { return splat_ao_; }
  // One line per mesh object whose mesh had problems or was repaired when loaded
  // ("scene.json: objects[0] 'x': x.obj: 12 faces turned ..."), for the commands to print as warnings.
  std::vector<std::string> mesh_warnings() const;
  // Every splat's row of the last update: bent normal xyz, AO, visibility of key lights 0-3.
  const std::vector<float>& splat_lighting() const;
  // Object i's range of splats (two-sided: its drawn splats, then their mirror images).
  std::pair<std::size_t, std::size_t> object_splats(std::size_t object) const;
  // Whether object i is drawn from both sides (ObjectSpec::two_sided, or its mesh is open).
  bool two_sided(std::size_t object) const { return objects_.at(object).two_sided; }
  std::size_t object_count() const { return objects_.size(); }
  glm::vec3 splat_world_position(std::size_t splat, float time) const;

  const ObjectAssets& assets(std::size_t object) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Scene scene_;
  Runtime& runtime_;
  int width_ = 0, height_ = 0;
  struct ObjectRange {
    std::size_t first = 0, count = 0;
    int asset = -1;  // index into assets, -1 for the floor
    // Two-sided: the asset's drawn splats, then the same mirrored (facing the other way).
    bool two_sided = false;
    // The drawn splat that range entry `s` shows.
    std::size_t source(std::size_t s) const { return two_sided ? s % (count / 2) : s; }
  };
  std::vector<ObjectRange> objects_;  // scene objects then the floor
  std::vector<ObjectAssets> assets_;
  std::vector<glm::vec4> splat_ao_;
  // What the per-splat lighting rows depend on besides placements.
  std::string lighting_settings(const FrameSettings& settings) const;
  void update_splat_lighting(const std::vector<glm::mat4>& placements, const FrameSettings& settings, FrameStats& stats);
  // Per object its run of splats to draw at `placements` seen from `eye`: the originals, or with
  // LOD on the prefix of its LOD sequence that may hold entries in their interval; `drawn` counts
  // the splats the vertex shader keeps (unchanged with LOD off).
  std::vector<SplatDraw> splat_draws(const std::vector<glm::mat4>& placements, glm::vec3 eye, std::uint32_t& drawn) const;
  // The steps of render(), in order, on one frame's state (presenter.cpp).
  struct Frame;
  void start_lighting(Frame& frame);
  void finish_lighting(Frame& frame);  // before the first pass that reads the per-splat lighting
  void draw_splats(Frame& frame);
  void build_light_lists(Frame& frame);
  void light_pixels(Frame& frame);
  void light_covered_pixels(Frame& frame);
  void light_floor_lattice(Frame& frame);
  void upload_frame_inputs(Frame& frame);
  void shade(Frame& frame);
};

// Irradiance SH (9 RGB coefficients) of the sky's radiance, by numerical projection.
std::vector<glm::vec3> sky_sh(const Sky& sky);

}  // namespace splatcl::present
