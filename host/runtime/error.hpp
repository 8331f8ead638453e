#pragma once
// One exception type for every user-facing failure: the CLI prints what() as one line and exits 1.
#include <stdexcept>
#include <string>

namespace splatcl {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace splatcl
