// HostNetworks (line_hosts.hpp): the plan's `ip` commands run, and everything removed again.
#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <sstream>
#include <string_view>
#include <system_error>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "sf/core/log.hpp"
#include "sf/core/process.hpp"
#include "sf/factory/line_hosts.hpp"

namespace sf::factory {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

// Where `ip netns add` keeps the names (iproute2's NETNS_RUN_DIR).
constexpr std::string_view kNetnsDir = "/run/netns";

std::string trimmed(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) {
    text.pop_back();
  }
  return text;
}

// Runs a command to its end; its output, or an error naming it and quoting what it said.
Result<std::string> run_command(const Command& command) {
  ProcessOptions o;
  o.argv = command;
  o.in = Stdio::null();
  o.out = Stdio::pipe();
  o.err = Stdio::to_stdout();
  auto done = Process::run(std::move(o), 30s);
  if (!done) {
    return Error(done.error()).with_context(fmt::format("`{}`", fmt::join(command, " ")));
  }
  if (!done->status.success()) {
    return make_error(Errc::io, fmt::format("`{}` failed ({}): {}", fmt::join(command, " "),
                                            done->status.describe(), trimmed(done->out)));
  }
  return done->out;
}

// Ends what still runs in a namespace of a crashed run (its processes would hold the namespace
// and its interfaces), then deletes the name.
Status remove_leftover(const std::string& netns) {
  auto pids = run_command({"ip", "netns", "pids", netns});
  if (pids) {
    std::istringstream in(*pids);
    for (pid_t pid = 0; in >> pid;) {
      if (pid > 1 && pid != ::getpid()) {
        ::kill(pid, SIGKILL);
      }
    }
  }
  auto deleted = run_command({"ip", "netns", "del", netns});
  return deleted ? Status{} : Status(deleted.error());
}

}  // namespace

Status hosts_supported() {
  if (::geteuid() != 0) {
    return make_error(Errc::unsupported,
                      "--hosts needs root: it makes network namespaces, veth pairs and bridges");
  }
  for (const char* program : {"ip", "sysctl"}) {
    if (!find_program(program)) {
      return make_error(Errc::unsupported,
                        fmt::format("--hosts needs `{}` on the PATH (iproute2, procps)", program));
    }
  }
  return {};
}

Status with_netns(const std::string& netns, const std::function<void()>& fn) {
  const std::string target_path = (fs::path(kNetnsDir) / netns).string();
  const int target = ::open(target_path.c_str(), O_RDONLY | O_CLOEXEC);
  if (target < 0) {
    return make_error(Errc::not_found,
                      fmt::format("network namespace {}: {}", netns, std::generic_category().message(errno)));
  }
  const int own = ::open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC);
  Status st;
  if (own < 0 || ::setns(target, CLONE_NEWNET) != 0) {
    st = make_error(Errc::io, fmt::format("entering the network namespace {}: {}", netns,
                                          std::generic_category().message(errno)));
  } else {
    fn();
    if (::setns(own, CLONE_NEWNET) != 0) {
      st = make_error(Errc::io, fmt::format("leaving the network namespace {}: {}", netns,
                                            std::generic_category().message(errno)));
    }
  }
  ::close(target);
  if (own >= 0) {
    ::close(own);
  }
  return st;
}

std::vector<std::string> existing_namespaces(const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const auto& n : names) {
    std::error_code ec;
    if (fs::exists(fs::path(kNetnsDir) / n, ec)) {
      out.push_back(n);
    }
  }
  return out;
}

Result<std::unique_ptr<HostNetworks>> HostNetworks::create(HostPlan plan, std::vector<std::string>* removed) {
  std::unique_ptr<HostNetworks> h(new HostNetworks(std::move(plan)));
  for (const auto& ns : existing_namespaces(h->plan_.namespaces())) {
    if (auto st = remove_leftover(ns); !st) {
      return Error(st.error()).with_context("removing a namespace an earlier run left");
    }
    if (removed != nullptr) {
      removed->push_back(ns);
    }
  }
  h->made_ = true;
  for (const auto& command : host_setup_commands(h->plan_)) {
    if (auto done = run_command(command); !done) {
      (void)h->remove();
      return done.error();
    }
  }
  return h;
}

HostNetworks::~HostNetworks() {
  if (auto st = remove(); !st) {
    sf::log::get("factory")->error("{}", st.error().message);
  }
}

Status HostNetworks::remove() {
  if (!made_) {
    return {};
  }
  made_ = false;
  Status first;
  for (const auto& command : host_teardown_commands(plan_)) {
    if (existing_namespaces({command.back()}).empty()) {
      continue;  // never made, or gone already
    }
    if (auto done = run_command(command); !done && first) {
      first = done.error();
    }
  }
  return first;
}

}  // namespace sf::factory
