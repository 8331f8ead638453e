#include "io/in_flight.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>

namespace splatcl {
namespace {

// Fixed storage, so the signal handler touches no allocator: a slot is claimed (state 1), filled,
// then published (kFile or kFolder); the handler removes published slots only.
constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;
constexpr int kFile = 2, kFolder = 3;
char paths[kSlots][kPathBytes];
std::atomic<int> states[kSlots];

void on_termination(int signal) {
  for (int i = 0; i < kSlots; ++i)
    if (states[i].load(std::memory_order_acquire) == kFile) ::unlink(paths[i]);
  // Then the folders, inner ones first whatever their slots: a pass removes those already empty.
  for (bool removed = true; removed;) {
    removed = false;
    for (int i = kSlots - 1; i >= 0; --i)
      if (states[i].load(std::memory_order_acquire) == kFolder && ::rmdir(paths[i]) == 0) {
        states[i].store(0, std::memory_order_release);
        removed = true;
      }
  }
  // End by the same signal, with its default action.
  ::signal(signal, SIG_DFL);
  ::raise(signal);
}

int register_slot(const std::string& path, int kind) {
  if (path.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int free = 0;
    if (states[i].compare_exchange_strong(free, 1, std::memory_order_acq_rel)) {
      std::memcpy(paths[i], path.c_str(), path.size() + 1);
      states[i].store(kind, std::memory_order_release);
      return i;
    }
  }
  return -1;
}

}  // namespace

int register_in_flight(const std::string& path) { return register_slot(path, kFile); }

int register_in_flight_folder(const std::string& path) { return register_slot(path, kFolder); }

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
