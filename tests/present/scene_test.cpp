// The presenter's scene files: the default scene, one-line errors naming the source and field,
// procedural meshes and cache keys, and the validation of every quality option.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "csm/build.hpp"
#include "csm/sphere_grid.hpp"
#include "present/assets.hpp"
#include "present/overrides.hpp"
#include "presenter_test_support.hpp"

namespace splatcl::present {
namespace {

using namespace testing;

// The error parse_scene gives for `text` as "bad.json", or "no error".
std::string message(const std::string& text) {
  try {
    parse_scene(text, "bad.json", ".");
  } catch (const Error& e) {
    return std::string(e.what());
  }
  return std::string("no error");
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
  EXPECT_NE(message("{\"objects\": [{\"mesh\": {\"procedural\": \"cone\"}}]}").find("bad.json: objects[0] 'object 0': 'procedural'"), std::string::npos);
  EXPECT_NE(message("{\"objects\": [], \"quality\": {\"mode\": \"fast\"}}").find("'mode'"), std::string::npos);
  EXPECT_NE(message("{\"objects\": [], \"lights\": {\"count\": -1}}").find("'count'"), std::string::npos);
  EXPECT_NE(message("[1, 2]").find("bad.json"), std::string::npos);
  EXPECT_NE(message("{\"objects\": [{\"name\": \"a\"}]}").find("bad.json: objects[0] 'a': 'mesh' is missing"), std::string::npos);
  EXPECT_THROW(parse_frame_size("640by480", "--size"), Error);
  EXPECT_EQ(parse_frame_size("640x480", "--size"), std::make_pair(640, 480));
}

// Values of the right type that would render nonsense are refused, each naming the file, the part
// of the scene and the field; the camera's geometric checks name the file too.
TEST(PresenterScene, RefusesValuesThatRenderNonsense) {
  const std::string box = R"({"name": "b", "mesh": {"procedural": "box"})";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"objects": [], "key_lights": [{"radius": 5}]})", "bad.json: key_lights[0]: 'position' is missing"},
      {R"({"objects": [], "key_lights": [{"position": [0, 3, 0], "color": [1, -1, 1]}]})", "key_lights[0]: 'color' must have no negative channel"},
      {R"({"objects": [], "lights": [{"position": [0, 1, 0], "color": [-0.5, 1, 1]}]})", "lights[0]: 'color' must have no negative channel"},
      {R"({"objects": [)" + box + R"(, "color": [1.5, 0.2, 0.2]}]})", "objects[0] 'b': 'color' must have every channel in [0, 1]"},
      {R"({"objects": [)" + box + R"(, "color": -0.1}]})", "objects[0] 'b': 'color' must have every channel in [0, 1]"},
      {R"({"objects": [)" + box + "}, " + box + "}]}", "'b' is used by objects[0] and objects[1]"},
      {R"({"objects": [], "floor": {"color": [0.5, 0.5, -0.5]}})", "bad.json: floor: 'color' must have every channel in [0, 1]"},
      {R"({"objects": [], "floor": {"size": -2}})", "bad.json: floor: 'size' must be positive"},
      {R"({"objects": [], "sky": {"ground": [0, -1, 0]}})", "'ground' must have no negative channel"},
      {R"({"objects": [], "quality": {"depth_offset": -0.001}})", "'depth_offset' must not be negative"},
      {R"({"objects": [], "quality": {"ao_bias": -0.01}})", "'ao_bias' must not be negative"},
      {R"({"objects": [], "quality": {"ao_bias": 2000}})", "'ao_bias' must be in [0, 1000] texels, not 2000"},
      {R"({"objects": [], "quality": {"shadow_lift": -0.01}})", "'shadow_lift' must not be negative"},
      {R"({"objects": [{"name": "a", "mesh": {"procedural": "box"}, "two_sided": "yes"}]})", "objects[0] 'a': 'two_sided' must be true or false"},
      {R"({"objects": [{"name": "a", "mesh": {"procedural": "box"}, "rotation_degrees": [0, 1e30, 0]}]})",
       "objects[0] 'a': 'rotation_degrees' 1e+30 is beyond 100 turns"},
      {R"({"objects": [], "quality": {"antialias": -1}})", "'antialias' must not be negative"},
      // Accepted with no upper bound until a helper's audit: 1e30 blended the objects through each
      // other (depth_offset) or turned them at random (the rates).
      {R"({"objects": [], "quality": {"antialias": 1.5}})", "'antialias' must be in [0, 1]"},
      {R"({"objects": [], "quality": {"depth_offset": 1e30}})", "'depth_offset' must be at most 1e+15 world units"},
      {R"({"objects": [], "quality": {"shadow_lift": 1e30}})", "'shadow_lift' must be at most 1e+15 world units"},
      {R"({"objects": [{"name": "a", "mesh": {"procedural": "box"}, "animation": {"spin_degrees_per_second": [0, 1e30, 0]}}]})",
       "objects[0] 'a': 'spin_degrees_per_second' 1e+30 is beyond 100 turns a second"},
      {R"({"objects": [{"name": "a", "mesh": {"procedural": "box"}, "animation": {"orbit": {"degrees_per_second": -4e4}}}]})",
       "objects[0] 'a': 'degrees_per_second' -40000 is beyond 100 turns a second"},
      {R"({"objects": [{"name": "a", "mesh": {"procedural": "box"}, "animation": {"orbit": {"phase_degrees": 1e30}}}]})",
       "objects[0] 'a': 'phase_degrees' 1e+30 is beyond 100 turns"},
      // A key given twice: the later value won silently (a helper's audit: an object named twice).
      {R"({"objects": [{"name": "a", "name": "b", "mesh": {"procedural": "box"}}]})", "bad.json: objects[0]: key 'name' appears twice in one object"},
      {R"({"objects": [], "quality": {"specular": 1, "specular": 2}})", "bad.json: quality: key 'specular' appears twice in one object"},
      {R"({"objects": [], "quality": {"specular": 1000}})", "'specular' must be in [0, 100]"},
      // A light beyond 1.8e19 from what it lit shaded it black (float squares of its distance are inf).
      {R"({"objects": [], "lights": [{"position": [0, 0, 2e19], "radius": 1e15}]})",
       "bad.json: lights[0]: 'position' coordinates must be within ±1e+15, not 2e+19"},
      {R"({"objects": [], "key_lights": [{"position": [0, 0, 1], "radius": 4e19}]})", "key_lights[0]: 'radius' must be in [1e-15, 1e+15], not 4e+19"},
      {R"({"objects": [], "lights": [{"position": [0, 0, 1], "radius": 1, "size": 1e30}]})", "lights[0]: 'size' must be in [0, 1e+15]"},
      {R"({"objects": [], "lights": {"count": 4, "radius": [1, 1e20]}})", "bad.json: lights: 'radius' must be within [1e-15, 1e+15]"},
      {R"({"objects": [], "lights": {"count": 4, "height": [1, 1e20]}})", "bad.json: lights: 'height' must be at most 1e+15"},
      {R"({"objects": [], "lights": {"count": 4, "extent": 1e20}})", "bad.json: lights: 'extent' must be at most 1e+15"},
      {R"({"objects": [], "lights": {"count": 4, "extent": -3}})", "bad.json: lights: 'extent' must not be negative"},
      {R"({"objects": [], "lights": {"count": 4, "height": [-1, 2]}})", "bad.json: lights: 'height' must not be negative"},
      {R"({"objects": [], "camera": {"eye": [0, 1, 0], "target": [0, 1, 0]}})", "bad.json: camera eye and target coincide"},
      {R"({"objects": [], "camera": {"eye": [0, 1, 0], "target": [0, 2, 0], "up": [0, -3, 0]}})", "bad.json: camera up vector is parallel"},
  };
  // Straight down or up without an "up": image up is -z (the default +y was refused as parallel),
  // and a short up vector keeps its direction.
  for (const float target_y : {-5.0f, 5.0f}) {
    const Scene top = parse_scene(R"({"objects": [], "camera": {"eye": [0, 0, 0], "target": [0, )" + std::to_string(target_y) + ", 0]}}",
                                  "top.json", ".");
    EXPECT_EQ(top.camera.up, (Vec3{0, 0, -1}));
    EXPECT_NO_THROW(view_frame(top.camera));
  }
  // Kept as a unit vector: glm::lookAt in float made NaN of [0, 1e-25, 0].
  EXPECT_EQ(parse_scene(R"({"objects": [], "camera": {"eye": [0, 1, 5], "target": [0, 0, 0], "up": [0, 1e-25, 0]}})", "short.json", ".").camera.up,
            (Vec3{0, 1, 0}));
  for (const auto& [text, expected] : cases) EXPECT_NE(message(text).find(expected), std::string::npos) << text << " gave: " << message(text);
  // The edges of the ranges are accepted.
  EXPECT_NO_THROW(parse_scene(R"({"objects": [], "quality": {"depth_offset": 0, "ao_bias": 0, "antialias": 0, "specular": 100}, "floor": true,
                                  "lights": {"count": 2, "extent": 0, "height": [0, 1]}})", "ok.json", "."));
  EXPECT_NO_THROW(parse_scene(R"({"objects": [)" + box + R"(, "color": [1, 0, 1]}], "floor": {"color": [1, 1, 1]}})", "ok.json", "."));
}

