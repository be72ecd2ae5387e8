// Small POSIX pieces of the server: an owned file descriptor and socket options.
#pragma once

#include <unistd.h>

#include <string>
#include <utility>

namespace sf::modbus::detail {

class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(UniqueFd&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  UniqueFd& operator=(UniqueFd&& other) noexcept {
    if (this != &other) {
      reset(std::exchange(other.fd_, -1));
    }
    return *this;
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd() { reset(); }

  [[nodiscard]] int get() const { return fd_; }
  [[nodiscard]] bool valid() const { return fd_ >= 0; }
  void reset(int fd = -1) {
    if (fd_ >= 0) {
      ::close(fd_);
    }
    fd_ = fd;
  }

 private:
  int fd_ = -1;
};

// O_NONBLOCK; false (errno set) on failure.
bool set_non_blocking(int fd);
// TCP_NODELAY: a response leaves at once instead of waiting for the peer's ACK (Nagle).
void set_no_delay(int fd);
// The local port a socket is bound to (0 when unknown).
unsigned local_port(int fd);
// "strerror (errno N)".
std::string errno_text(int err);

}  // namespace sf::modbus::detail
