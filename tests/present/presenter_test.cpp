// The presenter, headless (EGL surfaceless on Mesa llvmpipe, PoCL for the CL stages): the default
// scene against a stored reference image, clustered == tiled == brute-force shading on the same
// G-buffer, no holes against the triangle mesh, and ambient occlusion following a moved occluder.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

#include "present/assets.hpp"
#include "present/context.hpp"
#include "present/lod.hpp"
#include "present/presenter.hpp"
#include "present/scene.hpp"
#include "runtime/error.hpp"
#include "runtime/runtime.hpp"
#include "splats/surface_check.hpp"

namespace splatcl::present {
namespace {

class PresenterTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    runtime_ = Runtime::create("");
    context_ = GlContext::offscreen();
  }
  static void TearDownTestSuite() {
    context_.reset();
    runtime_.reset();
  }
  static std::shared_ptr<Runtime> runtime_;
  static std::unique_ptr<GlContext> context_;
};
std::shared_ptr<Runtime> PresenterTest::runtime_;
std::unique_ptr<GlContext> PresenterTest::context_;

// Small and quick: the default scene with its quality, fewer floor splats.
Scene test_scene() {
  Scene scene = default_scene();
  scene.floor.splats_per_side = 48;
  return scene;
}

TEST_F(PresenterTest, ContextIsOpenGl45Core) {
  EXPECT_NE(context_->renderer().find("4.5"), std::string::npos) << context_->renderer();
}

TEST(PresenterScene, DefaultSceneHasManyLightsAndAMovingOccluder) {
  const Scene scene = default_scene();
  EXPECT_GE(scene.lights.size(), 1024u);
  ASSERT_GE(scene.objects.size(), 2u);
  bool moving = false;
  for (const auto& o : scene.objects) moving |= o.occluder && o.placement(0.0f) != o.placement(1.0f);
  EXPECT_TRUE(moving);
  // Deterministic lights.
  EXPECT_EQ(generate_lights(scene.generated, scene.floor)[5].position, default_scene().lights[5].position);
}

TEST(PresenterScene, ErrorsNameTheSourceAndField) {
  const auto message = [](const std::string& text) {
    try {
      parse_scene(text, "bad.json", ".");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("{\"objects\": [{\"mesh\": {\"procedural\": \"cone\"}}]}").find("bad.json: 'procedural'"), std::string::npos);
  EXPECT_NE(message("{\"objects\": [], \"quality\": {\"mode\": \"fast\"}}").find("'mode'"), std::string::npos);
  EXPECT_NE(message("{\"objects\": [], \"lights\": {\"count\": -1}}").find("'count'"), std::string::npos);
  EXPECT_NE(message("[1, 2]").find("bad.json"), std::string::npos);
  EXPECT_NE(message("{\"objects\": [{\"name\": \"a\"}]}").find("'mesh' is missing in a"), std::string::npos);
  EXPECT_THROW(parse_frame_size("640by480", "--size"), Error);
  EXPECT_EQ(parse_frame_size("640x480", "--size"), std::make_pair(640, 480));
}

TEST(PresenterScene, ProceduralMeshesAndCacheKeys) {
  for (const char* shape : {"sphere", "torus", "box"}) {
    MeshSpec spec;
    spec.procedural = shape;
    spec.segments = 12;
    spec.rings = 6;
    const splats::Mesh mesh = make_object_mesh(spec, ".");
    EXPECT_GT(mesh.face_count(), 30u) << shape;
    // Closed: every edge is shared by exactly two faces, in opposite directions.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
      for (std::uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) {
        const std::uint32_t next = c + 1 == mesh.face_offsets[f + 1] ? mesh.face_offsets[f] : c + 1;
        ++edges[{mesh.corners[c], mesh.corners[next]}];
      }
    for (const auto& [edge, count] : edges) {
      EXPECT_EQ(count, 1) << shape;
      EXPECT_EQ(edges.count({edge.second, edge.first}), 1u) << shape;
    }
    EXPECT_NE(asset_key(mesh, "a"), asset_key(mesh, "b"));
  }
}

std::vector<float> read_png(const std::string& path, int& width, int& height) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  width = spec.width;
  height = spec.height;
  std::vector<float> pixels(static_cast<std::size_t>(width) * height * spec.nchannels);
  in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data());
  std::vector<float> rgb(static_cast<std::size_t>(width) * height * 3);
  // File rows are top-down; the presenter's are bottom-up.
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        rgb[(static_cast<std::size_t>(height - 1 - y) * width + x) * 3 + c] =
            pixels[(static_cast<std::size_t>(y) * width + x) * spec.nchannels + c];
  return rgb;
}