// An object's sampling text is refused before any asset is built (the splat stage's parser, not a
// copy of its grammar), naming the scene file and the object.
TEST(PresenterScene, ObjectSamplingIsCheckedBeforeAssetsAreBuilt) {
  const Scene scene = parse_scene(R"({"objects": [{"name": "good", "mesh": {"procedural": "box"}},
      {"name": "typo", "mesh": {"procedural": "box"}, "quality": {"sampling": "grid:0"}}]})", "s.json", ".");
  try {
    check_scene_settings(scene);
    ADD_FAILURE() << "grid:0 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("s.json: objects[1] 'typo': 'sampling': 'grid:0' is not"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(check_scene_settings(parse_scene(R"({"objects": [{"name": "a", "mesh": {"procedural": "box"}, "quality": {"sampling": "spacing:0.1"}}]})", "s.json", ".")));
}

// More key lights than the lighting holds are refused with the scene's name (by render and by
// cluster, which checks the scene alike).
TEST(PresenterScene, KeyLightCountIsCheckedBeforeAssetsAreBuilt) {
  std::string lights;
  for (int i = 0; i < 5; ++i) lights += std::string(i ? ", " : "") + R"({"position": [0, 3, 0]})";
  try {
    check_scene_settings(parse_scene(R"({"objects": [], "key_lights": [)" + lights + "]}", "k.json", "."));
    ADD_FAILURE() << "5 key lights accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("k.json: 'key_lights' lists 5 lights, at most 4"), std::string::npos) << e.what();
  }
}

