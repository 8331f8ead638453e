#include "present/presenter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <future>
#include <map>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "cluster/cluster.hpp"
#include "cluster/scene_input.hpp"
#include "csm/ao.hpp"
#include "csm/ao_receivers.hpp"
#include "csm/query_reach.hpp"
#include "csm/splat_lighting.hpp"
#include "csm/sphere_grid.hpp"
#include "csm/visibility.hpp"
#include "present/gbuffer.hpp"
#include "present/gl_objects.hpp"
#include "present/light_lists.hpp"
#include "present/passes.hpp"
#include "present/settings.hpp"
#include "present/shaders.hpp"
#include "present/shaders/layout.h"
#include "runtime/error.hpp"
#include "runtime/profiling.hpp"
#include "splats/neighbors.hpp"
#include "splats/normal_field.hpp"
#include "splats/surface_fit.hpp"

namespace splatcl::present {
namespace {

constexpr int kMaxKeyLights = MAX_KEY_LIGHTS;
// Floats per lighting row, and where its key-light visibility starts.
constexpr std::size_t kLightingRow = layout::kLightingRowFloats;
constexpr std::size_t kVisibilityAt = offsetof(layout::LightingRow, visibility) / sizeof(float);
static_assert(NO_LIGHT_LIST == cluster::kNoCluster);
static_assert(kLightingRow == csm::SplatLighting::kRowFloats && kVisibilityAt == csm::SplatLighting::kVisibilityAt &&
              kMaxKeyLights == csm::SplatLighting::kMaxKeyLights);
constexpr std::uint32_t kAoPatterns = 256;
constexpr std::uint32_t kAoSeed = 1;

constexpr const char* kDebugNames[] = {"final", "albedo", "normals", "ao", "clusters", "shadows", "depth", "footprints"};

csm::Transform to_transform(const glm::mat4& m) {
  csm::Transform t{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) t[static_cast<std::size_t>(4 * r + c)] = m[c][r];
  return t;
}

Vec4 vec4(glm::vec3 v) { return {v.x, v.y, v.z, 0.0f}; }

// Reversed depth: near maps to 1 and far to 0 in glClipControl's [0, 1] range (set by
// use_reversed_depth), so the float depth buffer keeps about 2^-24 relative precision at every
// distance. With the standard mapping its steps grew as distance^2 / near: at near 1e-4, or a camera
// 500 units out, they passed the visibility pass's offset and the floor's splats hid each other in
// bands. Depth tests are GREATER / GEQUAL against a clear of 0.
glm::mat4 reversed_depth_projection(const Camera& cam, float aspect) {
  return glm::perspectiveRH_ZO(cam.fov_y, aspect, cam.far_plane, cam.near_plane);
}
void use_reversed_depth() { glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE); }

// Per named GL pass: a timer query read after the frame, or with `wall` the wall clock between two
// glFinish calls. llvmpipe rasterises a pass when a later command needs its result, so its queries
// and the next wait (the depth readback) do not split the time between passes; the wall clock
// does, at the price of serialising the frame.
struct GpuTimers {
  bool wall = false;
  std::vector<gl::Query> queries;
  std::vector<std::string> names;
  std::vector<double> wall_ms;
  std::size_t used = 0;
  Stopwatch clock;
  void begin(const char* name) {
    if (used == queries.size()) {
      queries.push_back(gl::make_query());
      names.emplace_back();
      wall_ms.push_back(0.0);
    }
    names[used] = name;
    if (wall) {
      glFinish();
      clock.restart();
    }
    glBeginQuery(GL_TIME_ELAPSED, queries[used].get());
  }
  void end() {
    glEndQuery(GL_TIME_ELAPSED);
    if (wall) {
      glFinish();
      wall_ms[used] = clock.elapsed_ms();
    }
    ++used;
  }
  void collect(std::vector<StageTime>& out) {
    for (std::size_t i = 0; i < used; ++i) {
      GLuint64 ns = 0;
      glGetQueryObjectui64v(queries[i].get(), GL_QUERY_RESULT, &ns);
      out.push_back({names[i], wall ? wall_ms[i] : static_cast<double>(ns) * 1e-6});
    }
    used = 0;
  }
};

// The world point pixel (x, y) shows at view distance `distance`.
Vec3 pixel_world(const cluster::ClusterLayout& layout, const ViewFrame& frame, std::uint32_t x, std::uint32_t y, float distance) {
  return frame.eye + frame.direction_to_world(cluster::pixel_view_position(layout, x, y, distance));
}

// How far off the floor's plane a point may lie and still be the floor (the host's tests and the
// shading's, shade.frag.glsl on_floor).
// It follows the floor's size: a fixed 1e-3 missed the floor's own pixels in a scene in large units,
// whose positions are that far off by float steps.
float floor_tolerance(const FloorSpec& floor) { return kFloorToleranceShare * (floor.size + std::abs(floor.y)); }

// The pixels a splat covers (view z from the G-buffer, 0 = none): index and world position.
struct CoveredPixel {
  std::size_t index;
  cluster::Vec3 world;
};
std::vector<CoveredPixel> covered_pixels(const cluster::ClusterLayout& layout, const ViewFrame& frame,
                                         const std::vector<float>& view_z) {
  std::vector<CoveredPixel> covered;
  for (std::uint32_t y = 0; y < layout.config.height; ++y)
    for (std::uint32_t x = 0; x < layout.config.width; ++x) {
      const std::size_t p = std::size_t{y} * std::size_t{layout.config.width} + x;
      const auto d = cluster::pixel_distance(layout, view_z[p], cluster::DepthFormat::ViewZ);
      if (d) covered.push_back({p, pixel_world(layout, frame, x, y, *d)});
    }
  return covered;
}

// The floor's lighting rows on the pixel lattice (every FLOOR_LATTICE_STEP-th pixel in x and y),
// as the shading's two lattice textures: (bent normal, AO), smoothed over each node's 3 × 3 lattice
// neighbours that show floor (each node's 16 AO directions alone leave a grain), and key-light
// visibility per node, smoothed so only for the lights of non-zero size (`soft`: their few sample
// points leave bands in the penumbra); a point light's PCF is smooth already, and averaging spread
// its shadow edge over 12 pixels (mean error against ray tracing 0.099 in a plate's hole, 0.080 not
// averaged). A node that does not show floor (an object hides the node's floor point,
// which may lie far behind it, or the node is off the floor) takes the mean of its 3 × 3
// neighbours that do, so that the shading's bilinear filter reads the floor's nodes only; one
// with none of them holds kNoFloorNode, which makes the filtered value negative wherever it has
// any weight (shade.frag.glsl, floor_lattice).
constexpr std::size_t kFloorStep = FLOOR_LATTICE_STEP;
constexpr float kNoFloorNode = -1e6f;
std::size_t lattice_size(int pixels) { return (static_cast<std::size_t>(pixels) + kFloorStep - 1) / kFloorStep; }

// `rows`: kLightingRow per lattice node (row-major, `columns` wide), valid where `present`.
void floor_lattice_textures(const std::vector<float>& rows, const std::vector<std::uint8_t>& present, std::size_t columns,
                            const std::array<bool, kLightingRow - kVisibilityAt>& soft, std::vector<float>& ao, std::vector<float>& shadow) {
  static_assert(kLightingRow == 8 && kVisibilityAt == 4);
  const std::size_t lattice_rows = present.size() / columns;
  // The mean of `source` rows over the 3 × 3 neighbours of (x, y) where `present`; false where none is.
  const auto neighbour_mean = [&](const float* source, std::size_t x, std::size_t y, float* mean) {
    std::fill(mean, mean + kLightingRow, 0.0f);
    float count = 0.0f;
    for (std::size_t ny = y ? y - 1 : 0; ny <= std::min(lattice_rows - 1, y + 1); ++ny)
      for (std::size_t nx = x ? x - 1 : 0; nx <= std::min(columns - 1, x + 1); ++nx) {
        if (!present[ny * columns + nx]) continue;
        const float* v = source + kLightingRow * (ny * columns + nx);
        for (std::size_t c = 0; c < kLightingRow; ++c) mean[c] += v[c];
        count += 1.0f;
      }
    if (count == 0.0f) return false;
    for (std::size_t c = 0; c < kLightingRow; ++c) mean[c] /= count;
    return true;
  };
  std::vector<float> smoothed(rows.size());
  for (std::size_t y = 0; y < lattice_rows; ++y)
    for (std::size_t x = 0; x < columns; ++x)
      if (present[y * columns + x]) {
        float* out = &smoothed[kLightingRow * (y * columns + x)];
        neighbour_mean(rows.data(), x, y, out);
        for (std::size_t k = 0; k < soft.size(); ++k)
          if (!soft[k]) out[kVisibilityAt + k] = rows[kLightingRow * (y * columns + x) + kVisibilityAt + k];
      }
  ao.resize(4 * present.size());
  shadow.resize(4 * present.size());
  for (std::size_t y = 0; y < lattice_rows; ++y)
    for (std::size_t x = 0; x < columns; ++x) {
      const std::size_t node = y * columns + x;
      float value[kLightingRow];
      if (present[node])
        std::copy_n(&smoothed[kLightingRow * node], kLightingRow, value);
      else if (!neighbour_mean(smoothed.data(), x, y, value))
        std::fill(value, value + kLightingRow, kNoFloorNode);
      std::copy_n(value, 4, &ao[4 * node]);
      std::copy_n(value + kVisibilityAt, 4, &shadow[4 * node]);
    }
}

// Per splat of an object, its neighbours in compressed rows: index[first[i] .. first[i + 1]).
struct AoNeighbours {
  std::vector<std::uint32_t> first{0}, index;
};

// The splats each splat's ambient occlusion is averaged with: its 8 nearest (centres), those within
// twice its major semi-axis whose receiver normal is within 25° of its own. 16 directions per splat
// leave a splat's AO a noisy estimate (an occluder a few units away is hit by one direction or by
// none), which showed as speckle on smooth surfaces; the mean over the splat's neighbourhood on the
// same side of the surface keeps the AO's variation at the splat spacing and lowers the noise.
AoNeighbours ao_smoothing_neighbours(const std::vector<splats::SplatRecord>& splats, const std::vector<glm::vec3>& normals) {
  AoNeighbours near;
  if (splats.size() < 2) {
    near.first.assign(splats.size() + 1, 0);
    return near;
  }
  std::vector<Vec4> centres(splats.size());
  for (std::size_t i = 0; i < splats.size(); ++i) centres[i] = to_vec4(splats[i].center);
  const splats::Neighborhoods knn = splats::find_neighbors(centres, 8);
  const float cos_limit = std::cos(glm::radians(25.0f));
  for (std::size_t i = 0; i < splats.size(); ++i) {
    const float reach = 2.0f * length(splats[i].major);
    for (std::uint32_t k = 0; k < knn.k; ++k) {
      const std::uint32_t j = knn.row(i)[k];
      if (length(splats[j].center - splats[i].center) <= reach && glm::dot(normals[i], normals[j]) >= cos_limit) near.index.push_back(j);
    }
    near.first.push_back(static_cast<std::uint32_t>(near.index.size()));
  }
  return near;
}

// Replaces each splat's AO (and bent normal) in `rows` (one object's lighting rows) by the mean over
// itself and its neighbours.
void smooth_ao(const AoNeighbours& near, float* rows) {
  const std::size_t n = near.first.size() - 1;
  std::vector<float> ao(4 * n);
  for (std::size_t i = 0; i < n; ++i) {
    glm::vec4 sum(rows[kLightingRow * i], rows[kLightingRow * i + 1], rows[kLightingRow * i + 2], rows[kLightingRow * i + 3]);
    for (std::uint32_t r = near.first[i]; r < near.first[i + 1]; ++r) {
      const float* o = rows + kLightingRow * near.index[r];
      sum += glm::vec4(o[0], o[1], o[2], o[3]);
    }
    const float count = static_cast<float>(near.first[i + 1] - near.first[i] + 1);
    const glm::vec3 bent(sum);
    const glm::vec3 own(rows[kLightingRow * i], rows[kLightingRow * i + 1], rows[kLightingRow * i + 2]);
    const glm::vec3 mean_bent = glm::length(bent) > 0.0f ? glm::normalize(bent) : own;
    ao[4 * i] = mean_bent.x, ao[4 * i + 1] = mean_bent.y, ao[4 * i + 2] = mean_bent.z, ao[4 * i + 3] = sum.w / count;
  }
  for (std::size_t i = 0; i < n; ++i) std::copy(&ao[4 * i], &ao[4 * i] + 4, rows + kLightingRow * i);
}

// The floor's lattice nodes as receivers: the floor point each node's pixel ray meets, analytic
// from the camera (so the lattice does not wait for the G-buffer), active where that point lies
// in front within the far plane and on the drawn floor (its square grown by a floor disc's
// overhang). The normal is up. Nodes whose floor point an object hides are computed too (the
// G-buffer says which those are only after the splat passes; floor_nodes_shown).
csm::SplatLighting::Receivers floor_lattice_receivers(const FloorSpec& floor, const cluster::ClusterLayout& layout,
                                                      const ViewFrame& frame, const std::vector<std::uint32_t>& pixel_pattern_of) {
  const std::uint32_t width = layout.config.width, height = layout.config.height;
  const std::size_t columns = lattice_size(static_cast<int>(width)), nodes = columns * lattice_size(static_cast<int>(height));
  csm::SplatLighting::Receivers receivers;
  receivers.positions.assign(nodes, Vec4{});
  receivers.normals.assign(nodes, Vec4{0, 1, 0, 0});
  receivers.pattern_of.assign(nodes, 0);
  receivers.active.assign(nodes, 0);
  const float height_above = frame.eye.y - floor.y;
  if (!(height_above > 0.0f)) return receivers;  // the floor faces away: no floor pixel is drawn
  const float reach = 0.5f * floor.size + 0.75f * floor.size / static_cast<float>(floor.splats_per_side);
  for (std::uint32_t y = 0; y < height; y += kFloorStep)
    for (std::uint32_t x = 0; x < width; x += kFloorStep) {
      const Vec3 ray = frame.direction_to_world(cluster::pixel_view_position(layout, x, y, 1.0f));
      if (!(ray.y < 0.0f)) continue;
      const float distance = height_above / -ray.y;  // view depth: the ray has view z −1 per unit
      if (distance < layout.config.near_plane || distance > layout.config.far_plane) continue;
      const Vec3 point = pixel_world(layout, frame, x, y, distance);
      if (std::abs(point.x) > reach || std::abs(point.z) > reach) continue;
      const std::size_t node = (y / kFloorStep) * columns + x / kFloorStep;
      receivers.positions[node] = {point.x, floor.y, point.z, 0.0f};
      receivers.pattern_of[node] = pixel_pattern_of[std::size_t{y} * width + x];
      receivers.active[node] = 1;
    }
  return receivers;
}

// Per lattice node: its floor point is what its pixel shows (the G-buffer's depth puts the pixel on
// the floor's plane, to the tolerance the shading uses), among the `active` nodes.
std::vector<std::uint8_t> floor_nodes_shown(const FloorSpec& floor, const cluster::ClusterLayout& layout, const ViewFrame& frame,
                                            const std::vector<float>& view_z, const std::vector<std::uint8_t>& active) {
  const std::uint32_t width = layout.config.width;
  const std::size_t columns = lattice_size(static_cast<int>(width));
  const float tolerance = floor_tolerance(floor);
  std::vector<std::uint8_t> shown(active.size(), 0);
  for (std::size_t node = 0; node < active.size(); ++node) {
    if (!active[node]) continue;
    const auto x = static_cast<std::uint32_t>(node % columns * kFloorStep), y = static_cast<std::uint32_t>(node / columns * kFloorStep);
    const auto d = cluster::pixel_distance(layout, view_z[std::size_t{y} * width + x], cluster::DepthFormat::ViewZ);
    if (!d) continue;
    const Vec3 world = pixel_world(layout, frame, x, y, *d);
    shown[node] = std::abs(world.y - floor.y) <= tolerance;
  }
  return shown;
}

// The per-splat lighting's settings for the frame.
csm::SplatLighting::Settings lighting_settings_of(const Scene& scene, bool ambient_occlusion, const FrameSettings& settings) {
  const Quality& q = scene.quality;
  csm::SplatLighting::Settings lighting;
  lighting.ao = ambient_occlusion;
  lighting.shadows = settings.shadows == ShadowMode::Splat;
  lighting.filter = settings.filter;
  lighting.ao_samples = q.ao_samples;
  lighting.shadow_samples = q.shadow_samples;
  static_assert(kMaxSceneAoBias == csm::kMaxBiasTexels, "a scene's ao_bias has the CSM queries' range");
  lighting.bias = q.ao_bias;
  lighting.lift = q.shadow_lift;
  lighting.ground = scene.floor.enabled;
  for (const Light& light : scene.key_lights) lighting.key_lights.push_back({light.position, light.size});
  return lighting;
}

}  // namespace

