// Scene objects as users bring them: a mesh fitted to a size and rested on the floor, quality set
// per object, and ready-made splat files (splatcl's PLY and the 3D Gaussian Splatting export) as
// objects. Fits are checked against the object's placement matrix (not the fit's own arithmetic);
// splat-file objects against the mesh object whose splats they hold, rendered side by side.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdio>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>

#include "io/atomic_file.hpp"
#include "io/text_file.hpp"
#include "splats/gaussian_file.hpp"
#include "splats/splat_file.hpp"

#include "presenter_test_support.hpp"

namespace splatcl::present::testing {
namespace {

std::string temp_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("splatcl-scene-objects-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

Scene one_object_scene(const std::string& object_json, const std::string& directory = ".") {
  return parse_scene("{\"objects\": [" + object_json + "], \"lights\": {\"count\": 16}}", "s.json", directory);
}

struct Extent {
  glm::vec3 lo{INFINITY}, hi{-INFINITY};
  void add(glm::vec3 p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
  float largest() const { return std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}); }
};

TEST(SceneObjects, FitScalesToTheSizeAndRestsOnTheFloorUnderTheRotation) {
  const std::string torus = R"({"mesh": {"procedural": "torus", "radius": 0.9, "tube": 0.35, "segments": 24, "rings": 12},)";
  for (const char* rotation : {"[0, 0, 0]", "[70, 0, 0]", "[30, 45, -60]"}) {
    SCOPED_TRACE(rotation);
    const ObjectSpec plain = one_object_scene(torus + R"("rotation_degrees": )" + rotation + "}").objects[0];
    const ObjectSpec fitted = one_object_scene(torus + R"("fit": {"size": 3, "on_floor": true}, "position": [0.5, 0.25, -2], "rotation_degrees": )" +
                                               rotation + "}")
                                  .objects[0];
    const Mesh original = make_fitted_mesh(plain, ".");
    const Mesh mesh = make_fitted_mesh(fitted, ".");
    ASSERT_EQ(mesh.vertices.size(), original.vertices.size());
    // A uniform scale and a shift: every difference of two vertices scales by the same factor.
    Extent model, world;
    const float factor = 3.0f / [&] {
      Extent e;
      for (const auto& v : original.vertices) e.add({v.x, v.y, v.z});
      return e.largest();
    }();
    const glm::mat4 placement = fitted.placement(0.0f);
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      const glm::vec3 p(mesh.vertices[i].x, mesh.vertices[i].y, mesh.vertices[i].z);
      const glm::vec3 d = p - glm::vec3(mesh.vertices[0].x, mesh.vertices[0].y, mesh.vertices[0].z);
      const Vec3 o = original.vertices[i] - original.vertices[0];
      EXPECT_NEAR(glm::length(d - factor * glm::vec3(o.x, o.y, o.z)), 0.0f, 2e-5f) << "vertex " << i;
      model.add(p);
      world.add(glm::vec3(placement * glm::vec4(p, 1.0f)));
    }
    EXPECT_NEAR(model.largest(), 3.0f, 1e-5f);
    EXPECT_NEAR(world.lo.y, 0.25f, 1e-5f) << "the lowest point is at position.y";
  }
  // Without on_floor: the bounding box is centred on the object's origin.
  const ObjectSpec centred = one_object_scene(R"({"mesh": {"procedural": "box", "size": [2, 1, 0.5]}, "fit": {"size": 1}})").objects[0];
  Extent box;
  for (const auto& v : make_fitted_mesh(centred, ".").vertices) box.add({v.x, v.y, v.z});
  EXPECT_NEAR(box.largest(), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::length(box.lo + box.hi), 0.0f, 1e-6f);
}

// A mesh far from the origin keeps its detail through `fit`: the file is read about its bounding
// box's centre, in double. Read to float first, a unit-size sphere at 1e5 had its vertices moved by
// up to 0.0039 (0.4 % of its size) and its splats' outline was lumpy (a helper's audit).
TEST(SceneObjects, FitKeepsTheDetailOfAMeshFarFromTheOrigin) {
  const std::filesystem::path dir = temp_dir("far");
  std::vector<glm::dvec3> sphere;
  for (int i = 1; i < 12; ++i)
    for (int k = 0; k < 24; ++k) {
      const double theta = std::numbers::pi * i / 12, phi = 2 * std::numbers::pi * k / 24;
      sphere.push_back({0.5 * std::sin(theta) * std::cos(phi), 0.5 * std::cos(theta), 0.5 * std::sin(theta) * std::sin(phi)});
    }
  std::vector<std::array<int, 3>> faces;
  for (int i = 0; i + 1 < 11; ++i)
    for (int k = 0; k < 24; ++k) {
      const int a = i * 24 + k, b = i * 24 + (k + 1) % 24, c = a + 24, d = b + 24;
      faces.push_back({a, c, d}), faces.push_back({a, d, b});
    }
  // The same sphere at the origin and at `at`, as OBJ, OFF and ASCII PLY with doubles.
  const auto write = [&](const std::string& name, glm::dvec3 at) {
    std::string obj, off = fmt::format("OFF\n{} {} 0\n", sphere.size(), faces.size()),
                     ply = fmt::format("ply\nformat ascii 1.0\nelement vertex {}\nproperty double x\nproperty double y\nproperty double z\n"
                                       "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
                                       sphere.size(), faces.size());
    for (const glm::dvec3& v : sphere) {
      const std::string xyz = fmt::format("{:.17g} {:.17g} {:.17g}\n", v.x + at.x, v.y + at.y, v.z + at.z);
      obj += "v " + xyz, off += xyz, ply += xyz;
    }
    for (const auto& f : faces) {
      obj += fmt::format("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
      off += fmt::format("3 {} {} {}\n", f[0], f[1], f[2]), ply += fmt::format("3 {} {} {}\n", f[0], f[1], f[2]);
    }
    for (const auto& [extension, text] : {std::pair{".obj", obj}, {".off", off}, {".ply", ply}})
      splatcl::write_file_atomically((dir / (name + extension)).string(), text);
  };
  write("near", {0, 0, 0});
  write("far", {1e5, 1e5, 1e5});
  for (const char* extension : {".obj", ".off", ".ply"}) {
    SCOPED_TRACE(extension);
    const auto fitted = [&](const std::string& name) {
      return make_fitted_mesh(one_object_scene(fmt::format(R"({{"mesh": "{}{}", "fit": {{"size": 1, "on_floor": true}}}})", name, extension),
                                               dir.string())
                                  .objects[0],
                              dir.string());
    };
    const Mesh near = fitted("near"), far = fitted("far");
    ASSERT_EQ(near.vertices.size(), far.vertices.size());
    float moved = 0;
    for (std::size_t v = 0; v < near.vertices.size(); ++v) moved = std::max(moved, length(far.vertices[v] - near.vertices[v]));
    EXPECT_LE(moved, 1e-6f);
  }
  // A vertex no face uses does not set the box read about (at 1e6 it rounded the rest by 1/32).
  {
    std::ifstream in(dir / "far.obj");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    splatcl::write_file_atomically((dir / "stray.obj").string(), text + "v 1000000 0 0\n");
  }
  const auto fitted = [&](const std::string& file) {
    return make_fitted_mesh(one_object_scene(fmt::format(R"({{"mesh": "{}", "fit": {{"size": 1, "on_floor": true}}}})", file), dir.string()).objects[0],
                            dir.string());
  };
  const Mesh near = fitted("near.obj"), stray = fitted("stray.obj");
  ASSERT_EQ(near.vertices.size(), stray.vertices.size());
  for (std::size_t v = 0; v < near.vertices.size(); ++v) EXPECT_LE(length(stray.vertices[v] - near.vertices[v]), 1e-6f) << "vertex " << v;
}

// A trained capture's stray Gaussian far from the rest set the box a fit scales, and the object
// shrank to nothing without a word (a helper's audit: one Gaussian of semi-axis 40 beside a cow of
// size 1). The splat file's object now warns; a compact one does not.
TEST(SceneObjects, AFitAroundStraySplatsWarns) {
  std::vector<splats::SplatRecord> grid;
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) {
      splats::SplatRecord s;
      s.center = {0.05f * static_cast<float>(i), 0.0f, 0.05f * static_cast<float>(j)};
      s.normal = {0, 1, 0}, s.major = {0.03f, 0, 0}, s.minor = {0, 0, 0.03f};
      grid.push_back(s);
    }
  EXPECT_EQ(stray_splats_warning(grid), "");
  splats::SplatRecord floater = grid[0];
  floater.center = {30, 5, 0}, floater.major = {40, 0, 0}, floater.minor = {0, 0, 40};
  grid.push_back(floater);
  const std::string warning = stray_splats_warning(grid);
  EXPECT_EQ(warning.rfind("1 of 401 splats reach far outside the rest", 0), 0u) << warning;
}

TEST(SceneObjects, FitAndObjectQualityAreCheckedLikeEveryOtherKey) {
  const auto refused = [](const std::string& object, const std::string& expected) {
    try {
      one_object_scene(object);
      ADD_FAILURE() << "accepted " << object;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  const std::string box = R"("mesh": {"procedural": "box"})";
  refused("{" + box + R"(, "fit": {"size": 0}})", "'size' must be positive");
  // A fit or scale beyond what the assets' float geometry holds names the field (it named the mesh's
  // bounding sphere).
  refused("{" + box + R"(, "fit": {"size": 1e30}})", "'size' must be in [1e-15, 1e+15], not 1e+30");
  refused("{" + box + R"(, "scale": 1e-20})", "'scale' must be in [1e-15, 1e+15], not 1e-20");
  refused("{" + box + R"(, "fit": {"sise": 2}})", "'sise' is not a key of fit");
  refused("{" + box + R"(, "fit": 2})", "'fit' must be an object");
  refused("{" + box + R"(, "fit": {}})", "'fit' does nothing: give \"size\"");  // it did nothing without a word
  refused("{" + box + R"(, "fit": {"on_floor": false}})", "'fit' does nothing");
  refused("{" + box + R"(, "fit": {"on_floor": 1}})", "'on_floor' must be true or false");
  refused("{" + box + R"(, "quality": {"shading": "tiled"}})", "'shading' is not a key of objects[0].quality");
  refused("{" + box + R"(, "quality": {"eps_diagonal": -1}})", "'eps_diagonal' must be positive");
  refused("{" + box + R"(, "quality": {"csm_maps": 1000}})", "'csm_maps' 1000 is not a perfect square");
  refused("{" + box + R"(, "quality": {"crease_angle": 0}})", "'crease_angle' must be positive");
  refused("{" + box + R"(, "quality": {"crease_angle": 200}})", "'crease_angle' must be in (0, 180] degrees");
  refused("{" + box + R"(, "quality": {"surface_clip": -0.001}})", "'surface_clip' must be in [0, 0.1]");
  refused("{" + box + R"(, "quality": {"surface_clip": 0.5}})", "'surface_clip' must be in [0, 0.1]");
  refused(R"({"splats": "a.ply", "quality": {"surface_clip": 0.001}})", "its splats are used as they are");
  refused(R"({"splats": "a.ply", "quality": {"crease_angle": 30}})", "its splats are used as they are");
  refused("{" + box + R"(, "splats": "a.ply"})", "give either \"mesh\"");
  refused(R"({"name": "x"})", "objects[0] 'x': 'mesh' is missing");
  refused(R"({"splats": "a.ply", "texture": "t.png"})", "it brings its own colours");
  refused(R"({"splats": "a.ply", "quality": {"sampling": "auto"}})", "its splats are used as they are");
  refused(R"({"splats": ""})", "'splats' must be a file name");
  refused(R"({"mesh": "a.obj", "quality": {"csm_single_hit": "hollow"}})", "csm_single_hit");
}

TEST(SceneObjects, ObjectQualityOverridesOnlyThatObjectsAssets) {
  const Scene scene = parse_scene(R"({"objects": [
      {"name": "a", "mesh": {"procedural": "sphere", "segments": 12, "rings": 6}},
      {"name": "b", "mesh": {"procedural": "sphere", "segments": 12, "rings": 6},
       "quality": {"csm_maps": 256, "csm_resolution": 32, "eps_diagonal": 0.004, "splat_bound": "thesis", "sampling": "grid:1",
                   "crease_angle": 30, "surface_clip": 0.001}}],
      "quality": {"eps_diagonal": 0.002, "csm_maps": 1024, "csm_resolution": 16, "crease_angle": 75, "surface_clip": 0.003}})",
                                  "s.json", ".");
  const Quality a = object_quality(scene.quality, scene.objects[0]), b = object_quality(scene.quality, scene.objects[1]);
  EXPECT_EQ(a.csm_maps, 1024u);
  EXPECT_EQ(a.csm_resolution, 16u);
  EXPECT_FLOAT_EQ(a.eps_diagonal, 0.002f);
  EXPECT_EQ(a.splat_bound, "two-sided");
  EXPECT_EQ(a.sampling, "auto");
  EXPECT_FLOAT_EQ(a.crease_angle, 75.0f);
  EXPECT_FLOAT_EQ(a.surface_clip, 0.003f);
  EXPECT_EQ(b.csm_maps, 256u);
  EXPECT_EQ(b.csm_resolution, 32u);
  EXPECT_FLOAT_EQ(b.eps_diagonal, 0.004f);
  EXPECT_EQ(b.splat_bound, "thesis");
  EXPECT_EQ(b.sampling, "grid:1");
  EXPECT_FLOAT_EQ(b.crease_angle, 30.0f);
  EXPECT_FLOAT_EQ(b.surface_clip, 0.001f);
  EXPECT_EQ(b.shading, scene.quality.shading);  // the frame's settings stay the scene's
}

