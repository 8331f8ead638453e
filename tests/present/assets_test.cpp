// The presenter's assets: the cache hit the second time, unreadable entries rebuilt, and the splat
// method chosen by quality.splat_bound under its own cache key.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "splats/surface_check.hpp"

#include "presenter_test_support.hpp"

namespace splatcl::present {
namespace {

using namespace testing;

TEST_F(PresenterTest, AssetsComeFromTheCacheTheSecondTime) {
  Scene scene = test_scene();
  scene.objects.resize(1);
  { Presenter warm(scene, *runtime_, 32, 32, SPLATCL_TEST_CACHE); }
  Presenter presenter(scene, *runtime_, 32, 32, SPLATCL_TEST_CACHE);
  EXPECT_TRUE(presenter.assets(0).splats_cached);
  EXPECT_TRUE(presenter.assets(0).gaps_cached);
  EXPECT_TRUE(presenter.assets(0).drawn_cached);
  EXPECT_TRUE(presenter.assets(0).tree_cached);
  EXPECT_TRUE(presenter.assets(0).fields_cached);
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
  ASSERT_EQ(corrupted, 7u);  // splats, the drawn splats' gap splats and fit, LOD tree, normal fields, CSM, its thin-part answer
  {
    Presenter rebuilt(scene, *runtime_, 32, 32, dir.string());
    EXPECT_EQ(rebuilt.assets(0).thin_part_warning, "");  // not the garbage read as a warning
    EXPECT_FALSE(rebuilt.assets(0).splats_cached);
    EXPECT_FALSE(rebuilt.assets(0).gaps_cached);
    EXPECT_FALSE(rebuilt.assets(0).drawn_cached);
    EXPECT_FALSE(rebuilt.assets(0).fields_cached);
    EXPECT_FALSE(rebuilt.assets(0).tree_cached);
    EXPECT_FALSE(rebuilt.assets(0).csm_cached);
    EXPECT_GT(rebuilt.assets(0).splats.size(), 500u);
  }
  // The CSM alone rebuilt from a garbage thin-part answer: the answer is made again, not read as text.
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().extension() == ".thin1") std::ofstream(entry.path(), std::ios::trunc) << "not a cache entry";
  {
    Presenter again(scene, *runtime_, 32, 32, dir.string());
    EXPECT_TRUE(again.assets(0).csm_cached);
    EXPECT_EQ(again.assets(0).thin_part_warning, "");
  }
  Presenter cached(scene, *runtime_, 32, 32, dir.string());
  EXPECT_TRUE(cached.assets(0).splats_cached);
  EXPECT_TRUE(cached.assets(0).gaps_cached);
  EXPECT_TRUE(cached.assets(0).drawn_cached);
  EXPECT_TRUE(cached.assets(0).fields_cached);
  EXPECT_TRUE(cached.assets(0).tree_cached);
  EXPECT_TRUE(cached.assets(0).csm_cached);
  std::filesystem::remove_all(dir);
}

// The drawn splats' gap splats, their fit, the LOD tree over them and their normal fields are
// cached under the parameters that shape them: the same fit again reads all four, and the fit and
// fields read back are those computed, bit for bit; another surface_clip or splat scale k builds them anew (other gap
// splats); surface_clip 0 draws the splats as built, with no gap splats and no clip lines.
TEST_F(PresenterTest, GapSplatsAreCachedUnderTheFitsParameters) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "splatcl-present-gap-cache";
  std::filesystem::remove_all(dir);
  Scene scene = test_scene();
  scene.objects.resize(1);  // the torus, with the shipped thesis splats
  const auto load = [&](float surface_clip, float k) {
    scene.quality.surface_clip = surface_clip, scene.quality.splat_scale = k;
    return load_object_assets(scene.objects[0], scene, dir.string(), *runtime_);
  };
  const ObjectAssets first = load(0.001f, 1.05f);
  EXPECT_FALSE(first.gaps_cached);
  EXPECT_FALSE(first.drawn_cached);
  EXPECT_GT(first.gap_splats, 0u);
  ASSERT_EQ(first.drawn.size(), first.splats.size());
  ASSERT_EQ(first.second_clips.size(), first.drawn.size());
  const ObjectAssets again = load(0.001f, 1.05f);
  EXPECT_TRUE(again.splats_cached);
  EXPECT_TRUE(again.gaps_cached);
  EXPECT_TRUE(again.drawn_cached);
  EXPECT_TRUE(again.tree_cached);
  EXPECT_EQ(again.gap_splats, first.gap_splats);
  ASSERT_EQ(again.drawn.size(), first.drawn.size());
  ASSERT_EQ(again.second_clips.size(), first.second_clips.size());
  EXPECT_EQ(std::memcmp(again.drawn.data(), first.drawn.data(), first.drawn.size() * sizeof(first.drawn[0])), 0);
  EXPECT_EQ(std::memcmp(again.second_clips.data(), first.second_clips.data(), first.second_clips.size() * sizeof(first.second_clips[0])), 0);
  std::size_t cornered = 0;
  for (const splats::ClipLine& line : again.second_clips) cornered += std::isfinite(line.offset);
  EXPECT_GT(cornered, 0u);  // the cache holds second clip lines, not only the splats
  EXPECT_FALSE(first.fields_cached);
  EXPECT_TRUE(again.fields_cached);
  ASSERT_EQ(again.normal_fields.size(), first.drawn.size());
  ASSERT_EQ(again.node_fields.size(), first.tree.nodes.size());
  EXPECT_EQ(std::memcmp(again.normal_fields.data(), first.normal_fields.data(), first.normal_fields.size() * sizeof(first.normal_fields[0])), 0);
  EXPECT_EQ(std::memcmp(again.node_fields.data(), first.node_fields.data(), first.node_fields.size() * sizeof(first.node_fields[0])), 0);
  const ObjectAssets looser = load(0.0025f, 1.05f);
  EXPECT_TRUE(looser.splats_cached);
  EXPECT_FALSE(looser.gaps_cached);
  EXPECT_FALSE(looser.drawn_cached);
  EXPECT_FALSE(looser.tree_cached);
  EXPECT_LT(looser.gap_splats, first.gap_splats);  // a looser fit shortens fewer splats
  const ObjectAssets larger_k = load(0.001f, 1.2f);
  EXPECT_FALSE(larger_k.gaps_cached);
  EXPECT_FALSE(larger_k.drawn_cached);
  EXPECT_NE(larger_k.gap_splats, first.gap_splats);
  const ObjectAssets as_built = load(0.0f, 1.05f);
  EXPECT_EQ(as_built.gap_splats, 0u);
  EXPECT_FALSE(as_built.gaps_cached);
  ASSERT_EQ(as_built.drawn.size(), as_built.splats.size());
  for (std::size_t i = 0; i < as_built.drawn.size(); ++i) {
    ASSERT_EQ(as_built.drawn[i].major, as_built.splats[i].major) << i;
    ASSERT_TRUE(std::isinf(as_built.second_clips[i].offset)) << i;
  }
  std::filesystem::remove_all(dir);
}