// Reference: `splatcl render --size 160x120 -o tests/present/reference-default.png` (default scene,
// time 0). Tolerance: mean absolute difference ≤ 1/255, at most 0.5 % of the channel values off by
// more than 8/255 and 0.1 % by more than 32/255 (8-bit rounding and llvmpipe's float differences
// across CPUs). Regenerate it when the default scene changes on purpose.
TEST_F(PresenterTest, DefaultSceneMatchesReferenceImage) {
  int width = 0, height = 0;
  const std::vector<float> reference = read_png(SPLATCL_PRESENT_REFERENCE, width, height);
  ASSERT_FALSE(reference.empty()) << "missing " << SPLATCL_PRESENT_REFERENCE;
  Presenter presenter(default_scene(), *runtime_, width, height, SPLATCL_TEST_CACHE);
  presenter.render(0.0f);
  const std::vector<float> image = presenter.read_display_rgb();
  ASSERT_EQ(image.size(), reference.size());
  double sum = 0;
  std::size_t off = 0, far_off = 0;
  for (std::size_t i = 0; i < image.size(); ++i) {
    const double d = std::abs(image[i] - reference[i]);
    sum += d;
    off += d > 8.0 / 255.0;
    far_off += d > 32.0 / 255.0;
  }
  const double mean = sum / static_cast<double>(image.size());
  const std::string summary = "mean " + std::to_string(mean * 255) + "/255, " + std::to_string(off) + " values > 8/255, " +
                              std::to_string(far_off) + " > 32/255 of " + std::to_string(image.size());
  EXPECT_LE(mean, 1.0 / 255.0) << summary;
  EXPECT_LE(off, image.size() / 200) << summary;
  EXPECT_LE(far_off, image.size() / 1000) << summary;
}

TEST_F(PresenterTest, ClusteredTiledAndBruteForceShadingAgree) {
  Scene scene = test_scene();
  Presenter presenter(scene, *runtime_, 200, 150, SPLATCL_TEST_CACHE);
  std::vector<std::vector<float>> images;
  std::uint32_t clusters = 0, indices = 0;
  for (const char* shading : {"clustered", "tiled", "brute"}) {
    presenter.scene().quality.shading = shading;
    const FrameStats stats = presenter.render(0.5f);
    if (std::string(shading) == "clustered") clusters = stats.clusters, indices = stats.light_indices;
    images.push_back(presenter.read_hdr_rgb());
  }
  EXPECT_GT(clusters, 10u);
  EXPECT_GT(indices, clusters);                              // lights were assigned
  EXPECT_LT(indices, clusters * presenter.scene().lights.size() / 4);  // and culled
  double lit = 0;
  for (float v : images[2]) lit += v;
  EXPECT_GT(lit, 0.0);
  for (std::size_t k = 0; k < 2; ++k) {
    float worst = 0;
    for (std::size_t i = 0; i < images[2].size(); ++i) worst = std::max(worst, std::abs(images[k][i] - images[2][i]));
    // Conservative lists hold every light that reaches a pixel; lights are summed in the same
    // (ascending) order, so the sums agree up to float rounding of equal terms.
    EXPECT_LE(worst, 1e-5f) << (k == 0 ? "clustered" : "tiled");
  }
}

// The last render's splat coverage against the triangle meshes rendered with the same camera:
// covered share of the mesh pixels, and splat pixels outside the mesh relative to the mesh's.
struct Coverage {
  std::size_t mesh = 0;
  double covered = 0, spill = 0;
};
Coverage silhouette_coverage(Presenter& presenter, float time) {
  const auto splat_mask = presenter.read_coverage();
  const auto mesh_mask = presenter.render_mesh_mask(time);
  std::size_t covered = 0, outside = 0;
  Coverage c;
  for (std::size_t i = 0; i < mesh_mask.size(); ++i) {
    c.mesh += mesh_mask[i];
    covered += mesh_mask[i] & splat_mask[i];
    outside += splat_mask[i] & (1 - mesh_mask[i]);
  }
  c.covered = static_cast<double>(covered) / static_cast<double>(std::max<std::size_t>(c.mesh, 1));
  c.spill = static_cast<double>(outside) / static_cast<double>(std::max<std::size_t>(c.mesh, 1));
  return c;
}

TEST_F(PresenterTest, SplatsCoverTheMeshSilhouette) {
  Scene scene = test_scene();
  scene.floor.enabled = false;
  for (const bool points : {false, true}) {
    scene.quality.mode = points ? "points" : "splats";
    Presenter presenter(scene, *runtime_, 320, 240, SPLATCL_TEST_CACHE);
    for (const float time : {0.0f, 2.0f}) {
      presenter.render(time);
      const Coverage c = silhouette_coverage(presenter, time);
      ASSERT_GT(c.mesh, 1000u);
      if (!points) {
        EXPECT_GE(c.covered, 0.995) << "time " << time;
      }
      // Elliptical splats reach past the silhouette by a thin rim; the low-quality squares (side =
      // the projected major-axis diameter) by much more.
      EXPECT_LT(c.spill, points ? 0.6 : 0.08) << "mode " << scene.quality.mode;
    }
  }
}

