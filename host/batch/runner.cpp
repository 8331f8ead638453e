#include "batch/runner.hpp"
#include "io/json_keys.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <thread>

#include "csm/build_options.hpp"
#include "csm/csm_file.hpp"
#include "io/atomic_file.hpp"
#include "io/checksum.hpp"
#include "io/file_lock.hpp"
#include "io/output_files.hpp"
#include "runtime/error.hpp"
#include "runtime/profiling.hpp"
#include "runtime/runtime.hpp"
#include "splats/pipeline.hpp"
#include "splats/pipeline_options.hpp"
#include "splats/splat_file.hpp"
#include "splats/surface_check.hpp"

namespace splatcl::batch {
namespace {

namespace fs = std::filesystem;

// The kill-after-N-writes test hook (see kKillAfterWritesVariable).
std::atomic<long> writes_done{0};
long kill_after_writes = 0;

void count_write() {
  const long n = ++writes_done;
  if (kill_after_writes > 0 && n == kill_after_writes) std::raise(SIGKILL);
}

void write_counted(const std::string& path, std::string_view contents) {
  write_file_atomically(path, contents);
  count_write();
}

// A problem every model would hit alike (no OpenCL device): ends the run instead of failing models.
struct FatalError {
  std::exception_ptr error;
};

std::string describe(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const std::bad_alloc&) {
    return "out of memory";
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "unknown error";
  }
}

std::optional<nlohmann::json> read_record(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  try {
    nlohmann::json record = nlohmann::json::parse(in);
    if (record.is_object()) return record;
  } catch (const nlohmann::json::exception&) {
  }
  return std::nullopt;  // unreadable or damaged: rebuild
}

OutputFile describe_file(const std::string& name, const std::string& contents) {
  return {name, contents.size(), checksum_of(contents)};
}

OutputFile describe_written_file(const fs::path& dir, const std::string& name) {
  OutputFile file{name, 0, {}};
  file.checksum = checksum_of_file((dir / name).string(), &file.bytes);
  return file;
}

// The recorded output, when its input and parameters match, the same device (or the reference)
// made it, and every file still has its checksum. Another device, or the reference after an
// OpenCL run, can round differently: `--reference` reused the OpenCL run's files and the summary
// called them the reference's.
std::optional<OutputResult> reusable_output(const std::optional<nlohmann::json>& record, const fs::path& dir, const std::string& kind,
                                            const std::string& input_checksum, const nlohmann::json& params, const std::string& params_checksum,
                                            const std::string& made_by) {
  if (!record || record->value("input_checksum", "") != input_checksum) return std::nullopt;
  const auto outputs = record->find("outputs");
  if (outputs == record->end() || !outputs->is_object() || !outputs->contains(kind)) return std::nullopt;
  const auto& entry = (*outputs)[kind];
  if (!entry.is_object() || entry.value("params_checksum", "") != params_checksum || entry.value("made_by", "") != made_by) return std::nullopt;
  const auto files = entry.find("files");
  if (files == entry.end() || !files->is_array() || files->empty()) return std::nullopt;
  OutputResult result{kind, true, params, params_checksum, made_by, {}, 0};
  try {
    for (const auto& f : *files) {
      const std::string name = f.at("path").get<std::string>();
      std::error_code ec;
      const auto size = fs::file_size(dir / name, ec);
      if (ec || size != f.at("bytes").get<std::uint64_t>()) return std::nullopt;
      const OutputFile now = describe_written_file(dir, name);
      if (now.checksum != f.at("checksum").get<std::string>()) return std::nullopt;
      result.files.push_back(now);
    }
  } catch (const std::exception&) {
    return std::nullopt;
  }
  return result;
}

// An output the run was not asked for: the record's entry of it, kept when the record is of the same
// input bytes (its own checks decide, when a later run wants it, whether its files still hold).
void carry_output(const std::optional<nlohmann::json>& record, ModelResult& r, const std::string& kind) {
  if (!record) return;
  try {
    const auto outputs = record->find("outputs");
    if (record->value("input_checksum", "") == r.input_checksum && outputs != record->end() && outputs->is_object() &&
        outputs->contains(kind) && (*outputs)[kind].is_object())
      r.carried_outputs[kind] = (*outputs)[kind];
  } catch (const nlohmann::json::exception&) {  // a record of the wrong shape carries nothing
  }
}

// A record of the wrong shape (edited by hand, another version) counts as no record.
std::optional<OutputResult> reusable(const std::optional<nlohmann::json>& record, const fs::path& dir, const std::string& kind,
                                     const std::string& input_checksum, const nlohmann::json& params, const std::string& params_checksum,
                                     const std::string& made_by) {
  try {
    return reusable_output(record, dir, kind, input_checksum, params, params_checksum, made_by);
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

// An output's parameters checksum: of its parameters, with a texture image named by the checksum of
// its bytes rather than its path, as the mesh is (editing the image in place rebuilds the splats;
// moving the whole tree does not), of the splat file's format version (a newer splatcl rebuilds
// splat files its readers refuse rather than reusing them) and of the splat method's version (one
// whose method makes other splats rebuilds them).
std::string params_checksum(const std::string& kind, nlohmann::json params) {
  if (kind == "splats") {
    params["splat_file_version"] = splats::kSplatFileVersion;
    params["splat_method_version"] = splats::kSplatMethodVersion;
  }
  const auto texture = params.find("texture");
  if (texture != params.end() && texture->is_string() && !texture->get<std::string>().empty()) {
    const std::string path = texture->get<std::string>();
    try {
      *texture = "fnv1a64:" + checksum_of_file(path);
    } catch (const Error& e) {
      throw Error(std::string("texture: ") + e.what());
    }
  }
  return checksum_of(json_text(params, -1));
}

nlohmann::json files_json(const std::vector<OutputFile>& files) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& f : files) out.push_back({{"path", f.path}, {"bytes", f.bytes}, {"checksum", f.checksum}});
  return out;
}

nlohmann::json record_json(const ModelResult& r) {
  nlohmann::json outputs = r.carried_outputs;
  for (const auto& o : r.outputs)
    outputs[o.kind] = {{"params", o.params}, {"params_checksum", o.params_checksum}, {"made_by", o.made_by}, {"files", files_json(o.files)}};
  return {{"format", "splatcl-batch-record"}, {"version", 1},          {"id", r.id},
          {"input", r.input},                 {"input_checksum", r.input_checksum}, {"input_bytes", r.input_bytes},
          {"status", r.ok ? "ok" : "failed"}, {"reason", r.reason},    {"warning", r.warning},
          {"outputs", outputs}};
}

class Worker {
 public:
  Worker(const RunOptions& options, std::string made_by, std::function<void(const std::string&)> report)
      : options_(options), made_by_(std::move(made_by)), report_(std::move(report)) {}

