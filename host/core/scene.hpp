#pragma once
// The scene of every stage that renders a view (the presenter, and `splatcl cluster`, which ray casts
// it): objects (a mesh file, a procedural mesh or a splat file, a rigid placement, simple animation),
// a floor, many point lights (explicit or generated), shadowed key lights, a camera, an ambient sky
// and the presenter's quality settings. The JSON schema is documented in docs/presenter.md.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/camera.hpp"
#include "core/mesh.hpp"

namespace splatcl {

// A mesh file (path relative to the scene file), one of the procedural shapes, or a ready-made
// splat file (splatcl's splat PLY or a 3D Gaussian Splatting PLY) that is used as it is.
struct MeshSpec {
  std::string path;        // non-empty: a mesh file
  std::string splat_path;  // non-empty: a splat file instead of a mesh
  std::string procedural;  // "sphere", "torus", "box"
  float radius = 1.0f;     // sphere radius; torus major radius
  float tube = 0.35f;      // torus minor radius
  glm::vec3 size{1.0f};    // box edge lengths
  std::uint32_t segments = 32;  // around the main axis
  std::uint32_t rings = 16;     // sphere latitude rings; torus tube segments; box cells per edge
};

// Pose at time t: spin about the object's own centre, and an orbit of that centre about a point.
struct Animation {
  glm::vec3 spin_degrees_per_second{0.0f};
  float orbit_radius = 0.0f;              // 0 = no orbit
  glm::vec3 orbit_center{0.0f};
  float orbit_degrees_per_second = 0.0f;  // about +y
  float orbit_phase_degrees = 0.0f;
};

// How a mesh (or splat file) is fitted into the scene before its placement: uniformly scaled so that
// its bounding box's largest side is `size` (0: kept), its bounding-box centre moved to the object's
// origin, and with `on_floor` shifted so that its lowest point under `rotation_degrees` is at the
// origin's height: "position" [x, floor.y, z] then rests it on the floor. A spin about +y keeps it
// there; the fit is baked into the mesh, so `scale` still scales about the new origin.
struct MeshFit {
  float size = 0.0f;
  bool on_floor = false;
  bool enabled() const { return size > 0 || on_floor; }
};

// p' = scale · p + offset (model space).
struct FitTransform {
  float scale = 1.0f;
  glm::vec3 offset{0.0f};
  glm::vec3 apply(glm::vec3 p) const { return scale * p + offset; }
  Vec3 apply(Vec3 p) const {
    const glm::vec3 q = apply(glm::vec3(p.x, p.y, p.z));
    return {q.x, q.y, q.z};
  }
  void apply_to(std::vector<Vec3>& points) const {
    for (Vec3& p : points) p = apply(p);
  }
};

// Per-object overrides of the scene's quality settings that shape the cached assets.
struct AssetQualityOverrides {
  std::optional<std::string> sampling, splat_bound, csm_single_hit;
  std::optional<float> eps_diagonal, crease_angle, surface_clip;
  std::optional<std::uint32_t> csm_maps, csm_resolution;
};

struct ObjectSpec {
  std::string name;
  MeshSpec mesh;
  MeshFit fit;
  AssetQualityOverrides quality;
  glm::vec3 color{0.8f};
  // "color": "splats": albedo per splat from the splat file's colours (sRGB bytes), which the splat
  // pipeline takes from `texture` (through the mesh's texture coordinates) or else `color_field`.
  bool splat_colors = false;
  std::string color_field = "hard";  // splats::ColorField: grey, soft, hard, rainbow
  std::string texture;               // image file, relative to the scene file
  std::uint32_t color_tolerance = 255;  // φ of the splat fit: splats stop at colour steps above it (255: ignored)
  glm::vec3 position{0.0f};
  glm::vec3 rotation_degrees{0.0f};  // applied in x, y, z order
  float scale = 1.0f;
  Animation animation;
  bool occluder = true;  // casts shadows and ambient occlusion through its CSM
  // Drawn from both sides: each splat also as its mirror image facing the other way, lit on that
  // side (a scan's or sheet's inside seen through its holes). Not given: a mesh object whose mesh is
  // open (Mesh::closed false) is; a closed mesh and a splat file are not.
  std::optional<bool> two_sided;
  // Model → world at time t (seconds).
  glm::mat4 placement(float time) const;
};

struct FloorSpec {
  bool enabled = true;
  float y = 0.0f;
  float size = 12.0f;  // square side, centred on the origin
  glm::vec3 color{0.7f};
  std::uint32_t splats_per_side = 64;
};

struct Light {
  glm::vec3 position{0.0f};  // world space
  float radius = 1.0f;
  glm::vec3 color{1.0f};
  float size = 0.0f;  // key lights: radius of the spherical emitter sampled for soft shadows (0 = point)
};

// The most point lights a scene may have (listed, generated, --lights): more is refused with one
// line before anything is allocated (docs/reliability.md).
inline constexpr std::uint32_t kMaxSceneLights = 1u << 20;
// The Blinn-Phong highlight strength's bound, quality.specular and render/view --specular.
inline constexpr float kMaxSpecular = 100.0f;
// The default visibility ε and shadow lift as a share of the smallest object's bounding-box diagonal
// (Quality::depth_offset_auto, shadow_lift_auto): where that share is below the default length,
// and kAutoLengthShareLarge of it where that is above (a scene in large units), so the default
// scene, whose smallest diagonal is 2.42, keeps its 0.02.
inline constexpr float kAutoLengthShare = 0.01f;
inline constexpr float kAutoLengthShareLarge = 0.008f;
// The range of an object's "fit" size and "scale".
inline constexpr float kMinSceneExtent = 1e-15f, kMaxSceneExtent = 1e15f;
// Angles (rotation_degrees, an orbit's phase_degrees) at most 100 turns, and spin and orbit rates
// at most 100 turns a second: beyond, float angles turned objects at random.
inline constexpr float kMaxSceneDegrees = 36000.0f;
// quality.ao_bias at most: csm::kMaxBiasTexels (core cannot see csm; present/ checks they agree).
inline constexpr float kMaxSceneAoBias = 1000;
// quality.splat_scale (and the viewer's slider): the gaps a larger k opens at sharp edges are covered
// at a cost that grows with k: a 1-unit box (rings 2) renders in 2.0 s at 1.05, 6.9 s at 3 (1,880
// gap splats); a helper's audit saw 260 s at 10.
inline constexpr float kMinSplatScale = 0.25f, kMaxSplatScale = 3.0f;
// How far off the floor's plane a pixel may lie and still show the floor, as a share of the floor's
// side plus its height (float steps of positions there).
inline constexpr float kFloorToleranceShare = 1e-4f;

// Lights placed uniformly over the floor square (or `extent`) between two heights, with radii and
// bright hues from a seeded generator.
struct GeneratedLights {
  std::uint32_t count = 0;
  float radius_min = 0.8f, radius_max = 2.5f;
  float height_min = 0.2f, height_max = 3.0f;
  float extent = 0.0f;  // half side of the square; 0 = half the floor size
  float intensity = 0.6f;
  std::uint64_t seed = 7;
};

struct Quality {
  // Splat generation sampling (splatcl splats --samples): "auto" sizes the sample grid to the mesh
  // (its curvature and extent) within the splat stage's sample budget, so scanned meshes of tens of
  // thousands of vertices prepare in seconds; "grid:N" asks for N samples along the shortest edge.
  std::string sampling = "auto";
  // "two-sided" (as splatcl splats): splats within ε of the mesh and the mesh covered, so no
  // runaway splats (needles) on scans with holes and creases; "thesis": the thesis's splat method
  // alone (splatcl splats --thesis-only), which the shipped default scene of smooth generated
  // meshes uses at a finer ε.
  std::string splat_bound = "two-sided";
  float eps_diagonal = 0.001f;  // splat ε as a fraction of the mesh's bounding-box diagonal (splatcl splats --eps-diag)
  // Sharp edges for the splats (splatcl splats --crease-angle, degrees): faces meeting at more than
  // this keep their own normals and splats, which the surface fit then clips at the edge; 180 = none.
  // Applies with either splat_bound.
  float crease_angle = 60.0f;
  std::uint32_t csm_maps = 1024, csm_resolution = 64;
  // The CSM build's rule for single-surface pixels (csm build --single-hit): "auto", or "thin" for
  // an open occluder that something stands inside (a bowl, a roof), or "exact" / "sphere-exit".
  std::string csm_single_hit = "auto";
  std::uint32_t ao_samples = 16;
  // CSM depth bias of AO and shadow queries, in texels of each occluder's CSM (1 texel = its
  // bounding sphere's diameter / csm_resolution), so it scales with the occluder and shrinks as its
  // maps get finer.
  float ao_bias = 0.5f;
  // How far shadow receivers are lifted along their normal, world units (on top of the texels of
  // their own CSM that keep it from shadowing them, csm/query_reach.hpp).
  float shadow_lift = 0.02f;
  // Not given in the scene: lowered as depth_offset is (auto_scene_length), so a small scene's lift
  // does not carry its floor's receivers over its objects and out of their shadows.
  bool shadow_lift_auto = true;
  // k: multiplies every splat's axes. Above 1, it closes the single-pixel gaps the thesis's splats
  // leave between them in grazing views (tests/present/splat_geometry_test.cpp).
  float splat_scale = 1.05f;
  // Splats fitted to the mesh as loaded, measured at splat_scale (splats::clip_to_surface): cut by
  // a line where they overhang a sharp edge (two at a corner), their major axis shortened where
  // they stand off a curved surface, by more than this × the mesh's bounding-box diagonal, and the
  // gaps that leaves covered by more splats (splats::cover_drawn_gaps); 0 = drawn as built. How
  // far a splat may stand off the surface: at the silhouette of a close-up it shows as a fin of up
  // to this much, and past a convex edge over the next face seen at a grazing angle (0.0025, the
  // default until 2026-12-07, drew crescents of one face's colour on the next in close-ups of an
  // octahedron: PresenterTest.OctahedronCloseUpsShowLittleOverhangOverTheNextFace). Per object too.
  float surface_clip = 0.001f;
  float depth_offset = 0.02f;  // ε of the visibility pass, world units along the view ray
  // Not given in the scene: the presenter lowers depth_offset to kAutoLengthShare of the
  // smallest object's bounding-box diagonal where that is smaller, so that a small scene's ε does
  // not swallow its objects (present/presenter.cpp, auto_scene_length).
  bool depth_offset_auto = true;
  float gaussian = 2.0f;       // β: weight exp(−β r²) over the unit ellipse
  // Silhouette anti-aliasing of the final view's tone-mapped image (ResolvePass in
  // present/passes.hpp): a pixel is on an outline where its coverage differs from a neighbour's or
  // the view depth changes by more than this share of the farther one; 0 = off.
  float antialias = 0.1f;
  std::string mode = "splats";        // "splats" (three passes) or "points" (one pass, squares)
  std::string shading = "clustered";  // "clustered", "tiled" or "brute"
  std::uint32_t tile = 32;            // cluster / tile side in pixels
  std::string shadows = "splat";      // key-light shadows: "splat" (per splat), "pixel" or "off"
  std::string filter = "march";       // CSM shadow test of the key lights (csm::Filter)
  std::uint32_t shadow_samples = 4;   // points sampled on a key light of non-zero size
  bool ambient_occlusion = true;      // per-splat AO from every occluder
  bool pixel_ao = false;              // quality mode: AO per pixel of the G-buffer instead of per splat
  // The floor's AO and key-light shadows per pixel (independent of its splat spacing, at a cost per
  // frame that grows with the floor's pixels); false: per floor splat (Presenter::floor_per_pixel).
  bool floor_pixels = true;
  float lod_error = 0.0f;             // LOD: screen-space error threshold in pixels (0 = off: every splat)
  std::uint32_t lod_leaf = 16;        // LOD tree: octree leaves hold fewer splats than this
  float specular = 0.0f;              // Blinn-Phong highlight strength (0 = off: Lambert only)
  float shininess = 32.0f;            // Blinn-Phong exponent
};

struct Sky {
  glm::vec3 zenith{0.30f, 0.38f, 0.55f}, horizon{0.30f, 0.30f, 0.32f}, ground{0.10f, 0.09f, 0.08f};
};

struct Scene {
  std::string source;     // file name or "default scene"
  std::string directory;  // base for relative mesh paths
  std::vector<ObjectSpec> objects;
  FloorSpec floor;
  std::vector<Light> lights;  // explicit lights, plus the generated ones after parsing
  GeneratedLights generated;
  std::vector<Light> key_lights;  // shadowed
  Camera camera;
  Sky sky;
  Quality quality;
  float time = 0.0f;  // scene time of a single rendered frame
};

// "scene.json: objects[i] 'name'": where an error about an object (its fields, file or settings) is.
std::string object_where(const std::string& source, std::size_t index, const std::string& name);
std::string object_where(const Scene& scene, std::size_t index);

// The scene's quality with the object's overrides applied: what its assets are built with.
Quality object_quality(const Quality& scene_quality, const ObjectSpec& object);

// Parses scene JSON; errors name `source` and the field. Generated lights are appended to lights.
Scene parse_scene(std::string_view text, const std::string& source, const std::string& directory);
// Reads a scene file ("cannot read scene FILE" when missing).
Scene load_scene(const std::string& path);
// The embedded default scene (data/presenter-scene.json).
Scene default_scene();
const char* default_scene_name();

// Deterministic lights of a GeneratedLights spec.
std::vector<Light> generate_lights(const GeneratedLights& spec, const FloorSpec& floor);

// The object's mesh: loaded from its file, or generated.
Mesh make_object_mesh(const MeshSpec& spec, const std::string& directory);

// The transform that fits `points` (a mesh's vertices) as `fit` asks, under the object's rotation.
// Throws Error naming `what` when the points span nothing to scale.
FitTransform fit_transform(const std::vector<Vec3>& points, const MeshFit& fit, glm::vec3 rotation_degrees,
                           const std::string& what);
// The object's mesh with its fit applied (make_object_mesh for a mesh object).
Mesh make_fitted_mesh(const ObjectSpec& object, const std::string& directory);
// A path of the scene (mesh, texture, splat file), relative to the scene file's directory.
std::string scene_path(const std::string& path, const std::string& directory);

// The files a scene reads, as (what, path) pairs: the scene file itself (none for the default
// scene) and each object's mesh, splat file and texture. Commands keep their outputs off them.
std::vector<std::pair<std::string, std::string>> scene_input_files(const Scene& scene);

// Replaces the generated lights by `count` lights of the same spec (explicit lights stay).
void set_generated_light_count(Scene& scene, std::uint32_t count);

}  // namespace splatcl
