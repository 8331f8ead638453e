// Benchmark results (bench/record.hpp, bench/csv.hpp), JSON or CSV by SPLATCL_FUZZ_BENCH_CSV, as
// `bench report|compare|plot` read them. Results that read must write and read back to the same
// JSON (the CSV reader's errors are prefixed with the file by read_csv, so they name no file here).
#include "bench/csv.hpp"
#include "bench/record.hpp"
#include "fuzz_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace splatcl::bench;
  splatcl::fuzz::check_reader(data, size, SPLATCL_FUZZ_BENCH_CSV ? "" : "fuzz-results.json", [](const std::string& bytes) {
    const Results results = SPLATCL_FUZZ_BENCH_CSV ? results_from_csv(bytes) : parse_results(bytes, "fuzz-results.json");
    const std::string written = to_json(results).dump();
    if (to_json(parse_results(written, "fuzz-results.json written back")).dump() != written)
      splatcl::fuzz::finding("results do not read back as written");
  });
  return 0;
}
