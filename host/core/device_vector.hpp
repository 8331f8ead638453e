#pragma once
// A typed device buffer with a size and a capacity, as boost::compute::vector has: its storage
// grows when a larger size is asked for and is kept for every later, smaller size, so a stage that
// runs batch after batch allocates only when a batch outgrows all earlier ones. Errors name the
// buffer by the `what` given at construction.
#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "runtime/error.hpp"
#include "runtime/runtime.hpp"

namespace splatcl {

// Size of a buffer in bytes; 0 for a buffer that was never allocated.
inline std::size_t buffer_bytes(const cl::Buffer& buffer) { return buffer() ? buffer.getInfo<CL_MEM_SIZE>() : 0; }

// Throws Error naming `what` when a caller's `buffer` holds fewer than `bytes`.
inline void require_bytes(const cl::Buffer& buffer, std::size_t bytes, const char* what) {
  const std::size_t held = buffer_bytes(buffer);
  if (held < bytes)
    throw Error(std::string(what) + ": buffer holds " + std::to_string(held) + " bytes, " + std::to_string(bytes) +
                " needed");
}

template <class T>
class DeviceVector {
 public:
  DeviceVector(Runtime& runtime, std::string what, cl_mem_flags flags = CL_MEM_READ_WRITE)
      : runtime_(&runtime), what_(std::move(what)), flags_(flags) {}

  std::size_t size() const { return size_; }
  std::size_t capacity() const { return capacity_; }
  bool empty() const { return size_ == 0; }
  std::size_t bytes() const { return size_ * sizeof(T); }
  // The storage, for kernel arguments and copies (null until the first resize).
  const cl::Buffer& buffer() const { return buffer_; }

  // Sets the size to n. The storage is reallocated, its contents dropped, only when it holds fewer
  // than n elements; it always holds at least one, as OpenCL has no zero-sized buffers.
  void resize(std::size_t n) {
    if (n > capacity_ || !buffer_()) {
      const std::size_t elements = std::max<std::size_t>(n, 1);
      buffer_ = runtime_->buffer(flags_, elements * sizeof(T), what_.c_str());
      capacity_ = elements;
    }
    size_ = n;
  }

  // Resizes to values.size() and copies them in. With `blocking` false the copy is only queued:
  // the caller keeps `values` alive until the in-order queue has run it (a later blocking command).
  void assign(const std::vector<T>& values, bool blocking = true) {
    resize(values.size());
    if (values.empty()) return;
    try {
      runtime_->queue().enqueueWriteBuffer(buffer_, blocking ? CL_TRUE : CL_FALSE, 0, bytes(), values.data());
    } catch (...) {
      rethrow_as_error("uploading " + what_);
    }
  }

  // Blocking read of the first n elements (n ≤ size()).
  std::vector<T> read(std::size_t n) const {
    std::vector<T> values(std::min(n, size_));
    if (values.empty()) return values;
    try {
      runtime_->queue().enqueueReadBuffer(buffer_, CL_TRUE, 0, values.size() * sizeof(T), values.data());
    } catch (...) {
      rethrow_as_error("reading back " + what_);
    }
    return values;
  }
  std::vector<T> read() const { return read(size_); }

 private:
  Runtime* runtime_;
  std::string what_;
  cl_mem_flags flags_;
  cl::Buffer buffer_;
  std::size_t size_ = 0, capacity_ = 0;
};

}  // namespace splatcl