  ModelResult process(const ModelEntry& entry) {
    Stopwatch clock;
    ModelResult r;
    r.id = entry.id;
    r.input = entry.input;
    const fs::path dir(options_.output_dir);
    try {
      fs::create_directories((dir / entry.id).parent_path());
      // The record can be written (no folder in its place; a model's folder below the output
      // directory writable, which prepare_output_directory probed) before any work; each output
      // to build is checked in build_outputs. Without a folder listing: remove_stale_temporaries
      // lists each folder once for the whole run.
      check_output_path((dir / record_name(entry.id)).string(), "output");
      if (const fs::path folder = (dir / entry.id).parent_path(); folder.lexically_normal() != dir.lexically_normal())
        check_writable_directory(folder.string(), "output folder " + folder.string());
      r.input_checksum = checksum_of_file(entry.input, &r.input_bytes);
      build_outputs(entry, r, dir);
    } catch (const FatalError&) {
      throw;
    } catch (...) {
      add_reason(r, describe(std::current_exception()));
    }
    r.ok = r.reason.empty();
    try {
      write_counted((dir / record_name(entry.id)).string(), json_text(record_json(r)) + "\n");
    } catch (...) {
      add_reason(r, describe(std::current_exception()));
      r.ok = false;
    }
    r.total_ms = clock.elapsed_ms();
    return r;
  }

