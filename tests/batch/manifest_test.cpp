// Manifest parsing (JSON, CSV, directories): parameter layering, ids, and one-line errors that
// name the file, the entry and the key.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "batch/batch_test_support.hpp"
#include "batch/manifest.hpp"
#include "runtime/error.hpp"

namespace splatcl::batch {
namespace {

using test::ScratchDir;
using test::write_text;

std::vector<ModelEntry> json(const std::string& text, const nlohmann::json& overrides = nlohmann::json::object()) {
  return parse_json_manifest(text, "m.json", "meshes", overrides);
}
std::vector<ModelEntry> csv(const std::string& text, const nlohmann::json& overrides = nlohmann::json::object()) {
  return parse_csv_manifest(text, "m.csv", "meshes", overrides);
}

// The message of the Error `body` throws ("" when it does not throw).
template <class Body>
std::string error_of(Body&& body) {
  try {
    body();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Manifest, JsonEntriesResolvePathsAndSortById) {
  const auto models = json(R"({"models": ["b/zebra.obj", {"path": "/abs/apple.ply", "id": "fruit/apple"}, {"path": "c.off"}]})");
  ASSERT_EQ(models.size(), 3u);
  EXPECT_EQ(models[0].id, "c");
  EXPECT_EQ(models[0].input, "meshes/c.off");
  EXPECT_EQ(models[1].id, "fruit/apple");
  EXPECT_EQ(models[1].input, "/abs/apple.ply");
  EXPECT_EQ(models[2].id, "zebra");
  EXPECT_EQ(models[2].input, "meshes/b/zebra.obj");
  EXPECT_EQ(models[2].origin, "m.json: models[0]");
}

TEST(Manifest, ParametersLayerBuiltinDefaultsCommandLineModel) {
  const auto models = json(R"({"defaults": {"maps": 256, "res": 64, "k": 12, "eps_diag": 0.002},
                               "models": [{"path": "a.obj", "res": 32, "outputs": ["csm"], "clip": true}, "b.obj"]})",
                           {{"res", "16"}, {"k", 8}});
  ASSERT_EQ(models.size(), 2u);
  const ModelParams& a = models[0].params;
  const ModelParams& b = models[1].params;
  EXPECT_EQ(a.csm.maps, 256u);            // manifest default
  EXPECT_EQ(a.csm.res, 32u);              // model key beats the command line
  EXPECT_EQ(b.csm.res, 16u);              // command line beats the manifest default
  EXPECT_EQ(b.splats.k, 8u);
  EXPECT_DOUBLE_EQ(b.splats.eps_diag, 0.002);
  EXPECT_EQ(b.splats.samples, "auto");  // built-in
  EXPECT_EQ(b.csm.order, "zigzag-h");
  EXPECT_TRUE(a.splats.clip);
  EXPECT_FALSE(b.splats.clip);
  EXPECT_FALSE(a.want_splats);
  EXPECT_TRUE(a.want_csm);
  EXPECT_TRUE(b.want_splats && b.want_csm);
}

TEST(Manifest, JsonErrorsNameFileEntryAndKey) {
  EXPECT_EQ(error_of([] { json("{\"models\": [\"a.obj\",]}"); }).rfind("m.json: not valid JSON: parse error at line 1", 0), 0u);
  EXPECT_EQ(error_of([] { json(R"({"model": []})"); }), "m.json: unknown top-level key 'model' (known: defaults, models)");
  EXPECT_EQ(error_of([] { json(R"({"defaults": {}})"); }), "m.json: \"models\" must be a list");
  EXPECT_EQ(error_of([] { json(R"({"models": []})"); }), "m.json: no models");
  const std::string unknown = error_of([] { json(R"({"models": ["a.obj", {"path": "b.obj", "epsilon": 1}]})"); });
  EXPECT_EQ(unknown.rfind("m.json: models[1] (b): unknown parameter 'epsilon' (known: id, path, eps, eps_diag, color_tol,", 0), 0u) << unknown;
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "b.obj", "k": -3}]})"); }),
            "m.json: models[0] (b): 'k' must be an integer from 1 to 1024, got -3");
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "b.obj", "res": 2.5}]})"); }),
            "m.json: models[0] (b): 'res' must be an integer from 1 to 8192, got 2.5");
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "b.obj", "eps": "x"}]})"); }), "m.json: models[0] (b): 'eps' must be a number, got 'x'");
  EXPECT_EQ(error_of([] { json(R"({"models": [{"id": "b"}]})"); }), "m.json: models[0]: missing \"path\"");
  EXPECT_EQ(error_of([] { json(R"({"models": [3]})"); }), "m.json: models[0]: expected a path or an object with \"path\", got 3");
  EXPECT_EQ(error_of([] { json(R"({"defaults": {"color_tol": 300}, "models": ["a.obj"]})"); }),
            "m.json: defaults: 'color_tol' must be an integer from 0 to 255, got 300");
  EXPECT_EQ(error_of([] { json(R"({"models": ["a.obj"]})", {{"k", "many"}}); }),
            "command line: 'k' must be an integer from 1 to 1024, got 'many'");
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "b.obj", "outputs": ["png"]}]})"); }),
            "m.json: models[0] (b): 'outputs' has unknown output 'png' (one of: splats, csm)");
}

