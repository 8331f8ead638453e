// Level of detail: the sequential point tree (a cut at every threshold, its file round trip) and the
// presenter drawing fewer splats far away while keeping the silhouette.
#include <gtest/gtest.h>

#include <cfloat>
#include <filesystem>
#include <fstream>

#include "present/lod.hpp"

#include "presenter_test_support.hpp"

namespace splatcl::present {
namespace {

using namespace testing;

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

}  // namespace
}  // namespace splatcl::present
