#pragma once
// The project's one thread pool: parallel_for runs body(i, worker) for i in [0, n) on every CPU the
// process may use (usable_cpus: its affinity mask), at most `max_workers` when that is non-zero,
// with worker < worker_count(n, block, max_workers). Blocks of `block` indices come from a shared
// counter, so uneven work per index stays balanced; the worker index lets callers keep per-thread
// scratch. Exception-safe: the first exception a body throws stops the hand-out, every thread is
// joined, and it is rethrown to the caller (also when a thread cannot be started), so a failing
// worker is an error, never std::terminate.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "io/cpu_set.hpp"

namespace splatcl {

inline std::size_t worker_count(std::size_t n, std::size_t block, std::size_t max_workers = 0) {
  const std::size_t cpus = max_workers ? std::min<std::size_t>(max_workers, usable_cpus()) : usable_cpus();
  return std::clamp<std::size_t>((n + block - 1) / std::max<std::size_t>(block, 1), 1, std::max<std::size_t>(cpus, 1));
}

template <class Body>
void parallel_for(std::size_t n, std::size_t block, Body&& body, std::size_t max_workers = 0) {
  block = std::max<std::size_t>(block, 1);
  const std::size_t threads = worker_count(n, block, max_workers);
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto fail = [&](std::exception_ptr e) {
    std::lock_guard lock(failure_mutex);
    if (!failure) failure = e;
    next = n;
  };
  auto worker = [&](std::size_t w) {
    try {
      for (std::size_t begin; (begin = next.fetch_add(block)) < n;)
        for (std::size_t i = begin, end = std::min(n, begin + block); i < end; ++i) body(i, w);
    } catch (...) {
      fail(std::current_exception());
    }
  };
  if (threads <= 1) {
    worker(0);
  } else {
    std::vector<std::thread> pool;
    pool.reserve(threads);
    try {
      for (std::size_t t = 0; t < threads; ++t) pool.emplace_back(worker, t);
    } catch (...) {
      fail(std::current_exception());  // the threads already started see the stop and finish
    }
    for (auto& t : pool) t.join();
  }
  if (failure) std::rethrow_exception(failure);
}

}  // namespace splatcl