 private:
  static void add_reason(ModelResult& r, const std::string& reason) { r.reason += (r.reason.empty() ? "" : "; ") + reason; }

  Runtime* runtime() {
    if (options_.reference) return nullptr;
    if (!runtime_) {
      try {
        runtime_ = Runtime::create(options_.device);
      } catch (...) {
        throw FatalError{std::current_exception()};
      }
    }
    return runtime_.get();
  }

  void build_outputs(const ModelEntry& entry, ModelResult& r, const fs::path& dir) {
    // --force rebuilds what is asked for; what is not stays in the record (carry_output).
    const auto previous = read_record(dir / record_name(entry.id));
    const auto record = options_.force ? std::nullopt : previous;
    struct Pending {
      std::string kind;
      nlohmann::json params;
      std::string checksum;
    };
    std::vector<Pending> pending;
    // An output whose parameters cannot be checksummed (its texture unreadable) fails alone: the
    // other is still reused or built (a missing texture dropped a valid CSM from the record).
    auto consider = [&](const std::string& kind, const nlohmann::json& params) {
      // An output to build has its files checked before the work (a folder at ID.csm failed after
      // the build); like a bad texture, that fails it alone.
      std::string checksum;
      try {
        checksum = params_checksum(kind, params);
        if (auto reused = reusable(record, dir, kind, r.input_checksum, params, checksum, made_by_)) {
          r.outputs.push_back(std::move(*reused));
          return;
        }
        const std::vector<std::string> names = output_names(entry.id);
        for (std::size_t k = kind == "splats" ? 1 : 3, last = k + 2; k < last; ++k) check_output_path((dir / names[k]).string(), "output");
      } catch (const Error& e) {
        add_reason(r, kind + ": " + e.what());
        return;
      }
      pending.push_back({kind, params, checksum});
    };
    if (entry.params.want_splats) consider("splats", splats::to_json(entry.params.splats));
    if (entry.params.want_csm) consider("csm", csm::to_json(entry.params.csm));
    // `--outputs splats` dropped the CSM from the record, and the next full run rebuilt it.
    for (const auto& [kind, wanted] : {std::pair{"splats", entry.params.want_splats}, std::pair{"csm", entry.params.want_csm}})
      if (!wanted) carry_output(previous, r, kind);
    // What loading found wrong with the mesh, kept in the record for runs that reuse every output.
    bool warning_recorded = false;
    if (record) {
      const auto checksum = record->find("input_checksum"), warning = record->find("warning");
      if (checksum != record->end() && *checksum == r.input_checksum && warning != record->end() && warning->is_string())
        r.warning = *warning, warning_recorded = true;
    }
    if (pending.empty()) return;

    report_(entry.id + ": loading");
    const Mesh mesh = load_mesh(entry.input);
    // The recorded one is of these bytes and says what the (reused) splats got; splats built now
    // say it again (as given here, or oriented below): a rerun with keep_winding kept the earlier
    // run's "faces turned ..." for splats that face inward.
    const bool splats_built = std::any_of(pending.begin(), pending.end(), [](const Pending& p) { return p.kind == "splats"; });
    // What splatcl splats and csm build warn of too: the problems, and coordinates whose float
    // steps are coarse for the mesh's size (a box at 1e6 was reported "ok" without a word).
    const std::string far = float_step_warning(mesh);
    // The splats take the faces oriented (unless keep_winding) and a mesh far out about the centre
    // of its box, as splatcl splats does, decided by the same test on the file's box; the CSM
    // capture takes the file's faces and coordinates. A second load only where they differ.
    const RecentreTest recentre = splats::recentre_test(entry.params.splats);
    const Winding splat_winding = splats::winding(entry.params.splats);
    std::optional<Mesh> own;
    if (splats_built && (recentring_wanted(mesh, recentre) || (splat_winding == Winding::Orient && mesh.problems.winding_disagrees())))
      own = load_mesh_recentred(entry.input, splat_winding, recentre);
    const Mesh& splat_mesh = own ? *own : mesh;
    // A mesh the splats read about its centre says so; the CSM's coarse floats are still named when
    // a CSM is wanted. What splatcl splats reports of the oriented mesh ("N faces turned ..."): the
    // as-given "faces point inward" read as if the splats faced in.
    const auto join = [](std::string text, const std::string& part) { return text.empty() || part.empty() ? text + part : text + "; " + part; };
    std::string warning;
    if (!warning_recorded || splats_built) {
      warning = splat_mesh.problems.any() ? splat_mesh.problems.summary() : std::string();
      if (const std::string moved = splats::recentred_warning(splat_mesh); moved.empty())
        warning = join(warning, far);
      else
        warning = join(join(warning, "the splats: " + moved), entry.params.want_csm && !far.empty() ? "the CSM: " + far : std::string());
    } else {
      warning = without_thin_part(r.warning);
    }
    // Parts thinner than the CSM's hit epsilon, of the CSM as wanted now (built or reused): a rerun
    // that lowered hit_eps kept the earlier warning, one that rebuilt only the splats dropped it.
    if (entry.params.want_csm) warning = join(warning, csm_thin_part(entry, mesh));
    r.warning = warning;
    for (const auto& p : pending) {
      try {
        Stopwatch clock;
        OutputResult out{p.kind, false, p.params, p.checksum, made_by_, {}, 0};
        out.files = p.kind == "splats" ? build_splats(entry, splat_mesh, dir) : build_csm(entry, mesh, dir);
        out.build_ms = clock.elapsed_ms();
        r.outputs.push_back(std::move(out));
      } catch (const FatalError&) {
        throw;
      } catch (...) {
        add_reason(r, p.kind + ": " + describe(std::current_exception()));
      }
    }
    std::sort(r.outputs.begin(), r.outputs.end(), [](const OutputResult& a, const OutputResult& b) { return a.kind > b.kind; });
  }

