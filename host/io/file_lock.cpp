#include "io/file_lock.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "io/checksum.hpp"
#include "runtime/error.hpp"

namespace splatcl {
namespace {

// The byte standing for `key`: 62 bits of its FNV-1a checksum, far beyond any file size, so keys
// do not collide in practice and the lock file stays empty.
off_t key_offset(const std::string& key) { return static_cast<off_t>(fnv1a64(key) >> 2); }

}  // namespace

KeyLocks::KeyLocks(const std::string& path) : path_(path) {
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw Error("cannot open lock file " + path + ": " + std::strerror(errno));
}

KeyLocks::~KeyLocks() {
  if (fd_ >= 0) ::close(fd_);  // closing the descriptor releases this process's locks on the file
}

pid_t KeyLocks::try_lock(const std::string& key) {
  struct flock lock {};
  lock.l_type = F_WRLCK;
  lock.l_whence = SEEK_SET;
  lock.l_start = key_offset(key);
  lock.l_len = 1;
  if (::fcntl(fd_, F_SETLK, &lock) == 0) return 0;
  if (errno != EACCES && errno != EAGAIN) throw Error("cannot lock " + path_ + ": " + std::strerror(errno));
  struct flock holder = lock;
  if (::fcntl(fd_, F_GETLK, &holder) == 0 && holder.l_type != F_UNLCK && holder.l_pid > 0) return holder.l_pid;
  return -1;
}

}  // namespace splatcl