class SceneObjectsRender : public PresenterTest {};

// Without "depth_offset" ("shadow_lift") the visibility ε (the shadow lift) follows the smallest
// object (1/100 of its diagonal at its scale) where that is below the default, so a small scene does
// not blend its floor through its objects (lift its floor out of their shadows), and 1/125 of it
// where that is above; given, it is kept; the default scene keeps 0.02.
TEST_F(SceneObjectsRender, DefaultDepthOffsetAndShadowLiftFollowTheSmallestObject) {
  const auto lengths_of = [&](const std::string& text) {
    Presenter presenter(parse_scene(text, "eps.json", "."), *runtime_, 32, 24, SPLATCL_TEST_CACHE);
    return std::pair{presenter.scene().quality.depth_offset, presenter.scene().quality.shadow_lift};
  };
  const std::string small = R"({"name": "small", "mesh": {"procedural": "box", "size": [0.1, 0.1, 0.1], "rings": 2}, "position": [0, 0.05, 0]})";
  const float diagonal = 0.1f * std::sqrt(3.0f);
  const auto [offset, lift] = lengths_of(R"({"objects": [)" + small + "]}");
  EXPECT_NEAR(offset, 0.01f * diagonal, 1e-6f);
  EXPECT_NEAR(lift, 0.01f * diagonal, 1e-6f);
  // The object's scale counts.
  EXPECT_NEAR(lengths_of(R"({"objects": [{"name": "s", "mesh": {"procedural": "box", "rings": 2}, "scale": 0.05}]})").first,
              0.01f * 0.05f * std::sqrt(3.0f), 1e-6f);
  const auto given = lengths_of(R"({"objects": [)" + small + R"(], "quality": {"depth_offset": 0.02, "shadow_lift": 0.03}})");
  EXPECT_FLOAT_EQ(given.first, 0.02f);
  EXPECT_FLOAT_EQ(given.second, 0.03f);
  // The default scene's smallest object, its box, keeps the default; larger ones raise it to 0.008
  // of their diagonal.
  const auto as_default = lengths_of(R"({"objects": [{"name": "box", "mesh": {"procedural": "box", "size": [1.4, 1.4, 1.4], "rings": 2}}]})");
  EXPECT_FLOAT_EQ(as_default.first, 0.02f);
  EXPECT_FLOAT_EQ(as_default.second, 0.02f);
  const auto big = lengths_of(R"({"objects": [{"name": "big", "mesh": {"procedural": "box", "size": [30, 30, 30], "rings": 2}}]})");
  EXPECT_NEAR(big.first, 0.008f * 30 * std::sqrt(3.0f), 1e-5f);
  EXPECT_NEAR(big.second, 0.008f * 30 * std::sqrt(3.0f), 1e-5f);
}

