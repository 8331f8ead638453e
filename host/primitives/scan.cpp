#include <string>

#include "primitives/launch.hpp"
#include "primitives/primitives.hpp"
#include "runtime/error.hpp"

namespace splatcl::primitives {
namespace {

cl_uint inclusive_flag(ScanKind kind) { return kind == ScanKind::Inclusive ? 1u : 0u; }

}  // namespace

Scanner::Scanner(Runtime& runtime, Shape shape, const std::optional<LaunchParameters>& parameters)
    : runtime_(runtime),
      shape_(runtime.resolve(shape)),
      parameters_(detail::launch_parameters(runtime, Primitive::Scan, shape_, parameters)) {
  const std::string options = detail::group_options(parameters_) + " -DSCAN_ITEMS=" + std::to_string(parameters_.items_per_work_item);
  if (shape_ == Shape::Cpu) {
    reduce_kernel_ = runtime_.kernel("scan.cl", "scan_chunk_sums_cpu", options);
    scan_kernel_ = runtime_.kernel("scan.cl", "scan_chunks_cpu", options);
  } else {
    scan_kernel_ = runtime_.kernel("scan.cl", "scan_blocks_gpu", options);
    add_kernel_ = runtime_.kernel("scan.cl", "scan_add_offsets_gpu", options);
    const auto group = static_cast<std::size_t>(parameters_.group_size);
    validate_built_kernel(scan_kernel_, "scan_blocks_gpu", group, runtime_.info());
    validate_built_kernel(add_kernel_, "scan_add_offsets_gpu", group, runtime_.info());
  }
  total_ = runtime_.buffer(CL_MEM_READ_WRITE, sizeof(cl_uint), "scan total");
}

std::uint32_t Scanner::run(const cl::Buffer& in, const cl::Buffer& out, std::size_t n, ScanKind kind, bool read_total,
                           Profiler* profiler) {
  require_bytes(in, n * sizeof(cl_uint), "scan input");
  require_bytes(out, n * sizeof(cl_uint), "scan output");
  try {
    auto& queue = runtime_.queue();
    if (n == 0) {
      queue.enqueueFillBuffer(total_, cl_uint{0}, 0, sizeof(cl_uint));
    } else if (shape_ == Shape::Cpu) {
      run_cpu(in, out, n, kind, profiler);
    } else {
      run_gpu(in, out, n, kind, 0, profiler);
    }
    if (!read_total) return 0;
    cl_uint total = 0;
    queue.enqueueReadBuffer(total_, CL_TRUE, 0, sizeof(total), &total);
    return total;
  } catch (...) {
    rethrow_as_error("scan of " + std::to_string(n) + " values");
  }
}

void Scanner::run_cpu(const cl::Buffer& in, const cl::Buffer& out, std::size_t n, ScanKind kind,
                      Profiler* profiler) {
  const std::size_t chunks = detail::cpu_chunk_count(runtime_, n, parameters_);
  if (partials_.empty()) partials_.emplace_back(runtime_, "scan chunk sums");
  partials_[0].resize(chunks);
  const auto n_arg = static_cast<cl_ulong>(n);
  const auto chunks_arg = static_cast<cl_uint>(chunks);
  // Local size 1: each chunk is its own work-group, so PoCL spreads chunks over its threads.
  if (chunks > 1) {
    detail::set_args(reduce_kernel_, in, partials_[0].buffer(), n_arg, chunks_arg);
    enqueue_1d(runtime_.queue(), reduce_kernel_, chunks, 1, profiler, "scan chunk sums");
  }
  detail::set_args(scan_kernel_, in, out, partials_[0].buffer(), total_, n_arg, chunks_arg, inclusive_flag(kind));
  enqueue_1d(runtime_.queue(), scan_kernel_, chunks, 1, profiler, "scan chunks");
}

void Scanner::run_gpu(const cl::Buffer& in, const cl::Buffer& out, std::size_t n, ScanKind kind, std::size_t level,
                      Profiler* profiler) {
  const auto group = static_cast<std::size_t>(parameters_.group_size);
  const std::size_t blocks = div_up(n, group * static_cast<std::size_t>(parameters_.items_per_work_item));
  while (partials_.size() <= level) partials_.emplace_back(runtime_, "scan block sums");
  // A single block's sum is the grand total.
  if (blocks > 1) partials_[level].resize(blocks);
  // A handle, not a reference: the recursion below may grow partials_.
  const cl::Buffer block_sums = blocks > 1 ? partials_[level].buffer() : total_;
  const auto n_arg = static_cast<cl_ulong>(n);
  detail::set_args(scan_kernel_, in, out, block_sums, n_arg, inclusive_flag(kind));
  enqueue_1d(runtime_.queue(), scan_kernel_, blocks * group, group, profiler, "scan blocks");
  if (blocks == 1) return;
  run_gpu(block_sums, block_sums, blocks, ScanKind::Exclusive, level + 1, profiler);
  detail::set_args(add_kernel_, out, block_sums, n_arg);
  enqueue_1d(runtime_.queue(), add_kernel_, n, group, profiler, "scan add offsets");
}

}  // namespace splatcl::primitives
