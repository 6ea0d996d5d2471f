// The system calls the V4L2 camera makes, behind an interface so that tests can stand in for a
// driver (no camera, vivid or root is needed to test the streaming logic).
#pragma once

#include <poll.h>
#include <sys/stat.h>
#include <sys/types.h>

#include <cstddef>

namespace ale::linux_hal {

// Each call returns what the system call returns; on failure errno says why.
class V4l2Io {
 public:
  virtual ~V4l2Io() = default;
  virtual int open(const char* path, int flags) = 0;
  virtual int close(int fd) = 0;
  virtual int fstat(int fd, struct stat* st) = 0;
  virtual int ioctl(int fd, unsigned long request, void* arg) = 0;
  // MAP_FAILED on failure.
  virtual void* mmap(std::size_t length, int fd, off_t offset) = 0;
  virtual int munmap(void* addr, std::size_t length) = 0;
  virtual int poll(pollfd* fds, nfds_t count, int timeout_ms) = 0;
};

// The real system calls; ioctl() retries on EINTR.
V4l2Io& system_v4l2_io();

}  // namespace ale::linux_hal
