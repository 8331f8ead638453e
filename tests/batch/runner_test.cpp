// Resumable runs on tiny meshes with the native references (no OpenCL device needed): outputs and
// records, reuse verified by checksum, rebuilds after changes or corruption, per-model failures.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "batch/batch_test_support.hpp"
#include "batch/runner.hpp"
#include "batch/summary.hpp"
#include "io/checksum.hpp"
#include "io/image.hpp"
#include "splats/splat_file.hpp"
#include "splats/surface_check.hpp"
#include "csm/csm_file.hpp"

namespace splatcl::batch {
namespace {

using test::read_text;
using test::ScratchDir;
using test::write_text;

ModelEntry model(const ScratchDir& dir, const std::string& id, const std::string& file) {
  ModelEntry m;
  m.id = id;
  m.input = dir / file;
  m.origin = id;
  m.params.csm.maps = 16;
  m.params.csm.res = 8;
  m.params.splats.k = 6;
  return m;
}

RunOptions reference_options(const ScratchDir& dir) {
  RunOptions options;
  options.output_dir = dir / "out";
  options.reference = true;
  return options;
}

const OutputResult* output(const ModelResult& r, const std::string& kind) {
  for (const auto& o : r.outputs)
    if (o.kind == kind) return &o;
  return nullptr;
}

TEST(BatchRunner, BuildsValidOutputsThenReusesThem) {
  ScratchDir dir("runner-reuse");
  write_text(dir / "cube.obj", test::kCubeObj);
  write_text(dir / "set/wedge.obj", test::kWedgeObj);
  const std::vector<ModelEntry> models{model(dir, "cube", "cube.obj"), model(dir, "set/wedge", "set/wedge.obj")};
  const RunOptions options = reference_options(dir);

  const auto first = run_batch(models, options);
  ASSERT_EQ(first.size(), 2u);
  for (const auto& r : first) {
    ASSERT_TRUE(r.ok) << r.id << ": " << r.reason;
    EXPECT_FALSE(r.reused());
    ASSERT_EQ(r.outputs.size(), 2u);
    EXPECT_EQ(r.outputs[0].kind, "splats");
    EXPECT_EQ(r.outputs[1].kind, "csm");
    EXPECT_EQ(r.input_checksum, checksum_of(read_text(r.input)));
    for (const auto& o : r.outputs)
      for (const auto& f : o.files) EXPECT_EQ(f.checksum, checksum_of(read_text(options.output_dir + "/" + f.path))) << f.path;
  }
  // The outputs are real, valid files.
  EXPECT_GT(splats::read_splat_file(options.output_dir + "/set/wedge.splats.ply").splats.size(), 0u);
  EXPECT_EQ(csm::read_csm(options.output_dir + "/cube.csm").info.maps, 16u);
  EXPECT_TRUE(std::filesystem::exists(options.output_dir + "/cube.batch.json"));
  EXPECT_TRUE(std::filesystem::exists(options.output_dir + "/cube.csm.json"));
  EXPECT_TRUE(std::filesystem::exists(options.output_dir + "/cube.splats.json"));

  const std::string ply_before = read_text(options.output_dir + "/cube.splats.ply");
  const auto second = run_batch(models, options);
  for (const auto& r : second) {
    EXPECT_TRUE(r.ok);
    EXPECT_TRUE(r.reused()) << r.id;
  }
  EXPECT_EQ(read_text(options.output_dir + "/cube.splats.ply"), ply_before);

  RunOptions forced = options;
  forced.force = true;
  for (const auto& r : run_batch(models, forced)) EXPECT_FALSE(r.reused());
  EXPECT_EQ(read_text(options.output_dir + "/cube.splats.ply"), ply_before);  // deterministic
}

// A file name in another encoding (Latin-1 "caf\xE9.obj", not UTF-8) is built, recorded and then
// reused: every JSON writer failed on it ("[json.exception.type_error.316] invalid UTF-8 byte"),
// first the manifest checksum, so a directory run stopped before any model. The JSON files show
// the byte as U+FFFD.
TEST(BatchRunner, FileNamesThatAreNotUtf8AreBuiltAndReused) {
  ScratchDir dir("runner-latin1");
  write_text(dir / "in/caf\xE9.obj", test::kCubeObj);
  const std::vector<ModelEntry> models = scan_directory(dir / "in");
  ASSERT_EQ(models.size(), 1u);
  EXPECT_EQ(models[0].id, "caf_");
  EXPECT_FALSE(manifest_checksum(models).empty());
  const RunOptions options = reference_options(dir);
  const auto first = run_batch(models, options);
  ASSERT_EQ(first.size(), 1u);
  ASSERT_TRUE(first[0].ok) << first[0].reason;
  EXPECT_NE(read_text(options.output_dir + "/caf_.batch.json").find("caf\xEF\xBF\xBD.obj"), std::string::npos);
  const auto second = run_batch(models, options);
  ASSERT_TRUE(second[0].ok) << second[0].reason;
  EXPECT_TRUE(second[0].reused());
}

TEST(BatchRunner, RebuildsExactlyWhatChangedOrIsCorrupt) {
  ScratchDir dir("runner-rebuild");
  write_text(dir / "cube.obj", test::kCubeObj);
  std::vector<ModelEntry> models{model(dir, "cube", "cube.obj")};
  const RunOptions options = reference_options(dir);
  ASSERT_TRUE(run_batch(models, options).at(0).ok);

  // A CSM parameter changes: the splats are reused, the CSM rebuilt.
  models[0].params.csm.res = 4;
  auto r = run_batch(models, options).at(0);
  ASSERT_TRUE(r.ok);
  EXPECT_TRUE(output(r, "splats")->reused);
  EXPECT_FALSE(output(r, "csm")->reused);
  EXPECT_EQ(csm::read_csm(options.output_dir + "/cube.csm").info.resolution, 4u);

  // A corrupted output file is rebuilt, to the same bytes (the build is deterministic).
  const std::string ply_before = read_text(options.output_dir + "/cube.splats.ply");
  {
    std::string ply = ply_before;
    ply.back() = static_cast<char>(ply.back() ^ 1);
    write_text(options.output_dir + "/cube.splats.ply", ply);
  }
  r = run_batch(models, options).at(0);
  EXPECT_FALSE(output(r, "splats")->reused);
  EXPECT_TRUE(output(r, "csm")->reused);
  EXPECT_EQ(read_text(options.output_dir + "/cube.splats.ply"), ply_before);
  EXPECT_GT(splats::read_splat_file(options.output_dir + "/cube.splats.ply").splats.size(), 0u);

  // A changed input rebuilds both; a damaged record too.
  write_text(dir / "cube.obj", std::string(test::kCubeObj) + "# edited\n");
  r = run_batch(models, options).at(0);
  EXPECT_FALSE(output(r, "splats")->reused);
  EXPECT_FALSE(output(r, "csm")->reused);
  write_text(options.output_dir + "/cube.batch.json", "{\"truncated");
  EXPECT_FALSE(run_batch(models, options).at(0).reused());
  write_text(options.output_dir + "/cube.batch.json", R"({"input_checksum": 5, "outputs": {"csm": {"params_checksum": [], "files": 1}}})");
  EXPECT_FALSE(run_batch(models, options).at(0).reused());
  EXPECT_TRUE(run_batch(models, options).at(0).reused());

  // Only the outputs asked for are built and checked; the other stays in the record, and a run
  // that asks for both again reuses it (`--outputs csm` dropped the splats, which were rebuilt).
  models[0].params.want_splats = false;
  r = run_batch(models, options).at(0);
  ASSERT_EQ(r.outputs.size(), 1u);
  EXPECT_EQ(r.outputs[0].kind, "csm");
  EXPECT_TRUE(r.reused());
  EXPECT_TRUE(nlohmann::json::parse(read_text(options.output_dir + "/cube.batch.json")).at("outputs").contains("splats"));
  models[0].params.want_splats = true;
  EXPECT_TRUE(run_batch(models, options).at(0).reused());
  // --force rebuilds what is asked for, and keeps the other too.
  models[0].params.want_splats = false;
  RunOptions forced = options;
  forced.force = true;
  EXPECT_FALSE(run_batch(models, forced).at(0).reused());
  models[0].params.want_splats = true;
  r = run_batch(models, options).at(0);
  EXPECT_TRUE(output(r, "splats")->reused);
  EXPECT_TRUE(output(r, "csm")->reused);
  // Not across a changed input: the record's other output is of the old bytes.
  models[0].params.want_csm = false;
  write_text(dir / "cube.obj", std::string(test::kCubeObj) + "# edited again\n");
  r = run_batch(models, options).at(0);
  EXPECT_FALSE(output(r, "splats")->reused);
  EXPECT_FALSE(nlohmann::json::parse(read_text(options.output_dir + "/cube.batch.json")).at("outputs").contains("csm"));
}

// An output is reused only when the same device, or the reference, made it: another device may
// round differently (`--reference` after an OpenCL run reused the OpenCL files and the summary
// called them the reference's). The record says which made each output.
TEST(BatchRunner, OutputsOfAnotherDeviceAreRebuilt) {
  ScratchDir dir("runner-made-by");
  write_text(dir / "cube.obj", test::kCubeObj);
  const std::vector<ModelEntry> models{model(dir, "cube", "cube.obj")};
  const RunOptions options = reference_options(dir);
  ASSERT_TRUE(run_batch(models, options).at(0).ok);
  const std::string record_path = options.output_dir + "/cube.batch.json";
  nlohmann::json record = nlohmann::json::parse(read_text(record_path));
  EXPECT_EQ(record.at("outputs").at("splats").at("made_by"), "reference");
  EXPECT_EQ(record.at("outputs").at("csm").at("made_by"), "reference");

  // As if an OpenCL device had made the splats: they are rebuilt, the CSM reused.
  record["outputs"]["splats"]["made_by"] = "Some GPU";
  write_text(record_path, record.dump());
  auto r = run_batch(models, options).at(0);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_FALSE(output(r, "splats")->reused);
  EXPECT_EQ(output(r, "splats")->made_by, "reference");
  EXPECT_TRUE(output(r, "csm")->reused);

  // A record from before made_by existed is rebuilt once, then reused.
  record = nlohmann::json::parse(read_text(record_path));
  record["outputs"]["csm"].erase("made_by");
  write_text(record_path, record.dump());
  r = run_batch(models, options).at(0);
  EXPECT_TRUE(output(r, "splats")->reused);
  EXPECT_FALSE(output(r, "csm")->reused);
  EXPECT_TRUE(run_batch(models, options).at(0).reused());
}

TEST(BatchRunner, FailingModelsAreReportedAndTheRestComplete) {
  ScratchDir dir("runner-fail");
  write_text(dir / "cube.obj", test::kCubeObj);
  write_text(dir / "empty.obj", "# no faces\nv 0 0 0\n");
  write_text(dir / "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
  write_text(dir / "flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  const std::vector<ModelEntry> models{model(dir, "a-missing", "missing.obj"), model(dir, "b-empty", "empty.obj"),
                                       model(dir, "c-nan", "nan.obj"), model(dir, "d-cube", "cube.obj"), model(dir, "e-flat", "flat.obj")};
  const RunOptions options = reference_options(dir);
  std::vector<std::string> finished;
  const auto results = run_batch(models, options, {}, [&](const ModelResult& r) { finished.push_back(r.id); });
  ASSERT_EQ(results.size(), 5u);
  EXPECT_EQ(finished.size(), 5u);
  EXPECT_FALSE(results[0].ok);
  EXPECT_NE(results[0].reason.find("missing.obj"), std::string::npos) << results[0].reason;
  EXPECT_FALSE(results[1].ok);
  EXPECT_NE(results[1].reason.find("empty.obj"), std::string::npos) << results[1].reason;
  EXPECT_FALSE(results[2].ok);
  EXPECT_NE(results[2].reason.find("nan.obj"), std::string::npos) << results[2].reason;
  EXPECT_TRUE(results[3].ok) << results[3].reason;
  EXPECT_FALSE(results[4].ok);
  EXPECT_NE(results[4].reason.find("degenerate"), std::string::npos) << results[4].reason;
  // Failures are recorded and retried on the next run (never "reused").
  const auto again = run_batch(models, options);
  EXPECT_FALSE(again[0].ok);
  EXPECT_TRUE(again[3].reused());
  const nlohmann::json summary = make_summary({}, results);
  EXPECT_EQ(summary["counts"]["failed"], 4);
  EXPECT_EQ(summary["models"][0]["status"], "failed");
  EXPECT_TRUE(summary["models"][0].contains("reason"));
  EXPECT_EQ(failed_models(summary), 4u);
}

// A model whose CSM cannot fit in memory fails with the cause and the others are built: before,
// one with "res": 8192, "maps": 16384 grew until the out-of-memory killer ended the whole run, and
// every resume of it (a helper's audit). The reference build holds every map: 8 TiB here.
TEST(BatchRunner, AModelTooLargeForTheMemoryFailsAloneWithTheCause) {
  ScratchDir dir("runner-memory");
  write_text(dir / "cube.obj", test::kCubeObj);
  ModelEntry huge = model(dir, "a-huge", "cube.obj");
  huge.params.csm.res = 8192;
  huge.params.csm.maps = 16384;
  const auto results = run_batch({huge, model(dir, "b-cube", "cube.obj")}, reference_options(dir));
  ASSERT_EQ(results.size(), 2u);
  EXPECT_FALSE(results[0].ok);
  EXPECT_NE(results[0].reason.find("the reference CSM build at resolution 8192 with 16384 maps (it holds every map) needs about 8192.00 GiB more memory"),
            std::string::npos)
      << results[0].reason;
  EXPECT_TRUE(results[1].ok) << results[1].reason;
}

// A sphere of radius 100 far from the origin (a scan in georeferenced coordinates). At 1e6 floats
// step by 0.0625 (1.8e-4 of its diagonal), at 1e7 by 1, where no float splat file could keep ε
// (the model failed, "translate the mesh nearer the origin"). The splats now read both about the
// centre of their box, hold positions relative to it and record it (splatcl_origin), with a
// warning saying so. Checked against the analytic sphere in double, not the loader: every splat's
// centre plus the origin lies on the faceted sphere, its normal radial; and by splats verify's
// check against the mesh read about that origin.
TEST(BatchRunner, FarFromTheOriginIsBuiltAboutItsCentre) {
  ScratchDir dir("runner-bound");
  const auto sphere_at = [&](double offset) {
    std::string obj;
    constexpr int segments = 48, rings = 24;
    const double pi = 3.14159265358979323846;
    obj += fmt::format("v {:.10f} {:.10f} {:.10f}\n", offset, offset, offset + 100);
    for (int i = 1; i < rings; ++i)
      for (int j = 0; j < segments; ++j) {
        const double theta = pi * i / rings, phi = 2 * pi * j / segments;
        obj += fmt::format("v {:.10f} {:.10f} {:.10f}\n", offset + 100 * std::sin(theta) * std::cos(phi),
                           offset + 100 * std::sin(theta) * std::sin(phi), offset + 100 * std::cos(theta));
      }
    obj += fmt::format("v {:.10f} {:.10f} {:.10f}\n", offset, offset, offset - 100);
    const int south = 1 + (rings - 1) * segments + 1;  // 1-based
    const auto ring = [&](int i, int j) { return 2 + (i - 1) * segments + j % segments; };
    for (int j = 0; j < segments; ++j) obj += fmt::format("f 1 {} {}\n", ring(1, j), ring(1, j + 1));
    for (int i = 1; i + 1 < rings; ++i)
      for (int j = 0; j < segments; ++j) {
        obj += fmt::format("f {} {} {}\n", ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
        obj += fmt::format("f {} {} {}\n", ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
      }
    for (int j = 0; j < segments; ++j) obj += fmt::format("f {} {} {}\n", ring(rings - 1, j), south, ring(rings - 1, j + 1));
    return obj;
  };
  write_text(dir / "far.obj", sphere_at(1e6));
  write_text(dir / "farther.obj", sphere_at(1e7));
  std::vector<ModelEntry> entries{model(dir, "far", "far.obj"), model(dir, "farther", "farther.obj")};
  for (ModelEntry& entry : entries) {
    entry.params.want_csm = false;
    entry.params.splats = {};  // the defaults of splatcl splats
  }
  const auto results = run_batch(entries, reference_options(dir));
  ASSERT_EQ(results.size(), 2u);
  for (std::size_t m = 0; m < 2; ++m) {
    const double offset = m == 0 ? 1e6 : 1e7;
    const std::string name = m == 0 ? "far" : "farther";
    SCOPED_TRACE(name);
    ASSERT_TRUE(results[m].ok) << results[m].reason;
    EXPECT_NE(results[m].warning.find(fmt::format("the splats: coordinates reach {:.7g}, where floats step by {:g}", offset + 100, m == 0 ? 0.0625 : 1.0)),
              std::string::npos)
        << results[m].warning;
    EXPECT_NE(results[m].warning.find(fmt::format("read about the centre of its bounding box ({0}, {0}, {0})", offset)), std::string::npos)
        << results[m].warning;
    EXPECT_EQ(results[m].warning.find("the CSM"), std::string::npos) << results[m].warning;  // none was wanted
    const auto written = std::filesystem::path(dir / "out") / (name + ".splats.ply");
    const splats::SplatFile file = splats::read_splat_file(written.string());
    EXPECT_EQ(file.info.origin.x, offset);
    EXPECT_EQ(file.info.origin.y, offset);
    EXPECT_EQ(file.info.origin.z, offset);
    ASSERT_GT(file.splats.size(), 500u);
    // The 48 x 24 facets lie within 100 (1 - cos(pi/24) cos(pi/48)) = 1.07 of the sphere, inside it.
    const double sag = 100 * (1 - std::cos(3.14159265358979 / 24) * std::cos(3.14159265358979 / 48));
    for (const splats::SplatRecord& s : file.splats) {
      const DVec3 from_centre = file.info.origin + DVec3(s.center) - DVec3{offset, offset, offset};
      const double r = length(from_centre);
      ASSERT_LE(r, 100 + file.info.eps) << s.center.x << " " << s.center.y << " " << s.center.z;
      ASSERT_GE(r, 100 - sag - file.info.eps) << s.center.x << " " << s.center.y << " " << s.center.z;
      ASSERT_GT(dot(from_centre, DVec3(s.normal)) / r, 0.95);
    }
    splats::SurfaceCheckOptions check;
    check.eps = file.info.eps;
    check.surface_points = 50'000;
    check.seed = 99;  // not the builder's points
    const splats::SurfaceCheckReport report = splats::check_surface(load_mesh_about(dir / (name + ".obj"), Winding::Orient, file.info.origin), file.splats, check);
    EXPECT_TRUE(report.ok()) << splats::describe_failure(report);
  }
}

// batch's splats read a mesh about its centre by the same test as splatcl splats, on the file's
// box: a tetrahedron 624.99 long at 1e6 is coarse only by its exact box (as floats it is 625 long,
// exactly at the threshold), and batch wrote origin 0 with no warning where splats recentred. A
// mesh recentred for its fine eps, with floats fine for its size, names no CSM float steps (its
// warning ended "; the CSM: ").
TEST(BatchRunner, RecentresAsSplatsDoes) {
  ScratchDir dir("runner-recentre");
  write_text(dir / "long.obj", "v 1000000 0 0\nv 1000624.99 0 0\nv 1000000 1 0\nv 1000000 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  write_text(dir / "fine.obj", "v 1000 0 0\nv 1001 0 0\nv 1000 1 0\nv 1000 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  ModelEntry coarse = model(dir, "long", "long.obj"), fine = model(dir, "fine", "fine.obj");
  coarse.params.splats = {}, fine.params.splats = {};
  coarse.params.want_csm = false;
  fine.params.splats.eps = 0.0003;
  const auto results = run_batch({coarse, fine}, reference_options(dir));
  ASSERT_EQ(results.size(), 2u);
  for (const ModelResult& r : results) ASSERT_TRUE(r.ok) << r.id << ": " << r.reason;
  EXPECT_EQ(load_mesh_recentred(dir / "long.obj", Winding::Orient, splats::recentre_test(coarse.params.splats)).origin.x, 1000312.495);
  const splats::SplatFile long_file = splats::read_splat_file((std::filesystem::path(dir / "out") / "long.splats.ply").string());
  EXPECT_EQ(long_file.info.origin.x, 1000312.495);
  EXPECT_NE(results[0].warning.find("the splats: coordinates reach"), std::string::npos) << results[0].warning;
  const splats::SplatFile fine_file = splats::read_splat_file((std::filesystem::path(dir / "out") / "fine.splats.ply").string());
  EXPECT_EQ(fine_file.info.origin.x, 1000.5);
  EXPECT_NE(results[1].warning.find("the splats: coordinates reach 1001"), std::string::npos) << results[1].warning;
  EXPECT_EQ(results[1].warning.find("the CSM"), std::string::npos) << results[1].warning;
}

// A closed plate thinner than the CSM's hit epsilon: the model's warning names it ("the CSM: N of M
// sample rays ..."), of the CSM as wanted now, whichever outputs a rerun rebuilds or reuses. A
// rerun with single_hit exact (the CSM rebuilt, the splats reused) kept the earlier warning; one
// that changed only the splats (the CSM reused) dropped it.
TEST(BatchRunner, ThinPartWarningFollowsTheCsmAsWanted) {
  ScratchDir dir("runner-thin");
  write_text(dir / "plate.obj",
             "v -50 -0.0005 -50\nv 50 -0.0005 -50\nv 50 0.0005 -50\nv -50 0.0005 -50\nv -50 -0.0005 50\nv 50 -0.0005 50\n"
             "v 50 0.0005 50\nv -50 0.0005 50\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n");
  ModelEntry entry = model(dir, "plate", "plate.obj");
  const auto run = [&](const ModelEntry& e) {
    const auto results = run_batch({e}, reference_options(dir));
    EXPECT_EQ(results.size(), 1u);
    EXPECT_TRUE(results[0].ok) << results[0].reason;
    return results[0];
  };
  const auto thin_parts = [](const ModelResult& r) {
    std::size_t count = 0;
    for (std::size_t at = r.warning.find("sample rays that hit this closed mesh"); at != std::string::npos;
         at = r.warning.find("sample rays that hit this closed mesh", at + 1))
      ++count;
    return count;
  };
  const ModelResult first = run(entry);
  EXPECT_EQ(thin_parts(first), 1u) << first.warning;
  EXPECT_NE(first.warning.find("the CSM: "), std::string::npos) << first.warning;
  entry.params.csm.single_hit = "exact";
  const ModelResult exact = run(entry);
  EXPECT_TRUE(output(exact, "splats")->reused);
  EXPECT_FALSE(output(exact, "csm")->reused);
  EXPECT_EQ(thin_parts(exact), 0u) << exact.warning;
  entry.params.csm.single_hit = "auto";
  const ModelResult again = run(entry);
  EXPECT_EQ(thin_parts(again), 1u) << again.warning;
  entry.params.splats.k = 7;
  const ModelResult splats_only = run(entry);
  EXPECT_TRUE(output(splats_only, "csm")->reused);
  EXPECT_FALSE(output(splats_only, "splats")->reused);
  EXPECT_EQ(thin_parts(splats_only), 1u) << splats_only.warning;
  const ModelResult reused = run(entry);
  EXPECT_TRUE(output(reused, "csm")->reused && output(reused, "splats")->reused);
  EXPECT_EQ(reused.warning, splats_only.warning);
}

// An inside-out cube (every face wound clockwise seen from outside): its splats face outward, as
// splatcl splats makes them, and its CSM is the one of the cube as given; with keep_winding the
// splats face into it. Checked against the cube's centre, not the loader's normals.
TEST(BatchRunner, InsideOutModelsGetOutwardSplatsUnlessTheWindingIsKept) {
  ScratchDir dir("runner-inside-out");
  write_text(dir / "inside-out.obj",
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
             "f 2 3 4 1\nf 8 7 6 5\nf 5 6 2 1\nf 7 8 4 3\nf 6 7 3 2\nf 4 8 5 1\n");
  std::vector<ModelEntry> entries{model(dir, "turned", "inside-out.obj"), model(dir, "kept", "inside-out.obj")};
  entries[1].params.splats.keep_winding = true;
  const auto results = run_batch(entries, reference_options(dir));
  ASSERT_EQ(results.size(), 2u);
  const auto outward_share = [&](const std::string& id) {
    const splats::SplatFile file = splats::read_splat_file((std::filesystem::path(dir / "out") / (id + ".splats.ply")).string());
    std::size_t outward = 0;
    for (const auto& s : file.splats) outward += dot(s.center - Vec3{0.5f, 0.5f, 0.5f}, s.normal) > 0 ? 1 : 0;
    return static_cast<double>(outward) / static_cast<double>(file.splats.size());
  };
  for (const auto& r : results) ASSERT_TRUE(r.ok) << r.id << ": " << r.reason;
  // Each says what its splats got, as splatcl splats does (both said "faces point inward").
  EXPECT_NE(results[0].warning.find("6 faces turned to agree with their neighbours' winding (closed parts outward)"), std::string::npos)
      << results[0].warning;
  EXPECT_NE(results[1].warning.find("faces point inward"), std::string::npos) << results[1].warning;
  EXPECT_EQ(outward_share("turned"), 1.0);
  EXPECT_EQ(outward_share("kept"), 0.0);
  // The CSM does not depend on the winding the splats took.
  EXPECT_EQ(read_text(std::filesystem::path(dir / "out") / "turned.csm"), read_text(std::filesystem::path(dir / "out") / "kept.csm"));

  // Rerun with the winding kept for the first: its splats are rebuilt facing in, and its record
  // says so (it kept the earlier run's "turned ... face outward").
  entries[0].params.splats.keep_winding = true;
  const ModelResult rerun = run_batch({entries[0]}, reference_options(dir)).at(0);
  ASSERT_TRUE(rerun.ok) << rerun.reason;
  EXPECT_FALSE(output(rerun, "splats")->reused);
  EXPECT_TRUE(output(rerun, "csm")->reused);
  EXPECT_NE(rerun.warning.find("faces point inward"), std::string::npos) << rerun.warning;
  EXPECT_EQ(outward_share("turned"), 0.0);
}

// A model's outputs are checked before its work. A folder at the record's name fails the model at
// once, naming the file, and nothing is built (it gave a raw "basic_filebuf::underflow" message).
// A folder at one output's name fails that output alone, before its build (the build ran, then
// failed to write); the other output is still built, or reused and kept in the record.
TEST(BatchRunner, AModelsOutputsAreCheckedBeforeItsWork) {
  ScratchDir dir("runner-output-check");
  write_text(dir / "cube.obj", test::kCubeObj);
  const RunOptions options = reference_options(dir);
  const std::filesystem::path out(options.output_dir);
  std::filesystem::create_directories(out / "cube.batch.json");
  ModelResult r = run_batch({model(dir, "cube", "cube.obj")}, options).at(0);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.reason.rfind("cannot write output " + (out / "cube.batch.json").string() + ": it is a directory", 0), 0u) << r.reason;
  EXPECT_FALSE(std::filesystem::exists(out / "cube.splats.ply"));

  std::filesystem::remove_all(out);
  std::filesystem::create_directories(out / "cube.csm");
  r = run_batch({model(dir, "cube", "cube.obj")}, options).at(0);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.reason, "csm: cannot write output " + (out / "cube.csm").string() + ": it is a directory");
  ASSERT_NE(output(r, "splats"), nullptr);
  EXPECT_TRUE(std::filesystem::exists(out / "cube.splats.ply"));
  EXPECT_EQ(output(r, "csm"), nullptr);

  // Both built, then a folder where the CSM goes: the splats are reused and stay in the record.
  std::filesystem::remove_all(out / "cube.csm");
  ASSERT_TRUE(run_batch({model(dir, "cube", "cube.obj")}, options).at(0).ok);
  std::filesystem::remove(out / "cube.csm");
  std::filesystem::create_directories(out / "cube.csm");
  r = run_batch({model(dir, "cube", "cube.obj")}, options).at(0);
  EXPECT_FALSE(r.ok);
  ASSERT_NE(output(r, "splats"), nullptr);
  EXPECT_TRUE(output(r, "splats")->reused);
  EXPECT_NE(read_text(out / "cube.batch.json").find("\"splats\""), std::string::npos);
}

TEST(BatchRunner, ParallelJobsGiveTheSameOutputs) {
  ScratchDir dir("runner-jobs");
  write_text(dir / "cube.obj", test::kCubeObj);
  write_text(dir / "wedge.obj", test::kWedgeObj);
  std::vector<ModelEntry> models;
  for (int i = 0; i < 4; ++i) models.push_back(model(dir, "m" + std::to_string(i), i % 2 ? "cube.obj" : "wedge.obj"));
  RunOptions serial = reference_options(dir);
  RunOptions parallel = serial;
  parallel.output_dir = dir / "out-parallel";
  parallel.jobs = 3;
  const auto a = run_batch(models, serial), b = run_batch(models, parallel);
  for (std::size_t i = 0; i < models.size(); ++i) {
    ASSERT_TRUE(a[i].ok && b[i].ok);
    EXPECT_EQ(a[i].id, b[i].id);
    for (const std::string& name : {splats_name(a[i].id), csm_name(a[i].id)})
      EXPECT_EQ(read_text(serial.output_dir + "/" + name), read_text(parallel.output_dir + "/" + name)) << name;
  }
}

// The unit cube with texture coordinates: every face maps the whole image.
const char* kTexturedCubeObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 4/4 3/3 2/2\nf 5/1 6/2 7/3 8/4\nf 1/1 2/2 6/3 5/4\nf 3/1 4/2 8/3 7/4\nf 2/1 3/2 7/3 6/4\nf 1/1 5/2 8/3 4/4\n";

void write_solid_texture(const std::string& path, float r, float g, float b) {
  std::vector<float> rgb;
  for (int k = 0; k < 4; ++k) rgb.insert(rgb.end(), {r, g, b});
  write_image_rgb(path, 2, 2, rgb);
}

TEST(BatchRunner, TexturedModelsColourTheirSplatsAndRebuildWhenTheImageChanges) {
  ScratchDir dir("runner-texture");
  write_text(dir / "box.obj", kTexturedCubeObj);
  write_solid_texture(dir / "red.png", 1, 0, 0);
  std::vector<ModelEntry> models{model(dir, "box", "box.obj")};
  models[0].params.splats.texture = dir / "red.png";
  const RunOptions options = reference_options(dir);
  ModelResult r = run_batch(models, options).at(0);
  ASSERT_TRUE(r.ok) << r.reason;
  const splats::SplatFile red = splats::read_splat_file(options.output_dir + "/box.splats.ply");
  EXPECT_EQ(red.info.color_source, "texture:" + (dir / "red.png"));
  ASSERT_FALSE(red.splats.empty());
  for (const auto& splat : red.splats) EXPECT_TRUE(splat.color.r == 255 && splat.color.g == 0 && splat.color.b == 0);
  EXPECT_EQ(output(r, "splats")->params["texture"], dir / "red.png");

  // The image edited in place: the splats are rebuilt in the new colour, the CSM is reused.
  write_solid_texture(dir / "red.png", 0, 0, 1);
  r = run_batch(models, options).at(0);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_FALSE(output(r, "splats")->reused);
  EXPECT_TRUE(output(r, "csm")->reused);
  for (const auto& splat : splats::read_splat_file(options.output_dir + "/box.splats.ply").splats) EXPECT_EQ(splat.color.b, 255);
  EXPECT_TRUE(run_batch(models, options).at(0).reused());

  // A missing image or a mesh without texture coordinates fails the model, naming the cause.
  // The splats alone fail: the CSM is still reused and stays in the record (a missing texture
  // dropped it, so fixing the texture rebuilt it).
  models[0].params.splats.texture = dir / "missing.png";
  r = run_batch(models, options).at(0);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("splats: texture: cannot read " + (dir / "missing.png")), std::string::npos) << r.reason;
  ASSERT_NE(output(r, "csm"), nullptr);
  EXPECT_TRUE(output(r, "csm")->reused);
  EXPECT_NE(read_text(options.output_dir + "/box.batch.json").find("\"csm\""), std::string::npos);
  write_text(dir / "plain.obj", test::kCubeObj);
  std::vector<ModelEntry> plain{model(dir, "plain", "plain.obj")};
  plain[0].params.splats.texture = dir / "red.png";
  r = run_batch(plain, options).at(0);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("plain.obj has no texture coordinates"), std::string::npos) << r.reason;
}

TEST(BatchRunner, CsmParametersReachTheBuildAsInCsmBuild) {
  ScratchDir dir("runner-csm-params");
  write_text(dir / "cube.obj", test::kCubeObj);
  std::vector<ModelEntry> models{model(dir, "cube", "cube.obj")};
  models[0].params.want_splats = false;
  models[0].params.csm.capture = "raycast";
  models[0].params.csm.single_hit = "exact";
  models[0].params.csm.encoding = "compact";
  models[0].params.csm.batch = 3;
  const RunOptions options = reference_options(dir);
  ModelResult r = run_batch(models, options).at(0);
  ASSERT_TRUE(r.ok) << r.reason;
  csm::Encoding encoding = csm::Encoding::Plain;
  const csm::Csm raycast = csm::read_csm(options.output_dir + "/cube.csm", &encoding);
  EXPECT_EQ(raycast.info.capture, csm::CaptureMethod::Raycast);
  EXPECT_EQ(raycast.info.single_hit, csm::SingleHit::Exact);
  EXPECT_EQ(encoding, csm::Encoding::Compact);
  const nlohmann::json stats = nlohmann::json::parse(read_text(options.output_dir + "/cube.csm.json"));
  EXPECT_EQ(stats["capture"], "raycast");
  EXPECT_EQ(stats["batch_maps"], 3);
  // The batch size changes memory use, not the file: no rebuild.
  models[0].params.csm.batch = 5;
  EXPECT_TRUE(run_batch(models, options).at(0).reused());
  models[0].params.csm.capture = "raster";
  r = run_batch(models, options).at(0);
  EXPECT_FALSE(r.reused());
  EXPECT_EQ(csm::read_csm(options.output_dir + "/cube.csm").info.capture, csm::CaptureMethod::Raster);
}

TEST(BatchRunner, StaleTemporariesOfThisRunsModelsAreRemoved) {
  ScratchDir dir("runner-temps");
  write_text(dir / "cube.obj", test::kCubeObj);
  const RunOptions options = reference_options(dir);
  write_text(options.output_dir + "/cube.csm.tmp4242", "half");
  write_text(options.output_dir + "/other.csm.tmp4242", "not ours");
  ASSERT_TRUE(run_batch({model(dir, "cube", "cube.obj")}, options).at(0).ok);
  EXPECT_FALSE(std::filesystem::exists(options.output_dir + "/cube.csm.tmp4242"));
  EXPECT_TRUE(std::filesystem::exists(options.output_dir + "/other.csm.tmp4242"));
}

}  // namespace
}  // namespace splatcl::batch