const char* to_string(DebugView view) { return kDebugNames[static_cast<int>(view)]; }

DebugView parse_debug_view(const std::string& text) {
  for (int i = 0; i < 8; ++i)
    if (text == kDebugNames[i]) return static_cast<DebugView>(i);
  throw Error("unknown view '" + text + "' (one of: final, albedo, normals, ao, clusters, shadows, depth, footprints)");
}

std::vector<glm::vec3> sky_sh(const Sky& sky) {
  // Project L(d) = mix(ground | horizon | zenith by d.y) on the 9 real SH basis functions, then the
  // irradiance convolution is applied in the shader (Ramamoorthi & Hanrahan's quadratic form).
  std::vector<glm::vec3> sh(9, glm::vec3(0.0f));
  const int steps_theta = 64, steps_phi = 128;
  const float pi = std::numbers::pi_v<float>;
  for (int i = 0; i < steps_theta; ++i) {
    const float theta = pi * (static_cast<float>(i) + 0.5f) / steps_theta;
    const float weight = std::sin(theta) * (pi / steps_theta) * (2 * pi / steps_phi);
    for (int k = 0; k < steps_phi; ++k) {
      const float phi = 2 * pi * (static_cast<float>(k) + 0.5f) / steps_phi;
      const glm::vec3 d{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
      const glm::vec3 radiance = d.y >= 0 ? glm::mix(sky.horizon, sky.zenith, d.y) : glm::mix(sky.horizon, sky.ground, std::min(1.0f, -4 * d.y));
      // Basis order: Y00, Y1-1 (y), Y10 (z), Y11 (x), Y2-2 (xy), Y2-1 (yz), Y20, Y21 (xz), Y22 (x²−y²).
      // The shader's formula uses L1m in the (y, z, x) order and L2m likewise; with +y up here the
      // indices follow the world axes as written in the shader.
      const float basis[9] = {0.282095f,
                              0.488603f * d.y,
                              0.488603f * d.z,
                              0.488603f * d.x,
                              1.092548f * d.x * d.y,
                              1.092548f * d.y * d.z,
                              0.315392f * (3 * d.z * d.z - 1),
                              1.092548f * d.x * d.z,
                              0.546274f * (d.x * d.x - d.y * d.y)};
      for (int b = 0; b < 9; ++b) sh[static_cast<std::size_t>(b)] += radiance * (basis[b] * weight);
    }
  }
  return sh;
}

struct Presenter::Impl {
  // The passes (present/passes.hpp), made when the presenter is.
  std::unique_ptr<VisibilityPass> visibility_pass;
  std::unique_ptr<AccumulationPass> accumulation_pass;
  std::unique_ptr<PointPass> point_pass;
  std::unique_ptr<MeshMaskPass> mesh_pass;
  std::unique_ptr<ResolvePass> resolve_pass;
  ShadingPass shading_pass;
  gl::Buffer static_vbo, dynamic_vbo;
  gl::Texture static_rows_texture, lighting_rows_texture;  // over static_vbo and dynamic_vbo
  gl::VertexArray empty_vao;
  // Per object, each splat's shading normal at its centre (its Phong field's, model space): the
  // per-splat AO and shadow receivers face it, so their hemispheres follow the smooth surface the
  // shading shows rather than a low-poly mesh's facets.
  std::vector<std::vector<glm::vec3>> receiver_normals;
  // Per object, the splats whose AO each splat's is averaged with (ao_smoothing_neighbours).
  std::vector<AoNeighbours> ao_neighbours;
  // Everything sized by the frame, made again by resize().
  struct Targets {
    Targets(int width, int height) : gbuffer(width, height), shading(width, height), pixel(width, height), mesh(width, height) {}
    GBuffer gbuffer;
    ShadingTargets shading;
    PixelInputs pixel;
    MeshMaskTarget mesh;
  };
  std::unique_ptr<Targets> targets;
  // The point lights' rows and the light lists' offsets, counts and indices, each read by the
  // shading through a buffer texture over it.
  gl::Buffer light_buffers[4];
  gl::Texture light_textures[4];
  GLint max_buffer_texels = 0;
  std::vector<gl::Buffer> mesh_vbos;
  std::vector<gl::VertexArray> mesh_vaos;
  std::vector<GLsizei> mesh_vertices;
  GpuTimers timers;
  // The light-list stages (present/light_lists.hpp), sized by the frame.
  std::unique_ptr<ClusteredLightLists> clustered_lists;
  std::unique_ptr<TiledLightLists> tiled_lists;
  std::unique_ptr<BruteForceLights> brute_force_lights;
  std::vector<glm::mat4> last_placements;
  bool have_lighting = false;
  bool hdr_written = false;  // the last frame wrote the HDR target
  std::vector<float> upload_rows;  // lighting rows of every instance (LOD entries included) to upload
  // The per-splat lighting through the CSMs (csm/splat_lighting.hpp) and the settings text its
  // last update was made with (render() updates again when it differs).
  std::unique_ptr<csm::SplatLighting> lighting;
  std::unique_ptr<csm::SplatLighting> floor_lighting;  // of the floor's pixels (Presenter::floor_per_pixel)
  std::unique_ptr<csm::SplatLighting> pixel_lighting;  // of every covered pixel in the quality modes
  glm::mat4 floor_view{0.0f}, floor_proj{0.0f};         // the camera of its last update
  std::string lighting_signature;
  std::vector<Vec4> ao_patterns;
  std::vector<std::uint32_t> pixel_pattern_of;
  std::vector<glm::vec3> sh;
  std::uint32_t heat_max = 1;
  // Per scene object: its LOD sequence's instances (after all original splats) and the bounding
  // sphere of its splats (model space) for the coarse, per-object prefix selection.
  struct LodRange {
    std::size_t first = 0, count = 0;
    glm::vec3 center{0.0f};
    float radius = 0;
  };
  std::vector<LodRange> lod_ranges;
  std::vector<glm::vec3> lod_centers;  // model-space centre of every LOD entry, in instance order
};

Presenter::Presenter(Scene scene, Runtime& runtime, int width, int height, const std::string& cache_dir,
                     const AssetProgress& progress)
    : impl_(std::make_unique<Impl>()), scene_(std::move(scene)), runtime_(runtime) {
  check_scene_settings(scene_);  // before any object's assets are built
  Impl& g = *impl_;
  // Assets and the splat arrays: objects in scene order, then the floor, then every object's LOD
  // sequence (originals and tree nodes sorted by e_max). Per instance: centre, normal, major and
  // minor semi-axes, linear albedo, LOD interval [e_min, e_max), two clip lines (none: offset FLT_MAX).
  constexpr std::size_t kRow = SPLAT_ROW_FLOATS;
  std::vector<float> statics;
  const auto clip_of = [](float x, float y, float offset) {
    return std::isfinite(offset) ? glm::vec3(x, y, offset) : glm::vec3(0.0f, 0.0f, FLT_MAX);
  };
  const auto first_clip = [&](const splats::SplatRecord& s) { return clip_of(s.clip_x, s.clip_y, s.clip_offset); };
  const auto second_clip = [&](const std::vector<splats::ClipLine>& lines, std::size_t j) {
    return j < lines.size() ? clip_of(lines[j].x, lines[j].y, lines[j].offset) : glm::vec3(0.0f, 0.0f, FLT_MAX);
  };
  // n: the normal at the centre; du, dv: the Phong splat's normal field (zero: flat).
  const auto push_splat = [&](glm::vec3 c, glm::vec3 n, glm::vec3 u, glm::vec3 v, glm::vec3 albedo,
                              glm::vec2 lod = {0.0f, FLT_MAX}, glm::vec3 clip = {0.0f, 0.0f, FLT_MAX},
                              glm::vec3 clip2 = {0.0f, 0.0f, FLT_MAX}, glm::vec3 du = {}, glm::vec3 dv = {}) {
    layout::SplatRow row{};
    std::copy(&c.x, &c.x + 3, row.center);
    std::copy(&n.x, &n.x + 3, row.normal);
    std::copy(&du.x, &du.x + 3, row.normal_du);
    std::copy(&dv.x, &dv.x + 3, row.normal_dv);
    std::copy(&u.x, &u.x + 3, row.major);
    std::copy(&v.x, &v.x + 3, row.minor);
    std::copy(&albedo.x, &albedo.x + 3, row.albedo);
    row.lod[0] = lod.x, row.lod[1] = lod.y;
    std::copy(&clip.x, &clip.x + 3, row.clip);
    std::copy(&clip2.x, &clip2.x + 3, row.clip2);
    statics.resize(statics.size() + kRow);
    std::memcpy(&statics[statics.size() - kRow], &row, sizeof row);
  };
  const auto g3 = [](Vec3 a) { return glm::vec3(a.x, a.y, a.z); };
  // Per-splat colours are sRGB bytes; the shading works on linear albedo.
  const auto linear = [](Rgba8 c) {
    return glm::pow(glm::vec3(c.r, c.g, c.b) / 255.0f, glm::vec3(2.2f));
  };
  std::vector<std::vector<float>> albedo_rows(scene_.objects.size());  // per object, 3 floats per splat
  g.receiver_normals.assign(scene_.objects.size(), {});
  for (std::size_t i = 0; i < scene_.objects.size(); ++i) {
    const ObjectSpec& object = scene_.objects[i];
    try {
      assets_.push_back(load_object_assets(object, scene_, cache_dir, runtime_, progress));
    } catch (const Error& e) {
      throw Error(fmt::format("{}: {}", object_where(scene_, i), e.what()));  // which object's file or setting
    }
    const ObjectAssets& assets = assets_.back();
    const std::vector<splats::SplatRecord>& splats = assets.drawn;  // fitted to the mesh surface (quality.surface_clip)
    const bool two_sided = object.two_sided.value_or(object.mesh.splat_path.empty() && !assets.mesh.closed());
    objects_.push_back({statics.size() / kRow, (two_sided ? 2 : 1) * splats.size(), static_cast<int>(i), two_sided});
    for (const float side : {1.0f, -1.0f}) {
      if (side < 0 && !two_sided) break;
      // The back side mirrors the normal field, so the splat's plane faces the other way (culled
      // where the front is drawn) and its shading and lighting are the other side's.
      for (std::size_t j = 0; j < splats.size(); ++j) {
        const splats::SplatRecord& s = splats[j];
        const glm::vec3 albedo = object.splat_colors ? linear(s.color) : object.color;
        albedo_rows[i].insert(albedo_rows[i].end(), {albedo.x, albedo.y, albedo.z});
        const splats::NormalField& field = assets.normal_fields[j];  // Phong splats (ObjectAssets)
        push_splat(g3(s.center), side * g3(field.centre), g3(s.major), g3(s.minor), albedo, {0.0f, FLT_MAX}, first_clip(s),
                   second_clip(assets.second_clips, j), side * g3(field.du), side * g3(field.dv));
        if (side > 0) g.receiver_normals[i].push_back(glm::normalize(g3(field.centre)));
      }
    }
  }
  for (std::size_t i = 0; i < scene_.objects.size(); ++i) {
    AoNeighbours near = ao_smoothing_neighbours(assets_[i].drawn, g.receiver_normals[i]);
    if (objects_[i].two_sided) {  // the back side's splats average with the back side's
      const auto front = static_cast<std::uint32_t>(assets_[i].drawn.size()), entries = static_cast<std::uint32_t>(near.index.size());
      for (std::uint32_t s = 0; s < front; ++s) near.first.push_back(entries + near.first[s + 1]);
      for (std::uint32_t e = 0; e < entries; ++e) near.index.push_back(front + near.index[e]);
    }
    g.ao_neighbours.push_back(std::move(near));
  }
  Quality& q = scene_.quality;
  if (q.depth_offset_auto) q.depth_offset = auto_scene_length(q.depth_offset, scene_, assets_);
  if (q.shadow_lift_auto) q.shadow_lift = auto_scene_length(q.shadow_lift, scene_, assets_);
  if (scene_.floor.enabled) {
    const FloorSpec& f = scene_.floor;
    const float spacing = f.size / static_cast<float>(f.splats_per_side);
    const float radius = 0.75f * spacing;  // overlapping discs cover the square without holes
    objects_.push_back({statics.size() / kRow, std::size_t{f.splats_per_side} * f.splats_per_side, -1});
    // The discs along the square's sides are cut by a clip line at the side (two at a corner), so
    // its outline is straight, not scalloped (at least 2 discs per side: one line per axis).
    const std::uint32_t last = f.splats_per_side - 1;
    const auto side = [&](std::uint32_t j, glm::vec2 outward) {
      return j == 0 ? glm::vec3(-outward, 0.5f * spacing) : j == last ? glm::vec3(outward, 0.5f * spacing) : glm::vec3(0.0f, 0.0f, FLT_MAX);
    };
    for (std::uint32_t i = 0; i < f.splats_per_side; ++i)
      for (std::uint32_t k = 0; k < f.splats_per_side; ++k)
        push_splat({-0.5f * f.size + (static_cast<float>(i) + 0.5f) * spacing, f.y,
                    -0.5f * f.size + (static_cast<float>(k) + 0.5f) * spacing},
                   {0, 1, 0}, {radius, 0, 0}, {0, 0, radius}, f.color, {0.0f, FLT_MAX}, side(i, {1.0f, 0.0f}), side(k, {0.0f, 1.0f}));
  }
  const std::size_t splat_count = statics.size() / kRow;
  splat_ao_.assign(splat_count, glm::vec4(0, 1, 0, 1));
  for (std::size_t i = 0; i < scene_.objects.size(); ++i) {
    const SplatTree& tree = assets_[i].tree;
    Impl::LodRange range{statics.size() / kRow, tree.size(), {}, 0.0f};
    const auto& splats = assets_[i].drawn;
    glm::vec3 lo(FLT_MAX), hi(-FLT_MAX);
    for (const auto& s : splats) lo = glm::min(lo, g3(s.center)), hi = glm::max(hi, g3(s.center));
    if (!splats.empty()) range.center = 0.5f * (lo + hi);
    for (const auto& s : splats)
      range.radius = std::max(range.radius, glm::length(g3(s.center) - range.center) + glm::length(g3(s.major)));
    // Two-sided: the sequence, then its mirror image (the tree is over one side's splats).
    const std::vector<float> albedo = gather_tree_rows(tree, albedo_rows[i].data(), 3);
    for (const float side : {1.0f, -1.0f}) {
      if (side < 0 && !objects_[i].two_sided) break;
      for (std::size_t e = 0; e < tree.size(); ++e) {
        const std::uint32_t source = tree.source[e];
        const splats::SplatRecord& s = source < tree.splat_count ? splats[source] : tree.nodes[source - tree.splat_count];
        const std::size_t node = source - tree.splat_count;
        const splats::NormalField field = source < tree.splat_count ? assets_[i].normal_fields[source] : assets_[i].node_fields[node];
        push_splat(g3(s.center), side * g3(field.centre), g3(s.major), g3(s.minor), {albedo[3 * e], albedo[3 * e + 1], albedo[3 * e + 2]},
                   {tree.error_min[e], tree.error_max[e]}, first_clip(s),
                   source < tree.splat_count ? second_clip(assets_[i].second_clips, source) : glm::vec3(0.0f, 0.0f, FLT_MAX),
                   side * g3(field.du), side * g3(field.dv));
        g.lod_centers.push_back(g3(s.center));
      }
    }
    g.lod_ranges.push_back(range);
  }
  const std::size_t instance_count = statics.size() / kRow;  // originals and LOD entries

  g.visibility_pass = std::make_unique<VisibilityPass>();
  g.accumulation_pass = std::make_unique<AccumulationPass>();
  g.point_pass = std::make_unique<PointPass>();
  g.mesh_pass = std::make_unique<MeshMaskPass>();
  g.resolve_pass = std::make_unique<ResolvePass>();

  g.empty_vao = gl::make_vertex_array();
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &g.max_buffer_texels);
  if (statics.size() / 4 > static_cast<std::size_t>(g.max_buffer_texels))
    throw Error(fmt::format("{}: {} splats exceed this GL's buffer textures ({} texels, {} per splat)", scene_.source,
                            statics.size() / kRow, g.max_buffer_texels, SPLAT_ROW_TEXELS));
  g.static_vbo = gl::make_buffer();
  g.dynamic_vbo = gl::make_buffer();
  glNamedBufferStorage(g.static_vbo.get(), static_cast<GLsizeiptr>(std::max<std::size_t>(statics.size(), 1) * sizeof(float)),
                       statics.empty() ? nullptr : statics.data(), 0);
  glNamedBufferStorage(g.dynamic_vbo.get(), static_cast<GLsizeiptr>(std::max<std::size_t>(instance_count, 1) * kLightingRow * sizeof(float)),
                       nullptr, GL_DYNAMIC_STORAGE_BIT);
  // The splat shaders pull their rows from static_vbo and dynamic_vbo through buffer textures
  // (units UNIT_SPLAT_ROWS and UNIT_SPLAT_LIGHTING); the vertices of splat s are 3s..3s+2, one
  // triangle around its ellipse (points: vertex s).
  g.static_rows_texture = gl::make_buffer_texture(GL_RGBA32F, g.static_vbo.get());
  g.lighting_rows_texture = gl::make_buffer_texture(GL_RGBA32F, g.dynamic_vbo.get());
  for (std::size_t i = 0; i < 4; ++i) {
    g.light_buffers[i] = gl::make_buffer();
    g.light_textures[i] = gl::make_buffer_texture(i == 0 ? GL_RGBA32F : GL_R32UI, g.light_buffers[i].get());
  }

  // Triangle meshes of the objects, for the coverage test.
  for (const ObjectAssets& a : assets_) {
    std::vector<float> triangles;
    for (std::size_t f = 0; f < a.mesh.face_count(); ++f) {
      const std::uint32_t begin = a.mesh.face_offsets[f], end = a.mesh.face_offsets[f + 1];
      for (std::uint32_t c = begin + 1; c + 1 < end; ++c)
        for (const std::uint32_t corner : {begin, c, c + 1}) {
          const Vec3 p = a.mesh.vertices[a.mesh.corners[corner]];
          triangles.insert(triangles.end(), {p.x, p.y, p.z});
        }
    }
    gl::Buffer vbo_owner = gl::make_buffer();
    gl::VertexArray vao_owner = gl::make_vertex_array();
    const GLuint vbo = vbo_owner.get(), vao = vao_owner.get();
    glNamedBufferStorage(vbo, static_cast<GLsizeiptr>(std::max<std::size_t>(triangles.size(), 1) * sizeof(float)),
                         triangles.empty() ? nullptr : triangles.data(), 0);
    glVertexArrayVertexBuffer(vao, 0, vbo, 0, 3 * sizeof(float));
    glEnableVertexArrayAttrib(vao, 0);
    glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 0, 0);
    g.mesh_vbos.push_back(std::move(vbo_owner));
    g.mesh_vaos.push_back(std::move(vao_owner));
    g.mesh_vertices.push_back(static_cast<GLsizei>(triangles.size() / 3));
  }

  g.ao_patterns = csm::make_patterns(csm::PatternSet::HammersleyScrambled, kAoPatterns, scene_.quality.ao_samples, kAoSeed);
  std::vector<const csm::Csm*> csms;
  for (const ObjectAssets& a : assets_) csms.push_back(&a.csm);
  g.lighting = std::make_unique<csm::SplatLighting>(runtime_, csms, g.ao_patterns,
                                                    csm::choose_patterns(splat_count, kAoPatterns, kAoSeed));
  g.sh = sky_sh(scene_.sky);
  ambient_occlusion = scene_.quality.ambient_occlusion;
  pixel_ao = scene_.quality.pixel_ao;
  floor_per_pixel = scene_.quality.floor_pixels;
  resize(width, height);
}