// The truth those defaults claim: a scene scaled by 0.01 or by 10⁴ looks like the scene itself. A
// sphere resting on the floor beside a box, with a key light, in the normals and the shadows views:
// with the fixed ε of 0.02 the small scene showed the floor through the lower half of its objects;
// with the fixed shadow lift of 0.02 the floor's receivers rose above its objects and out of their
// shadows. In the large scene that ε let the splats of one surface hide each other (629 pixels
// apart in the normals view), and the floor's fixed 1e-3 tolerance missed the floor's own pixels,
// so its shadows came from its splats (468 pixels apart; 16 and 68 now).
TEST_F(SceneObjectsRender, AScaledSceneKeepsItsGeometryAndShadows) {
  const auto views_at = [&](float s) {
    const auto v = [&](float x, float y, float z) { return fmt::format("[{:.9g}, {:.9g}, {:.9g}]", s * x, s * y, s * z); };
    const std::string text = fmt::format(
        R"({{"objects": [{{"name": "ball", "mesh": {{"procedural": "sphere", "radius": {:.9g}, "segments": 24, "rings": 12}}, "position": {}}},
                         {{"name": "box", "mesh": {{"procedural": "box", "size": {}, "rings": 2}}, "position": {}}}],
             "floor": {{"size": {:.9g}, "splats_per_side": 16}}, "lights": {{"count": 0}},
             "key_lights": [{{"position": {}, "radius": {:.9g}}}],
             "camera": {{"eye": {}, "target": {}, "fov_y_degrees": 40, "near": {:.9g}, "far": {:.9g}}}}})",
        s * 1.0f, v(0, 1, 0), v(1, 1, 1), v(1.8f, 0.5f, 0.3f), s * 8.0f, v(-1.5f, 5, 1), s * 40.0f, v(0.5f, 1.2f, 5), v(0.5f, 0.6f, 0),
        s * 0.1f, s * 50.0f);
    Presenter presenter(parse_scene(text, "scaled.json", "."), *runtime_, 160, 120, SPLATCL_TEST_CACHE);
    std::vector<std::vector<float>> views;
    for (const DebugView view : {DebugView::Normals, DebugView::Shadows}) {
      presenter.debug_view = view;
      presenter.render(0.0f);
      views.push_back(presenter.read_display_rgb());
    }
    return views;
  };
  const auto full = views_at(1.0f);
  for (const float scale : {0.01f, 1e4f}) {
    const auto scaled = views_at(scale);
    ASSERT_EQ(full[0].size(), scaled[0].size());
    ASSERT_EQ(full[1].size(), scaled[1].size());
    const std::size_t pixels = full[0].size() / 3;
    std::size_t normals_differ = 0, shadows_differ = 0, dark = 0;
    double shadow_difference = 0;
    for (std::size_t i = 0; i < 3 * pixels; i += 3) {
      const std::vector<float>&a = full[0], &b = scaled[0];
      normals_differ += std::fabs(a[i] - b[i]) + std::fabs(a[i + 1] - b[i + 1]) + std::fabs(a[i + 2] - b[i + 2]) > 8.0f / 255.0f;
      const float shadow_full = full[1][i], shadow_scaled = scaled[1][i];  // grey: the darkest key light's visibility
      shadow_difference += std::fabs(shadow_full - shadow_scaled);
      shadows_differ += std::fabs(shadow_full - shadow_scaled) > 0.25f;
      dark += shadow_full < 0.5f;
    }
    fmt::print("scale {:g}: {} pixels differ in the normals view, {} in the shadows view (mean {:.4f})\n", scale, normals_differ,
               shadows_differ, shadow_difference / static_cast<double>(pixels));
    EXPECT_LE(normals_differ, 30u) << "scale " << scale << ", of " << pixels << " pixels";
    EXPECT_GT(dark, 500u) << "the objects cast shadows at 1x";
    // At 0.01 with the fixed lift of 0.02: 1,736 pixels apart, a mean difference of 0.068 (44 and
    // 0.0029 now, along the penumbrae and the box's contact with the floor).
    EXPECT_LE(shadows_differ, 150u) << "scale " << scale << ", of " << pixels << " pixels";
    EXPECT_LE(shadow_difference / static_cast<double>(pixels), 0.01) << "scale " << scale;
  }
}

