#pragma once
// Advisory locks between processes (POSIX record locks, which NFS also honours): one lock file
// holds a lock per key, each on its own byte, so a run can hold thousands with one descriptor.
// The kernel drops a process's locks when it ends, however it ends (SIGKILL included): a lock is
// never stale.
#include <sys/types.h>

#include <string>

namespace splatcl {

class KeyLocks {
 public:
  // Opens (creating it if needed) the lock file `path`. Throws Error naming it.
  explicit KeyLocks(const std::string& path);
  KeyLocks(const KeyLocks&) = delete;
  KeyLocks& operator=(const KeyLocks&) = delete;
  ~KeyLocks();  // releases every lock this object took

  // Takes the lock of `key` without waiting. Returns 0 when taken (or already held by this
  // process), otherwise the pid of the process holding it (-1 when the system does not say).
  pid_t try_lock(const std::string& key);

  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace splatcl
