// The presenter's assets: the cache hit the second time, unreadable entries rebuilt, and the splat
// method chosen by quality.splat_bound under its own cache key.
#include <gtest/gtest.h>

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
  EXPECT_TRUE(presenter.assets(0).tree_cached);
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
  ASSERT_EQ(corrupted, 4u);  // splats, the drawn splats' gap splats, LOD tree, CSM
  {
    Presenter rebuilt(scene, *runtime_, 32, 32, dir.string());
    EXPECT_FALSE(rebuilt.assets(0).splats_cached);
    EXPECT_FALSE(rebuilt.assets(0).gaps_cached);
    EXPECT_FALSE(rebuilt.assets(0).tree_cached);
    EXPECT_FALSE(rebuilt.assets(0).csm_cached);
    EXPECT_GT(rebuilt.assets(0).splats.size(), 500u);
  }
  Presenter cached(scene, *runtime_, 32, 32, dir.string());
  EXPECT_TRUE(cached.assets(0).splats_cached);
  EXPECT_TRUE(cached.assets(0).gaps_cached);
  EXPECT_TRUE(cached.assets(0).tree_cached);
  EXPECT_TRUE(cached.assets(0).csm_cached);
  std::filesystem::remove_all(dir);
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

}  // namespace
}  // namespace splatcl::present