TEST_F(SceneObjectsRender, ObjectQualityShapesTheBuiltAssets) {
  const Scene scene = parse_scene(R"({"objects": [
      {"name": "a", "mesh": {"procedural": "box", "rings": 4}},
      {"name": "b", "mesh": {"procedural": "box", "rings": 4}, "quality": {"csm_maps": 256, "csm_resolution": 32, "eps_diagonal": 0.004}},
      {"name": "c", "mesh": {"procedural": "box", "rings": 4}, "quality": {"crease_angle": 180}},
      {"name": "d", "mesh": {"procedural": "box", "rings": 4}, "quality": {"csm_single_hit": "thin"}}],
      "quality": {"eps_diagonal": 0.002, "csm_resolution": 16}})",
                                  "s.json", ".");
  const ObjectAssets a = load_object_assets(scene.objects[0], scene, SPLATCL_TEST_CACHE, *runtime_);
  const ObjectAssets b = load_object_assets(scene.objects[1], scene, SPLATCL_TEST_CACHE, *runtime_);
  EXPECT_EQ(a.csm.info.resolution, 16u);
  EXPECT_EQ(a.csm.info.maps, 1024u);
  EXPECT_EQ(b.csm.info.resolution, 32u);
  EXPECT_EQ(b.csm.info.maps, 256u);
  EXPECT_NE(a.key, b.key);
  // The crease angle shapes the splats: without it the box's splats bevel its edges.
  const ObjectAssets c = load_object_assets(scene.objects[2], scene, SPLATCL_TEST_CACHE, *runtime_);
  EXPECT_NE(a.key, c.key);
  // The CSM's single-hit rule: auto takes sphere-exit for the closed box; "thin" is built, recorded
  // and keyed as such.
  EXPECT_EQ(a.csm.info.single_hit, csm::SingleHit::SphereExit);
  const ObjectAssets d = load_object_assets(scene.objects[3], scene, SPLATCL_TEST_CACHE, *runtime_);
  EXPECT_EQ(d.csm.info.single_hit, csm::SingleHit::Thin);
  EXPECT_NE(a.key, d.key);
  const auto bevelled = [](const ObjectAssets& assets) {
    std::size_t count = 0;
    for (const auto& s : assets.splats) {
      const float largest = std::max({std::fabs(s.normal.x), std::fabs(s.normal.y), std::fabs(s.normal.z)});
      count += largest < std::cos(glm::radians(8.0f)) * length(s.normal);
    }
    return count;
  };
  EXPECT_EQ(bevelled(a), 0u);
  EXPECT_GT(bevelled(c), 0u);
}

