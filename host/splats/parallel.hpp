#pragma once
// Runs body(i, worker) for i in [0, n) on every CPU the process may use (usable_cpus: its affinity
// mask; worker < worker_count(n, block)), handing out blocks of `block` indices from a shared
// counter so uneven work per index stays balanced. The worker index lets callers keep per-thread
// scratch.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "io/cpu_set.hpp"

namespace splatcl::splats {

inline std::size_t worker_count(std::size_t n, std::size_t block) {
  return std::clamp<std::size_t>((n + block - 1) / block, 1, usable_cpus());
}

template <class Body>
void parallel_for(std::size_t n, std::size_t block, Body&& body) {
  const std::size_t threads = worker_count(n, block);
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto worker = [&](std::size_t w) {
    try {
      for (std::size_t begin; (begin = next.fetch_add(block)) < n;)
        for (std::size_t i = begin, end = std::min(n, begin + block); i < end; ++i) body(i, w);
    } catch (...) {
      std::lock_guard lock(failure_mutex);
      if (!failure) failure = std::current_exception();
      next = n;
    }
  };
  if (threads <= 1) {
    worker(0);
  } else {
    std::vector<std::thread> pool;
    for (std::size_t t = 0; t < threads; ++t) pool.emplace_back(worker, t);
    for (auto& t : pool) t.join();
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace splatcl::splats
