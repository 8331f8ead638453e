#pragma once
// Boost.Compute as a benchmark peer: its sort and unique on the same OpenCL device as ours.
// Boost.Compute needs the pre-3.0 OpenCL API, so it is compiled alone in splatcl_peers and this
// interface includes no Boost or OpenCL header.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace splatcl::bench {

inline constexpr const char* kImplBoostCompute = "boost.compute";

class BoostComputePeer {
 public:
  // The device whose CL_DEVICE_NAME equals `device_name` (as our runtime reports it, trailing
  // blanks ignored). Throws Error when there is none.
  explicit BoostComputePeer(const std::string& device_name);
  ~BoostComputePeer();
  BoostComputePeer(const BoostComputePeer&) = delete;
  BoostComputePeer& operator=(const BoostComputePeer&) = delete;

  // Copies keys to the device; reset() restores the working keys from this copy.
  void load(const std::vector<std::uint32_t>& keys);
  // Working keys = loaded keys, finished on the device (untimed setup of each run).
  void reset();
  // boost::compute::sort of the working keys, finished on the device.
  void sort();
  // boost::compute::unique of the working keys, finished; returns the count kept.
  std::size_t unique();
  // The first `count` working keys.
  std::vector<std::uint32_t> download(std::size_t count);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace splatcl::bench