// One sphere occluder over the floor, moved from A to B: the floor's AO drops under B, recovers under
// A, and far from both it changes only by the little a distant sphere can occlude.
TEST_F(PresenterTest, MovingAnOccluderMovesItsAmbientOcclusion) {
  Scene scene = test_scene();
  scene.objects.resize(1);
  ObjectSpec& ball = scene.objects[0];
  ball.mesh = MeshSpec{};
  ball.mesh.procedural = "sphere";
  ball.mesh.radius = 0.8f;
  ball.animation = Animation{};
  ball.rotation_degrees = glm::vec3(0.0f);
  const glm::vec3 a(-2.5f, 0.9f, 0.0f), b(2.5f, 0.9f, 0.0f);
  ball.position = a;
  Presenter presenter(scene, *runtime_, 64, 48, SPLATCL_TEST_CACHE);
  presenter.render(0.0f);
  const std::vector<glm::vec4> before = presenter.splat_ao();
  presenter.scene().objects[0].position = b;
  const FrameStats stats = presenter.render(0.0f);
  EXPECT_TRUE(stats.ao_updated);
  const std::vector<glm::vec4> after = presenter.splat_ao();
  const auto [first, count] = presenter.object_splats(presenter.object_count() - 1);  // the floor
  double near_a = 0, near_b = 0, far = 0;
  std::size_t n_a = 0, n_b = 0, n_far = 0, far_changed = 0;
  for (std::size_t s = first; s < first + count; ++s) {
    const glm::vec3 p = presenter.splat_world_position(s, 0.0f);
    const float da = glm::length(glm::vec2(p.x - a.x, p.z - a.z)), db = glm::length(glm::vec2(p.x - b.x, p.z - b.z));
    const double change = after[s].w - before[s].w;
    if (da < 0.5f) near_a += change, ++n_a;
    if (db < 0.5f) near_b += change, ++n_b;
    if (da > 3.5f && db > 3.5f) far += std::abs(change), ++n_far, far_changed += change != 0;
  }
  ASSERT_GT(n_a, 4u);
  ASSERT_GT(n_b, 4u);
  ASSERT_GT(n_far, 100u);
  EXPECT_GE(near_a / static_cast<double>(n_a), 0.15);   // uncovered where the ball was
  EXPECT_LE(near_b / static_cast<double>(n_b), -0.15);  // occluded where it is now
  // A sphere of radius 0.8 seen from ≥ 3.5 away covers under 6 % of the cosine-weighted hemisphere.
  EXPECT_LE(far / static_cast<double>(n_far), 0.03);
  EXPECT_LT(far_changed, n_far / 4);
  // Nothing moved: no recomputation and identical AO.
  EXPECT_FALSE(presenter.render(0.0f).ao_updated);
  EXPECT_EQ(presenter.splat_ao()[first].w, after[first].w);
}

TEST_F(PresenterTest, AssetsComeFromTheCacheTheSecondTime) {
  Scene scene = test_scene();
  scene.objects.resize(1);
  { Presenter warm(scene, *runtime_, 32, 32, SPLATCL_TEST_CACHE); }
  Presenter presenter(scene, *runtime_, 32, 32, SPLATCL_TEST_CACHE);
  EXPECT_TRUE(presenter.assets(0).splats_cached);
  EXPECT_TRUE(presenter.assets(0).csm_cached);
  EXPECT_GT(presenter.assets(0).splats.size(), 500u);
}

// A cache entry that cannot be read (here: every file overwritten with garbage) is rebuilt and
// replaced, not fatal; the rebuilt entries are then read from the cache.
TEST_F(PresenterTest, UnreadableCacheEntriesAreRebuilt) {
  Scene scene = test_scene();
  scene.objects.resize(1);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "splatcl-present-unreadable-cache";
  std::filesystem::remove_all(dir);
  { Presenter warm(scene, *runtime_, 32, 32, dir.string()); }
  std::size_t corrupted = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    std::ofstream(entry.path(), std::ios::trunc) << "not a cache entry";
    ++corrupted;
  }
  ASSERT_EQ(corrupted, 3u);  // splats, LOD tree, CSM
  {
    Presenter rebuilt(scene, *runtime_, 32, 32, dir.string());
    EXPECT_FALSE(rebuilt.assets(0).splats_cached);
    EXPECT_FALSE(rebuilt.assets(0).tree_cached);
    EXPECT_FALSE(rebuilt.assets(0).csm_cached);
    EXPECT_GT(rebuilt.assets(0).splats.size(), 500u);
  }
  Presenter cached(scene, *runtime_, 32, 32, dir.string());
  EXPECT_TRUE(cached.assets(0).splats_cached);
  EXPECT_TRUE(cached.assets(0).tree_cached);
  EXPECT_TRUE(cached.assets(0).csm_cached);
  std::filesystem::remove_all(dir);
}