  std::vector<OutputFile> build_splats(const ModelEntry& entry, const Mesh& mesh, const fs::path& dir) {
    using namespace splatcl::splats;
    const SplatSetup setup = splat_setup(entry.params.splats, mesh, entry.input);
    Runtime* device = runtime();
    SplatRun run = generate_splats(mesh, setup.colors, setup.options, device, [&](const std::string& phase) { report_(entry.id + ": splats " + phase); });
    // The same end-of-run check as `splatcl splats`: splats that break the bound the run promised
    // fail the model instead of being written and reported ok.
    const std::vector<SplatRecord> records = run.records();
    report_(entry.id + ": checking splats");
    check_before_writing(mesh, records, run.surface_bound, setup.options.fit.eps, entry.input, "");
    report_(entry.id + ": writing splats");
    const std::string ply = splats_name(entry.id), stats_name = entry.id + ".splats.json";
    write_splat_file((dir / ply).string(), records, splat_file_info(setup, run, entry.input));
    count_write();
    const std::string stats_text = json_text(splat_statistics(run, setup, entry.input, ply)) + "\n";
    write_counted((dir / stats_name).string(), stats_text);
    return {describe_written_file(dir, ply), describe_file(stats_name, stats_text)};
  }

  // "the CSM: " and csm::thin_part_warning of the model's CSM as its parameters capture it; empty
  // when there is none or the capture cannot be set up (the build then fails with the cause).
  static std::string csm_thin_part(const ModelEntry& entry, const Mesh& mesh) {
    using namespace splatcl::csm;
    const BuildOptions o = to_build_options(entry.params.csm);
    if (resolve_single_hit(o.single_hit, mesh) != SingleHit::SphereExit) return {};
    try {
      const std::string thin = thin_part_warning(CaptureScene(mesh, bounding_sphere(mesh), o.resolution, o.single_hit, o.hit_epsilon), mesh,
                                                 o.hit_epsilon > kMinHitEpsilon
                                                     ? "lower the model's hit_eps (e.g. to 1e-7) or set its single_hit to exact"
                                                     : "set the model's single_hit to exact (its hit_eps is at its least)");
      return thin.empty() ? thin : "the CSM: " + thin;
    } catch (const Error&) {
      return {};
    }
  }