Presenter::~Presenter() = default;

void Presenter::resize(int width, int height) {
  if (width <= 0 || height <= 0 || width > 8192 || height > 8192)
    throw Error(fmt::format("frame size {}x{} is outside 1..8192", width, height));
  if (width == width_ && height == height_) return;
  Impl& g = *impl_;
  g.targets.reset();
  g.targets = std::make_unique<Impl::Targets>(width, height);
  width_ = width;
  height_ = height;
  const cluster::ClusterConfig config = cluster::cluster_config(scene_.camera, static_cast<std::uint32_t>(width),
                                                                static_cast<std::uint32_t>(height), scene_.quality.tile,
                                                                scene_.quality.tile);
  g.clustered_lists = std::make_unique<ClusteredLightLists>(runtime_, config);
  g.tiled_lists = std::make_unique<TiledLightLists>(g.clustered_lists->layout());
  g.brute_force_lights = std::make_unique<BruteForceLights>(g.clustered_lists->layout());
}

std::pair<std::size_t, std::size_t> Presenter::object_splats(std::size_t object) const {
  return {objects_.at(object).first, objects_.at(object).count};
}

const ObjectAssets& Presenter::assets(std::size_t object) const { return assets_.at(object); }

const std::vector<float>& Presenter::splat_lighting() const { return impl_->lighting->rows(); }

