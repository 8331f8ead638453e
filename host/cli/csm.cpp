// splatcl csm: coherent shadow maps. `build` captures the dual-depth maps on the OpenCL device and
// compresses them per pixel while streaming; `info` describes a .csm file (and draws its coherence
// map); `verify` validates a file and, given its model, checks losslessness for every (map, pixel).
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string_view>

#include "bench/measure.hpp"
#include "cli/commands.hpp"
#include "cli/parameter_options.hpp"
#include "cli/model_input.hpp"
#include "cli/progress.hpp"
#include "csm/analysis.hpp"
#include "csm/build.hpp"
#include "csm/build_options.hpp"
#include "csm/csm_file.hpp"
#include "csm/quality.hpp"
#include "io/atomic_file.hpp"
#include "io/image.hpp"
#include "io/output_files.hpp"
#include "runtime/error.hpp"

namespace splatcl::cli {
namespace {

using namespace splatcl::csm;

struct BuildCommand {
  DeviceOptions device;
  std::string model, output, coherence, mode = "per-pixel";
  std::string pixel_order;  // empty: not given (hilbert); only --mode per-map takes it
  // The build parameters: the list `splatcl batch` shares, as --NAME options applied after parsing.
  std::shared_ptr<GivenParameters> given = std::make_shared<GivenParameters>();
  bool reference = false;
};

struct InfoCommand {
  std::string file, coherence;
};

struct QualityCommand {
  BuildCommand build;
  std::string csm_file, filter = "none";
  QualityOptions options;
};

struct AnalyzeCommand {
  BuildCommand build;
  std::vector<std::uint32_t> kmeans;
  bool wavelet = false;
  std::uint32_t seed = 1, iterations = 20;
};

struct VerifyCommand {
  DeviceOptions device;
  std::string file, model, capture;  // empty: the method recorded in the file
  bool reference = false;
};

// Map counts of a build on the progress line.
BuildProgress map_progress(ProgressLine& progress, const std::string& what) {
  return [&progress, what](std::uint32_t done, std::uint32_t total) {
    progress.show(fmt::format("{} {}/{} maps", what, done, total));
  };
}

double mib(double bytes) { return bytes / (1024.0 * 1024.0); }

double uncompressed_bytes(const CsmInfo& info) { return 8.0 * info.maps * info.resolution * info.resolution; }

// c = 1 − (S_px − 1)/(N − 1) (Talpe §5.3.6): white = one segment, black = a segment per map.
void write_coherence_map(const std::string& path, const Csm& csm) {
  const int m = static_cast<int>(csm.info.resolution);
  std::vector<float> rgb(csm.pixels() * 3);
  const double span = std::max(1.0, static_cast<double>(csm.info.maps) - 1);
  for (std::size_t p = 0; p < csm.pixels(); ++p) {
    const double segments = csm.offsets[p + 1] - csm.offsets[p];
    const auto c = static_cast<float>(1.0 - (segments - 1) / span);
    rgb[3 * p] = rgb[3 * p + 1] = rgb[3 * p + 2] = c;
  }
  write_image_rgb(path, m, m, rgb);
}

void print_parameters(const CsmInfo& info) {
  const SphereGrid grid(info.distribution, info.order, info.pole, info.maps);
  fmt::print("model      {} ({} triangles)\n", info.source.empty() ? "(unnamed)" : info.source, info.triangles);
  fmt::print("maps       {} = {} x {} ({} distribution, {} order, pole {}), {}x{} pixels\n", info.maps, grid.rows(), grid.cols(),
             to_string(info.distribution), to_string(info.order), to_string(info.pole), info.resolution, info.resolution);
  fmt::print("sphere     centre ({:.6g}, {:.6g}, {:.6g}), radius {:.6g}; single-surface pixels: {}; hit epsilon {:.3g}\n",
             info.sphere.centre.x, info.sphere.centre.y, info.sphere.centre.z, info.sphere.radius, to_string(info.single_hit),
             info.hit_epsilon);
  fmt::print("capture    {}\n", to_string(info.capture));
  const auto& t = info.object_transform;
  const bool identity = t == CsmInfo{}.object_transform;
  fmt::print("transform  {}\n", identity ? std::string("identity (the model as loaded)")
                                          : fmt::format("[{:.6g} {:.6g} {:.6g} {:.6g}; {:.6g} {:.6g} {:.6g} {:.6g}; {:.6g} {:.6g} {:.6g} {:.6g}] "
                                                        "(model file to object space, row-major)",
                                                        t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7], t[8], t[9], t[10], t[11]));
}

void print_sizes(const Csm& csm, double plain_bytes, double compact_bytes) {
  const double raw = uncompressed_bytes(csm.info);
  fmt::print("segments   {} ({:.2f} per pixel, {:.4f} B per (pixel, map) plain)\n", csm.segments(),
             static_cast<double>(csm.segments()) / static_cast<double>(csm.pixels()), plain_bytes / (raw / 8.0));
  fmt::print("size       uncompressed {:.2f} MiB; plain {:.2f} MiB ({:.1f}:1); compact {:.2f} MiB ({:.1f}:1, {:.1f}% of plain)\n",
             mib(raw), mib(plain_bytes), raw / plain_bytes, mib(compact_bytes), raw / compact_bytes, 100.0 * compact_bytes / plain_bytes);
}

// The build parameters of a CSM made in memory (csm quality, csm analyze): the shared list without
// the file encoding and the capture batch size, which only a written file or its memory use shows.
void add_in_memory_build_options(CLI::App& app, BuildCommand& b) {
  std::vector<ParameterInfo> in_memory;
  for (const ParameterInfo& p : csm_parameters())
    if (std::string_view(p.key) != "encoding" && std::string_view(p.key) != "batch") in_memory.push_back(p);
  add_parameter_options(app, in_memory, to_json(CsmParameters{}), b.given);
}

// The parameters given, with the same checks and translation as `splatcl batch` (csm/build_options.hpp).
CsmParameters parameters(const BuildCommand& c) {
  CsmParameters p;
  for (const auto& [option, value] : *c.given) set_parameter(p, option, value);
  return p;
}
BuildOptions build_options(const BuildCommand& c) {
  const CsmParameters p = parameters(c);
  validate(p, Spelling::Option);  // errors name the options as typed (--maps), not the manifest keys
  BuildOptions options = to_build_options(p);
  options.thin_part_remedy = options.hit_epsilon > kMinHitEpsilon ? "lower --hit-eps (e.g. to 1e-7) or pass --single-hit exact"
                                                                   : "pass --single-hit exact (--hit-eps is at its least)";
  return options;
}

// --mode other than per-pixel: the thesis's alternatives, compared by size (no .csm written).
int run_mode(const BuildCommand& c, CompressionMode mode) {
  if (!c.output.empty()) throw Error(fmt::format("csm build: --mode {} only measures sizes; -o writes per-pixel CSMs only", to_string(mode)));
  if (!c.coherence.empty())
    throw Error(fmt::format("csm build: --mode {} only measures sizes; --coherence maps per-pixel CSMs only", to_string(mode)));
  const BuildOptions options = build_options(c);
  ModeOptions mode_options;
  mode_options.mode = mode;
  mode_options.pixel_curve = parse_pixel_curve(c.pixel_order.empty() ? "hilbert" : c.pixel_order);
  ProgressLine progress("csm");
  const Mesh mesh = load_model(c.model, progress, Winding::AsGiven);
  std::shared_ptr<Runtime> runtime;
  if (!c.reference) runtime = Runtime::create(c.device.device);
  const ModeResult r = compress_in_mode(mesh, options, mode_options, runtime.get(), map_progress(progress, "captured and compressed"));
  progress.clear();
  CsmInfo info;
  info.maps = options.maps;
  info.resolution = options.resolution;
  const double raw = uncompressed_bytes(info);
  fmt::print("mode       {}{} on {} maps of {}x{} ({} distribution, {} order, {} capture)\n", to_string(mode),
             mode == CompressionMode::PerMap ? fmt::format(" (pixel order {})", to_string(mode_options.pixel_curve)) : std::string(),
             options.maps, options.resolution, options.resolution, to_string(options.distribution), to_string(options.order),
             to_string(options.capture));
  fmt::print("segments   {} in {} lists ({:.4f} per (pixel, map))\n", r.segments, r.lists,
             static_cast<double>(r.segments) / static_cast<double>(r.samples));
  fmt::print("size       uncompressed {:.2f} MiB; plain {:.2f} MiB ({:.1f}:1)\n", mib(raw), mib(static_cast<double>(r.plain_bytes())),
             raw / static_cast<double>(r.plain_bytes()));
  fmt::print("time       capture {:.2f} s, compression + check {:.2f} s; peak resident {:.0f} MiB\n", r.capture_ms / 1000,
             r.compress_ms / 1000, bench::peak_rss_mb());
  if (r.violations)
    throw Error(fmt::format("--mode {}: not lossless for {} of {} (map, pixel) samples", to_string(mode), r.violations, r.samples));
  fmt::print("lossless   all {} (map, pixel) samples decode through the mode's lookup to a depth in [z1, z2)\n", r.samples);
  return 0;
}

int run_build(const BuildCommand& c) {
  if (c.model.empty()) throw Error("csm build: a MODEL is required (see splatcl csm build --help)");
  const CompressionMode mode = parse_compression_mode(c.mode);
  if (!c.pixel_order.empty()) {
    (void)parse_pixel_curve(c.pixel_order);  // a bad --pixel-order is an error whatever the mode
    if (mode != CompressionMode::PerMap)
      throw Error(fmt::format("csm build: --pixel-order is the pixel curve of --mode per-map; --mode {} has none", to_string(mode)));
  }
  if (mode != CompressionMode::PerPixel) return run_mode(c, mode);
  if (c.output.empty()) throw Error("csm build: an output file is required (-o OUT.csm)");
  const BuildOptions options = build_options(c);
  const Encoding encoding = parse_encoding(parameters(c).encoding);
  // Both outputs writable before any work (a killed earlier run's temporaries of them are removed);
  // both staged and committed together, so a failure leaves neither.
  check_output_file(c.output, "-o");
  check_output_file(c.coherence, "--coherence");
  check_distinct_outputs({{"-o", c.output}, {"--coherence", c.coherence}});
  check_outputs_spare_inputs({{"-o", c.output}, {"--coherence", c.coherence}}, {{"model", c.model}});
  check_output_extension(c.output, "-o", {".csm"}, "a coherent shadow map");
  check_output_extension(c.coherence, "--coherence", {".png", ".exr"}, "the coherence map image");
  ProgressLine progress("csm");
  const Mesh mesh = load_model(c.model, progress, Winding::AsGiven);
  std::shared_ptr<Runtime> runtime;
  if (!c.reference) runtime = Runtime::create(c.device.device);
  const BuildResult result = build_csm(mesh, options, runtime.get(), map_progress(progress, "captured and compressed"));
  if (!result.thin_part_warning.empty()) queue_warning(c.model, result.thin_part_warning);
  progress.show("writing " + c.output);
  Stopwatch write_clock;
  const std::string plain = encode_csm(result.csm, Encoding::Plain);
  const std::string compact = encode_csm(result.csm, Encoding::Compact, &result.segments);
  StagedOutputs outputs;
  if (!c.coherence.empty()) outputs.stage(c.coherence);
  outputs.stage(c.output);
  outputs.write(c.output, [&](const std::string& path) { write_file_atomically(path, encoding == Encoding::Plain ? plain : compact); });
  if (!c.coherence.empty()) outputs.write(c.coherence, [&](const std::string& path) { write_coherence_map(path, result.csm); });
  outputs.commit();
  const double write_ms = write_clock.elapsed_ms();
  progress.clear();
  print_parameters(result.csm.info);
  print_sizes(result.csm, static_cast<double>(plain.size()), static_cast<double>(compact.size()));
  fmt::print("time       setup {:.2f} s, capture {:.2f} s, compression {:.2f} s (device), build {:.2f} s, encode + write {:.2f} s; "
             "{} maps per batch on {}\n",
             result.setup_ms / 1000, result.capture_ms / 1000, result.compress_ms / 1000, result.total_ms / 1000, write_ms / 1000,
             result.batch_maps, runtime ? runtime->info().name : std::string("the native reference"));
  fmt::print("memory     peak resident {:.0f} MiB\n", bench::peak_rss_mb());
  fmt::print("wrote      {} ({} encoding){}\n", c.output, to_string(encoding), c.coherence.empty() ? "" : ", " + c.coherence);
  return 0;
}

int run_info(const InfoCommand& c) {
  check_output_file(c.coherence, "--coherence");
  check_output_extension(c.coherence, "--coherence", {".png", ".exr"}, "the coherence map image");  // not after the report
  Encoding encoding = Encoding::Plain;
  std::size_t bytes = 0;
  const Csm csm = read_csm(c.file, &encoding, &bytes);
  print_parameters(csm.info);
  const double plain = encoding == Encoding::Plain ? static_cast<double>(bytes) : static_cast<double>(encode_csm(csm, Encoding::Plain).size());
  const double compact = encoding == Encoding::Compact ? static_cast<double>(bytes) : static_cast<double>(encode_csm(csm, Encoding::Compact).size());
  print_sizes(csm, plain, compact);
  std::uint32_t most = 0;
  for (std::size_t p = 0; p < csm.pixels(); ++p) most = std::max(most, csm.offsets[p + 1] - csm.offsets[p]);
  fmt::print("file       {} encoding, {} bytes; at most {} segments in one pixel\n", to_string(encoding), bytes, most);
  if (encoding == Encoding::Plain)
    fmt::print("note       compact size re-encoded from the stored depths (a fresh build also knows the intervals, and is smaller)\n");
  if (!c.coherence.empty()) {
    write_coherence_map(c.coherence, csm);
    fmt::print("wrote      {}\n", c.coherence);
  }
  return 0;
}

int run_analyze(const AnalyzeCommand& c) {
  if (c.build.model.empty()) throw Error("csm analyze: a MODEL is required (see splatcl csm analyze --help)");
  if (c.kmeans.empty() && !c.wavelet) throw Error("csm analyze: choose --kmeans K (repeatable) and/or --wavelet");
  const BuildOptions options = build_options(c.build);
  for (const std::uint32_t k : c.kmeans)  // before the build, not minutes after it
    if (k > options.maps) throw Error(fmt::format("--kmeans {} is more clusters than the {} maps (--maps)", k, options.maps));
  // Before the build too (it was refused after the capture and the k-means runs, which it hid).
  if (c.wavelet) require_wavelet_resolution(options.resolution);
  ProgressLine progress("csm");
  const Mesh mesh = load_model(c.build.model, progress, Winding::AsGiven);
  std::shared_ptr<Runtime> runtime;
  if (!c.build.reference) runtime = Runtime::create(c.build.device.device);
  CsmInfo info;
  info.maps = options.maps;
  info.resolution = options.resolution;
  const double raw = uncompressed_bytes(info);
  fmt::print("analysis   {} maps of {}x{} of {} ({} distribution, {} order, {} capture); uncompressed {:.2f} MiB\n", options.maps,
             options.resolution, options.resolution, c.build.model, to_string(options.distribution), to_string(options.order),
             to_string(options.capture), mib(raw));
  const BuildResult built = build_csm(mesh, options, runtime.get(), map_progress(progress, "per-pixel"));
  if (!built.thin_part_warning.empty()) queue_warning(c.build.model, built.thin_part_warning);
  const double plain = static_cast<double>(encode_csm(built.csm, Encoding::Plain).size());
  progress.clear();
  fmt::print("per-pixel  {} segments, {:.2f} MiB plain ({:.1f}:1)\n", built.csm.segments(), mib(plain), raw / plain);
  if (c.wavelet) {
    const WaveletResult w = wavelet_analysis(built.csm);
    fmt::print("wavelet    {} layers x 2 (depths, end indices) of {}x{}; transformed {:.2f} MiB, {:.1f} % zero coefficients, "
               "estimated {:.2f} MiB ({:.2f}x per-pixel)\n",
               w.layers, options.resolution, options.resolution, mib(static_cast<double>(w.transformed_bytes())),
               100.0 * static_cast<double>(w.zeros) / static_cast<double>(w.coefficients), mib(w.estimated_bytes()), w.estimated_bytes() / plain);
  }
  if (!c.kmeans.empty()) {
    std::vector<float> z1, z2;
    capture_all_maps(mesh, options, runtime.get(), z1, z2, std::uint64_t{6} << 30, map_progress(progress, "captured"));
    progress.show("k-means");
    const std::vector<KMeansResult> results =
        kmeans_analysis(z1, z2, options.maps, std::size_t{options.resolution} * options.resolution, c.kmeans, c.seed, c.iterations);
    progress.clear();
    for (const KMeansResult& r : results)
      fmt::print("k-means    k = {:>5}: {} iterations; {} segments, {:.2f} MiB plain ({:.1f}:1); wrong samples {} ({:.3f} %); "
                 "with corrections {:.2f} MiB ({:.1f}:1)\n",
                 r.k, r.iterations, r.segments, mib(static_cast<double>(r.plain_bytes)), raw / static_cast<double>(r.plain_bytes),
                 r.wrong_samples, 100.0 * static_cast<double>(r.wrong_samples) / static_cast<double>(r.samples),
                 mib(static_cast<double>(r.corrected_bytes())), raw / static_cast<double>(r.corrected_bytes()));
  }
  return 0;
}

int run_verify(const VerifyCommand& c) {
  // The recapture's options need the model; checked before the file is read and called valid.
  if (c.model.empty()) {
    for (const auto& [given, option] : {std::pair{!c.capture.empty(), "--capture"}, std::pair{c.reference, "--reference"},
                                        std::pair{!c.device.device.empty(), "--device"}})
      if (given) throw Error(fmt::format("csm verify: {} is for the recapture, which needs the MODEL the file was built from", option));
  }
  if (!c.capture.empty()) (void)parse_capture_method(c.capture);
  std::shared_ptr<Runtime> runtime;
  if (!c.model.empty() && !c.reference) runtime = Runtime::create(c.device.device);
  ProgressLine progress("csm");
  progress.show("reading " + c.file);
  Encoding encoding = Encoding::Plain;
  const Csm csm = read_csm(c.file, &encoding);
  progress.clear();
  fmt::print("file       {}: valid ({} encoding, {} segments, {} maps of {}x{})\n", c.file, to_string(encoding), csm.segments(),
             csm.info.maps, csm.info.resolution, csm.info.resolution);
  if (c.model.empty()) return 0;
  const Mesh mesh = load_model(c.model, progress, Winding::AsGiven);
  const CaptureMethod method = c.capture.empty() ? csm.info.capture : parse_capture_method(c.capture);
  const LosslessReport report = check_lossless(csm, mesh, runtime.get(), map_progress(progress, "recaptured"), method);
  progress.clear();
  if (report.violations)
    throw Error(fmt::format("{}: not lossless for {} of {} (map, pixel) samples; first at map {}, pixel {}: stored {:.9g} outside [{:.9g}, "
                            "{:.9g}){}",
                            c.file, report.violations, report.samples, report.first_map, report.first_pixel, report.first_depth,
                            report.first_z1, report.first_z2,
                            report.tolerance > 0 ? fmt::format(" by more than twice the hit epsilon, {:g} (recaptured by {}, the file by {})",
                                                               report.tolerance, to_string(method), to_string(csm.info.capture))
                                                 : std::string()));
  if (report.tolerance > 0) {
    fmt::print("lossless   {} of {} (map, pixel) samples of {} keep their depth-test result, recaptured by {} as a cross-check of the "
               "file's {} (depths within twice the hit epsilon, {:g}); the other {} are hit by one method only, at triangle edges\n",
               report.samples - report.edge_disagreements, report.samples, c.model, to_string(method), to_string(csm.info.capture),
               report.tolerance, report.edge_disagreements);
  } else {
    fmt::print("lossless   all {} (map, pixel) samples of {} keep their depth-test result (recaptured by {}{})\n", report.samples, c.model,
               to_string(method), c.capture.empty() ? ", as recorded in the file" : "");
  }
  return 0;
}

int run_quality(const QualityCommand& c) {
  if (c.build.model.empty()) throw Error("csm quality: a MODEL is required (see splatcl csm quality --help)");
  QualityOptions options = c.options;
  options.filter = parse_filter(c.filter);
  validate(options);  // before the model is loaded or anything allocated
  if (!c.csm_file.empty() && !c.build.given->empty()) {  // they were ignored silently
    std::string names;
    for (const auto& [name, value] : *c.build.given) names += (names.empty() ? "" : ", ") + name;
    throw Error(fmt::format("--csm {}: the build options {} do not apply to a CSM read from a file; drop them or --csm", c.csm_file, names));
  }
  ProgressLine progress("csm");
  const Mesh mesh = load_model(c.build.model, progress, Winding::AsGiven);
  std::shared_ptr<Runtime> runtime;
  if (!c.build.reference) runtime = Runtime::create(c.build.device.device);
  Csm csm;
  if (!c.csm_file.empty()) {
    csm = read_csm(c.csm_file);
    try {  // measure_quality checks it too, without naming the file
      require_quality_csm(csm, mesh);
    } catch (const Error& e) {
      throw Error(c.csm_file + ": " + e.what());
    }
  } else {
    csm = build_csm(mesh, build_options(c.build), runtime.get(), map_progress(progress, "captured and compressed")).csm;
  }
  progress.show("rendering " + std::to_string(options.views) + " views");
  const QualityReport report = measure_quality(csm, mesh, options, runtime.get());
  progress.clear();
  print_parameters(csm.info);
  fmt::print("study      {} views of {}x{} pixels, pinhole {:g} deg {}; point light at (1.05, {:g}] R; seed {}; "
             "filter {}, bias {:g}\n",
             options.views, options.image, options.image, options.fov_degrees,
             options.camera_distance == 1 ? std::string("on the bounding sphere") : fmt::format("at {:g} R from the centre", options.camera_distance),
             options.light_max, options.seed, c.filter, options.bias);
  fmt::print("wrong      {:.3f} % of image pixels, {:.3f} % of object pixels ({} of {} object pixels; the reference shadows {:.1f} % of "
             "the object pixels)\n",
             report.percent_of_image(), report.percent_of_object(), report.wrong, report.object_pixels,
             report.object_pixels ? 100.0 * static_cast<double>(report.exact_shadowed) / static_cast<double>(report.object_pixels) : 0.0);
  fmt::print("shaded     {:.3f} % of image pixels, {:.3f} % of object pixels differ in a diffusely shaded render ({} wrong among {} "
             "pixels facing the light, {} of them falsely shadowed; the thesis's metric)\n",
             report.shaded_percent_of_image(), report.shaded_percent_of_object(), report.wrong_facing, report.facing_pixels,
             report.false_shadow_facing);
  fmt::print("queries    {} CSM visibility queries (screen order) in {:.1f} ms wall on {}", report.object_pixels, report.query_ms,
             runtime ? runtime->info().name : std::string("the native reference"));
  if (report.kernel_ms > 0)
    fmt::print("; kernel {:.1f} ms = {:.1f} M queries/s", report.kernel_ms, static_cast<double>(report.object_pixels) / report.kernel_ms / 1e3);
  fmt::print("\n");
  return 0;
}

}  // namespace

