#pragma once
// Progress of long work. On a terminal: one rewritten stderr line. Otherwise (a job log, a pipe):
// a plain line at most every kLogIntervalSeconds (SPLATCL_PROGRESS_SECONDS overrides), the first
// only once the work has run that long, so short commands log nothing and long ones show movement
// (a CSM build of a large scan was silent for minutes in a cluster job's log).
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "runtime/error.hpp"

namespace splatcl::cli {

inline constexpr double kLogIntervalSeconds = 30;
inline constexpr const char* kLogIntervalVariable = "SPLATCL_PROGRESS_SECONDS";

// The interval between log lines: $SPLATCL_PROGRESS_SECONDS (0 or more, finite), else the default.
// A bad value is an error (main checks it before any work), not silently the default.
inline double log_interval_seconds() {
  const char* given = std::getenv(kLogIntervalVariable);
  if (!given || !*given) return kLogIntervalSeconds;
  char* end = nullptr;
  const double seconds = std::strtod(given, &end);
  if (end == given || *end != '\0' || !(seconds >= 0) || !std::isfinite(seconds))
    throw Error(std::string(kLogIntervalVariable) + " '" + given + "' is not a number of seconds, 0 or more");
  return seconds;
}

class ProgressLine {
 public:
  explicit ProgressLine(std::string prefix)
      : prefix_(std::move(prefix)), terminal_(isatty(fileno(stderr)) != 0), interval_(log_interval_seconds()), last_(Clock::now()) {}
  ~ProgressLine() { clear(); }
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  void show(const std::string& text) {
    if (!terminal_) {
      const auto now = Clock::now();
      if (std::chrono::duration<double>(now - last_).count() < interval_) return;
      last_ = now;
      std::fprintf(stderr, "%s: %s\n", prefix_.c_str(), text.c_str());
      std::fflush(stderr);
      return;
    }
    std::fprintf(stderr, "\r\033[K%s: %s", prefix_.c_str(), text.c_str());
    std::fflush(stderr);
    shown_ = true;
  }
  void clear() {
    if (terminal_ && shown_) std::fprintf(stderr, "\r\033[K");
    shown_ = false;
  }

 private:
  using Clock = std::chrono::steady_clock;
  std::string prefix_;
  bool terminal_ = false, shown_ = false;
  double interval_ = kLogIntervalSeconds;
  Clock::time_point last_;
};

}  // namespace splatcl::cli