// A mesh object, and the same splats read from a splatcl splat file and from a 3DGS export, drawn
// alone with the same camera: the splat file gives the very same depth (same splat geometry) and an
// image within a quarter of a level (the Phong splats' normal fields: the mesh object's fitted to the mesh, the
// splat file's to the neighbouring splats); the 3DGS export the same within its float round trip;
// the discs' shadow map shades the floor as the mesh's.
TEST_F(SceneObjectsRender, SplatFilesDrawAsTheMeshObjectTheyCameFrom) {
  const std::string dir = temp_dir("splat-files");
  const std::string sphere = R"("mesh": {"procedural": "sphere", "radius": 1, "segments": 24, "rings": 12}, "quality": {"eps_diagonal": 0.004})";
  const std::string place = R"("color": [0.8, 0.5, 0.3], "position": [0, 1.1, 0])";
  const auto scene_of = [&](const std::string& object) {
    Scene s = parse_scene(R"({"objects": [)" + object + R"(], "lights": {"count": 32, "seed": 3},
        "key_lights": [{"position": [3, 6, 4], "radius": 20, "color": [0.7, 0.65, 0.55]}],
        "camera": {"eye": [0, 2.5, 4.5], "target": [0, 0.8, 0], "up": [0, 1, 0], "fov_y_degrees": 45, "near": 0.1, "far": 30}})",
                          "s.json", dir);
    s.floor.splats_per_side = 48;
    s.quality.surface_clip = 0;  // the mesh object draws its splats as built, as the splat file holds them
    return s;
  };
  const Scene mesh_scene = scene_of("{" + sphere + ", " + place + "}");
  const ObjectAssets built = load_object_assets(mesh_scene.objects[0], mesh_scene, SPLATCL_TEST_CACHE, *runtime_);
  splats::write_splat_file(dir + "/sphere.splats.ply", built.splats, splats::SplatFileInfo{"sphere", "auto", 0.01f, 10, 255, "grey", false});
  splats::write_gaussian_file(dir + "/sphere.3dgs.ply", built.splats);

  const Scene ours = scene_of(R"({"splats": "sphere.splats.ply", )" + place + "}");
  const Scene gaussian = scene_of(R"({"splats": "sphere.3dgs.ply", )" + place + "}");
  const ObjectAssets from_file = load_object_assets(ours.objects[0], ours, SPLATCL_TEST_CACHE, *runtime_);
  ASSERT_EQ(from_file.splats.size(), built.splats.size());
  EXPECT_EQ(from_file.mesh.face_count(), built.splats.size()) << "one disc per splat";
  for (std::size_t i = 0; i < built.splats.size(); ++i) {
    EXPECT_EQ(from_file.splats[i].center, built.splats[i].center);
    EXPECT_EQ(from_file.splats[i].major, built.splats[i].major);
  }

  std::vector<float> view_z;  // of the last render
  const auto render = [&](const Scene& scene, bool shadows) {
    Presenter presenter(scene, *runtime_, 160, 120, SPLATCL_TEST_CACHE);
    presenter.scene().quality.shadows = shadows ? "splat" : "off";
    presenter.ambient_occlusion = shadows;
    presenter.render(0.0f);
    view_z = presenter.read_view_z();
    return presenter.read_display_rgb();
  };
  const auto mean_difference = [](const std::vector<float>& a, const std::vector<float>& b) {
    double sum = 0;
    for (std::size_t i = 0; i < a.size(); ++i) sum += std::abs(a[i] - b[i]);
    return sum / static_cast<double>(a.size());
  };
  const std::vector<float> reference = render(mesh_scene, false);
  const std::vector<float> reference_z = view_z;
  const double flat = mean_difference(render(ours, false), reference);  // of the splat file
  const std::vector<float> ours_z = view_z;
  const double gaussian_difference = mean_difference(render(gaussian, false), reference);
  std::printf("splat file against the mesh object: mean difference %.3f/255 (3DGS export %.3f/255)\n", flat * 255, gaussian_difference * 255);
  EXPECT_EQ(ours_z, reference_z) << "the same splats, the same depth";
  EXPECT_LT(flat, 0.25 / 255.0);
  EXPECT_LT(gaussian_difference, 0.25 / 255.0);
  // Shadows and AO from the discs' CSM instead of the mesh's: the sphere's own shading and its
  // shadow on the floor agree to a few levels.
  const double lit = mean_difference(render(ours, true), render(mesh_scene, true));
  EXPECT_LT(lit, 4.0 / 255.0) << "mean difference " << lit * 255 << "/255";
  std::filesystem::remove_all(dir);
}