glm::vec3 Presenter::splat_world_position(std::size_t splat, float time) const {
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    const ObjectRange& r = objects_[i];
    if (splat < r.first || splat >= r.first + r.count) continue;
    if (r.asset < 0) {
      const FloorSpec& f = scene_.floor;
      const std::size_t local = splat - r.first;
      const float spacing = f.size / static_cast<float>(f.splats_per_side);
      return {-0.5f * f.size + (static_cast<float>(local / f.splats_per_side) + 0.5f) * spacing, f.y,
              -0.5f * f.size + (static_cast<float>(local % f.splats_per_side) + 0.5f) * spacing};
    }
    const auto c = assets_[static_cast<std::size_t>(r.asset)].drawn[r.source(splat - r.first)].center;
    return glm::vec3(scene_.objects[i].placement(time) * glm::vec4(c.x, c.y, c.z, 1.0f));
  }
  throw Error(fmt::format("splat {} out of range", splat));
}

std::string Presenter::lighting_settings(const FrameSettings& settings) const {
  const Quality& q = scene_.quality;
  const bool do_shadows = settings.shadows == ShadowMode::Splat && !scene_.key_lights.empty();
  return fmt::format("{} {} {} {} {} {} {} {} {} {}", ambient_occlusion, do_shadows, static_cast<int>(settings.filter), splat_ao_.size(), q.ao_samples,
                     q.shadow_samples, q.ao_bias, q.shadow_lift, scene_.key_lights.size(), scene_.floor.enabled);
}

