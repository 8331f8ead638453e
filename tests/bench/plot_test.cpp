// bench plot: gnuplot draws PNGs of throughput per case and device and of size and thread scaling.
// Skipped only where gnuplot is not installed (scripts/setup.sh installs it, so CI runs it).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <unistd.h>

#include "bench/plot.hpp"
#include "runtime/error.hpp"

namespace splatcl::bench {
namespace {

namespace fs = std::filesystem;

Record record(const std::string& impl, std::uint64_t size, double median_ms, int threads = 0) {
  Record r;
  r.suite = "csm";
  r.case_name = "capture";
  r.impl = impl;
  r.device = impl == kImplOpenCL ? "pthread-test" : kHostDevice;
  r.size = size;
  r.size_unit = "rays";
  r.runs = 1;
  r.median_ms = r.min_ms = r.max_ms = median_ms;
  r.throughput = static_cast<double>(size) / (median_ms * 1e-3);
  r.throughput_unit = "rays/s";
  if (threads) r.extra["pocl_threads"] = threads;
  return r;
}

bool is_png(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in && std::string(magic + 1, 3) == "PNG" && fs::file_size(path) > 1000;
}

TEST(BenchPlot, WritesThroughputAndScalingPngs) {
  if (find_gnuplot().empty()) GTEST_SKIP() << "gnuplot is not installed (scripts/setup.sh installs gnuplot-nox)";
  Results results;
  for (const std::uint64_t size : {1000u, 2000u, 4000u}) {
    results.records.push_back(record(kImplOpenCL, size, static_cast<double>(size) / 900));
    results.records.push_back(record(kImplReference, size, static_cast<double>(size) / 1000));
    results.records.push_back(record("embree", size, static_cast<double>(size) / 3000));
  }
  results.records.push_back(record(kImplOpenCL, 4000, 8, 1));
  results.records.push_back(record(kImplOpenCL, 4000, 4.5, 2));
  Record other = record(kImplOpenCL, 100, 1);
  other.suite = "primitives \"x\"";
  other.case_name = "scan";
  results.records.push_back(other);

  const fs::path dir = fs::temp_directory_path() / ("splatcl-plot-test-" + std::to_string(::getpid()));
  const std::vector<std::string> pngs = write_plots(results, (dir / "plots").string());
  ASSERT_EQ(pngs.size(), 4u) << testing::PrintToString(pngs);
  for (const auto& png : pngs) EXPECT_TRUE(is_png(png)) << png;
  EXPECT_TRUE(fs::exists(dir / "plots" / "throughput-csm.png"));
  EXPECT_TRUE(fs::exists(dir / "plots" / "scaling-size-csm.png"));
  EXPECT_TRUE(fs::exists(dir / "plots" / "scaling-threads-csm.png"));
  EXPECT_TRUE(fs::exists(dir / "plots" / "plots.gp"));
  for (const auto& entry : fs::directory_iterator(dir / "plots")) EXPECT_NE(entry.path().extension(), ".part") << entry.path();
  // The kept script redraws the PNGs themselves (it named *.png.part, which a rerun left beside them).
  std::ifstream kept(dir / "plots" / "plots.gp");
  const std::string script((std::istreambuf_iterator<char>(kept)), {});
  EXPECT_EQ(script.find(".part"), std::string::npos);
  EXPECT_NE(script.find("throughput-csm.png\""), std::string::npos);
  fs::remove_all(dir);
}

TEST(BenchPlot, NothingToPlotIsAnError) {
  Record r = record(kImplOpenCL, 10, 1);
  r.throughput.reset();
  Results results;
  results.records = {r};
  const fs::path dir = fs::temp_directory_path() / ("splatcl-plot-empty-" + std::to_string(::getpid()));
  EXPECT_THROW(write_plots(results, dir.string()), Error);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace splatcl::bench
