#pragma once
// Markdown rendering of benchmark results: the table printed after a run and the tables in docs,
// both generated from records, never typed by hand.
#include <string>
#include <vector>

#include "bench/record.hpp"

namespace splatcl::bench {

// "radix-sort-u32 bits=20": the case with the extra fields that make a variant of the problem.
std::string case_label(const Record& record);
// "opencl bitmask (cpu shape)": the implementation with its variant and kernel shape.
std::string impl_label(const Record& record);

// One line describing the machine and device the figures were measured on.
std::string machine_line(const Json& machine);

// Padded markdown table, one row per record, in record order: case_label, impl_label, size,
// median/min/max ms, throughput, speedup over the baseline of the case, peak RSS. Records with the
// same case label and size are compared (see describes_implementation); the baseline is the
// reference, else the first record that is neither the reference nor opencl.
// Optional columns appear when they apply: device (records from several devices), vs peer (the
// first peer's median / median), of stream BW (records with "bytes": bytes / median as a share of
// the stream-copy throughput of the same device found in `context`).
std::string markdown_table(const std::vector<Record>& records, const std::vector<Record>& context);
std::string markdown_table(const std::vector<Record>& records);

// Machine line, then one table per suite under a "### suite" heading, then the legend.
std::string markdown_report(const Results& results);

}  // namespace splatcl::bench
