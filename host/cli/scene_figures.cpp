#include "cli/scene_figures.hpp"

namespace splatcl::cli {

std::vector<ObjectFigures> object_figures(const present::Presenter& presenter, const splatcl::Scene& scene) {
  std::vector<ObjectFigures> out;
  for (std::size_t i = 0; i < scene.objects.size() && i < presenter.object_count(); ++i) {
    const present::ObjectAssets& a = presenter.assets(i);
    ObjectFigures f;
    f.name = scene.objects[i].name;
    f.occluder = scene.objects[i].occluder;
    f.two_sided = presenter.two_sided(i);
    const splatcl::MeshSpec& mesh = scene.objects[i].mesh;
    const bool splat_file = !mesh.splat_path.empty();
    f.source = splat_file ? "splat file " + mesh.splat_path : mesh.path.empty() ? "procedural " + mesh.procedural : "mesh " + mesh.path;
    f.vertices = splat_file ? 0 : a.mesh.vertices.size();
    f.faces = splat_file ? 0 : a.mesh.face_count();
    f.splats = a.splats.size();
    f.gap_splats = a.gap_splats;
    f.lod_entries = a.tree.size();
    f.csm_maps = a.csm.info.maps;
    f.csm_resolution = a.csm.info.resolution;
  f.csm_single_hit = csm::to_string(a.csm.info.single_hit);
    f.csm_segments = a.csm.segments();
    const double pixels = static_cast<double>(f.csm_maps) * f.csm_resolution * f.csm_resolution;
    f.csm_segments_per_pixel = pixels > 0 ? static_cast<double>(f.csm_segments) / pixels : 0;
    f.csm_bytes = sizeof(std::uint32_t) * a.csm.offsets.size() + sizeof(float) * a.csm.depth.size() +
                  sizeof(std::uint32_t) * a.csm.end.size();
    f.splats_cached = a.splats_cached, f.gaps_cached = a.gaps_cached, f.drawn_cached = a.drawn_cached, f.tree_cached = a.tree_cached;
    f.fields_cached = a.fields_cached, f.csm_cached = a.csm_cached;
    f.build_ms = a.build_ms;
    f.key = a.key;
    out.push_back(std::move(f));
  }
  return out;
}

nlohmann::json to_json(const std::vector<ObjectFigures>& objects) {
  nlohmann::json list = nlohmann::json::array();
  for (const ObjectFigures& f : objects)
    list.push_back({{"name", f.name},
                    {"occluder", f.occluder},
                    {"two_sided", f.two_sided},
                    {"source", f.source},
                    {"vertices", f.vertices},
                    {"faces", f.faces},
                    {"splats", f.splats},
                    {"gap_splats", f.gap_splats},
                    {"lod_entries", f.lod_entries},
                    {"csm_maps", f.csm_maps},
                    {"csm_resolution", f.csm_resolution},
                    {"csm_single_hit", f.csm_single_hit},
                    {"csm_segments", f.csm_segments},
                    {"csm_segments_per_pixel", f.csm_segments_per_pixel},
                    {"csm_bytes", f.csm_bytes},
                    {"splats_cached", f.splats_cached},
                    {"gaps_cached", f.gaps_cached},
                    {"drawn_cached", f.drawn_cached},
                    {"tree_cached", f.tree_cached},
                    {"fields_cached", f.fields_cached},
                    {"csm_cached", f.csm_cached},
                    {"build_ms", f.build_ms},
                    {"cache_key", f.key}});
  return list;
}

nlohmann::json settings_json(const splatcl::Scene& scene, present::DebugView view, bool ambient_occlusion, bool pixel_ao, bool floor_pixels) {
  const splatcl::Quality& q = scene.quality;
  return {{"shading", q.shading},
          {"mode", q.mode},
          {"shadows", q.shadows},
          {"filter", q.filter},
          {"ambient_occlusion", ambient_occlusion},
          {"pixel_ao", pixel_ao},
          {"floor_pixels", floor_pixels},
          {"lod_error", q.lod_error},
          {"specular", q.specular},
          {"debug_view", present::to_string(view)},
          {"splat_scale", q.splat_scale},
          {"surface_clip", q.surface_clip},
          {"antialias", q.antialias},
          {"depth_offset", q.depth_offset},
          {"shadow_lift", q.shadow_lift},
          {"lights", scene.lights.size()},
          {"key_lights", scene.key_lights.size()}};
}

}  // namespace splatcl::cli