TEST(Manifest, CombinationsAreValidatedWhenRead) {
  const std::string maps = error_of([] { json(R"({"models": [{"path": "b.obj", "maps": 1000}]})"); });
  EXPECT_EQ(maps.rfind("m.json: models[0] (b): 'maps': ", 0), 0u) << maps;
  EXPECT_NE(maps.find("not a perfect square"), std::string::npos) << maps;
  // A map count that does not fit is fine when no CSM is wanted.
  EXPECT_NO_THROW(json(R"({"models": [{"path": "b.obj", "maps": 1000, "outputs": ["splats"]}]})"));
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "b.obj", "samples": "grid:0"}]})"); }).rfind("m.json: models[0] (b): 'samples': ", 0), 0u);
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "b.obj", "order": "spiral"}]})"); }).rfind("m.json: models[0] (b): 'order': unknown map order 'spiral'", 0), 0u);
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "b.obj", "color_field": "blue"}]})"); }),
            "m.json: models[0] (b): 'color_field': colour field 'blue' is not grey, soft, hard or rainbow");
}

TEST(Manifest, IdsMustBeUniqueAndSafe) {
  EXPECT_EQ(error_of([] { json(R"({"models": ["x/a.obj", "y/a.ply"]})"); }),
            "m.json: models[1]: model id 'a' is used twice (m.json: models[0] and m.json: models[1]); give one an \"id\"");
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "a.obj", "id": "../up"}]})"); }),
            "m.json: models[0] (../up): model id '../up' has a segment starting with '.'");
  EXPECT_NO_THROW(check_model_id("set-1/chair_02.v2"));
  for (const std::string bad : {"", "a//b", "/abs", "a/", ".hidden", "a b", "a\\b", "ü"}) EXPECT_THROW(check_model_id(bad), Error) << bad;
}

TEST(Manifest, CsvColumnsQuotingCommentsAndEmptyCells) {
  const auto models = csv(
      "# studio set\n"
      "id,path,maps,res,outputs,clip,samples\n"
      "chair,\"chairs/big, old.obj\",64,,csm,yes,\n"
      "\n"
      "table,table.ply,,16,splats+csm,false,grid:2\r\n",
      {{"res", 32}});
  ASSERT_EQ(models.size(), 2u);
  EXPECT_EQ(models[0].id, "chair");
  EXPECT_EQ(models[0].input, "meshes/chairs/big, old.obj");
  EXPECT_EQ(models[0].origin, "m.csv:3");
  EXPECT_EQ(models[0].params.csm.maps, 64u);
  EXPECT_EQ(models[0].params.csm.res, 32u);  // empty cell: the default (here from the command line)
  EXPECT_FALSE(models[0].params.want_splats);
  EXPECT_TRUE(models[0].params.splats.clip);
  EXPECT_EQ(models[1].origin, "m.csv:5");
  EXPECT_EQ(models[1].params.csm.maps, 4096u);
  EXPECT_EQ(models[1].params.csm.res, 16u);
  EXPECT_EQ(models[1].params.splats.samples, "grid:2");
  EXPECT_TRUE(models[1].params.want_splats && models[1].params.want_csm);
}