// An object far from the origin for its size: the float step where it goes (its position, or its
// orbit) against its size. A unit sphere: nothing at the origin, a warning at 1e4 (step 0.001, 0.03 %
// of its size) and 1e6 (0.0625, 1.8 %: it cracked), refused at 1e7 (1, 29 %: it vanished) and when
// its orbit takes it there; an orbit about the origin ignores position's x and z.
TEST(PresenterAssets, AnObjectFarFromTheOriginForItsSizeIsWarnedOfOrRefused) {
  const auto check = [](const std::string& placement) {
    const Scene scene = parse_scene(R"({"objects": [{"name": "ball", "mesh": {"procedural": "sphere"}, )" + placement + "}]}", "far.json", ".");
    return far_placement_check(scene.objects[0], make_fitted_mesh(scene.objects[0], "."));
  };
  EXPECT_EQ(check(R"("position": [0, 1, 0])"), "");
  EXPECT_EQ(check(R"("position": [100, 1, 100])"), "");
  EXPECT_NE(check(R"("position": [1e4, 1, 1e4])").find("placed where coordinates reach"), std::string::npos);
  EXPECT_NE(check(R"("position": [1e6, 1, 1e6])").find("placed where coordinates reach"), std::string::npos);
  EXPECT_THROW(check(R"("position": [1e7, 1, 1e7])"), Error);
  EXPECT_THROW(check(R"("position": [0, 1, 0], "animation": {"orbit": {"radius": 1e7}})"), Error);
  EXPECT_EQ(check(R"("position": [1e7, 1, 1e7], "animation": {"orbit": {"radius": 2}})"), "");
  EXPECT_EQ(check(R"("position": [1e6, 1, 1e6], "scale": 1e4)"), "");  // as far, but as large
  // Floats step by the largest |coordinate|: at (3000, 3000, 3000) by 2^-12 (0.007 % of the
  // sphere's 3.5 diagonal), not by the step at the centre's length 5196 (2^-11, 0.014 %, warned).
  EXPECT_EQ(check(R"("position": [3000, 3000, 3000])"), "");
  EXPECT_NE(check(R"("position": [1e4, 1, 1e4])").find("placed where coordinates reach 10001.73"), std::string::npos)
      << check(R"("position": [1e4, 1, 1e4])");
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

// Splats at 1e-12 scale: their axes' cross product squares to below float range, and the file was
// refused as "no splat has an area" while the same mesh renders (a helper's audit of 3DGS files).
TEST(PresenterAssets, TinySplatsStillHaveDiscs) {
  std::vector<splats::SplatRecord> tiny(3);
  for (std::size_t i = 0; i < tiny.size(); ++i) {
    tiny[i].center = {static_cast<float>(i) * 3e-12f, 0, 0};
    tiny[i].normal = {0, 0, 1};
    tiny[i].major = {1e-12f, 0, 0};
    tiny[i].minor = {0, 5e-13f, 0};
  }
  const Mesh discs = splat_disc_mesh(tiny, "tiny.ply");
  EXPECT_EQ(discs.face_count(), 3u);
  tiny[0].minor = tiny[1].minor = tiny[2].minor = {0, 0, 0};
  EXPECT_THROW(splat_disc_mesh(tiny, "flat.ply"), Error);  // no area at all: still refused
}

}  // namespace
}  // namespace splatcl::present