  // A recorded warning less its thin-part clause (csm_thin_part: always the last, "the CSM: N of M
  // sample rays that hit this closed mesh ..."), which is made again. (No std::regex: GCC 12 warns
  // of its internals under the sanitizers.)
  static std::string without_thin_part(const std::string& warning) {
    const std::string_view clause = "the CSM: ", rest = " sample rays that hit this closed mesh ";
    for (std::size_t at = warning.find(clause); at != std::string::npos; at = warning.find(clause, at + 1)) {
      const std::size_t counts = at + clause.size(), rays = warning.find(rest, counts);
      const std::string_view between = std::string_view(warning).substr(counts, rays == std::string::npos ? 0 : rays - counts);
      const std::size_t of = between.find(" of ");
      const auto digits = [](std::string_view text) {
        return !text.empty() && text.find_first_not_of("0123456789") == std::string_view::npos;
      };
      if (rays != std::string::npos && of != std::string_view::npos && digits(between.substr(0, of)) && digits(between.substr(of + 4)))
        return warning.substr(0, at >= 2 && warning.compare(at - 2, 2, "; ") == 0 ? at - 2 : at);
    }
    return warning;
  }

  std::vector<OutputFile> build_csm(const ModelEntry& entry, const Mesh& mesh, const fs::path& dir) {
    using namespace splatcl::csm;
    BuildOptions options = to_build_options(entry.params.csm);
    options.thin_part_remedy.clear();  // csm_thin_part checks, for a reused CSM too
    const Encoding encoding = file_encoding(entry.params.csm);
    Runtime* device = runtime();
    const BuildResult result = splatcl::csm::build_csm(mesh, options, device, [&](std::uint32_t done, std::uint32_t total) {
      report_(fmt::format("{}: csm {}/{} maps", entry.id, done, total));
    });
    report_(entry.id + ": writing csm");
    const std::string bytes = encode_csm(result.csm, encoding, encoding == Encoding::Compact ? &result.segments : nullptr);
    const std::string name = csm_name(entry.id), stats_name = entry.id + ".csm.json";
    write_counted((dir / name).string(), bytes);
    const auto& info = result.csm.info;
    const double uncompressed = 8.0 * info.maps * info.resolution * info.resolution;
    const nlohmann::json stats{
        {"model", entry.input},
        {"output", name},
        {"maps", info.maps},
        {"resolution", info.resolution},
        {"distribution", to_string(info.distribution)},
        {"order", to_string(info.order)},
        {"pole", to_string(info.pole)},
        {"single_hit", to_string(info.single_hit)},
        {"capture", to_string(options.capture)},
        {"encoding", to_string(encoding)},
        {"triangles", info.triangles},
        {"segments", result.csm.segments()},
        {"segments_per_pixel", static_cast<double>(result.csm.segments()) / static_cast<double>(result.csm.pixels())},
        {"file_bytes", bytes.size()},
        {"uncompressed_bytes", uncompressed},
        {"compression_ratio", uncompressed / static_cast<double>(bytes.size())},
        {"batch_maps", result.batch_maps},
        {"device", device ? device->info().name : std::string("reference")},
        {"time_ms", {{"setup", result.setup_ms}, {"capture", result.capture_ms}, {"compress", result.compress_ms}, {"total", result.total_ms}}}};
    const std::string stats_text = json_text(stats) + "\n";
    write_counted((dir / stats_name).string(), stats_text);
    return {describe_file(name, bytes), describe_file(stats_name, stats_text)};
  }

