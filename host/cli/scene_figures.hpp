#pragma once
// The figures `splatcl view`'s panel shows and `splatcl render --json` writes, from one place: each
// object's mesh, splat, LOD and CSM figures, and the frame's mode and toggle settings.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "present/presenter.hpp"

namespace splatcl::cli {

struct ObjectFigures {
  std::string name;
  bool occluder = true;
  bool two_sided = false;  // drawn from both sides (its splats twice, the second time mirrored)
  std::string source;  // "mesh FILE", "procedural SHAPE" or "splat file FILE"
  std::size_t vertices = 0, faces = 0;  // of the mesh; 0 for a splat file (its CSM's discs are not a mesh)
  std::size_t splats = 0;       // the object's splats (LOD off)
  std::size_t gap_splats = 0;   // of them, added where the splats as drawn left the surface uncovered
  std::size_t lod_entries = 0;  // splats and octree nodes of its LOD tree
  std::uint32_t csm_maps = 0, csm_resolution = 0;
  std::string csm_single_hit;  // the rule its CSM was built with (auto resolved: csm/csm_file.hpp SingleHit)
  std::size_t csm_segments = 0;
  double csm_segments_per_pixel = 0;  // segments over maps × resolution² pixels
  std::size_t csm_bytes = 0;          // the CSM in memory: offsets, depths and end indices
  bool splats_cached = false, gaps_cached = false, drawn_cached = false, tree_cached = false, fields_cached = false,
       csm_cached = false;
  double build_ms = 0;                // building (or loading) the assets
  std::string key;                    // asset cache key
};

std::vector<ObjectFigures> object_figures(const present::Presenter& presenter, const splatcl::Scene& scene);
nlohmann::json to_json(const std::vector<ObjectFigures>& objects);

// The modes and toggles of a frame: shading baseline, mode, shadows and their filter, AO (on, per
// pixel), the floor per pixel, LOD,
// Blinn-Phong, debug view, splat scale k, depth ε, light count.
nlohmann::json settings_json(const splatcl::Scene& scene, present::DebugView view, bool ambient_occlusion, bool pixel_ao, bool floor_pixels);

}  // namespace splatcl::cli
