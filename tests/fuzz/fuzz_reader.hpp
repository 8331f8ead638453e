#pragma once
// What every reader harness checks on every input: the reader either returns, or refuses with a
// splatcl::Error whose message is one line naming the file (the CLI prints it as `splatcl: WHAT`).
// Anything else — another exception type (a library's bare message), a message on several lines or
// without the file's name, a crash, a sanitizer report, an allocation beyond libFuzzer's limit —
// aborts, which libFuzzer (and the replay driver) report as a finding.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>

#include "runtime/error.hpp"

namespace splatcl::fuzz {

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

// Inputs read and refused so far in this process (the replay driver prints them, so a test sees
// that its valid seeds still read).
inline std::size_t inputs_read = 0, inputs_refused = 0;

// Runs read(bytes) and applies the checks above; `name` is the file name the reader was given
// (empty: the reader's errors need not name it, because its caller adds the name).
template <class Read>
void check_reader(const std::uint8_t* data, std::size_t size, const std::string& name, Read&& read) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    read(bytes);
    ++inputs_read;
  } catch (const Error& e) {
    ++inputs_refused;
    const std::string_view message = e.what();
    if (message.empty() || message.find('\n') != std::string_view::npos) finding("the error is not one line: '" + std::string(message) + "'");
    if (!name.empty() && message.find(name) == std::string_view::npos)
      finding("the error does not name the file " + name + ": '" + std::string(message) + "'");
  } catch (const std::exception& e) {
    finding(std::string("an exception other than splatcl::Error: ") + e.what());
  }
}

// check_reader on the input as it is, then on reseal(input): the input with its checksum recomputed,
// so that mutations reach the checks behind a checksum.
template <class Read, class Reseal>
void check_reader_and_resealed(const std::uint8_t* data, std::size_t size, const std::string& name, Read&& read, Reseal&& reseal) {
  check_reader(data, size, name, read);
  const std::string sealed = reseal(std::string(reinterpret_cast<const char*>(data), size));
  check_reader(reinterpret_cast<const std::uint8_t*>(sealed.data()), sealed.size(), name, read);
}

}  // namespace splatcl::fuzz
