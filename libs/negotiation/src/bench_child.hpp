// A process `cnp bench` starts: a contractor (`smartfactory agent machine`) or a ddsperf pong or
// ping. Stopped (TERM, then KILL) when destroyed.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/negotiation/bench.hpp"

namespace sf::negotiation::detail {

class BenchChild {
 public:
  // Runs `args` (argv[0] looked up in PATH) with `extra_env` added to this process's environment,
  // stdout and stderr to `output`, under the scheduling policy `policy` (its threads inherit it).
  static Result<BenchChild> spawn(const std::vector<std::string>& args,
                                  const std::vector<std::string>& extra_env, const std::string& output,
                                  SchedulingPolicy policy = SchedulingPolicy::normal);

  BenchChild(BenchChild&& o) noexcept;
  BenchChild& operator=(BenchChild&&) = delete;
  BenchChild(const BenchChild&) = delete;
  BenchChild& operator=(const BenchChild&) = delete;
  ~BenchChild() { stop(); }

  // Waits for the process to exit by itself (up to `bound`); true if it did.
  bool wait(std::chrono::nanoseconds bound);
  void stop();

  [[nodiscard]] pid_t pid() const { return pid_; }
  // The CPU time of a process that exited in wait().
  [[nodiscard]] std::optional<std::chrono::nanoseconds> cpu_at_exit() const { return cpu_at_exit_; }

 private:
  explicit BenchChild(pid_t pid) : pid_(pid) {}
  pid_t pid_;
  std::optional<std::chrono::nanoseconds> cpu_at_exit_;
};

}  // namespace sf::negotiation::detail