  const RunOptions& options_;
  const std::string made_by_;
  std::function<void(const std::string&)> report_;
  std::shared_ptr<Runtime> runtime_;
};

// A write killed mid-way leaves NAME.tmpPID beside NAME (io/atomic_file.hpp); remove those of this
// run's models before starting. Each model belongs to exactly one shard, and a second run over the
// same models is refused by their locks (lock_models, taken before this), so no running writer's
// temporaries are touched. Only the folders of this run's own outputs are listed, each once and
// not recursively: on a shared file system (NFS, Lustre) a shard does not walk the other shards'
// output trees.
void remove_stale_temporaries(const std::vector<ModelEntry>& models, const fs::path& dir) {
  std::map<fs::path, std::set<std::string>> names_in;  // folder -> output file names of this run there
  for (const auto& m : models)
    for (const std::string& name : output_names(m.id)) {
      const fs::path target = (dir / name).lexically_normal();
      names_in[target.parent_path()].insert(target.filename().string());
    }
  std::vector<fs::path> stale;
  for (const auto& [folder, names] : names_in) {
    std::error_code ec;  // a folder not made yet holds nothing stale
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string entry = it->path().filename().string();
      const auto at = entry.rfind(".tmp");
      if (at == std::string::npos || at + 4 == entry.size()) continue;
      if (entry.find_first_not_of("0123456789", at + 4) != std::string::npos) continue;
      if (names.count(entry.substr(0, at))) stale.push_back(it->path());
    }
  }
  std::error_code ignored;
  for (const auto& p : stale) fs::remove(p, ignored);
}

}  // namespace

bool ModelResult::reused() const {
  return ok && !outputs.empty() && std::all_of(outputs.begin(), outputs.end(), [](const OutputResult& o) { return o.reused; });
}

nlohmann::json to_json(const ModelResult& r) {
  nlohmann::json outputs = nlohmann::json::object();
  for (const auto& o : r.outputs)
    outputs[o.kind] = {{"reused", o.reused}, {"params", o.params}, {"params_checksum", o.params_checksum},
                       {"files", files_json(o.files)}, {"build_ms", o.build_ms}};
  nlohmann::json out{{"id", r.id},
                     {"input", r.input},
                     {"status", r.ok ? "ok" : "failed"},
                     {"reused", r.reused()},
                     {"input_checksum", r.input_checksum},
                     {"input_bytes", r.input_bytes},
                     {"outputs", outputs},
                     {"total_ms", r.total_ms}};
  if (!r.ok) out["reason"] = r.reason;
  if (!r.warning.empty()) out["warning"] = r.warning;
  return out;
}

std::string record_name(const std::string& id) { return id + ".batch.json"; }
std::string splats_name(const std::string& id) { return id + ".splats.ply"; }
std::string csm_name(const std::string& id) { return id + ".csm"; }
std::vector<std::string> output_names(const std::string& id) {
  // build_outputs relies on the order: the record, the splats' two files, the CSM's two.
  return {record_name(id), splats_name(id), id + ".splats.json", csm_name(id), id + ".csm.json"};
}