TEST_F(PresenterTest, DebugViewsRender) {
  Presenter presenter(test_scene(), *runtime_, 96, 64, SPLATCL_TEST_CACHE);
  for (int v = 0; v < 8; ++v) {
    presenter.debug_view = static_cast<DebugView>(v);
    presenter.render(0.0f);
    const auto rgb = presenter.read_display_rgb();
    double sum = 0;
    for (float x : rgb) sum += x;
    EXPECT_GT(sum, 0.0) << to_string(presenter.debug_view);
  }
  EXPECT_THROW(parse_debug_view("wireframe"), Error);
}

}  // namespace
}  // namespace splatcl::present

// --- Frame-rate work: incremental per-splat lighting, shading variants, Blinn-Phong. ---
namespace splatcl::present {
namespace {

// The incremental update (only receivers a moved occluder may reach) gives the rows of a full
// recomputation bit for bit: the default scene's torus orbiting and spinning, small steps and jumps,
// and a sphere teleported across the floor.
TEST_F(PresenterTest, IncrementalSplatLightingEqualsFullRecomputation) {
  for (const bool teleport : {false, true}) {
    Scene scene = test_scene();
    if (teleport) {
      scene.objects[1].animation = Animation{};
      scene.objects[0].animation = Animation{};
    }
    // Both from the cache: assets built in memory on a cache miss need not equal their cached files
    // bit for bit (the CSM file's depth encoding), and the comparison needs identical assets.
    { Presenter warm(scene, *runtime_, 16, 16, SPLATCL_TEST_CACHE); }
    Presenter incremental(scene, *runtime_, 64, 48, SPLATCL_TEST_CACHE);
    Presenter full(scene, *runtime_, 64, 48, SPLATCL_TEST_CACHE);
    full.incremental_lighting = false;
    for (std::size_t i = 0; i < full.scene().objects.size(); ++i)
      ASSERT_TRUE(full.assets(i).csm_cached && incremental.assets(i).csm_cached) << "object " << i;
    std::size_t partial_updates = 0;
    const float times[] = {0.0f, 1.0f / 30, 2.0f / 30, 0.5f, 3.0f, 3.0f + 1.0f / 30};
    for (std::size_t step = 0; step < std::size(times); ++step) {
      if (teleport) {
        const glm::vec3 spot = step % 2 ? glm::vec3(2.5f, 1.0f, 1.5f) : glm::vec3(-1.6f, 1.0f, -1.4f);
        incremental.scene().objects[1].position = full.scene().objects[1].position = spot;
      }
      const FrameStats a = incremental.render(times[step]), b = full.render(times[step]);
      ASSERT_EQ(a.ao_updated, b.ao_updated);
      if (step > 0 && a.ao_updated) {
        EXPECT_EQ(b.lighting_receivers, b.splats);
        partial_updates += a.lighting_receivers < a.splats;
      }
      const std::vector<float>& x = incremental.splat_lighting();
      const std::vector<float>& y = full.splat_lighting();
      ASSERT_EQ(x.size(), y.size());
      std::size_t differ = 0;
      for (std::size_t i = 0; i < x.size(); ++i) differ += std::memcmp(&x[i], &y[i], sizeof(float)) != 0;
      EXPECT_EQ(differ, 0u) << "step " << step << (teleport ? " (teleport)" : " (default animation)");
    }
    EXPECT_GE(partial_updates, 2u);  // the incremental path skipped receivers on most updates
  }
}

// quality.splat_bound picks the splat method: the thesis's (default, the shipped scene's look) or
// the two-sided variant of splatcl splats, whose splats keep the bound against the object's mesh
// (checked on the surface) and live under their own cache key.
TEST_F(PresenterTest, SplatBoundChoosesTheSplatMethod) {
  EXPECT_EQ(default_scene().quality.splat_bound, "thesis");
  EXPECT_THROW(parse_scene("{\"objects\": [], \"quality\": {\"splat_bound\": \"yes\"}}", "s.json", "."), Error);
  Scene scene = default_scene();
  const auto box = std::find_if(scene.objects.begin(), scene.objects.end(), [](const ObjectSpec& o) { return o.name == "box"; });
  ASSERT_NE(box, scene.objects.end());
  scene.quality.eps_diagonal = 0.004f;  // a coarse ε keeps the test short
  const ObjectAssets thesis = load_object_assets(*box, scene, SPLATCL_TEST_CACHE, *runtime_);
  scene.quality.splat_bound = "two-sided";
  const ObjectAssets bounded = load_object_assets(*box, scene, SPLATCL_TEST_CACHE, *runtime_);
  EXPECT_NE(thesis.key, bounded.key);
  splats::SurfaceCheckOptions check;
  check.eps = scene.quality.eps_diagonal * bounded.mesh.bounds().diagonal();
  check.surface_points = 50'000;
  EXPECT_TRUE(splats::check_surface(bounded.mesh, bounded.splats, check).ok());
  EXPECT_FALSE(splats::check_surface(thesis.mesh, thesis.splats, check).ok());
}

TEST(PresenterScene, SpecularIsOffByDefaultAndValidated) {
  EXPECT_EQ(default_scene().quality.specular, 0.0f);
  const Scene on = parse_scene("{\"objects\": [], \"quality\": {\"specular\": 0.5, \"shininess\": 16}}", "s.json", ".");
  EXPECT_EQ(on.quality.specular, 0.5f);
  EXPECT_EQ(on.quality.shininess, 16.0f);
  EXPECT_THROW(parse_scene("{\"objects\": [], \"quality\": {\"specular\": -1}}", "s.json", "."), Error);
  EXPECT_THROW(parse_scene("{\"objects\": [], \"quality\": {\"shininess\": 0}}", "s.json", "."), Error);
  Scene scene = default_scene();
  Overrides overrides;
  overrides.specular = 0.25;
  apply_overrides(scene, overrides);
  EXPECT_EQ(scene.quality.specular, 0.25f);
}

// Blinn-Phong adds a non-negative highlight where a light reaches the pixel: the background and a
// scene lit only by the sky are unchanged, lit pixels never get darker and some get brighter.
TEST_F(PresenterTest, SpecularChangesOnlyLitPixels) {
  Scene scene = test_scene();
  for (const bool lit : {true, false}) {
    if (!lit) scene.lights.clear(), scene.key_lights.clear();
    Presenter presenter(scene, *runtime_, 96, 72, SPLATCL_TEST_CACHE);
    presenter.render(0.0f);
    const std::vector<float> lambert = presenter.read_hdr_rgb();
    const std::vector<std::uint8_t> covered = presenter.read_coverage();
    presenter.scene().quality.specular = 0.5f;
    presenter.render(0.0f);
    const std::vector<float> phong = presenter.read_hdr_rgb();
    ASSERT_EQ(lambert.size(), phong.size());
    std::size_t brighter = 0, darker = 0, background_changed = 0;
    for (std::size_t i = 0; i < phong.size(); ++i) {
      brighter += phong[i] > lambert[i];
      darker += phong[i] < lambert[i] - 1e-6f * std::max(1.0f, lambert[i]);
      background_changed += !covered[i / 3] && phong[i] != lambert[i];
    }
    EXPECT_EQ(darker, 0u);
    EXPECT_EQ(background_changed, 0u);
    if (lit) {
      EXPECT_GT(brighter, phong.size() / 100);
    } else {
      EXPECT_EQ(brighter, 0u);  // no light, no highlight
    }
  }
}


// ---- Per-splat colours and level of detail (sequential point trees) ----

// Splats on a unit sphere (round, radius 0.12), deterministic.
std::vector<splats::SplatRecord> sphere_splats(std::size_t count) {
  std::vector<splats::SplatRecord> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    const float y = 1.0f - 2.0f * (static_cast<float>(i) + 0.5f) / static_cast<float>(count);
    const float r = std::sqrt(1.0f - y * y), phi = static_cast<float>(i) * 2.39996323f;
    const glm::vec3 n(r * std::cos(phi), y, r * std::sin(phi));
    const glm::vec3 t1 = glm::normalize(glm::cross(std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0), n));
    const glm::vec3 t2 = glm::cross(n, t1);
    out[i].center = {n.x, n.y, n.z};
    out[i].normal = {n.x, n.y, n.z};
    out[i].major = {0.12f * t1.x, 0.12f * t1.y, 0.12f * t1.z};
    out[i].minor = {0.1f * t2.x, 0.1f * t2.y, 0.1f * t2.z};
    out[i].color = {static_cast<std::uint8_t>(i % 256), 0, 255, 255};
  }
  return out;
}

