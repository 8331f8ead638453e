#pragma once
// One `splatcl bench <suite>` invocation: the device, the options shared by every suite, the records
// measured so far, progress on a terminal, and at the end the table on stdout and the --json file.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bench/measure.hpp"
#include "bench/record.hpp"
#include "cli/progress.hpp"
#include "runtime/error.hpp"
#include "runtime/runtime.hpp"

namespace splatcl::bench {

// A 1920×1080 frame: one cluster key per pixel.
inline constexpr std::uint64_t kFullHdPixels = 1920ull * 1080ull;
// Cluster keys of a 1920×1080 frame with 32×32 tiles take about 20 bits (11 tile, 8 slice bits).
inline constexpr unsigned kClusterKeyBits = 20;

struct SessionOptions {
  std::uint64_t size = kFullHdPixels;
  MeasureOptions measure;
  std::string device;     // selector as for choose_device
  std::string json_path;  // empty: no file
  // Small inputs, for tests and smoke runs: suites shrink their problems (figures not comparable).
  bool quick = false;
  // Problem size factor of size scaling (--scaling size): suites multiply their standard sizes by it.
  double scale = 1.0;
  // False for the smaller steps of size scaling: the streaming-copy rows do not depend on the
  // suite's problem size, so they are measured once per device, at the standard size.
  bool measure_bandwidth = true;
  // False for every device after the first of a multi-device run: host rows (reference, std,
  // Embree) run once untimed, so their outputs still exist, but are not measured and recorded again.
  bool measure_host = true;
};

// What one measured row is; the session adds timing, throughput and peak RSS.
struct Case {
  std::string name;       // "radix-sort-u32"
  std::string impl;       // kImplOpenCL, kImplReference or a peer's name
  bool on_device = true;  // false: runs on the host outside OpenCL (device = kHostDevice)
  std::uint64_t size = 0;
  std::string size_unit;  // throughput is size_unit per second
  Json extra = Json::object();
};

// Both kernel shapes: every suite measures each on every device.
inline constexpr Shape kBothShapes[] = {Shape::Cpu, Shape::Gpu};

// An OpenCL row of case `name`: `problem` fields ({"bits": 20}) name the variant of the problem,
// `implementation` fields ({"variant": "bitmask"}) how it is solved; "shape" is added.
Case opencl_case(const std::string& name, Shape shape, std::uint64_t size, const std::string& size_unit,
                 const Json& problem = Json::object(), const Json& implementation = Json::object());
// The native reference row of case `name`, on the host.
Case reference_case(const std::string& name, std::uint64_t size, const std::string& size_unit,
                    const Json& problem = Json::object(), const Json& implementation = Json::object());
// "compact opencl bitmask (cpu shape)", for progress and error messages.
std::string describe(const Case& c);

class Session {
 public:
  Session(std::string suite, SessionOptions options);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  Runtime& runtime() { return *runtime_; }
  const SessionOptions& options() const { return options_; }
  const std::string& suite() const { return suite_; }
  const std::vector<Record>& records() const { return records_; }

  // Times one case (see measure()): setup() is untimed, run() is timed and must return after its
  // work has finished. With a profiler, per-kernel device times are recorded as "device_ms".
  // A host row (c.on_device false) when !options().measure_host runs once, untimed and unrecorded.
  const Record& measure(const Case& c, const std::function<void()>& setup, const std::function<void()>& run,
                        Profiler* profiler = nullptr);

  // The record the last measure() call added, for fields known only after the run.
  Record& last_record() { return records_.empty() ? unrecorded_ : records_.back(); }
  // Takes back the record the last measure() call added, with a warning naming why on stderr:
  // for a peer library whose output is wrong on this device (its time would mean nothing), where
  // failing the whole run would hide every other result.
  void withdraw_last_record(const std::string& why);

  Results results() const;
  // Prints the markdown report on stdout and writes the --json file when one was asked for.
  void finish() const;

 private:
  void show_progress(const std::string& text, bool final_line);

  std::string suite_;
  SessionOptions options_;
  std::shared_ptr<Runtime> runtime_;
  std::vector<Record> records_;
  bool progress_;  // stderr is a terminal
  bool progress_line_open_ = false;
  // Otherwise (a job log): a plain line at most every SPLATCL_PROGRESS_SECONDS (bench printed
  // nothing at all there, not even which suites had finished).
  std::unique_ptr<cli::ProgressLine> log_;
  Record unrecorded_;  // what measure() returns for a host row it does not record
};

// The tuning database a run on `device` reads, and whether it has a record for the device.
std::string tuning_used(const DeviceInfo& device);

// Waits for the session device's queue (Error naming the benchmark on failure).
void finish(Runtime& runtime);
// Copies `bytes` from one device buffer to another and waits: restores a case's input outside the timing.
void copy_buffer(Runtime& runtime, const cl::Buffer& from, const cl::Buffer& to, std::size_t bytes);
// Fills `bytes` of the buffer with 0xA5 bytes before a kernel shape writes its output there, so that
// the check after it cannot pass on what another shape left in the buffer.
void poison_buffer(Runtime& runtime, const cl::Buffer& buffer, std::size_t bytes);
// n keys uniformly drawn from [0, 2^bits) (bits up to 32) from a fixed seed: the same inputs on every run and machine.
std::vector<std::uint32_t> random_keys(std::size_t n, unsigned bits, std::uint64_t seed);

// A suite's standard size scaled by SessionOptions::scale, at least 1.
std::uint64_t scaled(const Session& session, std::uint64_t standard);

// Benchmarks time only correct work: throws Error naming the case when `actual` differs from
// `expected`.
template <class T>
void expect_same_output(const std::string& what, const std::vector<T>& actual, const std::vector<T>& expected) {
  if (actual.size() != expected.size())
    throw Error("bench " + what + ": output has " + std::to_string(actual.size()) + " elements, the reference " +
                std::to_string(expected.size()));
  for (std::size_t i = 0; i < actual.size(); ++i)
    if (actual[i] != expected[i]) throw Error("bench " + what + ": output differs from the reference at index " + std::to_string(i));
}

}  // namespace splatcl::bench
