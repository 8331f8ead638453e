#pragma once
// PNG plots of benchmark results, drawn by gnuplot: a script and its data files are written to a
// directory and gnuplot is run on it, so the user can edit and rerun the script.
//   throughput-<suite>.png      throughput of every case per implementation and device (log scale;
//                               the largest size and thread count of each case)
//   scaling-size-<suite>.png    throughput against problem size, where a run measured several sizes
//   scaling-threads-<suite>.png speedup over one thread against POCL_MAX_PTHREAD_COUNT, where a run
//                               measured several thread counts
#include <string>
#include <vector>

#include "bench/record.hpp"

namespace splatcl::bench {

// The gnuplot program on PATH, or empty.
std::string find_gnuplot();

// Writes `dir`/plots.gp and its .dat files (creating `dir`), runs gnuplot and returns the PNG paths.
// Each PNG is written under a temporary name and renamed once gnuplot succeeded. Throws Error when
// there is nothing to plot, when gnuplot is not installed (naming the script, which is kept) or
// when it fails.
std::vector<std::string> write_plots(const Results& results, const std::string& dir);

}  // namespace splatcl::bench