void Presenter::update_splat_lighting(const std::vector<glm::mat4>& placements, const FrameSettings& settings,
                                      FrameStats& stats) {
  Impl& g = *impl_;
  const std::size_t n = splat_ao_.size();
  std::vector<Vec4> positions(n), normals(n);
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    const ObjectRange& r = objects_[i];
    const glm::mat4 m = r.asset < 0 ? glm::mat4(1.0f) : placements[i];
    for (std::size_t s = 0; s < r.count; ++s) {
      glm::vec3 c, nrm;
      if (r.asset < 0) {
        c = splat_world_position(r.first + s, 0.0f);
        nrm = {0, 1, 0};
      } else {
        const std::size_t source = r.source(s);
        const auto& rec = assets_[static_cast<std::size_t>(r.asset)].drawn[source];
        c = glm::vec3(m * glm::vec4(rec.center.x, rec.center.y, rec.center.z, 1.0f));
        nrm = glm::normalize(glm::mat3(m) * g.receiver_normals[static_cast<std::size_t>(r.asset)][source]);
        if (source != s) nrm = -nrm;  // the back side
      }
      positions[r.first + s] = vec4(c);
      normals[r.first + s] = vec4(nrm);
    }
  }
  csm::SplatLighting::Receivers receivers{std::move(positions), std::move(normals), {}, {}, {}};
  for (std::size_t i = 0; i < scene_.objects.size(); ++i)
    receivers.objects.push_back({objects_[i].first, objects_[i].count, scene_.objects[i].occluder});
  std::vector<csm::Transform> transforms;
  for (const glm::mat4& placement : placements) transforms.push_back(to_transform(placement));
  const csm::SplatLighting::Settings lighting = lighting_settings_of(scene_, ambient_occlusion, settings);
  const std::string signature = lighting_settings(settings);
  // Set again when the update completes: one that fails half way forces a full update next time.
  g.lighting_signature.clear();
  const csm::SplatLighting::Update update = g.lighting->update(receivers, transforms, lighting, incremental_lighting);
  for (const auto& [name, ms] : update.stages) stats.stages.push_back({name, ms});
  stats.lighting_receivers = update.receivers;
  std::vector<float> dynamic = g.lighting->rows();
  g.lighting_signature = signature;
  const Stopwatch smoothing;
  for (std::size_t i = 0; i < scene_.objects.size(); ++i) smooth_ao(g.ao_neighbours[i], dynamic.data() + objects_[i].first * kLightingRow);
  stats.stages.push_back({"host: AO smoothing", smoothing.elapsed_ms()});
  for (std::size_t s = 0; s < n; ++s)
    splat_ao_[s] = {dynamic[kLightingRow * s], dynamic[kLightingRow * s + 1], dynamic[kLightingRow * s + 2], dynamic[kLightingRow * s + 3]};
  // LOD sequences: an original splat's entry takes its row, a tree node the mean of the rows of the
  // splats under it.
  for (std::size_t i = 0; i < g.lod_ranges.size(); ++i)
    for (std::size_t side = 0; side < (objects_[i].two_sided ? 2u : 1u); ++side) {
      const std::size_t first = objects_[i].first + side * assets_[i].drawn.size();
      const std::vector<float> rows = gather_tree_rows(assets_[i].tree, dynamic.data() + first * kLightingRow, kLightingRow);
      dynamic.insert(dynamic.end(), rows.begin(), rows.end());
    }
  g.upload_rows = std::move(dynamic);  // render() uploads them: this may run beside the GL thread
  stats.ao_updated = true;
}

std::vector<SplatDraw> Presenter::splat_draws(const std::vector<glm::mat4>& placements, glm::vec3 eye,
                                              std::uint32_t& drawn) const {
  const Impl& g = *impl_;
  const Quality& q = scene_.quality;
  const Camera& cam = scene_.camera;
  // LOD (off at lod_error 0): an entry's error budget is its eye distance in model units times the
  // angle of lod_error pixels. Per object the CPU sends the prefix of the sequence whose e_max
  // exceeds the budget at the nearest point of the object's bounding sphere; the vertex shader
  // keeps the entries whose interval holds their own budget. The same test counts them here.
  const bool lod = q.lod_error > 0;
  const float lod_angle = q.lod_error * 2.0f * std::tan(0.5f * cam.fov_y) / static_cast<float>(height_);
  std::vector<std::size_t> lod_prefix(g.lod_ranges.size(), 0);
  if (lod) {
    std::size_t selected = objects_.size() > scene_.objects.size() ? objects_.back().count : 0;  // the floor
    for (std::size_t i = 0; i < g.lod_ranges.size(); ++i) {
      const Impl::LodRange& range = g.lod_ranges[i];
      const SplatTree& tree = assets_[i].tree;
      const float scale = scene_.objects[i].scale;
      const glm::vec3 center(placements[i] * glm::vec4(range.center, 1.0f));
      const float nearest = std::max(0.0f, glm::length(eye - center) / scale - range.radius);
      lod_prefix[i] = tree.prefix(nearest * lod_angle);
      for (std::size_t e = 0; e < lod_prefix[i]; ++e) {
        const glm::vec3 c(placements[i] * glm::vec4(g.lod_centers[range.first - g.lod_ranges[0].first + e], 1.0f));
        const float budget = glm::length(eye - c) * (lod_angle / scale);
        selected += budget >= tree.error_min[e] && budget < tree.error_max[e] ? (objects_[i].two_sided ? 2 : 1) : 0;
      }
    }
    drawn = static_cast<std::uint32_t>(selected);
  }

  std::vector<SplatDraw> draws;
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    const ObjectRange& r = objects_[i];
    if (r.count == 0) continue;
    SplatDraw d{r.asset < 0 ? glm::mat4(1.0f) : placements[i], r.first, r.count, 0.0f};
    if (i < scene_.objects.size()) d.object = static_cast<std::uint32_t>(i);
    if (r.two_sided) d.count = r.count / 2, d.mirror = r.count / 2;  // the mirrored splats follow the front's
    if (lod && r.asset >= 0) {
      d.first = g.lod_ranges[i].first;
      d.count = lod_prefix[i];
      d.lod = lod_angle / scene_.objects[i].scale;
      if (r.two_sided) d.mirror = assets_[i].tree.size();  // so does the mirrored sequence
    }
    if (d.count > 0) draws.push_back(d);
  }
  return draws;
}

// One render()'s state, passed from step to step.
struct Presenter::Frame {
  FrameSettings settings;
  FrameStats stats;
  std::vector<glm::mat4> placements;
  // The per-splat lighting of moved occluders, when it runs this frame (start_lighting).
  std::future<FrameStats> lighting;
  glm::vec3 eye{};
  glm::mat4 view{1}, proj{1};
  ViewFrame view_frame;
  std::vector<float> view_z;  // read back from the G-buffer
  // The scene's lights in view space, and as the shading's rows (layout::kLightRowFloats each).
  std::vector<cluster::PointLight> lights;
  std::vector<float> light_rows;
  LightListBuilder* builder = nullptr;
  FrameLightLists lists;
  // Per pixel: key-light visibility (4 floats) and (bent normal, AO); empty where the shading takes
  // the splats' values.
  std::vector<float> pixel_shadow;
  std::vector<Vec4> pixel_ao;
  // light_pixels' inputs: the G-buffer's normals and the objects' CSMs.
  std::vector<float> normals;
  std::vector<const csm::Csm*> csms;
  // The floor's lattice this frame: which of AO and shadows it holds; from light_floor_lattice (on
  // the worker when it runs there) its nodes' rows, the active nodes, stages and counts; then its
  // two textures (floor_lattice_textures) over the nodes the G-buffer shows as floor.
  bool floor_ao = false, floor_shadows = false, floor_on_worker = false;
  // The quality modes: key-light shadows / AO of every covered pixel (light_pixels).
  bool shadow_pixels = false, ao_pixels = false;
  std::vector<float> floor_rows;
  std::vector<std::uint8_t> floor_active;
  FrameStats floor_stats;
  std::vector<float> floor_ao_nodes, floor_shadow_nodes;
  // The worker thread of the frame's CL lighting (start_lighting). Last, so that it is joined
  // before anything it uses goes.
  std::future<void> worker;
};

