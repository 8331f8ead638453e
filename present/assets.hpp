#pragma once
// Per-object assets built on first use and cached on disk: the splat set (splatcl splats) and the
// coherent shadow map (splatcl csm build) of a mesh, or a splat file read as it is with the shadow
// map of its splats' discs, and the splats' LOD tree (present/lod.hpp). Cache files are named by an FNV-1a hash of the
// mesh content (vertices and faces) and of every parameter that shapes the result, and written
// atomically by the splat and CSM writers, so a stale or half-written entry is never read.
#include <functional>
#include <string>
#include <vector>

#include "csm/csm_file.hpp"
#include "present/lod.hpp"
#include "core/scene.hpp"
#include "runtime/runtime.hpp"
#include "core/mesh.hpp"
#include "splats/normal_field.hpp"
#include "splats/splat_file.hpp"
#include "splats/surface_fit.hpp"

namespace splatcl::present {

struct ObjectAssets {
  Mesh mesh;  // the fitted mesh; for a splat file, its splats as hexagonal discs (the CSM's geometry)
  // The splats as built (or read from the splat file), then the gap splats of the fit below.
  std::vector<splats::SplatRecord> splats;
  // The same splats as drawn (a mesh object with quality.surface_clip): each fitted to the surface
  // at the splat scale k (splats::clip_to_surface: clip lines at sharp edges, `second_clips` at
  // corners, shortened where it stands off a curved surface), and gap splats where the fitted
  // splats leave the surface uncovered (splats::cover_drawn_gaps). Else `splats` as they are.
  std::vector<splats::SplatRecord> drawn;
  std::vector<splats::ClipLine> second_clips;  // one per drawn splat (offset +inf: none)
  std::size_t gap_splats = 0;                  // the last ones of `splats` and `drawn`
  SplatTree tree;  // level-of-detail hierarchy over `splats`
  // The Phong splats' normal fields (splats::NormalField) of the drawn splats and of the tree's
  // nodes: from the mesh's smooth normals, or for a splat file from its splats' neighbours.
  std::vector<splats::NormalField> normal_fields, node_fields;
  csm::Csm csm;
  std::string key;  // cache key (hex)
  bool splats_cached = false, gaps_cached = false, drawn_cached = false, tree_cached = false, fields_cached = false, csm_cached = false;
  double build_ms = 0;
  std::string fit_warning;  // a splat file's fit: stray_splats_warning, empty when none
  std::string placement_warning;  // far_placement_check's warning, empty when none
  std::string thin_part_warning;  // csm::thin_part_warning of the object's CSM capture, empty when none
};

// The presenter draws, lights and shadows in float world coordinates: an object placed far from
// the origin for its size (`position`, its orbit) moves by the float step there. Empty, or a
// warning where that step exceeds kFloatStepWarning of the object's size (its placed mesh's
// diagonal); an Error beyond kFarPlacementShare, where its coordinates have 16 steps across it or
// fewer. A unit sphere at 1e7 (step 2, 58 % of its size) vanished from the frame with no word (a
// helper's audit); at 1e6 (0.0625, 1.8 %: a warning) it lost 4.4 % of its pixels to cracks and
// moved by pixels; at 1e5 (0.23 %) 7 of 32,467 pixels were uncovered.
inline constexpr double kFarPlacementShare = 1.0 / 16;
std::string far_placement_check(const ObjectSpec& object, const Mesh& mesh);

// Empty, or a warning when a few splats reach far beyond the rest (the discs' box more than 10x the
// diagonal of the central 98 % of the centres): a fit would scale the object by them.
std::string stray_splats_warning(const std::vector<splats::SplatRecord>& splats);

// Cache directory: $SPLATCL_CACHE, else $XDG_CACHE_HOME/splatcl, else ~/.cache/splatcl, else
// ./.splatcl-cache.
std::string default_cache_dir();

// The hash of a mesh's content and the parameter text, as 16 hex digits.
std::string asset_key(const Mesh& mesh, const std::string& parameters);

// Called as asset building goes: `what` names the object and the step ("bunny: splats: growing",
// "bunny: coherent shadow map 300/1024"); `finished` is true once per built step, with what it made
// and how long it took ("bunny: 15,318 splats in 4.2 s"), for a line that stays.
using AssetProgress = std::function<void(const std::string& what, bool finished)>;

// The splats of a splat file: splatcl's splat PLY, or a 3D Gaussian Splatting PLY (each Gaussian as
// the ellipse of its two largest axes, docs/presenter.md). Throws Error naming the file.
struct SplatObjectFile {
  std::vector<splats::SplatRecord> splats;
  DVec3 origin{0, 0, 0};  // the file's splatcl_origin (the positions are relative to it); zero for a 3DGS file of another tool
  std::string checksum;  // FNV-1a of the file's bytes, hex (part of the cache keys)
};
SplatObjectFile read_splat_object(const std::string& path);

// Each splat as a hexagon inscribed in its ellipse (clip lines ignored), as one mesh: the geometry a
// splat file's shadow map is captured from. Throws Error naming `what` when no splat has area.
Mesh splat_disc_mesh(const std::vector<splats::SplatRecord>& splats, const std::string& what);

// Refuses what the scene reader alone cannot check: more key lights than the lighting holds, and an
// object's asset settings that only the splat stage would reject (its sampling text). Before any
// object's assets are built; the error names the scene file (and the object). `splatcl cluster`
// checks the same, so a scene it accepts is one render accepts.
void check_scene_settings(const Scene& scene);
// Loads the object's assets from `cache_dir` or builds and stores them. Throws Error naming the
// mesh or the cache file.
ObjectAssets load_object_assets(const ObjectSpec& object, const Scene& scene, const std::string& cache_dir,
                                Runtime& runtime, const AssetProgress& progress = {});

}  // namespace splatcl::present