TEST(Manifest, CsvErrorsNameFileAndLine) {
  EXPECT_EQ(error_of([] { csv("path,epsilon\na.obj,1\n"); }).rfind("m.csv:1: unknown column 'epsilon' (known: id, path, eps,", 0), 0u);
  EXPECT_EQ(error_of([] { csv("id,maps\na,16\n"); }), "m.csv:1: the header has no 'path' column");
  EXPECT_EQ(error_of([] { csv("path,k\na.obj,1\nb.obj\n"); }), "m.csv:3: 1 fields, but the header has 2");
  EXPECT_EQ(error_of([] { csv("path,k\na.obj,zero\n"); }), "m.csv:2 (a): 'k' must be an integer from 1 to 1024, got 'zero'");
  EXPECT_EQ(error_of([] { csv("id,path,clip\nchair,a.obj,maybe\n"); }), "m.csv:2 (chair): 'clip' must be true or false, got 'maybe'");
  EXPECT_EQ(error_of([] { csv("path\n\"a.obj\n"); }), "m.csv:2: unterminated quote");
  EXPECT_EQ(error_of([] { csv("path,path\na.obj,b.obj\n"); }), "m.csv:1: column 'path' appears twice");
  // Two spellings of one parameter (the later column won silently), and JSON keys given twice.
  EXPECT_EQ(error_of([] { csv("path,eps_diag,eps-diag\na.obj,0.001,0.002\n"); }), "m.csv:1: columns 'eps_diag' and 'eps-diag' name the same parameter");
  // Where the object lies is named (the error said only "m.json").
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "a.obj", "eps-diag": 0.002, "eps_diag": 0.001}]})"); }),
            "m.json: models[0]: keys 'eps-diag' and 'eps_diag' in one object name the same parameter");
  EXPECT_EQ(error_of([] { json(R"({"models": ["x.obj", [1, {}], {"path": "a.obj", "k": 8, "k": 12}]})"); }),
            "m.json: models[2]: key 'k' appears twice in one object");
  EXPECT_EQ(error_of([] { json(R"({"defaults": {"k": 8, "k": 12}, "models": ["a.obj"]})"); }),
            "m.json: defaults: key 'k' appears twice in one object");
  EXPECT_EQ(error_of([] { json(R"({"models": ["a.obj"], "models": ["b.obj"]})"); }), "m.json: key 'models' appears twice in one object");
  // The same key in two objects is no duplicate.
  EXPECT_EQ(json(R"({"defaults": {"k": 8}, "models": [{"path": "a.obj", "k": 12}, {"path": "b.obj", "k": 9}]})").size(), 2u);
  EXPECT_EQ(error_of([] { csv("# nothing\n"); }), "m.csv: empty (expected a header line with a 'path' column)");
  EXPECT_EQ(error_of([] { csv("path\n"); }), "m.csv: no models");
}

// Fuzz findings (tests/fuzz/corpus/manifest_*/regression-*): a number beyond double range escaped
// as nlohmann's own exception, without the file's name; a CSV line that is not UTF-8 was read, and
// its path then broke the JSON of the checksum and the summary.
TEST(Manifest, NumberOverflowAndNonUtf8AreErrorsNamingTheFile) {
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "a.obj", "eps": 1e999}]})"); }),
            "m.json: not valid JSON: number overflow parsing '1e999'");
  EXPECT_EQ(error_of([] { csv("path\na.obj\nb\xEF.obj\n"); }), "m.csv:3: not UTF-8 text");
  EXPECT_NE(csv("id,path\nm,mod\xC3\xA8le.obj\n").front().input.find("mod\xC3\xA8le.obj"), std::string::npos);
}