TEST(PresenterLod, TreeIsASequenceWithACutAtEveryThreshold) {
  for (const std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{15}, std::size_t{16}, std::size_t{1000}}) {
    const auto splats = sphere_splats(count);
    const SplatTree tree = build_splat_tree(splats);
    ASSERT_EQ(tree.splat_count, count);
    ASSERT_EQ(tree.size(), count + tree.nodes.size());
    if (count == 0) continue;
    EXPECT_EQ(tree.nodes.size() > 1, count >= 16) << count;  // leaves hold fewer than 16
    // Every original and node exactly once, sorted by e_max descending, intervals non-empty or
    // empty only at equal bounds.
    std::vector<int> seen(tree.size(), 0);
    for (std::size_t e = 0; e < tree.size(); ++e) {
      ++seen[tree.source[e]];
      if (e) {
        EXPECT_GE(tree.error_max[e - 1], tree.error_max[e]);
      }
      EXPECT_LE(tree.error_min[e], tree.error_max[e]);
      if (tree.source[e] < count) {
        EXPECT_EQ(tree.error_min[e], 0.0f);
      }
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int k) { return k == 1; }));
    EXPECT_EQ(tree.error_max[0], FLT_MAX);  // the root
    // A cut at every budget: each original splat is drawn itself or through exactly one ancestor
    // interval holding the budget (overlap at the boundaries allows two).
    std::vector<std::size_t> position(count);
    for (std::size_t k = 0; k < count; ++k) position[tree.order[k]] = k;
    for (const float budget : {0.0f, 1e-4f, 0.01f, 0.05f, 0.2f, 1.0f, 10.0f}) {
      std::vector<int> drawn_over(count, 0);
      for (std::size_t e = 0; e < tree.prefix(budget); ++e) {
        if (!(budget >= tree.error_min[e] && budget < tree.error_max[e])) continue;
        const std::uint32_t s = tree.source[e];
        if (s < count) {
          ++drawn_over[s];
        } else {
          for (std::uint32_t k = tree.node_begin[s - count]; k < tree.node_end[s - count]; ++k) ++drawn_over[tree.order[k]];
        }
      }
      for (std::size_t s = 0; s < count; ++s) {
        EXPECT_GE(drawn_over[s], 1) << "splat " << s << " budget " << budget;
        EXPECT_LE(drawn_over[s], 2) << "splat " << s << " budget " << budget;
      }
      // Entries past the prefix can never be drawn at this budget or above.
      for (std::size_t e = tree.prefix(budget); e < tree.size(); ++e) EXPECT_LE(tree.error_max[e], budget);
    }
    // Budget 0 draws exactly the originals.
    std::size_t at_zero = 0;
    for (std::size_t e = 0; e < tree.size(); ++e) at_zero += 0.0f >= tree.error_min[e] && 0.0f < tree.error_max[e];
    EXPECT_EQ(at_zero, count);
    // A node encloses its splats' centres and takes their mean row.
    std::vector<float> rows(count);
    for (std::size_t s = 0; s < count; ++s) rows[s] = static_cast<float>(s);
    const std::vector<float> gathered = gather_tree_rows(tree, rows.data(), 1);
    for (std::size_t e = 0; e < tree.size(); ++e) {
      const std::uint32_t s = tree.source[e];
      if (s < count) {
        EXPECT_EQ(gathered[e], static_cast<float>(s));
        continue;
      }
      const std::size_t node = s - count;
      double mean = 0;
      const glm::vec3 c(tree.nodes[node].center.x, tree.nodes[node].center.y, tree.nodes[node].center.z);
      const float radius = glm::length(glm::vec3(tree.nodes[node].major.x, tree.nodes[node].major.y, tree.nodes[node].major.z));
      for (std::uint32_t k = tree.node_begin[node]; k < tree.node_end[node]; ++k) {
        mean += tree.order[k];
        const auto& p = splats[tree.order[k]].center;
        EXPECT_LE(glm::length(glm::vec3(p.x, p.y, p.z) - c), radius * 1.0001f);
      }
      EXPECT_NEAR(gathered[e], mean / (tree.node_end[node] - tree.node_begin[node]), 1e-3);
    }
  }
}