FrameStats Presenter::render(float time) {
  Frame f;
  f.settings = FrameSettings::parse(scene_.quality);
  impl_->timers.wall = wall_clock_passes;
  Stopwatch frame_clock;
  f.stats.splats = static_cast<std::uint32_t>(splat_ao_.size());
  for (const ObjectSpec& o : scene_.objects) f.placements.push_back(o.placement(time));
  const Camera& cam = scene_.camera;
  f.eye = {cam.eye.x, cam.eye.y, cam.eye.z};
  f.view = glm::lookAt(f.eye, {cam.target.x, cam.target.y, cam.target.z}, {cam.up.x, cam.up.y, cam.up.z});
  f.proj = reversed_depth_projection(cam, static_cast<float>(width_) / static_cast<float>(height_));
  f.view_frame = view_frame(cam);
  start_lighting(f);
  if (f.settings.mode == RenderMode::Points) finish_lighting(f);
  draw_splats(f);

  // Readback of the view-space depth for the cluster stage.
  Stopwatch clock;
  f.view_z = read_view_z();
  f.stats.stages.push_back({"readback: depth", clock.elapsed_ms()});
  build_light_lists(f);
  light_pixels(f);
  upload_frame_inputs(f);
  shade(f);
  impl_->timers.collect(f.stats.stages);
  if (const GLenum error = glGetError(); error != GL_NO_ERROR)
    throw Error(fmt::format("OpenGL error 0x{:x} while rendering a frame", error));
  f.stats.frame_ms = frame_clock.elapsed_ms();
  return std::move(f.stats);
}

std::vector<std::string> Presenter::mesh_warnings() const {
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < scene_.objects.size(); ++i) {
    if (scene_.objects[i].mesh.splat_path.empty() && assets_[i].mesh.problems.any())
      lines.push_back(fmt::format("{}: {}: {}", object_where(scene_, i), assets_[i].mesh.source, assets_[i].mesh.problems.summary()));
    if (!assets_[i].fit_warning.empty()) lines.push_back(fmt::format("{}: {}", object_where(scene_, i), assets_[i].fit_warning));
    if (!assets_[i].placement_warning.empty())
      lines.push_back(fmt::format("{}: {}", object_where(scene_, i), assets_[i].placement_warning));
    if (!assets_[i].thin_part_warning.empty())
      lines.push_back(fmt::format("{}: {}", object_where(scene_, i), assets_[i].thin_part_warning));
  }
  return lines;
}

float auto_scene_length(float length, const Scene& scene, const std::vector<ObjectAssets>& assets) {
  float smallest = INFINITY;
  for (std::size_t i = 0; i < scene.objects.size() && i < assets.size(); ++i)
    smallest = std::min(smallest, scene.objects[i].scale * assets[i].mesh.bounds().diagonal());
  if (!std::isfinite(smallest)) return length;
  if (kAutoLengthShare * smallest < length) return kAutoLengthShare * smallest;
  return std::max(length, kAutoLengthShareLarge * smallest);
}

// The frame's CL lighting: the per-splat lighting of moved occluders (update_splat_lighting), then
// the floor's lattice (light_floor_lattice). Both run on one worker thread beside the splat passes,
// which do not read them: llvmpipe bins the splats on one thread and the lighting's host code
// leaves the CL device idle in between, so each fills the other's idle core. finish_lighting waits
// for the per-splat rows and uploads them before the first pass that reads them; light_pixels
// waits for the lattice. Only the worker uses the lighting's CL objects meanwhile, only this
// thread GL. A first update runs on this thread: it builds the CL programs while llvmpipe compiles
// its shaders, and both would then use LLVM at once; so do the points mode's (its one pass reads
// the rows) and every update while the passes are timed by wall clock.
void Presenter::start_lighting(Frame& f) {
  Impl& g = *impl_;
  // Also when a lighting setting changed (the viewer's AO and shadow toggles), moving or not.
  const bool relight =
      !g.have_lighting || f.placements != g.last_placements || g.lighting_signature != lighting_settings(f.settings);
  f.shadow_pixels = f.settings.shadows == ShadowMode::Pixel && !scene_.key_lights.empty();
  f.ao_pixels = pixel_ao && ambient_occlusion;
  f.floor_shadows = floor_per_pixel && scene_.floor.enabled && f.settings.shadows == ShadowMode::Splat && !scene_.key_lights.empty();
  // The pixel-AO mode too keeps the floor on its lattice (16 directions per node, filtered): per pixel
  // its 16 directions were noise (mean |AO - ray-cast| 0.031 against 0.017, a helper's audit).
  f.floor_ao = floor_per_pixel && scene_.floor.enabled && ambient_occlusion;
  for (const ObjectAssets& a : assets_) f.csms.push_back(&a.csm);
  // The pattern of a pixel is fixed per pixel index, so the noise does not crawl between frames.
  const std::size_t pixels = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  if (g.pixel_pattern_of.size() != pixels) g.pixel_pattern_of = csm::choose_patterns(pixels, kAoPatterns, kAoSeed);

  const bool may_overlap = overlap_lighting && !wall_clock_passes;
  const bool splats_on_worker = relight && may_overlap && g.have_lighting && f.settings.mode != RenderMode::Points;
  f.floor_on_worker = (f.floor_ao || f.floor_shadows) && may_overlap && g.floor_lighting && (!relight || splats_on_worker);
  if (relight && !splats_on_worker) {
    f.lighting = std::async(std::launch::deferred, [this, &f] {
      FrameStats stats;
      update_splat_lighting(f.placements, f.settings, stats);
      return stats;
    });
  }
  if (!splats_on_worker && !f.floor_on_worker) return;
  std::shared_ptr<std::promise<FrameStats>> splat_rows;
  if (splats_on_worker) {
    splat_rows = std::make_shared<std::promise<FrameStats>>();
    f.lighting = splat_rows->get_future();
  }
  f.worker = std::async(std::launch::async, [this, &f, splat_rows] {
    if (splat_rows) {
      try {
        FrameStats stats;
        update_splat_lighting(f.placements, f.settings, stats);
        splat_rows->set_value(std::move(stats));
      } catch (...) {
        splat_rows->set_exception(std::current_exception());  // finish_lighting rethrows it
        return;
      }
    }
    if (f.floor_on_worker) light_floor_lattice(f);
  });
}

void Presenter::finish_lighting(Frame& f) {
  if (!f.lighting.valid()) return;
  Impl& g = *impl_;
  const FrameStats worker = f.lighting.get();
  f.stats.stages.insert(f.stats.stages.end(), worker.stages.begin(), worker.stages.end());
  f.stats.ao_updated = worker.ao_updated;
  f.stats.lighting_receivers = worker.lighting_receivers;
  Stopwatch clock;
  if (!g.upload_rows.empty())
    glNamedBufferSubData(g.dynamic_vbo.get(), 0, static_cast<GLsizeiptr>(g.upload_rows.size() * sizeof(float)), g.upload_rows.data());
  f.stats.stages.push_back({"upload: splat AO/shadows", clock.elapsed_ms()});
  g.last_placements = f.placements;
  g.have_lighting = true;
}

// The splats into the G-buffer: points, or the visibility and accumulation passes.
void Presenter::draw_splats(Frame& f) {
  Impl& g = *impl_;
  const Quality& q = scene_.quality;
  const bool footprints = debug_view == DebugView::Footprints;
  glViewport(0, 0, width_, height_);
  glBindVertexArray(g.empty_vao.get());
  glBindTextureUnit(UNIT_SPLAT_ROWS, g.static_rows_texture.get());
  glBindTextureUnit(UNIT_SPLAT_LIGHTING, g.lighting_rows_texture.get());
  SplatFrame splat_frame;
  splat_frame.view = f.view;
  splat_frame.proj = f.proj;
  splat_frame.eye = f.eye;
  splat_frame.scale = q.splat_scale;
  // The per-splat ambient term (splat_head.glsl): 2 = the AO itself for the AO view.
  splat_frame.ambient = debug_view == DebugView::AmbientOcclusion ? 2 : ambient_occlusion ? 0 : 1;
  splat_frame.sh = g.sh.data();
  // A back copy must stand a whole blending window (ε) in front of a front side to show: 2ε on top
  // of the visibility pass's ε (splat.vert.glsl). 1ε left 4 of the 13 pixels of the saddle test.
  splat_frame.back_offset = 2 * q.depth_offset;
  const std::vector<SplatDraw> draws = splat_draws(f.placements, f.eye, f.stats.splats);
  glDisable(GL_CULL_FACE);
  // The accumulation targets are the G-buffer; the fourth holds key lights 1-3 only.
  const GBuffer& gbuffer = g.targets->gbuffer;
  use_reversed_depth();
  // The quality modes' per-pixel lighting needs each pixel's object (light_covered_pixels).
  const bool object_ids = f.shadow_pixels || f.ao_pixels;
  gbuffer.bind_and_clear(scene_.key_lights.size() > 1 ? 4 : 3, object_ids && f.settings.mode == RenderMode::Points);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);  // reversed depth (reversed_depth_projection)
  if (f.settings.mode == RenderMode::Points) {
    g.timers.begin("gl: points");
    g.point_pass->run(splat_frame, draws, height_, footprints);
    g.timers.end();
  } else {
    g.timers.begin("gl: splat visibility");
    g.visibility_pass->run(gbuffer, splat_frame, draws, q.depth_offset, object_ids);
    g.timers.end();
    glFlush();  // llvmpipe rasterises the binned pass while this thread waits for the lighting
    finish_lighting(f);
    g.timers.begin("gl: splat accumulation");
    g.accumulation_pass->run(gbuffer, splat_frame, draws, q.gaussian, footprints);
    g.timers.end();
  }
  glDisable(GL_DEPTH_TEST);
}