// The map count is checked against the grid's shape, not by building the grid: 2^24 maps took over
// a second per model (a fuzz finding: tests/fuzz/corpus/manifest_json/regression-10m-maps.json).
TEST(Manifest, TheLargestMapCountIsCheckedQuickly) {
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(json(R"({"defaults": {"maps": 16777216}, "models": ["a.obj", "b.obj", "c.obj", "d.obj"]})").size(), 4u);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.5);
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "a.obj", "maps": 16777215}]})"); }).rfind("m.json: models[0] (a): 'maps': ", 0), 0u);
}

TEST(Manifest, LoadManifestChoosesByExtensionAndNamesMissingFiles) {
  ScratchDir dir("manifest-load");
  write_text(dir / "set.json", R"({"models": ["a.obj"]})");
  write_text(dir / "set.csv", "path\na.obj\n");
  write_text(dir / "set.txt", "path\na.obj\n");
  EXPECT_EQ(load_manifest(dir / "set.json").at(0).input, dir / "a.obj");
  EXPECT_EQ(load_manifest(dir / "set.csv").at(0).input, dir / "a.obj");
  EXPECT_EQ(error_of([&] { load_manifest(dir / "set.txt"); }),
            "cannot tell the manifest format of " + (dir / "set.txt") + ": name it .json or .csv (or pass a directory of meshes)");
  EXPECT_EQ(error_of([&] { load_manifest(dir / "missing.json"); }), "cannot read manifest " + (dir / "missing.json") + ": No such file or directory");
}

TEST(Manifest, DirectoryScanFindsMeshesRecursivelySkippingHiddenAndOutput) {
  ScratchDir dir("manifest-scan");
  for (const char* name : {"a.obj", "sub/b.PLY", "sub/deeper/c.off", "d.stl", ".hidden.obj", ".git/e.obj", "notes.txt", "out/f.obj"})
    write_text(dir / name, "x");
  const auto models = scan_directory(dir.path().string(), dir / "out", {{"maps", 64}});
  std::vector<std::string> ids;
  for (const auto& m : models) ids.push_back(m.id);
  EXPECT_EQ(ids, (std::vector<std::string>{"a", "d", "sub/b", "sub/deeper/c"}));
  EXPECT_EQ(models[2].input, dir / "sub/b.PLY");
  EXPECT_EQ(models[2].params.csm.maps, 64u);
  write_text(dir / "a.ply", "x");
  EXPECT_NE(error_of([&] { scan_directory(dir.path().string(), dir / "out"); }).find("model id 'a' is used twice"), std::string::npos);
  EXPECT_EQ(error_of([&] { scan_directory(dir / "none"); }), "cannot read directory " + (dir / "none") + ": it does not exist");
  std::filesystem::create_directories(dir / "empty");
  write_text(dir / "empty/readme.txt", "x");
  EXPECT_EQ(error_of([&] { scan_directory(dir / "empty"); }), "no meshes (.obj, .ply, .off, .stl) in " + (dir / "empty"));
  // Every model of a directory takes the command line's values: a bad combination is blamed on it,
  // not on the first model.
  EXPECT_EQ(error_of([&] { scan_directory(dir.path().string(), dir / "out", {{"maps", 1000}}); })
                .rfind("command line: 'maps': 1000 is not a perfect square", 0),
            0u);
}

// File names with characters an id may not hold (a space, an accent) get '_' there; before, one
// such file refused the whole directory run. A manifest's own ids are still checked, the byte named.
TEST(Manifest, DirectoryScanTurnsOtherCharactersOfAFileNameIntoUnderscores) {
  ScratchDir dir("manifest-scan-names");
  for (const char* name : {"Chair 01.obj", "St\xC3\xBChle/a+b.stl"}) write_text(dir / name, "x");
  std::vector<std::string> ids;
  for (const auto& m : scan_directory(dir.path().string())) ids.push_back(m.id);
  EXPECT_EQ(ids, (std::vector<std::string>{"Chair_01", "St__hle/a_b"}));
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "a.obj", "id": "St\u00fchle"}]})"); }),
            "m.json: models[0] (St\xC3\xBChle): model id 'St\xC3\xBChle' has the character '\\xC3' (use letters, digits, '.', '_', '-' and '/')");
}