TEST(PresenterLod, TreeFileRoundTripsAndRejectsDamage) {
  const auto splats = sphere_splats(300);
  const SplatTree tree = build_splat_tree(splats);
  const std::string path = (std::filesystem::temp_directory_path() / "splatcl-present-tree.spt").string();
  write_splat_tree(path, tree);
  const SplatTree back = read_splat_tree(path, 300);
  EXPECT_EQ(back.source, tree.source);
  EXPECT_EQ(back.error_min, tree.error_min);
  EXPECT_EQ(back.error_max, tree.error_max);
  EXPECT_EQ(back.order, tree.order);
  ASSERT_EQ(back.nodes.size(), tree.nodes.size());
  EXPECT_EQ(back.nodes.back().center.x, tree.nodes.back().center.x);
  EXPECT_THROW(read_splat_tree(path, 301), Error);  // built over another splat set
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    f.put('\x7f');
  }
  EXPECT_THROW(read_splat_tree(path, 300), Error);  // checksum
  std::filesystem::resize_file(path, 20);
  EXPECT_THROW(read_splat_tree(path, 300), Error);
  EXPECT_THROW(read_splat_tree(path + ".missing", 300), Error);
  std::filesystem::remove(path);
}

TEST(PresenterScene, SplatColoursAndLodOptionsAreValidated) {
  const Scene scene = parse_scene(
      R"({"objects": [{"mesh": {"procedural": "box"}, "color": "splats", "color_field": "soft"},
                       {"mesh": {"procedural": "box"}, "color": [0.1, 0.2, 0.3]}],
          "quality": {"lod_error": 1.5, "lod_leaf": 8}})",
      "s.json", ".");
  EXPECT_TRUE(scene.objects[0].splat_colors);
  EXPECT_EQ(scene.objects[0].color_field, "soft");
  EXPECT_FALSE(scene.objects[1].splat_colors);
  EXPECT_EQ(scene.quality.lod_error, 1.5f);
  EXPECT_EQ(scene.quality.lod_leaf, 8u);
  EXPECT_EQ(default_scene().quality.lod_error, 0.0f);  // LOD is off by default
  const auto fails = [](const std::string& text, const std::string& field) {
    try {
      parse_scene(text, "s.json", ".");
    } catch (const Error& e) {
      return std::string(e.what()).find(field) != std::string::npos;
    }
    return false;
  };
  EXPECT_TRUE(fails(R"({"objects": [{"mesh": {"procedural": "box"}, "color": "texture"}]})", "'color'"));
  EXPECT_TRUE(fails(R"({"objects": [{"mesh": {"procedural": "box"}, "color": "splats", "color_field": "plaid"}]})", "'color_field'"));
  EXPECT_TRUE(fails(R"({"objects": [{"mesh": {"procedural": "box"}, "color_field": "soft"}]})", "'color_field'"));
  EXPECT_TRUE(fails(R"({"objects": [], "quality": {"lod_error": -1}})", "'lod_error'"));
  Scene s = default_scene();
  Overrides o;
  o.lod = 2;
  apply_overrides(s, o);
  EXPECT_EQ(s.quality.lod_error, 2.0f);
}