// The lights in view space and their lists from the shading method's builder.
void Presenter::build_light_lists(Frame& f) {
  Impl& g = *impl_;
  f.lights = cluster::view_lights(scene_.lights, f.view_frame);
  f.light_rows.assign(std::max<std::size_t>(f.lights.size(), 1) * layout::kLightRowFloats, 0.0f);
  for (std::size_t i = 0; i < f.lights.size(); ++i) {
    const Light& l = scene_.lights[i];
    const float row[layout::kLightRowFloats] = {f.lights[i].center.x, f.lights[i].center.y, f.lights[i].center.z,
                                                1.0f / (l.radius * l.radius), l.color.x, l.color.y, l.color.z, 0};
    std::copy(row, row + layout::kLightRowFloats, f.light_rows.begin() + static_cast<std::ptrdiff_t>(layout::kLightRowFloats * i));
  }
  const ShadingMethod shading = f.settings.shading;
  f.builder = shading == ShadingMethod::Brute || f.lights.empty() ? static_cast<LightListBuilder*>(g.brute_force_lights.get())
              : shading == ShadingMethod::Clustered              ? static_cast<LightListBuilder*>(g.clustered_lists.get())
                                                                 : g.tiled_lists.get();
  f.lists = f.builder->build(f.view_z, f.lights, f.stats.stages);
  f.stats.clusters = f.lists.clusters;
  f.stats.light_indices = f.lists.light_indices;
}

// Per-pixel key-light shadows and AO through the same CSM tables: of every covered pixel in the
// quality modes, else on the floor's lattice (floor_per_pixel), so that the floor's shadows and AO
// do not step at its splat spacing; the shading takes the splats' values elsewhere.
void Presenter::light_pixels(Frame& f) {
  Impl& g = *impl_;
  const bool shadow_pixels = f.shadow_pixels, ao_pixels = f.ao_pixels;
  if (shadow_pixels || ao_pixels) {
    Stopwatch c;
    light_covered_pixels(f);
    f.stats.stages.push_back({!ao_pixels ? "cl: pixel shadows" : shadow_pixels ? "cl: pixel AO and shadows" : "cl: pixel AO", c.elapsed_ms()});
  }
  if (!f.floor_ao && !f.floor_shadows) return;
  Stopwatch wait;
  if (f.floor_on_worker) {
    f.worker.get();
    f.stats.stages.push_back({"wait: floor lattice", wait.elapsed_ms()});
  } else {
    light_floor_lattice(f);
  }
  f.stats.stages.insert(f.stats.stages.end(), f.floor_stats.stages.begin(), f.floor_stats.stages.end());
  f.stats.floor_nodes = f.floor_stats.floor_nodes;
  f.stats.floor_receivers = f.floor_stats.floor_receivers;
  Stopwatch textures;
  const std::vector<std::uint8_t> shown = floor_nodes_shown(scene_.floor, g.clustered_lists->layout(), f.view_frame, f.view_z, f.floor_active);
  std::array<bool, kLightingRow - kVisibilityAt> soft{};
  for (std::size_t k = 0; k < scene_.key_lights.size() && k < soft.size(); ++k) soft[k] = scene_.key_lights[k].size > 0;
  floor_lattice_textures(f.floor_rows, shown, lattice_size(width_), soft, f.floor_ao_nodes, f.floor_shadow_nodes);
  f.stats.stages.push_back({"host: floor lattice textures", textures.elapsed_ms()});
}

// The quality modes' AO with bent normal and key-light visibility of every covered pixel, made as
// the splats' rows are (csm::SplatLighting, full update): each pixel is a receiver of the object
// its nearest splat belongs to (the object target of the visibility pass), lifted off that
// object's surface for that object's CSM only; the floor's pixels belong to none. Lifted for every
// CSM by the coarsest texel around (until 2026-12-07: a pixel did not name its object), a ball
// resting on a thin 3 x 3 plate read AO 0.095 off ray casting within 0.6 of the contact, up to 0.684
// (0.051 and 0.230 now); on a plate 8 units wide 0.245, up to 0.949 (0.051 now, with the depth
// bias in texels; docs/presenter.md).
void Presenter::light_covered_pixels(Frame& f) {
  Impl& g = *impl_;
  f.normals = read_normals();
  const std::vector<std::uint32_t> object_of = g.targets->gbuffer.read_object_ids();
  std::vector<CoveredPixel> covered = covered_pixels(f.builder->layout(), f.view_frame, f.view_z);
  // SplatLighting's objects are runs of receivers: the pixels by object, the floor's after them.
  const std::size_t objects = scene_.objects.size();
  const auto object_at = [&](const CoveredPixel& c) { return std::min<std::size_t>(object_of[c.index], objects); };
  // The floor's pixels (of no object) need nothing here when its lattice holds their AO and no
  // shadow is asked per pixel; they keep w = -1 (not computed), and the shading takes the lattice.
  if (f.floor_ao && !f.shadow_pixels)
    covered.erase(std::remove_if(covered.begin(), covered.end(), [&](const CoveredPixel& c) { return object_at(c) == objects; }),
                  covered.end());
  std::vector<std::size_t> count(objects + 1, 0);
  for (const CoveredPixel& c : covered) ++count[object_at(c)];
  csm::SplatLighting::Receivers receivers;
  std::vector<std::size_t> next(objects + 1, 0);
  for (std::size_t i = 0; i < objects; ++i) {
    receivers.objects.push_back({next[i], count[i], scene_.objects[i].occluder});
    next[i + 1] = next[i] + count[i];
  }
  receivers.positions.resize(covered.size());
  receivers.normals.resize(covered.size());
  receivers.pattern_of.resize(covered.size());
  std::vector<std::size_t> pixel_of(covered.size());
  for (const CoveredPixel& c : covered) {
    const std::size_t r = next[object_at(c)]++, p = c.index;
    receivers.positions[r] = {c.world.x, c.world.y, c.world.z, 0};
    receivers.normals[r] = {f.normals[3 * p], f.normals[3 * p + 1], f.normals[3 * p + 2], 0};
    receivers.pattern_of[r] = g.pixel_pattern_of[p];
    pixel_of[r] = p;
  }
  csm::SplatLighting::Settings settings = lighting_settings_of(scene_, true, f.settings);
  settings.ao = f.ao_pixels;
  settings.shadows = f.shadow_pixels;
  if (!g.pixel_lighting) g.pixel_lighting = std::make_unique<csm::SplatLighting>(runtime_, f.csms, g.ao_patterns, std::vector<std::uint32_t>{});
  std::vector<csm::Transform> transforms;
  for (const glm::mat4& placement : f.placements) transforms.push_back(to_transform(placement));
  g.pixel_lighting->update(receivers, transforms, settings, false);
  const std::vector<float>& rows = g.pixel_lighting->rows();
  constexpr std::size_t kRow = csm::SplatLighting::kRowFloats, kAt = csm::SplatLighting::kVisibilityAt;
  const std::size_t pixels = f.view_z.size();
  if (f.ao_pixels) {
    f.pixel_ao.assign(pixels, Vec4{0, 1, 0, -1});
    for (std::size_t r = 0; r < pixel_of.size(); ++r)
      f.pixel_ao[pixel_of[r]] = {rows[kRow * r], rows[kRow * r + 1], rows[kRow * r + 2], rows[kRow * r + 3]};
  }
  if (f.shadow_pixels) {
    f.pixel_shadow.assign(pixels * 4, 1.0f);
    for (std::size_t r = 0; r < pixel_of.size(); ++r)
      std::copy_n(rows.begin() + static_cast<std::ptrdiff_t>(kRow * r + kAt), 4, f.pixel_shadow.begin() + static_cast<std::ptrdiff_t>(4 * pixel_of[r]));
  }
}

// The floor's lattice nodes (floor_lattice_receivers) as receivers of no object: the per-splat
// lighting's queries, culled per occluder instance (csm/query_reach.hpp), the same rows as the AO
// kernel and PCF batches; 1/16 of the floor's pixels (its shadows and AO are soft). With the camera
// and the frame size unchanged since the last frame every node shows the same floor point and
// keeps its visibility through the occluders that did not move (the incremental update, rows equal
// to the full update's bit for bit); only the moved ones are queried. Writes only f.floor_*: it
// may run on the worker thread.
void Presenter::light_floor_lattice(Frame& f) {
  Impl& g = *impl_;
  Stopwatch clock;
  const cluster::ClusterLayout& layout = g.clustered_lists->layout();
  csm::SplatLighting::Receivers receivers = floor_lattice_receivers(scene_.floor, layout, f.view_frame, g.pixel_pattern_of);
  for (std::size_t i = 0; i < scene_.objects.size(); ++i) receivers.objects.push_back({0, 0, scene_.objects[i].occluder});
  csm::SplatLighting::Settings floor_settings = lighting_settings_of(scene_, ambient_occlusion, f.settings);
  floor_settings.ao = f.floor_ao;
  floor_settings.shadows = f.floor_shadows;
  if (!g.floor_lighting)
    g.floor_lighting = std::make_unique<csm::SplatLighting>(runtime_, f.csms, g.ao_patterns, std::vector<std::uint32_t>{});
  std::vector<csm::Transform> transforms;
  for (const glm::mat4& placement : f.placements) transforms.push_back(to_transform(placement));
  // A moved camera moves every node's floor point: the full update, cheaper than re-caching all.
  const bool same_view = g.floor_view == f.view && g.floor_proj == f.proj;
  g.floor_view = f.view;
  g.floor_proj = f.proj;
  const csm::SplatLighting::Update update =
      g.floor_lighting->update(receivers, transforms, floor_settings, incremental_lighting && same_view);
  f.floor_stats.floor_receivers = update.receivers;
  f.floor_stats.floor_nodes = static_cast<std::uint32_t>(std::count(receivers.active.begin(), receivers.active.end(), std::uint8_t{1}));
  f.floor_rows = g.floor_lighting->rows();
  f.floor_active = std::move(receivers.active);
  f.floor_stats.stages.push_back({f.floor_on_worker ? "cl: floor lattice (worker)" : "cl: floor lattice", clock.elapsed_ms()});
}