// A splat file whose positions are relative to an origin (splats read a mesh far out about its
// box's centre; splatcl's 3DGS export keeps it as a comment): without a fit its splats go where the
// model's coordinates put them, the origin added; with a fit they are placed by their box, where the origin cancels, as the same splats
// recorded at origin zero.
TEST_F(SceneObjectsRender, SplatFileOriginPlacesItsSplats) {
  const std::string dir = temp_dir("splat-origin");
  std::vector<splats::SplatRecord> grid;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      grid.push_back({{0.2f * static_cast<float>(i), 0, 0.2f * static_cast<float>(j)}, {0, 1, 0}, {0.15f, 0, 0}, {0, 0, 0.15f}, Rgba8{200, 200, 200, 255}});
  splats::SplatFileInfo info{"plate", "auto", 0.01f, 10, 255, "grey", false};
  splats::write_splat_file(dir + "/at-zero.ply", grid, info);
  info.origin = {12.5, 0.25, -3};
  splats::write_splat_file(dir + "/at-origin.ply", grid, info);
  const auto assets_of = [&](const std::string& object) {
    const Scene s = parse_scene(R"({"objects": [)" + object + "]}", "s.json", dir);
    return load_object_assets(s.objects[0], s, SPLATCL_TEST_CACHE, *runtime_);
  };
  splats::write_gaussian_file(dir + "/at-origin.3dgs.ply", grid, info.origin);
  for (const char* file : {"at-origin.ply", "at-origin.3dgs.ply"}) {
    const ObjectAssets placed = assets_of(fmt::format(R"({{"splats": "{}"}})", file));
    ASSERT_EQ(placed.splats.size(), grid.size()) << file;
    for (std::size_t i = 0; i < grid.size(); ++i) EXPECT_EQ(placed.splats[i].center, to_float(info.origin + DVec3(grid[i].center))) << file << " " << i;
  }
  // An origin that takes the splats beyond float range is refused, naming it (it placed them at inf).
  info.origin = {1e300, 0, 0};
  splats::write_splat_file(dir + "/beyond.ply", grid, info);
  try {
    assets_of(R"({"splats": "beyond.ply"})");
    ADD_FAILURE() << "splats at 1e300 were placed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("beyond.ply: its splats placed at its splatcl_origin (1e+300, 0, 0) leave float range"),
              std::string::npos)
        << e.what();
  }
  info.origin = {12.5, 0.25, -3};
  const ObjectAssets fitted = assets_of(R"({"splats": "at-origin.ply", "fit": {"size": 2, "on_floor": true}})");
  const ObjectAssets fitted_zero = assets_of(R"({"splats": "at-zero.ply", "fit": {"size": 2, "on_floor": true}})");
  ASSERT_EQ(fitted.splats.size(), grid.size());
  for (std::size_t i = 0; i < grid.size(); ++i) {
    EXPECT_EQ(fitted.splats[i].center, fitted_zero.splats[i].center) << i;
    EXPECT_EQ(fitted.splats[i].major, fitted_zero.splats[i].major) << i;
  }
  std::filesystem::remove_all(dir);
}

