// The processes of the Contract Net benchmark (contractors, ddsperf) and what they cost.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "sf/bench/cnp.hpp"
#include "sf/core/process.hpp"

namespace sf::negotiation::detail {

// `args` with `env` added to the environment, stdout and stderr to `output`, under `policy`.
Result<Process> spawn_logged(std::vector<std::string> args, std::vector<std::string> env,
                             const std::string& output, SchedulingPolicy policy = SchedulingPolicy::inherit);

// The CPU time of all `pids` (process_cpu_time); nullopt if one cannot be read.
std::optional<std::chrono::nanoseconds> cpu_time_of(const std::vector<pid_t>& pids);

inline double microseconds(std::chrono::nanoseconds t) {
  return std::chrono::duration<double, std::micro>(t).count();
}

}  // namespace sf::negotiation::detail