// The lights, their lists, the per-pixel list index and the per-pixel lighting to the GL buffers.
void Presenter::upload_frame_inputs(Frame& f) {
  Impl& g = *impl_;
  Stopwatch clock;
  const auto upload = [&](GLuint buffer, const void* data, std::size_t bytes) {
    // Bound buffers must not be empty: short contents are padded to 16 bytes.
    std::array<std::uint8_t, 16> padded{};
    if (bytes < padded.size()) {
      if (bytes > 0) std::memcpy(padded.data(), data, bytes);
      data = padded.data();
      bytes = padded.size();
    }
    glNamedBufferData(buffer, static_cast<GLsizeiptr>(bytes), data, GL_STREAM_DRAW);
  };
  const cluster::LightLists& lists = f.lists.lists;
  const std::size_t texels = std::max({f.light_rows.size() / 4, lists.offsets.size(), lists.indices.size()});
  if (texels > static_cast<std::size_t>(g.max_buffer_texels))
    throw Error(fmt::format("lights: {} light rows and {} light-list entries exceed this GL's buffer textures ({} texels)",
                            f.light_rows.size() / layout::kLightRowFloats, lists.indices.size(), g.max_buffer_texels));
  upload(g.light_buffers[0].get(), f.light_rows.data(), f.light_rows.size() * sizeof(float));
  upload(g.light_buffers[1].get(), lists.offsets.data(), lists.offsets.size() * 4);
  upload(g.light_buffers[2].get(), lists.counts.data(), lists.counts.size() * 4);
  upload(g.light_buffers[3].get(), lists.indices.data(), lists.indices.size() * 4);
  const PixelInputs& pixel = g.targets->pixel;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(pixel.light_list.get(), 0, 0, 0, width_, height_, GL_RED_INTEGER, GL_UNSIGNED_INT, f.lists.pixel_list.data());
  if (!f.pixel_ao.empty()) glTextureSubImage2D(pixel.ao.get(), 0, 0, 0, width_, height_, GL_RGBA, GL_FLOAT, f.pixel_ao.data());
  if (!f.pixel_shadow.empty())
    glTextureSubImage2D(pixel.shadow.get(), 0, 0, 0, width_, height_, GL_RGBA, GL_FLOAT, f.pixel_shadow.data());
  if (f.floor_ao)
    glTextureSubImage2D(pixel.floor_ao.get(), 0, 0, 0, pixel.lattice_columns, pixel.lattice_rows, GL_RGBA, GL_FLOAT,
                        f.floor_ao_nodes.data());
  if (f.floor_shadows)
    glTextureSubImage2D(pixel.floor_shadow.get(), 0, 0, 0, pixel.lattice_columns, pixel.lattice_rows, GL_RGBA, GL_FLOAT,
                        f.floor_shadow_nodes.data());
  g.heat_max = 1;
  for (const std::uint32_t c : lists.counts) g.heat_max = std::max(g.heat_max, c);
  f.stats.heat_max = g.heat_max;
  f.stats.stages.push_back({"upload: lights+lists", clock.elapsed_ms()});
}

// The final shading, then the silhouette resolve.
void Presenter::shade(Frame& f) {
  Impl& g = *impl_;
  const Quality& q = scene_.quality;
  g.timers.begin("gl: shading");
  const int keys = static_cast<int>(scene_.key_lights.size());
  ShadeVariant variant;
  variant.debug = debug_view == DebugView::Footprints ? static_cast<int>(DebugView::Albedo) : static_cast<int>(debug_view);
  variant.brute_force = f.builder->brute_force();
  variant.pixel_shadows = !f.pixel_shadow.empty();
  variant.pixel_ao = !f.pixel_ao.empty();
  variant.hdr_output = hdr_output;
  variant.key_count = f.settings.shadows == ShadowMode::Off ? 0 : keys;
  variant.floor_ao = f.floor_ao;
  variant.floor_shadows = f.floor_shadows;
  variant.specular = q.specular > 0;
  const cluster::ClusterLayout& layout = f.builder->layout();
  ShadeFrame shade_frame;
  shade_frame.view = f.view;
  shade_frame.tan_half = {layout.tan_half_x, layout.tan_half_y};
  shade_frame.viewport = {static_cast<float>(width_), static_cast<float>(height_)};
  shade_frame.light_count = static_cast<int>(f.lights.size());
  for (int k = 0; k < variant.key_count; ++k) {
    const Light& l = scene_.key_lights[static_cast<std::size_t>(k)];
    const cluster::Vec3 c = f.view_frame.point_to_view({l.position.x, l.position.y, l.position.z});
    shade_frame.key_center[k] = {c.x, c.y, c.z, 1.0f / (l.radius * l.radius)};
    shade_frame.key_color[k] = l.color;
  }
  shade_frame.sh = g.sh.data();
  shade_frame.heat_max = static_cast<float>(g.heat_max);
  shade_frame.light_rows = g.light_textures[0].get();
  shade_frame.list_offsets = g.light_textures[1].get();
  shade_frame.list_counts = g.light_textures[2].get();
  shade_frame.list_indices = g.light_textures[3].get();
  shade_frame.specular = q.specular;
  shade_frame.shininess = q.shininess;
  const glm::vec3 floor_up = glm::mat3(f.view) * glm::vec3(0, 1, 0);  // the floor's normal in view space
  shade_frame.floor_plane = {floor_up, f.eye.y - scene_.floor.y};
  shade_frame.floor_tolerance = floor_tolerance(scene_.floor);
  glBindVertexArray(g.empty_vao.get());
  ShadingTargets& shading = g.targets->shading;
  g.shading_pass.run(shading.framebuffer(hdr_output), g.targets->gbuffer, g.targets->pixel, variant, shade_frame);
  g.hdr_written = hdr_output;
  g.timers.end();
  // Debug views show the G-buffer's values as they are, unfiltered.
  shading.resolved = q.antialias > 0 && debug_view == DebugView::Final;
  if (shading.resolved) {
    // Only the tiles that may hold an outline are filtered, the rest copied. They are found while
    // llvmpipe rasterises the shading pass (flushed), not before it starts.
    glFlush();
    const std::vector<std::array<std::int32_t, 4>> tiles = resolve_outline_tiles
                                                               ? outline_rectangles(f.view_z, width_, height_, q.antialias)
                                                               : std::vector<std::array<std::int32_t, 4>>{{0, 0, width_, height_}};
    g.timers.begin("gl: silhouette resolve");
    g.resolve_pass->run(shading.resolved_framebuffer(), shading.shaded_framebuffer(), shading.shaded_display(), g.targets->gbuffer,
                        q.antialias, tiles);
    g.timers.end();
  }
}

std::vector<float> Presenter::read_display_rgb() const { return impl_->targets->shading.read_display_rgb(); }
std::vector<float> Presenter::read_hdr_rgb() const {
  if (!impl_->hdr_written) throw Error("the last frame was rendered without HDR output (Presenter::hdr_output)");
  return impl_->targets->shading.read_hdr_rgb();
}
std::vector<std::uint8_t> Presenter::read_coverage() const { return impl_->targets->gbuffer.read_coverage(); }
std::vector<float> Presenter::read_view_z() const { return impl_->targets->gbuffer.read_view_z(); }
std::vector<float> Presenter::read_normals() const { return impl_->targets->gbuffer.read_normals(); }

std::vector<std::uint8_t> Presenter::render_mesh_mask(float time) {
  Impl& g = *impl_;
  const Camera& cam = scene_.camera;
  const glm::mat4 view = glm::lookAt(glm::vec3(cam.eye.x, cam.eye.y, cam.eye.z), {cam.target.x, cam.target.y, cam.target.z},
                                     {cam.up.x, cam.up.y, cam.up.z});
  const glm::mat4 proj = reversed_depth_projection(cam, static_cast<float>(width_) / static_cast<float>(height_));
  use_reversed_depth();
  glViewport(0, 0, width_, height_);
  glBindFramebuffer(GL_FRAMEBUFFER, g.targets->mesh.framebuffer());
  const float zero[4] = {0, 0, 0, 0}, farthest = 0.0f;
  glDepthMask(GL_TRUE);
  glClearBufferfv(GL_COLOR, 0, zero);
  glClearBufferfv(GL_DEPTH, 0, &farthest);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  std::vector<glm::mat4> models;
  std::vector<GLuint> vertex_arrays;
  for (std::size_t i = 0; i < scene_.objects.size(); ++i) {
    models.push_back(scene_.objects[i].placement(time));
    vertex_arrays.push_back(g.mesh_vaos[i].get());
  }
  g.mesh_pass->run(view, proj, models, vertex_arrays, g.mesh_vertices);
  glDisable(GL_DEPTH_TEST);
  return g.targets->mesh.read_mask();
}

std::vector<float> Presenter::read_mesh_view_z() const { return impl_->targets->mesh.read_view_z(); }

unsigned Presenter::display_framebuffer() const { return impl_->targets->shading.display_framebuffer(); }

}  // namespace splatcl::present
