// The presenter's images: the default scene against a stored reference image, clustered == tiled ==
// brute-force shading on the same G-buffer, no holes against the triangle mesh, the debug views,
// Blinn-Phong, per-splat colours, and wall-clock pass timing.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cstring>
#include <string>

#include "presenter_test_support.hpp"

namespace splatcl::present {
namespace {

using namespace testing;

TEST_F(PresenterTest, ContextIsOpenGl45Core) {
  EXPECT_NE(context_->renderer().find("4.5"), std::string::npos) << context_->renderer();
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

// Every debug view shows what it names: values in [0, 1]; the final view's sky behind the splats,
// black there in the others; grey where the view is one number (AO, shadows, depth); normals of
// unit length; colours in the light-count heat map; each view different from the final image.
TEST_F(PresenterTest, DebugViewsRender) {
  Presenter presenter(test_scene(), *runtime_, 96, 64, SPLATCL_TEST_CACHE);
  std::vector<float> final_rgb;
  for (int v = 0; v < 8; ++v) {
    const DebugView view = static_cast<DebugView>(v);
    presenter.debug_view = view;
    presenter.render(0.0f);
    const std::vector<float> rgb = presenter.read_display_rgb();
    const std::vector<std::uint8_t> covered = presenter.read_coverage();
    ASSERT_EQ(rgb.size(), 3 * covered.size()) << to_string(view);
    const bool grey = view == DebugView::AmbientOcclusion || view == DebugView::Shadows || view == DebugView::Depth;
    std::size_t splat_pixels = 0, out_of_range = 0, background_lit = 0, not_grey = 0, coloured = 0;
    double splat_sum = 0, normal_length = 0;
    for (std::size_t p = 0; p < covered.size(); ++p) {
      const float r = rgb[3 * p], g = rgb[3 * p + 1], b = rgb[3 * p + 2];
      for (const float c : {r, g, b}) out_of_range += !(c >= 0.0f && c <= 1.0f);
      if (!covered[p]) {
        background_lit += r + g + b > 0.0f;
        continue;
      }
      ++splat_pixels;
      splat_sum += r + g + b;
      not_grey += r != g || g != b;
      coloured += std::max({r, g, b}) - std::min({r, g, b}) > 0.1f;
      if (view == DebugView::Normals) {  // 0.5 n + 0.5, then the display's 1/2.2 gamma
        const auto component = [](float c) { return 2.0 * std::pow(static_cast<double>(c), 2.2) - 1.0; };
        normal_length += std::hypot(component(r), component(g), component(b));
      }
    }
    const std::string name = to_string(view);
    ASSERT_GT(splat_pixels, covered.size() / 10) << name;
    EXPECT_EQ(out_of_range, 0u) << name;
    EXPECT_GT(splat_sum, 0.0) << name;
    if (view == DebugView::Final) {
      EXPECT_EQ(background_lit, covered.size() - splat_pixels) << "the sky behind the splats";
      final_rgb = rgb;
      continue;
    }
    EXPECT_EQ(background_lit, 0u) << name;
    EXPECT_NE(rgb, final_rgb) << name;
    if (grey) {
      EXPECT_EQ(not_grey, 0u) << name;
    }
    if (view == DebugView::Normals) {
      EXPECT_NEAR(normal_length / static_cast<double>(splat_pixels), 1.0, 0.01);
    }
    if (view == DebugView::LightsPerCluster) {
      EXPECT_GT(coloured, splat_pixels / 2) << name;
    }
  }
  EXPECT_THROW(parse_debug_view("wireframe"), Error);
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

// The depth buffer holds reversed depth (near 1, far 0), so its float steps stay about 2^-24 of
// the distance at every distance. With the standard mapping they grew as distance^2 / near: at near
// 1e-5 they passed the visibility pass's offset and the floor's splats hid each other in bands, and
// the torus showed dark specks. A near plane 10^4 times closer gives the same image.
TEST_F(PresenterTest, ASmallNearPlaneGivesTheSameImage) {
  const auto render_with_near = [&](float near_plane) {
    Scene scene = test_scene();
    scene.camera.near_plane = near_plane;
    Presenter presenter(scene, *runtime_, 160, 120, SPLATCL_TEST_CACHE);
    presenter.render(0.0f);
    return presenter.read_display_rgb();
  };
  const std::vector<float> usual = render_with_near(0.1f), close = render_with_near(1e-5f);
  ASSERT_EQ(usual.size(), close.size());
  std::size_t off = 0;
  for (std::size_t i = 0; i < usual.size(); ++i) off += std::abs(usual[i] - close[i]) > 8.0f / 255.0f;
  EXPECT_EQ(off, 0u) << "of " << usual.size() << " values";
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
  EXPECT_EQ(pass_names(walled), (std::vector<std::string>{"gl: splat visibility", "gl: splat accumulation", "gl: shading", "gl: silhouette resolve"}));
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
