// BOOST_COMPUTE_USE_OFFLINE_CACHE stays undefined: Boost.Compute tests it with #ifdef, and its
// on-disk program cache in $HOME would make timings depend on earlier runs.
#include "bench/peers/boost_compute.hpp"

#include <boost/compute/algorithm/copy.hpp>
#include <boost/compute/algorithm/sort.hpp>
#include <boost/compute/algorithm/unique.hpp>
#include <boost/compute/command_queue.hpp>
#include <boost/compute/container/vector.hpp>
#include <boost/compute/context.hpp>
#include <boost/compute/device.hpp>
#include <boost/compute/exception.hpp>
#include <boost/compute/system.hpp>
#include <boost/compute/utility/program_cache.hpp>

#include "runtime/error.hpp"

namespace compute = boost::compute;

namespace splatcl::bench {
namespace {

std::string trimmed(std::string text) {
  while (!text.empty() && (text.back() == '\0' || text.back() == ' ' || text.back() == '\n')) text.pop_back();
  return text;
}

compute::device find_device(const std::string& name) {
  const std::string wanted = trimmed(name);
  for (const auto& device : compute::system::devices())
    if (trimmed(device.name()) == wanted) return device;
  throw Error("Boost.Compute peer: no OpenCL device named '" + wanted + "'");
}

// Boost.Compute reports failures with its own exception types; the CLI expects splatcl::Error.
template <class F>
auto guarded(const char* what, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const compute::program_build_failure& e) {
    throw Error(std::string("Boost.Compute ") + what + ": kernel build failed: " + e.what());
  } catch (const compute::opencl_error& e) {
    throw Error(std::string("Boost.Compute ") + what + ": " + e.what());
  }
}

}  // namespace

struct BoostComputePeer::State {
  compute::device device;
  compute::context context;
  compute::command_queue queue;
  compute::vector<std::uint32_t> loaded;
  compute::vector<std::uint32_t> working;
  std::size_t count = 0;

  explicit State(const compute::device& d)
      : device(d), context(d), queue(context, d), loaded(context), working(context) {}
};

BoostComputePeer::BoostComputePeer(const std::string& device_name) {
  guarded("setup", [&] { state_ = std::make_unique<State>(find_device(device_name)); });
}

// Boost.Compute keeps the programs its algorithms built in a process-wide cache per context, a
// static released among the static destructors, after those of the OpenCL implementations' LLVM:
// a bench run on Oclgrind (beside Intel's runtime) aborted at exit ("corrupted double-linked
// list", exit 134). Emptied here, with the context still alive.
BoostComputePeer::~BoostComputePeer() {
  if (!state_) return;
  try {
    compute::program_cache::get_global_cache(state_->context)->clear();
  } catch (...) {  // a failed release leaves the cache to the exit, as before
  }
}

void BoostComputePeer::load(const std::vector<std::uint32_t>& keys) {
  guarded("upload", [&] {
    state_->count = keys.size();
    state_->loaded.resize(keys.size(), state_->queue);
    state_->working.resize(keys.size(), state_->queue);
    compute::copy(keys.begin(), keys.end(), state_->loaded.begin(), state_->queue);
    state_->queue.finish();
  });
}

void BoostComputePeer::reset() {
  guarded("copy", [&] {
    state_->working.resize(state_->count, state_->queue);
    compute::copy(state_->loaded.begin(), state_->loaded.end(), state_->working.begin(), state_->queue);
    state_->queue.finish();
  });
}

void BoostComputePeer::sort() {
  guarded("sort", [&] {
    compute::sort(state_->working.begin(), state_->working.end(), state_->queue);
    state_->queue.finish();
  });
}

std::size_t BoostComputePeer::unique() {
  return guarded("unique", [&] {
    const auto end = compute::unique(state_->working.begin(), state_->working.end(), state_->queue);
    state_->queue.finish();
    return static_cast<std::size_t>(end - state_->working.begin());
  });
}

std::vector<std::uint32_t> BoostComputePeer::download(std::size_t count) {
  return guarded("download", [&] {
    std::vector<std::uint32_t> keys(std::min(count, state_->working.size()));
    compute::copy(state_->working.begin(), state_->working.begin() + static_cast<std::ptrdiff_t>(keys.size()),
                  keys.begin(), state_->queue);
    return keys;
  });
}

}  // namespace splatcl::bench