// A spinning or orbiting object at a late time turns by its rate × time reduced to a turn in
// double: the float product of 2e6 s at 1 degree/s kept about 0.2 degrees of the angle's precision.
TEST(PresenterScene, LateTimesTurnObjectsPrecisely) {
  const Scene scene = parse_scene(R"({"objects": [{"name": "s", "mesh": {"procedural": "box"}, "animation": {"spin_degrees_per_second": [0, 1, 0]}},
      {"name": "o", "mesh": {"procedural": "box"}, "animation": {"orbit": {"radius": 2, "degrees_per_second": 1, "phase_degrees": 0}}}]})",
                                  "late.json", ".");
  const float late = 2000000.25f;  // exactly representable; 2000000.25 degrees is 200.25 modulo a turn
  ASSERT_EQ(static_cast<double>(late), 2000000.25);
  const double angle = 200.25 * std::numbers::pi / 180.0;
  const glm::mat4 spin = scene.objects[0].placement(late);
  EXPECT_NEAR(spin[0][0], std::cos(angle), 1e-6);
  EXPECT_NEAR(spin[2][0], std::sin(angle), 1e-6);
  const glm::mat4 orbit = scene.objects[1].placement(late);
  EXPECT_NEAR(orbit[3][0], 2 * std::cos(angle), 1e-5);
  EXPECT_NEAR(orbit[3][2], 2 * std::sin(angle), 1e-5);
}

// The scene reader (core) checks csm_maps itself, as a perfect square; the assets build their maps
// with csm's default distribution and order. The two rules must agree on every count the reader
// allows.
TEST(PresenterScene, CsmMapCountsAreExactlyThoseTheDefaultGridTakes) {
  const csm::BuildOptions defaults;
  for (std::uint32_t maps = 16; maps <= 65536; maps += (maps < 1100 ? 1 : 97)) {
    bool grid_takes = true;
    try {
      (void)csm::grid_shape(defaults.distribution, defaults.order, maps);
    } catch (const Error&) {
      grid_takes = false;
    }
    bool scene_takes = true;
    try {
      (void)parse_scene(R"({"objects": [], "quality": {"csm_maps": )" + std::to_string(maps) + "}}", "maps.json", ".");
    } catch (const Error&) {
      scene_takes = false;
    }
    ASSERT_EQ(scene_takes, grid_takes) << maps << " maps";
  }
  EXPECT_NO_THROW(parse_scene(R"({"objects": [], "quality": {"csm_maps": 65536}})", "maps.json", "."));
}

TEST(PresenterScene, ProceduralMeshesAndCacheKeys) {
  for (const char* shape : {"sphere", "torus", "box"}) {
    MeshSpec spec;
    spec.procedural = shape;
    spec.segments = 12;
    spec.rings = 6;
    const Mesh mesh = make_object_mesh(spec, ".");
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

}  // namespace
}  // namespace splatcl::present
