// splatcl bench splats: the splat stage phase by phase (sampling, kNN, fit = PCA frames + growth +
// safe points, growth alone from the same frames, selection, optimisation, metrics, output) and end
// to end, the fit phases on the session's OpenCL device beside the native reference, on
// stanford-bunny at ε = 0.0003 and ogre at ε = 0.001 × its bounding-box diagonal; and end to end in
// the two-sided variant (`splatcl splats`'s default) on both and on a generated flat 100×100-vertex
// grid at ε = 0.001 × its diagonal.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>

#include "bench/suites.hpp"
#include "io/in_flight.hpp"
#include "splats/pipeline.hpp"
#include "splats/pipeline_options.hpp"
#include "splats/reference.hpp"

namespace splatcl::bench {
namespace {

namespace spl = splatcl::splats;

struct BenchModel {
  const char* name;
  const char* file;     // nullptr: generated (the flat grid)
  double eps;           // absolute; 0: eps_diagonal × the bounding-box diagonal
  double eps_diagonal;
};

constexpr BenchModel kModels[] = {{"stanford-bunny", "stanford-bunny.obj", 0.0003, 0}, {"ogre", "ogre.obj", 0, 0.001}};
// A 130k-vertex scan at ε = 0.001 of the diagonal: none of the test models is that large,
// so the bunny's triangles are split in four at their edge midpoints (139k vertices, the same surface).
constexpr BenchModel kSubdividedBunny{"stanford-bunny-midpoint-4x", "stanford-bunny.obj", 0, 0.001};
// 100×100 vertices, 99×99 quads over the unit square: no test model needed.
constexpr BenchModel kFlatGrid{"flat-grid-100", nullptr, 0, 0.001};
constexpr std::size_t kFlatGridSide = 100;

std::filesystem::path model_path(const BenchModel& model) { return std::filesystem::path(splats_models_dir()) / model.file; }

}  // namespace

// Fails before any timing when a model is missing, naming what to pass.
void check_splats_models() {
  const std::string& dir = splats_models_dir();
  if (!std::filesystem::is_directory(dir))
    throw Error("bench splats: models directory " + dir + (std::filesystem::exists(dir) ? " is not a directory" : " does not exist") + " (--models DIR)");
  for (const BenchModel& model : kModels) {
    if (!std::filesystem::is_regular_file(model_path(model)))
      throw Error("bench splats: missing model " + model_path(model).string() + " (--models DIR)");
    // Read too: an empty or broken file passed and failed the suite after the other suites ran.
    (void)load_mesh(model_path(model).string());
  }
}

namespace {

// Benchmarks time only correct work: the device fit must equal the reference's exactly.
void expect_same_fit(const std::string& what, const spl::FitResult& actual, const spl::FitResult& expected) {
  expect_same_output(what + " covered offsets", actual.covered.offsets, expected.covered.offsets);
  expect_same_output(what + " covered samples", actual.covered.items, expected.covered.items);
  expect_same_output(what + " safe samples", actual.safe.items, expected.safe.items);
  if (actual.splats.size() != expected.splats.size() ||
      std::memcmp(actual.splats.data(), expected.splats.data(), actual.splats.size() * sizeof(spl::SplatShape)) != 0)
    throw Error("bench " + what + ": splat shapes differ from the reference");
  if (std::memcmp(actual.clips.data(), expected.clips.data(), actual.clips.size() * sizeof(Vec4)) != 0)
    throw Error("bench " + what + ": clip lines differ from the reference");
}

// A scratch PLY for the output phase, removed when the suite ends, or by a terminating signal
// (io/in_flight.hpp: SIGTERM left it in the temporary directory).
class ScratchFile {
 public:
  ScratchFile()
      : path_((std::filesystem::temp_directory_path() / fmt::format("splatcl-bench-splats-{}.ply", ::getpid())).string()),
        slot_(register_in_flight(path_)) {}
  ~ScratchFile() {
    unregister_in_flight(slot_);
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int slot_;
};

// Size scaling: every stride-th vertex of the model (stride = 1 / scale), as a point set. The bunny's
// and ogre's vertex orders follow their surfaces, so the kept vertices spread evenly over them.
std::size_t vertex_stride(const Session& session) {
  const double scale = session.options().scale;
  return scale >= 1 ? 1 : static_cast<std::size_t>(std::max(1.0, std::round(1 / scale)));
}

// The flat grid under size scaling: side × side vertices with side = 100 · √scale (at least 2), so the
// vertex count follows the scale; ε stays 0.001 × the unit square's diagonal.
std::size_t flat_grid_side(const Session& session) {
  const double scale = session.options().scale;
  if (scale >= 1) return kFlatGridSide;
  return std::max<std::size_t>(2, static_cast<std::size_t>(std::lround(kFlatGridSide * std::sqrt(scale))));
}

// side × side vertices over the unit square at z = 0, (side − 1)² quads facing +z.
Mesh flat_grid(std::size_t side) {
  std::vector<Vec3> vertices;
  vertices.reserve(side * side);
  // i / (side − 1) rounded once to float: what an OBJ written with these coordinates reads back as.
  auto at = [&](std::size_t i) { return static_cast<float>(static_cast<double>(i) / static_cast<double>(side - 1)); };
  for (std::size_t j = 0; j < side; ++j)
    for (std::size_t i = 0; i < side; ++i) vertices.push_back({at(i), at(j), 0});
  std::vector<std::vector<std::uint32_t>> faces;
  faces.reserve((side - 1) * (side - 1));
  for (std::size_t j = 0; j + 1 < side; ++j)
    for (std::size_t i = 0; i + 1 < side; ++i) {
      const auto a = static_cast<std::uint32_t>(j * side + i), s = static_cast<std::uint32_t>(side);
      faces.push_back({a, a + 1, a + 1 + s, a + s});
    }
  return make_mesh(vertices, faces, fmt::format("flat grid {}x{}", side, side));
}

// Every face fan-triangulated and each triangle split in four at its edge midpoints (one new vertex
// per edge, shared by its faces): the same surface with four times the triangles.
Mesh midpoint_subdivided(const Mesh& mesh) {
  std::vector<Vec3> vertices = mesh.vertices;
  std::unordered_map<std::uint64_t, std::uint32_t> midpoints;
  const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
    const auto [it, added] = midpoints.try_emplace(key, static_cast<std::uint32_t>(vertices.size()));
    if (added) {
      const Vec3 p = vertices[a], q = vertices[b];
      vertices.push_back({0.5f * (p.x + q.x), 0.5f * (p.y + q.y), 0.5f * (p.z + q.z)});
    }
    return it->second;
  };
  std::vector<std::vector<std::uint32_t>> faces;
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    for (std::uint32_t c = mesh.face_offsets[f] + 1; c + 1 < mesh.face_offsets[f + 1]; ++c) {
      const std::uint32_t a = mesh.corners[mesh.face_offsets[f]], b = mesh.corners[c], d = mesh.corners[c + 1];
      const std::uint32_t ab = midpoint(a, b), bd = midpoint(b, d), da = midpoint(d, a);
      faces.push_back({a, ab, da});
      faces.push_back({ab, b, bd});
      faces.push_back({da, bd, d});
      faces.push_back({ab, bd, da});
    }
  return make_mesh(vertices, faces, mesh.source + " (triangles split at their edge midpoints)");
}

// ε to 4 significant digits, so the case label reads 0.0003 and not the float's double expansion.
Json problem_of(const BenchModel& model, float eps) { return Json{{"model", model.name}, {"eps", std::stod(fmt::format("{:.4g}", eps))}}; }

// The two-sided end-to-end rows must write the same splats, bit for bit, field by field (memcmp, so
// that -0 and NaN count as differences too; the struct itself may have padding).
void expect_same_splats(const std::string& what, const std::vector<spl::SplatRecord>& actual,
                        const std::vector<spl::SplatRecord>& expected) {
  if (actual.size() != expected.size())
    throw Error(fmt::format("bench {}: {} splats written, the reference {}", what, actual.size(), expected.size()));
  for (std::size_t i = 0; i < actual.size(); ++i) {
    const spl::SplatRecord &a = actual[i], &e = expected[i];
    const bool same = std::memcmp(&a.center, &e.center, sizeof a.center) == 0 && std::memcmp(&a.normal, &e.normal, sizeof a.normal) == 0 &&
                      std::memcmp(&a.major, &e.major, sizeof a.major) == 0 && std::memcmp(&a.minor, &e.minor, sizeof a.minor) == 0 &&
                      std::memcmp(&a.color, &e.color, sizeof a.color) == 0 && std::memcmp(&a.clip_x, &e.clip_x, sizeof a.clip_x) == 0 &&
                      std::memcmp(&a.clip_y, &e.clip_y, sizeof a.clip_y) == 0 &&
                      std::memcmp(&a.clip_offset, &e.clip_offset, sizeof a.clip_offset) == 0;
    if (!same) throw Error("bench " + what + ": splat " + std::to_string(i) + " differs from the reference's");
  }
}

// End to end as `splatcl splats MODEL -o OUT --no-check` runs it by default: the two-sided variant
// (splats::splat_setup from a default SplatParameters with the model's ε), load (`load`: read or
// generate the mesh), every phase, write the PLY; the end-of-run surface check (what --no-check
// skips) is not timed. The device fit, then the reference's, which must write the same splats. Each
// record's size is its run's sample count (sampling "auto": the vertices plus face points where they
// are sparser than the auto spacing, so not the thesis rows' count); its "run" object holds the last
// timed run's counts, phase times (as `--stats`'s "phase_ms") and peak RSS per 1000 samples.
void measure_two_sided(Session& session, const BenchModel& model, const std::string& source, const std::function<Mesh()>& load,
                       const ScratchFile& scratch) {
  spl::SplatParameters params;
  if (model.eps > 0)
    params.eps = model.eps;
  else
    params.eps_diag = model.eps_diagonal;
  const spl::SplatSetup setup = spl::splat_setup(params, load(), source);
  const Json problem = problem_of(model, setup.options.fit.eps);
  struct Outcome {
    std::vector<spl::SplatRecord> records;
    std::uint64_t samples = 0;
    Json run = Json::object();
  };
  auto end_to_end = [&](Runtime* fit_runtime, Outcome& out) {
    Stopwatch load_clock;
    const Mesh mesh = load();
    const double load_ms = load_clock.elapsed_ms();
    spl::SplatRun run = spl::generate_splats(mesh, setup.colors, setup.options, fit_runtime);
    run.phases.insert(run.phases.begin(), {"load", load_ms});
    out.records = run.records();
    Stopwatch write_clock;
    spl::write_splat_file(scratch.path(), out.records, spl::splat_file_info(setup, run, source));
    run.phases.push_back({"write", write_clock.elapsed_ms()});
    Json phase_ms = Json::object();
    for (const spl::PhaseTime& p : run.phases) phase_ms[p.phase] = p.ms;
    out.samples = run.samples.size();
    out.run = Json{{"samples", out.samples},
                   {"vertices", mesh.vertices.size()},
                   {"output_splats", run.output_count()},
                   {"selected_splats", run.selected.size()},
                   {"gap_splats", run.gap_splats.size()},
                   {"shrunk_splats", run.surface_fit.shrunk},
                   {"phase_ms", std::move(phase_ms)}};
  };
  // What only the run knows: the sample count (size and throughput) and the run's figures.
  auto complete = [&](const Outcome& out) {
    Record& record = session.last_record();
    record.size = out.samples;
    record.size_unit = "samples";
    if (out.samples > 0 && record.median_ms > 0) {
      record.throughput = static_cast<double>(out.samples) / (record.median_ms * 1e-3);
      record.throughput_unit = "samples/s";
    }
    Json run = out.run;
    if (record.peak_rss_mb && out.samples > 0) run["peak_rss_mb_per_1000_samples"] = *record.peak_rss_mb * 1000.0 / static_cast<double>(out.samples);
    record.extra["run"] = std::move(run);
  };
  const char* name = "end-to-end-two-sided";
  Outcome device, reference;
  const Case device_case{name, kImplOpenCL, true, 0, "samples", problem};
  session.measure(device_case, {}, [&] { end_to_end(&session.runtime(), device); });
  complete(device);
  session.measure(reference_case(name, 0, "samples", problem), {}, [&] { end_to_end(nullptr, reference); });
  complete(reference);
  expect_same_splats(describe(device_case), device.records, reference.records);
}

Mesh every_nth_vertex(Mesh mesh, std::size_t stride) {
  if (stride <= 1) return mesh;
  Mesh kept;
  kept.source = fmt::format("{} (every {}th vertex)", mesh.source, stride);
  for (std::size_t i = 0; i < mesh.vertices.size(); i += stride) {
    kept.vertices.push_back(mesh.vertices[i]);
    kept.normals.push_back(mesh.normals[i]);
  }
  return kept;
}

void run_thesis_cases(Session& session, const BenchModel& model, const ScratchFile& scratch) {
  const std::string path = model_path(model).string();
  const Mesh whole = load_mesh(path);
  const std::size_t stride = vertex_stride(session);
  const Mesh mesh = every_nth_vertex(whole, stride);
  spl::PipelineOptions options;
  // ε and the colour bounds of the whole model at every size, so the case stays the same problem.
  options.fit.eps = static_cast<float>(model.eps > 0 ? model.eps : model.eps_diagonal * whole.bounds().diagonal());
  spl::ColorSource colors;
  colors.bounds = whole.bounds();
  const spl::SplatFileInfo info{path, spl::to_string(options.sampling), options.fit.eps, options.k, 255, "grey", false};
  const Json problem = problem_of(model, options.fit.eps);
  Runtime& runtime = session.runtime();

  spl::Samples samples = spl::sample_mesh(mesh, options.sampling, colors);
  const std::uint64_t n = samples.size();
  auto host_case = [&](const char* name) { return reference_case(name, n, "samples", problem); };
  auto device_case = [&](const char* name) { return Case{name, kImplOpenCL, true, n, "samples", problem}; };

  session.measure(host_case("sampling"), {}, [&] { samples = spl::sample_mesh(mesh, options.sampling, colors); });
  spl::Neighborhoods neighbors;
  // The kNN graph is FLANN's exact single kd-tree (splats/neighbors.hpp), with the pipeline's
  // opposed-sheet filter (since 2026-12-06: rows near a thin part's other side search wider).
  session.measure(Case{"knn", "flann", false, n, "samples", problem}, {},
                  [&] { neighbors = spl::find_neighbors(samples.positions, options.k, &samples.normals, spl::crease_cosine(options.fit.crease_degrees));
                  });

  // Fit: PCA frames, growth and safe points.
  spl::FitResult expected, fit;
  Profiler profiler;
  session.measure(device_case("fit"), {}, [&] { fit = spl::fit_splats(runtime, samples, neighbors, options.fit, nullptr, nullptr, &profiler); },
                  &profiler);
  session.measure(host_case("fit"), {}, [&] { expected = spl::reference::fit_splats(samples, neighbors, options.fit); });
  expect_same_fit(describe(device_case("fit")), fit, expected);

  // Growth and safe points alone, both from the reference's frames.
  Profiler grow_profiler;
  session.measure(device_case("growth"), {},
                  [&] { fit = spl::fit_splats(runtime, samples, neighbors, options.fit, &expected.frames, nullptr, &grow_profiler); },
                  &grow_profiler);
  spl::FitResult grown;
  session.measure(host_case("growth"), {}, [&] { grown = spl::reference::grow_splats(samples, neighbors, expected.frames, options.fit); });
  expect_same_fit(describe(device_case("growth")), fit, expected);
  expect_same_fit(describe(host_case("growth")), grown, expected);

  spl::Rows inverse;
  std::vector<std::uint32_t> greedy;
  session.measure(host_case("selection"), {}, [&] {
    inverse = spl::inverse_index(expected.safe, samples.size());
    greedy = spl::greedy_cover(expected.safe, inverse, neighbors.weight);
  });
  std::vector<std::uint32_t> picked, selected;
  session.measure(host_case("optimisation"), [&] { picked = greedy; }, [&] {
    selected = spl::optimise_selection(std::move(picked), expected.safe, inverse, neighbors.weight, neighbors, options.rounds);
  });
  session.measure(host_case("metrics"), {}, [&] {
    std::vector<std::uint8_t> chosen(samples.size(), 0);
    for (const std::uint32_t j : selected) chosen[j] = 1;
    spl::coverage_errors(samples, expected.splats, inverse, nullptr);
    spl::coverage_errors(samples, expected.splats, inverse, &chosen);
  });
  std::vector<spl::SplatRecord> records;
  for (const std::uint32_t j : selected) {
    const spl::SplatShape& s = expected.splats[j];
    records.push_back({xyz(s.center), xyz(s.normal), xyz(s.major), xyz(s.minor), samples.colors[j]});
  }
  session.measure(host_case("output"), {}, [&] { spl::write_splat_file(scratch.path(), records, info); });

  // End to end, as `splatcl splats` runs it: load, every phase, write.
  std::vector<std::uint32_t> device_selection, reference_selection;
  auto end_to_end = [&](Runtime* fit_runtime, std::vector<std::uint32_t>& selection) {
    const Mesh loaded = every_nth_vertex(load_mesh(path), stride);
    const spl::SplatRun run = spl::generate_splats(loaded, colors, options, fit_runtime);
    spl::write_splat_file(scratch.path(), run.records(), info);
    selection = run.selected;
  };
  session.measure(device_case("end-to-end"), {}, [&] { end_to_end(&runtime, device_selection); });
  session.measure(host_case("end-to-end"), {}, [&] { end_to_end(nullptr, reference_selection); });
  expect_same_output(describe(device_case("end-to-end")) + " selection", device_selection, reference_selection);
  expect_same_output(describe(host_case("end-to-end")) + " selection", reference_selection, selected);
}

// A model's rows: the thesis's phase by phase and end to end, then the two-sided end to end (once the
// thesis rows' data is freed). Size scaling keeps a point set of every stride-th vertex, which has no
// surface to bound by: the two-sided rows are left out below the standard size.
void run_model(Session& session, const BenchModel& model, const ScratchFile& scratch) {
  run_thesis_cases(session, model, scratch);
  if (vertex_stride(session) > 1) return;
  const std::string path = model_path(model).string();
  measure_two_sided(session, model, path, [&] { return load_mesh(path); }, scratch);
}

// The flat grid, two-sided end to end only. The thesis's rows are left out: its growth is capped only
// by the sets' memory (2^26 / samples), so every splat on a plane grows over most of the grid
// (`splatcl splats GRID --thesis-only --samples vertices`: 14.7 s and 1.0 GiB for one run on 2 cores,
// docs/results/splats.md, "Cost of the two-sided bound").
void run_flat_grid(Session& session, const ScratchFile& scratch) {
  const std::size_t side = flat_grid_side(session);
  measure_two_sided(session, kFlatGrid, fmt::format("{} (generated, {}x{} vertices)", kFlatGrid.name, side, side),
                    [&] { return flat_grid(side); }, scratch);
}

}  // namespace

std::string& splats_models_dir() {
  static std::string dir = SPLATCL_MODELS_DIR;
  return dir;
}

void run_splats_suite(Session& session) {
  check_splats_models();
  const ScratchFile scratch;
  // --quick: the bunny and the flat grid (≈ 10 s more on 2 cores), not ogre.
  for (const BenchModel& model : kModels) {
    run_model(session, model, scratch);
    if (session.options().quick) break;
  }
  if (!session.options().quick && vertex_stride(session) == 1) {
    const std::string path = model_path(kSubdividedBunny).string();
    const Mesh subdivided = midpoint_subdivided(load_mesh(path));
    measure_two_sided(session, kSubdividedBunny, fmt::format("{} ({} vertices)", subdivided.source, subdivided.vertices.size()),
                      [&] { return subdivided; }, scratch);
  }
  run_flat_grid(session, scratch);
}

}  // namespace splatcl::bench
