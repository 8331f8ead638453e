#include <limits>
#include <string>

#include "primitives/launch.hpp"
#include "primitives/primitives.hpp"
#include "runtime/error.hpp"

namespace splatcl::primitives {
namespace {

}  // namespace

Compactor::Compactor(Runtime& runtime, Shape shape, const std::optional<LaunchParameters>& parameters)
    : runtime_(runtime),
      shape_(runtime.resolve(shape)),
      parameters_(detail::launch_parameters(runtime, Primitive::Compact, shape_, parameters)),
      counts_(runtime, shape_ == Shape::Cpu ? "compaction counts" : "compaction block counts") {
  const std::string options =
      detail::group_options(parameters_) + " -DCOMPACT_ROUNDS=" + std::to_string(parameters_.items_per_work_item);
  if (shape_ == Shape::Cpu) {
    count_kernel_ = runtime_.kernel("compact.cl", "compact_count_cpu", options);
    scatter_kernel_ = runtime_.kernel("compact.cl", "compact_scatter_cpu", options);
  } else {
    count_kernel_ = runtime_.kernel("compact.cl", "compact_count_gpu", options);
    scatter_kernel_ = runtime_.kernel("compact.cl", "compact_scatter_gpu", options);
    const auto group = static_cast<std::size_t>(parameters_.group_size);
    validate_built_kernel(count_kernel_, "compact_count_gpu", group, runtime_.info());
    validate_built_kernel(scatter_kernel_, "compact_scatter_gpu", group, runtime_.info());
    block_scanner_.emplace(runtime_, Shape::Gpu);
  }
}

std::size_t Compactor::keep_flagged(const cl::Buffer& values, const cl::Buffer& flags, const cl::Buffer& out,
                                    std::size_t n, Profiler* profiler) {
  require_bytes(flags, n * sizeof(cl_uint), "keep_flagged flags");
  return compact(values, flags, out, n, false, profiler);
}

std::size_t Compactor::unique(const cl::Buffer& values, const cl::Buffer& out, std::size_t n, Profiler* profiler) {
  return compact(values, values, out, n, true, profiler);
}

std::size_t Compactor::compact(const cl::Buffer& values, const cl::Buffer& flags, const cl::Buffer& out,
                               std::size_t n, bool unique_mode, Profiler* profiler) {
  const char* what = unique_mode ? "unique" : "keep_flagged";
  if (n > std::numeric_limits<cl_uint>::max())
    throw Error(std::string(what) + ": " + std::to_string(n) + " values exceed the 2^32 - 1 supported");
  require_bytes(values, n * sizeof(cl_uint), what);
  require_bytes(out, n * sizeof(cl_uint), what);
  if (n == 0) return 0;
  try {
    auto& queue = runtime_.queue();
    const auto n_arg = static_cast<cl_ulong>(n);
    const cl_uint mode_arg = unique_mode ? 1u : 0u;
    cl_uint total = 0;
    if (shape_ == Shape::Cpu) {
      const std::size_t chunks = detail::cpu_chunk_count(runtime_, n, parameters_);
      const auto chunks_arg = static_cast<cl_uint>(chunks);
      counts_.resize(chunks + 1);
      if (chunks > 1) {
        detail::set_args(count_kernel_, values, flags, counts_.buffer(), n_arg, chunks_arg, mode_arg);
        enqueue_1d(queue, count_kernel_, chunks, 1, profiler, "compact count");
      }
      detail::set_args(scatter_kernel_, values, flags, out, counts_.buffer(), n_arg, chunks_arg, mode_arg);
      enqueue_1d(queue, scatter_kernel_, chunks, 1, profiler, "compact scatter");
      queue.enqueueReadBuffer(counts_.buffer(), CL_TRUE, chunks * sizeof(cl_uint), sizeof(total), &total);
    } else {
      const auto group = static_cast<std::size_t>(parameters_.group_size);
      const std::size_t blocks = div_up(n, group * static_cast<std::size_t>(parameters_.items_per_work_item));
      counts_.resize(blocks);
      detail::set_args(count_kernel_, values, flags, counts_.buffer(), n_arg, mode_arg);
      enqueue_1d(queue, count_kernel_, blocks * group, group, profiler, "compact count");
      block_scanner_->run(counts_.buffer(), counts_.buffer(), blocks, ScanKind::Exclusive, false, profiler);
      detail::set_args(scatter_kernel_, values, flags, out, counts_.buffer(), n_arg, mode_arg);
      enqueue_1d(queue, scatter_kernel_, blocks * group, group, profiler, "compact scatter");
      queue.enqueueReadBuffer(block_scanner_->total_buffer(), CL_TRUE, 0, sizeof(total), &total);
    }
    return total;
  } catch (...) {
    rethrow_as_error(std::string(what) + " of " + std::to_string(n) + " values");
  }
}

}  // namespace splatcl::primitives