// A closed object thinner than the CSM's hit epsilon (a 10 x 0.0001 x 10 box: epsilon 0.000141
// units) is met once by the rays through it and stored as solid behind it: the presenter warns with
// the scene's spelling of the remedy, which silences it; a box 1 thick is not warned of.
TEST_F(SceneObjectsRender, ThinClosedObjectsAreWarnedOf) {
  const std::string dir = temp_dir("thin-object");
  const auto warning_of = [&](const std::string& size, const std::string& rule) {
    const Scene s = parse_scene(R"({"objects": [{"name": "plate", "mesh": {"procedural": "box", "size": )" + size +
                                    R"(}, "quality": {"csm_maps": 64, "csm_resolution": 16, "csm_single_hit": ")" + rule + R"("}}]})",
                                "s.json", dir);
    return load_object_assets(s.objects[0], s, SPLATCL_TEST_CACHE, *runtime_).thin_part_warning;
  };
  const std::string thin = warning_of("[10, 0.0001, 10]", "auto");
  EXPECT_NE(thin.find("sample rays that hit this closed mesh"), std::string::npos) << thin;
  // The same from a fresh cache (built), from the cached answer, and sampled again for a cached CSM
  // whose answer is missing.
  {
    const Scene s = parse_scene(R"({"objects": [{"name": "plate", "mesh": {"procedural": "box", "size": [10, 0.0001, 10]},
        "quality": {"csm_maps": 64, "csm_resolution": 16}}]})", "s.json", dir);
    const std::string cache = dir + "/cache";
    std::filesystem::create_directories(cache);
    const ObjectAssets built = load_object_assets(s.objects[0], s, cache, *runtime_);
    EXPECT_FALSE(built.csm_cached);
    EXPECT_EQ(built.thin_part_warning, thin);
    std::size_t answers = 0;
    for (const auto& file : std::filesystem::directory_iterator(cache))
      if (file.path().extension() == ".thin1") ++answers;
    EXPECT_EQ(answers, 1u);
    const ObjectAssets cached = load_object_assets(s.objects[0], s, cache, *runtime_);
    EXPECT_TRUE(cached.csm_cached);
    EXPECT_EQ(cached.thin_part_warning, thin);
    for (const auto& file : std::filesystem::directory_iterator(cache))
      if (file.path().extension() == ".thin1") std::filesystem::remove(file.path());
    EXPECT_EQ(load_object_assets(s.objects[0], s, cache, *runtime_).thin_part_warning, thin);
  }
  EXPECT_NE(thin.find("give the object \"quality\": {\"csm_single_hit\": \"exact\"}"), std::string::npos) << thin;
  EXPECT_EQ(warning_of("[10, 0.0001, 10]", "exact"), "");
  EXPECT_EQ(warning_of("[10, 1, 10]", "auto"), "");
  std::filesystem::remove_all(dir);
}

