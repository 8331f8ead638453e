#pragma once
// Progress of long work on one rewritten stderr line, shown only when stderr is a terminal, so
// piped or logged output stays clean.
#include <unistd.h>

#include <cstdio>
#include <string>

namespace splatcl::cli {

class ProgressLine {
 public:
  explicit ProgressLine(std::string prefix) : prefix_(std::move(prefix)), enabled_(isatty(fileno(stderr)) != 0) {}
  ~ProgressLine() { clear(); }
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  void show(const std::string& text) {
    if (!enabled_) return;
    std::fprintf(stderr, "\r\033[K%s: %s", prefix_.c_str(), text.c_str());
    std::fflush(stderr);
    shown_ = true;
  }
  void clear() {
    if (enabled_ && shown_) std::fprintf(stderr, "\r\033[K");
    shown_ = false;
  }

 private:
  std::string prefix_;
  bool enabled_ = false, shown_ = false;
};

}  // namespace splatcl::cli
