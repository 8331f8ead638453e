#include "io/cpu_set.hpp"

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>

namespace splatcl {

unsigned usable_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) return static_cast<unsigned>(std::max(1, CPU_COUNT(&set)));
  return std::max(1u, std::thread::hardware_concurrency());
}

void limit_opencl_threads_to_cpu_set() {
  if (std::getenv("POCL_MAX_PTHREAD_COUNT")) return;
  // The machine's online CPUs, as PoCL counts them (some C libraries answer hardware_concurrency
  // from the affinity mask too).
  const long online = sysconf(_SC_NPROCESSORS_ONLN);
  const unsigned cpus = usable_cpus();
  if (online > 0 && cpus < static_cast<unsigned long>(online)) setenv("POCL_MAX_PTHREAD_COUNT", std::to_string(cpus).c_str(), 0);
}

}  // namespace splatcl
