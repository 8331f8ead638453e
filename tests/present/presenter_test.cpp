// The presenter, headless (EGL surfaceless on Mesa llvmpipe, PoCL for the CL stages): the default
// scene against a stored reference image, clustered == tiled == brute-force shading on the same
// G-buffer, no holes against the triangle mesh, and ambient occlusion following a moved occluder.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>

#include "present/context.hpp"
#include "present/presenter.hpp"
#include "present/scene.hpp"
#include "runtime/error.hpp"
#include "runtime/runtime.hpp"

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

TEST_F(PresenterTest, SplatsCoverTheMeshSilhouette) {
  Scene scene = test_scene();
  scene.floor.enabled = false;
  for (const bool points : {false, true}) {
    scene.quality.mode = points ? "points" : "splats";
    Presenter presenter(scene, *runtime_, 320, 240, SPLATCL_TEST_CACHE);
    for (const float time : {0.0f, 2.0f}) {
      presenter.render(time);
      const auto splat_mask = presenter.read_coverage();
      const auto mesh_mask = presenter.render_mesh_mask(time);
      std::size_t mesh = 0, covered = 0, outside = 0;
      for (std::size_t i = 0; i < mesh_mask.size(); ++i) {
        mesh += mesh_mask[i];
        covered += mesh_mask[i] & splat_mask[i];
        outside += splat_mask[i] & (1 - mesh_mask[i]);
      }
      ASSERT_GT(mesh, 1000u);
      const double coverage = static_cast<double>(covered) / static_cast<double>(mesh);
      if (!points) {
        EXPECT_GE(coverage, 0.995) << "time " << time;
      }
      // Elliptical splats reach past the silhouette by a thin rim; the low-quality squares (side =
      // the projected major-axis diameter) by much more.
      EXPECT_LT(static_cast<double>(outside) / static_cast<double>(mesh), points ? 0.6 : 0.08) << "mode " << scene.quality.mode;
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
  ASSERT_EQ(corrupted, 2u);
  {
    Presenter rebuilt(scene, *runtime_, 32, 32, dir.string());
    EXPECT_FALSE(rebuilt.assets(0).splats_cached);
    EXPECT_FALSE(rebuilt.assets(0).csm_cached);
    EXPECT_GT(rebuilt.assets(0).splats.size(), 500u);
  }
  Presenter cached(scene, *runtime_, 32, 32, dir.string());
  EXPECT_TRUE(cached.assets(0).splats_cached);
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
