// Host-vector conveniences: upload, run on the device, download.
#include <string>

#include "primitives/primitives.hpp"
#include "runtime/error.hpp"

namespace splatcl::primitives {
namespace {

template <class Key>
void sort_host(Runtime& runtime, std::vector<Key>& keys, std::vector<std::uint32_t>* values, unsigned bits,
               Shape shape) {
  if (values && values->size() != keys.size())
    throw Error("radix sort: " + std::to_string(keys.size()) + " keys but " + std::to_string(values->size()) +
                " values");
  try {
    RadixSorter sorter(runtime, sizeof(Key) == 8 ? KeyType::U64 : KeyType::U32, values != nullptr, shape);
    const cl::Buffer keys_buffer = upload(runtime, keys, "radix sort keys");
    cl::Buffer values_buffer;
    if (values) values_buffer = upload(runtime, *values, "radix sort values");
    sorter.sort(keys_buffer, values ? &values_buffer : nullptr, keys.size(), bits);
    keys = download<Key>(runtime, keys_buffer, keys.size(), "sorted keys");
    if (values) *values = download<std::uint32_t>(runtime, values_buffer, values->size(), "sorted values");
  } catch (...) {
    rethrow_as_error("radix sort of " + std::to_string(keys.size()) + " host keys");
  }
}

}  // namespace

std::vector<std::uint32_t> scan(Runtime& runtime, const std::vector<std::uint32_t>& in, ScanKind kind, Shape shape) {
  try {
    Scanner scanner(runtime, shape);
    const cl::Buffer buffer = upload(runtime, in, "scan values");
    scanner.run(buffer, buffer, in.size(), kind, false);
    return download<std::uint32_t>(runtime, buffer, in.size(), "scan results");
  } catch (...) {
    rethrow_as_error("scan of " + std::to_string(in.size()) + " host values");
  }
}

std::vector<std::uint32_t> keep_flagged(Runtime& runtime, const std::vector<std::uint32_t>& values,
                                        const std::vector<std::uint32_t>& flags, Shape shape) {
  if (flags.size() != values.size())
    throw Error("keep_flagged: " + std::to_string(values.size()) + " values but " + std::to_string(flags.size()) +
                " flags");
  try {
    Compactor compactor(runtime, shape);
    const cl::Buffer values_buffer = upload(runtime, values, "compaction values");
    const cl::Buffer flags_buffer = upload(runtime, flags, "compaction flags");
    const cl::Buffer out =
        runtime.buffer(CL_MEM_READ_WRITE, values.size() * sizeof(std::uint32_t), "compaction output");
    return download<std::uint32_t>(runtime, out, compactor.keep_flagged(values_buffer, flags_buffer, out, values.size()),
                                   "compaction results");
  } catch (...) {
    rethrow_as_error("keep_flagged of " + std::to_string(values.size()) + " host values");
  }
}

std::vector<std::uint32_t> unique(Runtime& runtime, const std::vector<std::uint32_t>& values, Shape shape) {
  try {
    Compactor compactor(runtime, shape);
    const cl::Buffer values_buffer = upload(runtime, values, "unique values");
    const cl::Buffer out = runtime.buffer(CL_MEM_READ_WRITE, values.size() * sizeof(std::uint32_t), "unique output");
    return download<std::uint32_t>(runtime, out, compactor.unique(values_buffer, out, values.size()), "unique results");
  } catch (...) {
    rethrow_as_error("unique of " + std::to_string(values.size()) + " host values");
  }
}

void radix_sort(Runtime& runtime, std::vector<std::uint32_t>& keys, std::vector<std::uint32_t>* values, unsigned bits,
                Shape shape) {
  sort_host(runtime, keys, values, bits, shape);
}

void radix_sort(Runtime& runtime, std::vector<std::uint64_t>& keys, std::vector<std::uint32_t>* values, unsigned bits,
                Shape shape) {
  sort_host(runtime, keys, values, bits, shape);
}

}  // namespace splatcl::primitives