TEST(Manifest, UnknownParametersNameTheModelAndTheParameter) {
  const std::string json_error = error_of([] { json(R"({"models": ["a.obj", {"path": "b.obj", "id": "chairs/oak", "mapz": 64}]})"); });
  EXPECT_EQ(json_error.rfind("m.json: models[1] (chairs/oak): unknown parameter 'mapz' (known: id, path, ", 0), 0u) << json_error;
  // The list names every parameter of both stages.
  for (const char* key : {"eps_diag", "texture", "literal_lambda", "retest_violator", "maps", "capture", "batch", "outputs"})
    EXPECT_NE(json_error.find(key), std::string::npos) << key;
  const std::string defaults_error = error_of([] { json(R"({"defaults": {"colour_tol": 3}, "models": ["a.obj"]})"); });
  EXPECT_EQ(defaults_error.rfind("m.json: defaults: unknown parameter 'colour_tol' (known: ", 0), 0u) << defaults_error;
  EXPECT_EQ(error_of([] { csv("path,k,resolution\na.obj,3,64\n"); }).rfind("m.csv:1: unknown column 'resolution' (known: id, path, ", 0), 0u);
  EXPECT_EQ(error_of([] { json(R"({"models": ["a.obj"]})", {{"bogus", 1}}); }).rfind("command line: unknown parameter 'bogus'", 0), 0u);
}

TEST(Manifest, ParametersAreTheStagesOwnWithTheirOptionSpellings) {
  std::vector<std::string> expected;
  for (const ParameterInfo& p : splats::splat_parameters()) expected.push_back(p.key);
  for (const ParameterInfo& p : csm::csm_parameters()) expected.push_back(p.key);
  expected.push_back("outputs");
  EXPECT_EQ(parameter_keys(), expected);
  // A key may be written as the option is (eps-diag, --single-hit), in manifests and CSV headers.
  const auto models = json(R"({"models": [{"path": "a.obj", "eps-diag": 0.004, "--single-hit": "exact", "capture": "raycast",
                                           "literal_lambda": true, "retest-violator": true, "batch": 8}]})");
  const ModelParams& p = models.at(0).params;
  EXPECT_DOUBLE_EQ(p.splats.eps_diag, 0.004);
  EXPECT_EQ(p.csm.single_hit, "exact");
  EXPECT_EQ(p.csm.capture, "raycast");
  EXPECT_TRUE(p.splats.literal_lambda);
  EXPECT_TRUE(p.splats.retest_violator);
  EXPECT_EQ(p.csm.batch, 8u);
  EXPECT_EQ(csv("path,eps-diag,color-tol\na.obj,0.01,9\n").at(0).params.splats.color_tol, 9);
  // A JSON manifest spells booleans true and false; "yes" is for CSV cells and options.
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "b.obj", "clip": "yes"}]})"); }), "m.json: models[0] (b): 'clip' must be true or false, got 'yes'");
  EXPECT_TRUE(csv("path,clip\na.obj,yes\n").at(0).params.splats.clip);
  EXPECT_EQ(error_of([] { json(R"({"models": [{"path": "b.obj", "capture": "photo"}]})"); }).rfind("m.json: models[0] (b): 'capture': ", 0), 0u);
  // Every parameter is in a run's record, so each one takes part in the resume checksum.
  for (const ParameterInfo& info : splats::splat_parameters()) EXPECT_TRUE(splats::to_json(p.splats).contains(info.key)) << info.key;
  for (const ParameterInfo& info : csm::csm_parameters()) {
    if (std::string(info.key) == "hit_eps") continue;  // below
    EXPECT_EQ(csm::to_json(p.csm).contains(info.key), std::string(info.key) != "batch") << info.key;  // batch: memory only
  }
  // hit_eps only when not the default, so that records written before it existed keep their checksum.
  csm::CsmParameters thin;
  EXPECT_FALSE(csm::to_json(thin).contains("hit_eps"));
  thin.hit_eps = 1e-7f;
  EXPECT_TRUE(csm::to_json(thin).contains("hit_eps"));
}

