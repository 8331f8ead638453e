#include "io/in_flight.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>

namespace splatcl {
namespace {

// Fixed storage, so the signal handler touches no allocator: a slot is claimed (state 1), filled,
// then published (state 2); the handler unlinks published slots only.
constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;
char paths[kSlots][kPathBytes];
std::atomic<int> states[kSlots];

void on_termination(int signal) {
  for (int i = 0; i < kSlots; ++i)
    if (states[i].load(std::memory_order_acquire) == 2) ::unlink(paths[i]);
  // End by the same signal, with its default action.
  ::signal(signal, SIG_DFL);
  ::raise(signal);
}

}  // namespace

int register_in_flight(const std::string& path) {
  if (path.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int free = 0;
    if (states[i].compare_exchange_strong(free, 1, std::memory_order_acq_rel)) {
      std::memcpy(paths[i], path.c_str(), path.size() + 1);
      states[i].store(2, std::memory_order_release);
      return i;
    }
  }
  return -1;
}

void unregister_in_flight(int slot) {
  if (slot >= 0 && slot < kSlots) states[slot].store(0, std::memory_order_release);
}

void remove_in_flight_files_on_termination() {
  struct sigaction action {};
  action.sa_handler = on_termination;
  sigemptyset(&action.sa_mask);
  for (const int signal : {SIGTERM, SIGINT, SIGHUP}) ::sigaction(signal, &action, nullptr);
}

}  // namespace splatcl