// The shipped scene of scanned models (data/scans-scene.json), when the test models are present:
// each scan fitted to its size and resting on the floor.
TEST(SceneObjects, ScansSceneRestsEachScanOnTheFloor) {
  const std::string models = SPLATCL_MODELS_DIR;
  if (!std::filesystem::exists(models + "/stanford-bunny.obj") || !std::filesystem::exists(models + "/nefertiti.obj"))
    GTEST_SKIP() << "the test models are not in " << models << " (link them into data/models)";
  const std::string dir = temp_dir("scans");
  std::filesystem::create_directory_symlink(models, dir + "/models");
  const std::string path = std::string(SPLATCL_DATA_DIR) + "/scans-scene.json";
  const Scene scene = parse_scene(read_text_file(path, "scene"), path, dir);
  std::size_t scans = 0;
  for (const ObjectSpec& object : scene.objects) {
    if (object.mesh.path.empty()) continue;
    ++scans;
    SCOPED_TRACE(object.name);
    const Mesh mesh = make_fitted_mesh(object, scene.directory);
    Extent model, world;
    const glm::mat4 placement = object.placement(0.0f);
    for (const auto& v : mesh.vertices) {
      model.add({v.x, v.y, v.z});
      world.add(glm::vec3(placement * glm::vec4(v.x, v.y, v.z, 1.0f)));
    }
    EXPECT_NEAR(model.largest(), object.fit.size, 1e-5f * object.fit.size);
    EXPECT_NEAR(world.lo.y, scene.floor.y, 1e-4f);
    EXPECT_LT(std::max(std::abs(world.lo.x), std::abs(world.hi.x)), 0.5f * scene.floor.size) << "on the floor square";
  }
  EXPECT_EQ(scans, 2u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace splatcl::present::testing