void check_run_paths(const std::string& input, bool input_is_directory, const std::string& output_dir, const std::string& summary,
                     const std::vector<ModelEntry>& all_models) {
  const fs::path in = comparable_path(input), out = comparable_path(output_dir), sum = comparable_path(summary);
  if (input_is_directory) {
    if (in == out) throw Error("batch: the output directory " + output_dir + " is the input directory: outputs would be read as meshes by later runs");
    if (path_within(out, in))
      throw Error("batch: the output directory " + output_dir + " is inside the input directory " + input + ": choose one outside it");
    if (path_within(in, out))
      throw Error("batch: the output directory " + output_dir + " contains the input directory " + input + ": choose one outside it");
  } else if (sum == in) {
    throw Error("batch: --summary " + summary + " is the manifest " + input);
  }
  std::map<fs::path, const ModelEntry*> inputs;
  std::vector<fs::path> input_paths;  // per model, in all_models' order: resolved once (metadata calls on a shared file system)
  for (const auto& m : all_models) inputs.emplace(input_paths.emplace_back(comparable_path(m.input)), &m);
  if (const auto it = inputs.find(sum); it != inputs.end())
    throw Error("batch: --summary " + summary + " is the input of model '" + it->second->id + "' (" + it->second->origin + ")");
  // Written over, the lock file would let a second run build the models this one holds; and read
  // (a model's mesh or texture), closing it dropped every lock this process held on it (POSIX
  // record locks: a second run then built the same models at once; a helper's audit).
  // The summary's folder has one too (lock_models).
  for (const auto& [lock_file, whose] : {std::pair{comparable_path((fs::path(output_dir) / kLockFileName).string()), "the output directory's"},
                                         std::pair{sum.parent_path() / kLockFileName, "the summary folder's"}}) {
    if (sum == lock_file) throw Error("batch: --summary " + summary + " is " + whose + " lock file");
    for (std::size_t k = 0; k < all_models.size(); ++k) {
      const ModelEntry& m = all_models[k];
      if (input_paths[k] == lock_file) throw Error("batch: the input of model '" + m.id + "' (" + m.origin + ") is " + whose + " lock file");
      if (!m.params.splats.texture.empty() && comparable_path(m.params.splats.texture) == lock_file)
        throw Error("batch: the texture of model '" + m.id + "' (" + m.origin + ") is " + whose + " lock file");
    }
  }
  std::map<fs::path, std::pair<std::string, const ModelEntry*>> targets;  // every output: its name and model
  for (const auto& m : all_models)
    for (const std::string& name : output_names(m.id)) targets.emplace(comparable_path((fs::path(output_dir) / name).string()), std::pair{name, &m});
  for (const auto& [target, owner] : targets) {
    const auto& [name, m] = owner;
    if (target == sum) throw Error("batch: --summary " + summary + " is the output " + name + " of model '" + m->id + "'");
    if (!input_is_directory && target == in) throw Error("batch: the output " + name + " of model '" + m->id + "' is the manifest " + input);
    if (const auto it = inputs.find(target); it != inputs.end())
      throw Error("batch: the output " + name + " of model '" + m->id + "' is the input of model '" + it->second->id + "' (" + it->second->input + ")");
    for (fs::path folder = target.parent_path(); path_within(folder, out) && folder != out; folder = folder.parent_path())
      if (const auto it = targets.find(folder); it != targets.end())
        throw Error("batch: the output " + name + " of model '" + m->id + "' lies in " + it->second.first + ", the output of model '" +
                    it->second.second->id + "'");
  }
  // The run makes only the output directory: a summary elsewhere needs its folder now, before the
  // output directory and its lock file are made (they were, and then the summary was refused).
  const fs::path summary_dir = fs::path(summary).has_parent_path() ? fs::path(summary).parent_path() : fs::path(".");
  std::error_code ec;
  if (comparable_path(summary_dir.string()) != out && !fs::is_directory(summary_dir, ec))
    throw Error("cannot write --summary " + summary + ": directory " + summary_dir.string() + " does not exist");
}

void prepare_output_directory(const std::string& output_dir) {
  std::error_code ec;
  fs::create_directories(output_dir, ec);
  if (ec || !fs::is_directory(output_dir)) throw Error("cannot create output directory " + output_dir + (ec ? ": " + ec.message() : ""));
  check_writable_directory(output_dir, "output directory " + output_dir);
}