// A long box coloured by the soft field (red at low x to white at high x along its longest axis):
// the albedo view shows red on the left end and white on the right end.
TEST_F(PresenterTest, PerSplatColoursReachTheAlbedo) {
  Scene scene = test_scene();
  scene.floor.enabled = false;
  scene.objects.resize(1);
  ObjectSpec& bar = scene.objects[0];
  bar = ObjectSpec{};
  bar.name = "bar";
  bar.mesh.procedural = "box";
  bar.mesh.size = {4.0f, 1.0f, 1.0f};
  bar.mesh.rings = 8;
  bar.splat_colors = true;
  bar.color_field = "soft";
  bar.position = {0.0f, 0.8f, 0.0f};
  Presenter presenter(scene, *runtime_, 160, 120, SPLATCL_TEST_CACHE);
  presenter.debug_view = DebugView::Albedo;
  presenter.render(0.0f);
  const auto rgb = presenter.read_hdr_rgb();
  const auto mask = presenter.read_coverage();
  int lo = 160, hi = -1;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x)
      if (mask[static_cast<std::size_t>(y) * 160 + static_cast<std::size_t>(x)]) lo = std::min(lo, x), hi = std::max(hi, x);
  ASSERT_GT(hi - lo, 40);
  // Mean albedo over the covered pixels of the outer eighths of the bar's width.
  const auto mean = [&](int x0, int x1) {
    glm::dvec3 sum(0.0);
    int n = 0;
    for (int y = 0; y < 120; ++y)
      for (int x = x0; x <= x1; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * 160 + static_cast<std::size_t>(x);
        if (!mask[p]) continue;
        sum += glm::dvec3(rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2]);
        ++n;
      }
    return n ? sum / static_cast<double>(n) : sum;
  };
  const int eighth = (hi - lo) / 8;
  const glm::dvec3 left = mean(lo, lo + eighth), right = mean(hi - eighth, hi);
  EXPECT_GT(left.r, 0.8) << "left red";
  EXPECT_LT(left.g, 0.2) << "left not white";
  EXPECT_GT(right.r, 0.8) << "right red channel";
  EXPECT_GT(right.g, 0.55) << "right white";
  EXPECT_GT(right.b, 0.55) << "right white";
  // The scene colour of the object is ignored when the splats carry colours.
  bar.splat_colors = false;
  bar.color = {0.0f, 0.0f, 1.0f};
  Presenter uniform(scene, *runtime_, 160, 120, SPLATCL_TEST_CACHE);
  uniform.debug_view = DebugView::Albedo;
  uniform.render(0.0f);
  const auto blue = uniform.read_hdr_rgb();
  for (std::size_t p = 0; p < mask.size(); ++p)
    if (mask[p]) {
      ASSERT_EQ(blue[3 * p], 0.0f);
    }
}

// The default scene seen from 3.5 times farther: LOD at 2 pixels draws fewer splats and still
// covers the triangle meshes' silhouette; LOD 0 is the same image as LOD off, bit for bit.
TEST_F(PresenterTest, LodDrawsFewerSplatsFarAwayAndKeepsTheSilhouette) {
  Scene scene = test_scene();
  scene.floor.enabled = false;
  const auto target = scene.camera.target;
  scene.camera.eye = target + 3.5f * (scene.camera.eye - target);
  Presenter presenter(scene, *runtime_, 320, 240, SPLATCL_TEST_CACHE);
  const FrameStats off = presenter.render(0.0f);
  const auto image_off = presenter.read_hdr_rgb();
  const Coverage coverage_off = silhouette_coverage(presenter, 0.0f);
  presenter.scene().quality.lod_error = 2.0f;
  const FrameStats on = presenter.render(0.0f);
  const Coverage coverage_on = silhouette_coverage(presenter, 0.0f);
  ASSERT_GT(coverage_on.mesh, 500u);
  EXPECT_LT(on.splats, off.splats / 2) << on.splats << " of " << off.splats;
  EXPECT_GE(coverage_on.covered, 0.995) << "LOD off: " << coverage_off.covered;
  EXPECT_LT(coverage_on.spill, 0.25) << "LOD off: " << coverage_off.spill;
  presenter.scene().quality.lod_error = 0.0f;
  const FrameStats zero = presenter.render(0.0f);
  EXPECT_EQ(zero.splats, off.splats);
  EXPECT_EQ(presenter.read_hdr_rgb(), image_off);
  // Closer than the coarsest level needs, the same threshold keeps (nearly) every original splat.
  Presenter near(test_scene(), *runtime_, 320, 240, SPLATCL_TEST_CACHE);
  const FrameStats near_off = near.render(0.0f);
  near.scene().quality.lod_error = 0.05f;
  EXPECT_GE(near.render(0.0f).splats, near_off.splats * 9 / 10);
}