Action register_csm(CLI::App& app) {
  auto* sub = app.add_subcommand("csm", "Coherent shadow maps: build from a mesh, inspect, verify, measure shadow quality");
  sub->require_subcommand(1);

  auto* build = sub->add_subcommand("build", "Capture N orthographic dual-depth maps of a mesh on its bounding sphere (OpenCL "
                                              "rasterization or ray casting) and compress them per pixel while streaming; writes a .csm file. "
                                              "The compressed maps are held in memory: a build that would not fit stops with the cause "
                                              "($SPLATCL_MEMORY_LIMIT, e.g. 8G, caps it further)");
  auto b = std::make_shared<BuildCommand>();
  add_device_option(*build, b->device);
  build->add_option("model", b->model, "Input mesh (OBJ, PLY, OFF, STL)");
  build->add_option("-o,--output", b->output, "Output .csm file");
  add_parameter_options(*build, csm_parameters(), to_json(CsmParameters{}), b->given);
  build->add_option("--mode", b->mode, "Compression: per-pixel (writes the .csm), or for size comparison only: per-map, hilbert-3d "
                                       "(blocks of M maps), hilbert-4d (all maps in memory)")
      ->capture_default_str();
  build->add_option("--pixel-order", b->pixel_order, "Pixel curve of --mode per-map: hilbert (default), zigzag-h, zigzag-v");
  build->add_option("--coherence", b->coherence, "Also write the coherence map (PNG: white = one segment, black = one per map)");
  build->add_flag("--reference", b->reference, "Use the native C++ reference instead of the OpenCL kernels (keeps all maps in memory)");

  auto* info = sub->add_subcommand("info", "Describe a .csm file: parameters, segments, plain and compact sizes");
  auto i = std::make_shared<InfoCommand>();
  info->add_option("file", i->file, "A .csm file")->required();
  info->add_option("--coherence", i->coherence, "Also write the coherence map (PNG)");

  auto* verify = sub->add_subcommand("verify", "Validate a .csm file; with its MODEL, recapture every map (by the capture method the "
                                                "file records) and check that each (map, pixel) keeps its depth-test result (losslessness)");
  auto v = std::make_shared<VerifyCommand>();
  add_device_option(*verify, v->device);
  verify->add_option("file", v->file, "A .csm file")->required();
  verify->add_option("model", v->model, "The mesh it was built from");
  verify->add_flag("--reference", v->reference, "Recapture with the native C++ reference");
  verify->add_option("--capture", v->capture, "Recapture with this method (raster or raycast) instead of the one recorded in the file: "
                                              "a cross-check, which may fail at triangle-edge pixels");

  auto* quality = sub->add_subcommand("quality", "Shadow quality study (Talpe §6.1): % of pixels whose CSM shadow test "
                                                  "differs from exact ray casting, over random views and point lights");
  auto q = std::make_shared<QualityCommand>();
  add_device_option(*quality, q->build.device);
  quality->add_option("model", q->build.model, "Input mesh (OBJ, PLY, OFF, STL)");
  quality->add_option("--csm", q->csm_file, "Use this .csm (built from MODEL as loaded) instead of building one");
  add_in_memory_build_options(*quality, q->build);
  quality->add_option("--views", q->options.views, fmt::format("Random camera and light configurations, 1..{}", kMaxQualityViews))->capture_default_str();
  quality->add_option("--image", q->options.image, fmt::format("Image size (square) per view, 1..{} pixels", kMaxQualityImage))->capture_default_str();
  quality->add_option("--fov", q->options.fov_degrees, "Camera field of view in degrees")->capture_default_str();
  quality->add_option("--camera-distance", q->options.camera_distance,
                      "Camera distance from the centre in sphere radii, 1..1e6: 1 is on the bounding sphere (Talpe §6.1); "
                      "1/sin(fov/2) (1.414 at 90 deg) frames the whole sphere, for models whose surface reaches it")
      ->capture_default_str();
  quality->add_option("--light-max", q->options.light_max, "Largest light distance from the centre, in sphere radii, (1.05, 1e6]")->capture_default_str();
  quality->add_option("--seed", q->options.seed, "Random seed of the views and lights")->capture_default_str();
  quality->add_option("--filter", q->filter, "Shadow test: none (1 texel), same-map (4x4 texels), cross-map (2x2 texels in 4 maps) or march (the true light ray through the texels of the 4 nearest maps, blocked in at least 2: shadow edges in place; more acne than the PCFs on receivers that lie on the surface)")->capture_default_str();
  quality->add_option("--bias", q->options.bias, "Shadow offset in texels of the CSM, 0..1000 (shadow when the stored depth g < depth - bias/M, depth in units of the bounding diameter)")->capture_default_str();
  quality->add_flag("--reference", q->build.reference, "Use the native C++ references instead of the OpenCL kernels");

  auto* analyze = sub->add_subcommand("analyze", "Offline analyses of the compression thesis: k-means clustering of maps before "
                                                  "per-pixel compression (lossy; errors and correction cost) and the Haar-wavelet layer re-layout");
  auto a = std::make_shared<AnalyzeCommand>();
  add_device_option(*analyze, a->build.device);
  analyze->add_option("model", a->build.model, "Input mesh (OBJ, PLY, OFF, STL)");
  add_in_memory_build_options(*analyze, a->build);
  analyze->add_option("--kmeans", a->kmeans, "Cluster the maps into K clusters, 1 .. --maps (repeatable; all maps are kept in memory)")
      ->check(CLI::Range(1u, std::numeric_limits<std::uint32_t>::max()));
  analyze->add_option("--iterations", a->iterations, "Largest number of k-means (Lloyd) iterations, at least 1")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1000000u));
  analyze->add_option("--seed", a->seed, "Seed of the k-means start")->capture_default_str();
  analyze->add_flag("--wavelet", a->wavelet, "Haar-wavelet re-layout of the per-pixel segments: zero coefficients and size estimate (a power-of-two --res)");
  analyze->add_flag("--reference", a->build.reference, "Use the native C++ references instead of the OpenCL kernels");

  return [b, i, v, q, a, build, info, verify, quality, analyze]() -> int {
    if (build->parsed()) return run_build(*b);
    if (analyze->parsed()) return run_analyze(*a);
    if (info->parsed()) return run_info(*i);
    if (quality->parsed()) return run_quality(*q);
    return run_verify(*v);
  };
}

}  // namespace splatcl::cli