RunLocks lock_models(const std::vector<ModelEntry>& models, const std::string& output_dir, const std::string& summary_path) {
  RunLocks locks;
  // The summary's in the lock file of its own folder, which every run naming it shares. One
  // process must not open one lock file twice: closing either descriptor would drop all its POSIX
  // locks. Model ids cannot contain ':', so the summary's key is no model's.
  const fs::path summary = comparable_path(summary_path), folder = summary.parent_path();
  const auto lock_summary = [&](KeyLocks& file) {
    if (const pid_t holder = file.try_lock("summary:" + summary.string()); holder != 0)
      throw Error(fmt::format("batch: the summary {} is being written by another batch run{}; run one batch per summary at a time (lock {})",
                              summary_path, holder > 0 ? fmt::format(" (pid {})", holder) : "", file.path()));
  };
  // A summary elsewhere first: refused there, the run has not made its output directory (it made
  // an empty one with a lock file).
  const bool summary_elsewhere = folder != comparable_path(output_dir);
  if (summary_elsewhere) {
    locks.summary = std::make_unique<KeyLocks>((folder / kLockFileName).string());
    lock_summary(*locks.summary);
  }
  prepare_output_directory(output_dir);
  locks.models = std::make_unique<KeyLocks>((fs::path(output_dir) / kLockFileName).string());
  for (const auto& m : models) {
    const pid_t holder = locks.models->try_lock(m.id);
    if (holder != 0)
      throw Error(fmt::format("batch: model '{}' in {} is being built by another batch run{}; run one batch per model and output "
                              "directory at a time (lock {})",
                              m.id, output_dir, holder > 0 ? fmt::format(" (pid {})", holder) : "", locks.models->path()));
  }
  if (!summary_elsewhere) lock_summary(*locks.models);
  if (const char* hold = std::getenv(kHoldLocksVariable)) std::this_thread::sleep_for(std::chrono::milliseconds(std::atol(hold)));
  return locks;
}

std::vector<ModelResult> run_batch(const std::vector<ModelEntry>& models, const RunOptions& options, const BatchProgress& progress,
                                   const ModelFinished& finished_model) {
  if (options.output_dir.empty()) throw Error("batch: an output directory is required");
  // What makes the outputs, as the summary's `device` names it (no device: an error before any work).
  const std::string made_by = options.reference ? std::string("reference") : choose_device(options.device).name;
  prepare_output_directory(options.output_dir);
  if (const char* hook = std::getenv(kKillAfterWritesVariable)) kill_after_writes = std::atol(hook);
  remove_stale_temporaries(models, options.output_dir);

  std::vector<ModelResult> results(models.size());
  std::mutex mutex;
  std::size_t finished = 0, failed = 0;
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stop{false};
  std::exception_ptr fatal;
  auto report = [&](const std::string& now) {
    std::lock_guard lock(mutex);
    if (progress) progress(finished, models.size(), failed, now);
  };
  auto work = [&] {
    Worker worker(options, made_by, report);
    for (std::size_t i; !stop && (i = next.fetch_add(1)) < models.size();) {
      try {
        results[i] = worker.process(models[i]);
      } catch (const FatalError& e) {
        std::lock_guard lock(mutex);
        if (!fatal) fatal = e.error;
        stop = true;
        return;
      }
      std::lock_guard lock(mutex);
      ++finished;
      if (!results[i].ok) ++failed;
      if (finished_model) finished_model(results[i]);
      if (progress) progress(finished, models.size(), failed, results[i].id + (results[i].ok ? " done" : " failed"));
    }
  };
  const unsigned jobs = std::max(1u, std::min<unsigned>(options.jobs, static_cast<unsigned>(std::max<std::size_t>(1, models.size()))));
  if (jobs == 1) {
    work();
  } else {
    std::vector<std::thread> threads;
    for (unsigned j = 0; j < jobs; ++j) threads.emplace_back(work);
    for (auto& t : threads) t.join();
  }
  if (fatal) std::rethrow_exception(fatal);
  return results;
}

}  // namespace splatcl::batch
