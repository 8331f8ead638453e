// The driver of a harness where libFuzzer is not available (GCC builds, which CI uses): feeds every
// file named on the command line, or found in a directory named there, to the harness's
// LLVMFuzzerTestOneInput once, in name order, and fails when an input takes more than the time
// libFuzzer's long runs allow (-timeout, 1 s; --timeout S changes it). A finding aborts inside the
// harness, naming the input just printed to stderr. It prints how many inputs the reader read and
// how many it refused.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  double timeout_s = 1.0;
  std::vector<fs::path> inputs;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--timeout" && i + 1 < argc) {
      timeout_s = std::atof(argv[++i]);
      continue;
    }
    std::error_code ec;
    if (fs::is_directory(arg, ec)) {
      for (const auto& entry : fs::directory_iterator(arg))
        if (entry.is_regular_file()) inputs.push_back(entry.path());
    } else if (fs::is_regular_file(arg, ec)) {
      inputs.emplace_back(arg);
    } else {
      std::fprintf(stderr, "%s: %s: no such file or directory\n", argv[0], arg.c_str());
      return 1;
    }
  }
  if (inputs.empty()) {
    std::fprintf(stderr, "usage: %s [--timeout SECONDS] FILE|DIR...: no inputs given\n", argv[0]);
    return 1;
  }
  std::sort(inputs.begin(), inputs.end());
  double slowest_s = 0;
  std::string slowest;
  for (const fs::path& input : inputs) {
    std::ifstream in(input, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.eof() && in.fail()) {
      std::fprintf(stderr, "%s: cannot read %s\n", argv[0], input.c_str());
      return 1;
    }
    std::fprintf(stderr, "input %s (%zu bytes)\n", input.c_str(), bytes.size());
    const auto start = std::chrono::steady_clock::now();
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (seconds > slowest_s) slowest_s = seconds, slowest = input.string();
    if (seconds > timeout_s) {
      std::fprintf(stderr, "%s: %s took %.2f s, more than %.2f s\n", argv[0], input.c_str(), seconds, timeout_s);
      return 1;
    }
  }
  std::printf("%zu inputs, no finding: %zu read, %zu refused; slowest %.3f s (%s)\n", inputs.size(), splatcl::fuzz::inputs_read,
              splatcl::fuzz::inputs_refused, slowest_s, slowest.c_str());
  return 0;
}
