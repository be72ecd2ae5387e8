#include "processes.hpp"

#include <dirent.h>

#include <cstdint>
#include <fstream>

#include <fmt/format.h>

namespace sf::negotiation {
namespace detail {

Result<Process> spawn_logged(std::vector<std::string> args, std::vector<std::string> env,
                             const std::string& output, SchedulingPolicy policy) {
  ProcessOptions o;
  o.argv = std::move(args);
  o.env = std::move(env);
  o.out = Stdio::file(output);
  o.err = Stdio::to_stdout();
  o.scheduling = policy;
  return Process::spawn(std::move(o));
}

std::optional<std::chrono::nanoseconds> cpu_time_of(const std::vector<pid_t>& pids) {
  std::chrono::nanoseconds total{0};
  for (const pid_t pid : pids) {
    const auto t = process_cpu_time(pid);
    if (!t) {
      return std::nullopt;
    }
    total += *t;
  }
  return total;
}

}  // namespace detail

std::optional<std::chrono::nanoseconds> process_cpu_time(int pid) {
  const std::string dir = fmt::format("/proc/{}/task", pid);
  DIR* tasks = ::opendir(dir.c_str());
  if (tasks == nullptr) {
    return std::nullopt;
  }
  std::int64_t total = 0;
  bool any = false;
  while (const dirent* e = ::readdir(tasks)) {
    if (e->d_name[0] == '.') {
      continue;
    }
    std::ifstream stat{fmt::format("{}/{}/schedstat", dir, e->d_name)};
    std::int64_t on_cpu = 0;  // the first field: time spent on a CPU, in nanoseconds
    if (stat >> on_cpu) {
      total += on_cpu;
      any = true;
    }
  }
  ::closedir(tasks);
  if (!any) {
    return std::nullopt;
  }
  return std::chrono::nanoseconds{total};
}

}  // namespace sf::negotiation
