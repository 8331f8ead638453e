// The presenter's per-splat lighting: ambient occlusion following a moved occluder, the incremental
// update equal to a full recomputation (per splat and on the floor's pixel lattice), settings
// changed without motion, and the lighting beside the visibility pass on a worker thread equal to
// the serial order.
#include <gtest/gtest.h>

#include <cstring>
#include <iterator>
#include <set>

#include "presenter_test_support.hpp"

namespace splatcl::present {
namespace {

using namespace testing;

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

// The floor's pixel lattice kept incrementally (nodes keep their visibility through the occluders
// that did not move while the camera is still) gives the image of the full update every frame bit
// for bit: the torus orbiting, nodes hidden and uncovered by it, a pause, a camera move and motion
// after it; and with the camera still most nodes are served from the cache.
TEST_F(PresenterTest, IncrementalFloorLatticeEqualsFullRecomputation) {
  const Scene scene = test_scene();
  { Presenter warm(scene, *runtime_, 16, 16, SPLATCL_TEST_CACHE); }
  Presenter incremental(scene, *runtime_, 160, 120, SPLATCL_TEST_CACHE);
  Presenter full(scene, *runtime_, 160, 120, SPLATCL_TEST_CACHE);
  full.incremental_lighting = false;
  // The first frame is a full update; a frame whose set of moving occluders differs from the last
  // one's (motion starts or stops) and the first after a camera move re-cache every node.
  const float d = 1.0f / 30;
  const float times[] = {0.0f, d, 2 * d, 3 * d, 3 * d, 3 * d, 0.6f, 0.6f + d, 0.6f + 2 * d, 0.6f + 3 * d, 0.6f + 4 * d};
  const std::set<std::size_t> served = {2, 3, 5, 7, 10};
  for (std::size_t step = 0; step < std::size(times); ++step) {
    if (step == 8) {  // the camera moves between two frames with motion
      for (Presenter* p : {&incremental, &full}) p->scene().camera.eye = {1.5f, 4.0f, 7.8f};
    }
    const FrameStats a = incremental.render(times[step]), b = full.render(times[step]);
    ASSERT_GT(b.floor_nodes, 500u);
    ASSERT_EQ(a.floor_nodes, b.floor_nodes) << "step " << step;
    EXPECT_EQ(b.floor_receivers, b.floor_nodes);
    if (served.count(step)) {
      EXPECT_LT(a.floor_receivers, b.floor_nodes / 4) << "step " << step;
    } else {
      EXPECT_EQ(a.floor_receivers, a.floor_nodes) << "step " << step;
    }
    if (step == 5) {
      EXPECT_EQ(a.floor_receivers, 0u);  // paused: nothing to recompute
    }
    EXPECT_TRUE(incremental.read_display_rgb() == full.read_display_rgb()) << "step " << step;
    EXPECT_TRUE(incremental.read_hdr_rgb() == full.read_hdr_rgb()) << "step " << step;
  }
}

}  // namespace
}  // namespace splatcl::present