// A lighting setting changed with nothing moving (the viewer paused, AO or shadows toggled): the
// rows follow at the next frame, and switching back gives the first rows again.
TEST_F(PresenterTest, LightingSettingsChangeTheRowsWithoutMotion) {
  Presenter presenter(test_scene(), *runtime_, 96, 72, SPLATCL_TEST_CACHE);
  presenter.render(0.5f);
  const std::vector<float> with_ao = presenter.splat_lighting();
  EXPECT_FALSE(presenter.render(0.5f).ao_updated);  // same time, same settings: nothing to do
  presenter.ambient_occlusion = false;
  EXPECT_TRUE(presenter.render(0.5f).ao_updated);
  EXPECT_NE(presenter.splat_lighting(), with_ao);
  presenter.ambient_occlusion = true;
  EXPECT_TRUE(presenter.render(0.5f).ao_updated);
  EXPECT_EQ(presenter.splat_lighting(), with_ao);
  presenter.scene().quality.shadows = "off";
  EXPECT_TRUE(presenter.render(0.5f).ao_updated);
  EXPECT_NE(presenter.splat_lighting(), with_ao);
}

// The per-splat lighting beside the visibility pass (worker thread) or after it: the same rows and
// the same image, frame after frame with the torus moving.
TEST_F(PresenterTest, OverlappedLightingEqualsSerialLighting) {
  Presenter overlapped(test_scene(), *runtime_, 160, 120, SPLATCL_TEST_CACHE);
  Presenter serial(test_scene(), *runtime_, 160, 120, SPLATCL_TEST_CACHE);
  serial.overlap_lighting = false;
  for (const float time : {0.0f, 0.1f, 0.2f, 0.2f, 1.5f}) {
    const FrameStats a = overlapped.render(time);
    const FrameStats b = serial.render(time);
    EXPECT_EQ(a.ao_updated, b.ao_updated) << time;
    EXPECT_EQ(a.lighting_receivers, b.lighting_receivers) << time;
    EXPECT_EQ(overlapped.splat_lighting(), serial.splat_lighting()) << time;
    EXPECT_EQ(overlapped.read_display_rgb(), serial.read_display_rgb()) << time;
  }
}

// Timing the GL passes by wall clock (glFinish around each pass) changes no pixel and reports the
// same passes; without HDR output the tone-mapped image is the same and read_hdr_rgb refuses.
TEST_F(PresenterTest, WallClockPassesAndHdrOutputChangeNoPixel) {
  Presenter presenter(test_scene(), *runtime_, 160, 120, SPLATCL_TEST_CACHE);
  const auto pass_names = [](const FrameStats& stats) {
    std::vector<std::string> names;
    for (const StageTime& s : stats.stages)
      if (s.name.rfind("gl: ", 0) == 0) names.push_back(s.name);
    return names;
  };
  const FrameStats queried = presenter.render(0.25f);
  const auto display = presenter.read_display_rgb();
  const auto hdr = presenter.read_hdr_rgb();
  presenter.wall_clock_passes = true;
  const FrameStats walled = presenter.render(0.25f);
  EXPECT_EQ(pass_names(walled), pass_names(queried));
  EXPECT_EQ(pass_names(walled), (std::vector<std::string>{"gl: splat visibility", "gl: splat accumulation", "gl: shading"}));
  for (const StageTime& s : walled.stages) {
    if (s.name.rfind("gl: ", 0) == 0) {
      EXPECT_GT(s.ms, 0.0) << s.name;  // a wall clock around real work
    }
  }
  EXPECT_EQ(presenter.read_display_rgb(), display);
  EXPECT_EQ(presenter.read_hdr_rgb(), hdr);
  presenter.hdr_output = false;
  presenter.render(0.25f);
  EXPECT_EQ(presenter.read_display_rgb(), display);
  EXPECT_THROW(presenter.read_hdr_rgb(), Error);
}

}  // namespace
}  // namespace splatcl::present