TEST(Manifest, TexturePathsResolveAgainstTheManifestFolder) {
  const auto models = json(R"({"defaults": {"texture": "textures/wood.png"},
                               "models": ["a.obj", {"path": "b.obj", "texture": "/abs/stone.png"},
                                          {"path": "c.obj", "texture": "../textures/c.jpg"}]})");
  ASSERT_EQ(models.size(), 3u);
  EXPECT_EQ(models[0].params.splats.texture, "meshes/textures/wood.png");
  EXPECT_EQ(models[1].params.splats.texture, "/abs/stone.png");
  EXPECT_EQ(models[2].params.splats.texture, "textures/c.jpg");
  const auto rows = csv("id,path,texture\nx,x.obj,x.png\ny,y.obj,\n");
  EXPECT_EQ(rows[0].params.splats.texture, "meshes/x.png");
  EXPECT_EQ(rows[1].params.splats.texture, "");  // empty cell: no texture
  // On the command line a path is relative to the working directory, as for any option.
  EXPECT_EQ(json(R"({"models": ["a.obj"]})", {{"texture", "here.png"}}).at(0).params.splats.texture, "here.png");
  // The manifest checksum (merge) follows the texture.
  EXPECT_NE(manifest_checksum(json(R"({"models": [{"path": "a.obj", "texture": "t1.png"}]})")),
            manifest_checksum(json(R"({"models": [{"path": "a.obj", "texture": "t2.png"}]})")));
}

TEST(Manifest, ChecksumFollowsIdsInputsAndParameters) {
  const auto base = json(R"({"models": ["a.obj", "b.obj"]})");
  const auto reordered = json(R"({"models": ["b.obj", "a.obj"]})");
  const auto other_res = json(R"({"models": ["a.obj", {"path": "b.obj", "res": 64}]})");
  const auto other_path = json(R"({"models": ["a.obj", "c/b.obj"]})");
  EXPECT_EQ(manifest_checksum(base), manifest_checksum(reordered));
  EXPECT_NE(manifest_checksum(base), manifest_checksum(other_res));
  EXPECT_NE(manifest_checksum(base), manifest_checksum(other_path));
  EXPECT_EQ(manifest_checksum(base).size(), 16u);
}

// A studio's share may be case-insensitive: ids that differ only in case are named (a warning).
TEST(Manifest, IdsDifferingOnlyInCaseArePaired) {
  const auto models = json(R"({"models": [{"path": "a.obj", "id": "Chair"}, {"path": "b.obj", "id": "chair"},
                                          {"path": "c.obj", "id": "table"}, {"path": "d.obj", "id": "CHAIR"}]})");
  const auto pairs = ids_differing_in_case_only(models);
  ASSERT_EQ(pairs.size(), 2u);  // sorted by id: CHAIR, Chair, chair, table
  EXPECT_EQ(pairs[0], (std::pair<std::string, std::string>{"CHAIR", "Chair"}));
  EXPECT_EQ(pairs[1], (std::pair<std::string, std::string>{"CHAIR", "chair"}));
  EXPECT_TRUE(ids_differing_in_case_only(json(R"({"models": ["a.obj", "b.obj"]})")).empty());
}

// Shards of one run may name the manifest otherwise (set.json from its folder, man/set.json, an
// absolute path): the inputs and textures resolve to other spellings of the same files, and merge
// refused the shards (a helper's audit of batch).
TEST(Manifest, ChecksumIsTheSameHoweverTheManifestsFolderIsSpelled) {
  const std::string text = R"({"defaults": {"texture": "t.png"}, "models": ["a.obj", {"path": "sub/../b.obj"}]})";
  const std::string here = std::filesystem::current_path().string();
  const std::string checksum = manifest_checksum(parse_json_manifest(text, "m.json", "meshes", {}));
  for (const std::string& folder : std::vector<std::string>{here + "/meshes", "./meshes", "meshes/", "other/../meshes", here + "/meshes/."})
    EXPECT_EQ(manifest_checksum(parse_json_manifest(text, "m.json", folder, {})), checksum) << folder;
  EXPECT_NE(manifest_checksum(parse_json_manifest(text, "m.json", "other", {})), checksum);
}

}  // namespace
}  // namespace splatcl::batch
