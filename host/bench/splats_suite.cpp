// splatcl bench splats: the splat stage phase by phase (sampling, kNN, fit = PCA frames + growth +
// safe points, growth alone from the same frames, selection, optimisation, metrics, output) and end
// to end, the fit phases on the session's OpenCL device beside the native reference, on
// stanford-bunny at ε = 0.0003 and ogre at ε = 0.001 × its bounding-box diagonal.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "bench/suites.hpp"
#include "splats/pipeline.hpp"
#include "splats/reference.hpp"

namespace splatcl::bench {
namespace {

namespace spl = splatcl::splats;

struct BenchModel {
  const char* name;
  const char* file;
  double eps;           // absolute; 0: eps_diagonal × the bounding-box diagonal
  double eps_diagonal;
};

constexpr BenchModel kModels[] = {{"stanford-bunny", "stanford-bunny.obj", 0.0003, 0}, {"ogre", "ogre.obj", 0, 0.001}};

std::filesystem::path model_path(const BenchModel& model) { return std::filesystem::path(splats_models_dir()) / model.file; }

// Fails before any timing when a model is missing, naming what to pass.
void check_models() {
  const std::string& dir = splats_models_dir();
  if (!std::filesystem::is_directory(dir)) throw Error("bench splats: models directory " + dir + " does not exist (--models DIR)");
  for (const BenchModel& model : kModels)
    if (!std::filesystem::is_regular_file(model_path(model)))
      throw Error("bench splats: missing model " + model_path(model).string() + " (--models DIR)");
}

// Benchmarks time only correct work: the device fit must equal the reference's exactly.
void expect_same_fit(const std::string& what, const spl::FitResult& actual, const spl::FitResult& expected) {
  expect_same_output(what + " covered offsets", actual.covered.offsets, expected.covered.offsets);
  expect_same_output(what + " covered samples", actual.covered.items, expected.covered.items);
  expect_same_output(what + " safe samples", actual.safe.items, expected.safe.items);
  if (actual.splats.size() != expected.splats.size() ||
      std::memcmp(actual.splats.data(), expected.splats.data(), actual.splats.size() * sizeof(spl::SplatShape)) != 0)
    throw Error("bench " + what + ": splat shapes differ from the reference");
  if (std::memcmp(actual.clips.data(), expected.clips.data(), actual.clips.size() * sizeof(spl::Vec4)) != 0)
    throw Error("bench " + what + ": clip lines differ from the reference");
}

// A scratch PLY for the output phase, removed when the suite ends.
class ScratchFile {
 public:
  ScratchFile()
      : path_((std::filesystem::temp_directory_path() / fmt::format("splatcl-bench-splats-{}.ply", ::getpid())).string()) {}
  ~ScratchFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Size scaling: every stride-th vertex of the model (stride = 1 / scale), as a point set. The bunny's
// and ogre's vertex orders follow their surfaces, so the kept vertices spread evenly over them.
std::size_t vertex_stride(const Session& session) {
  const double scale = session.options().scale;
  return scale >= 1 ? 1 : static_cast<std::size_t>(std::max(1.0, std::round(1 / scale)));
}

spl::Mesh every_nth_vertex(spl::Mesh mesh, std::size_t stride) {
  if (stride <= 1) return mesh;
  spl::Mesh kept;
  kept.source = fmt::format("{} (every {}th vertex)", mesh.source, stride);
  for (std::size_t i = 0; i < mesh.vertices.size(); i += stride) {
    kept.vertices.push_back(mesh.vertices[i]);
    kept.normals.push_back(mesh.normals[i]);
  }
  return kept;
}

void run_model(Session& session, const BenchModel& model, const ScratchFile& scratch) {
  const std::string path = model_path(model).string();
  const spl::Mesh whole = spl::load_mesh(path);
  const std::size_t stride = vertex_stride(session);
  const spl::Mesh mesh = every_nth_vertex(whole, stride);
  spl::PipelineOptions options;
  // ε and the colour bounds of the whole model at every size, so the case stays the same problem.
  options.fit.eps = static_cast<float>(model.eps > 0 ? model.eps : model.eps_diagonal * whole.bounds().diagonal());
  spl::ColorSource colors;
  colors.bounds = whole.bounds();
  const spl::SplatFileInfo info{path, spl::to_string(options.sampling), options.fit.eps, options.k, 255, "grey", false};
  // ε to 4 significant digits, so the case label reads 0.0003 and not the float's double expansion.
  const Json problem{{"model", model.name}, {"eps", std::stod(fmt::format("{:.4g}", options.fit.eps))}};
  Runtime& runtime = session.runtime();

  spl::Samples samples = spl::sample_mesh(mesh, options.sampling, colors);
  const std::uint64_t n = samples.size();
  auto host_case = [&](const char* name) { return reference_case(name, n, "samples", problem); };
  auto device_case = [&](const char* name) { return Case{name, kImplOpenCL, true, n, "samples", problem}; };

  session.measure(host_case("sampling"), {}, [&] { samples = spl::sample_mesh(mesh, options.sampling, colors); });
  spl::Neighborhoods neighbors;
  // The kNN graph is FLANN's exact single kd-tree (splats/neighbors.hpp): the peer library itself.
  session.measure(Case{"knn", "flann", false, n, "samples", problem}, {},
                  [&] { neighbors = spl::find_neighbors(samples.positions, options.k); });

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
    records.push_back({spl::xyz(s.center), spl::xyz(s.normal), spl::xyz(s.major), spl::xyz(s.minor), samples.colors[j]});
  }
  session.measure(host_case("output"), {}, [&] { spl::write_splat_file(scratch.path(), records, info); });

  // End to end, as `splatcl splats` runs it: load, every phase, write.
  std::vector<std::uint32_t> device_selection, reference_selection;
  auto end_to_end = [&](Runtime* fit_runtime, std::vector<std::uint32_t>& selection) {
    const spl::Mesh loaded = every_nth_vertex(spl::load_mesh(path), stride);
    const spl::SplatRun run = spl::generate_splats(loaded, colors, options, fit_runtime);
    spl::write_splat_file(scratch.path(), run.records(), info);
    selection = run.selected;
  };
  session.measure(device_case("end-to-end"), {}, [&] { end_to_end(&runtime, device_selection); });
  session.measure(host_case("end-to-end"), {}, [&] { end_to_end(nullptr, reference_selection); });
  expect_same_output(describe(device_case("end-to-end")) + " selection", device_selection, reference_selection);
  expect_same_output(describe(host_case("end-to-end")) + " selection", reference_selection, selected);
}

}  // namespace

std::string& splats_models_dir() {
  static std::string dir = SPLATCL_MODELS_DIR;
  return dir;
}

void run_splats_suite(Session& session) {
  check_models();
  const ScratchFile scratch;
  // --quick: the bunny only.
  for (const BenchModel& model : kModels) {
    run_model(session, model, scratch);
    if (session.options().quick) break;
  }
}

}  // namespace splatcl::bench
