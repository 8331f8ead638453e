#pragma once
// One exception type for every user-facing failure: the CLI prints what() as one line and exits 1,
// as it does for a bad command line. Commands whose run can end with a partial result give it its
// own status, documented in their --help: `splatcl batch` and `batch merge` exit 2 when the run
// completed but some models failed; `splatcl bench compare` exits 1 when a record regressed.
#include <stdexcept>
#include <string>

namespace splatcl {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace splatcl
