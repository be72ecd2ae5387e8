#include "agent_common.hpp"

#include <sys/prctl.h>
#include <unistd.h>

#include <csignal>
#include <iostream>

#include <fmt/format.h>

#include "sf/core/clock.hpp"
#include "sf/dds/introspection.hpp"

namespace sf::app::agents {

void add_dds_options(CLI::App& cmd, DdsCliOptions& o) {
  cmd.add_option("--machining-domain", o.machining_domain, "DDS domain id of the MachiningDomain")
      ->check(CLI::Range(0U, 232U))
      ->capture_default_str();
  cmd.add_option("--conveying-domain", o.conveying_domain, "DDS domain id of the ConveyingDomain")
      ->check(CLI::Range(0U, 232U))
      ->capture_default_str();
  cmd.add_option("--partition", o.partition,
                 "DDS partition: only agents in the same partition negotiate (one per plant or test run)")
      ->capture_default_str();
  cmd.add_option("--interface", o.interface,
                 "Network interface: 'lo' = loopback only (unicast discovery, no multicast), "
                 "otherwise a NIC name or address with multicast discovery")
      ->capture_default_str();
  cmd.add_option("--lease-ms", o.lease_ms,
                 "Liveliness lease of a machine's BID writers: a machine silent this long is presumed dead")
      ->check(CLI::Range(50U, 600'000U))
      ->capture_default_str();
  cmd.add_option("--spin-us", o.spin_us,
                 "Poll for incoming messages this long before sleeping: lower latency for more CPU")
      ->capture_default_str();
  cmd.add_option("--delivery", o.delivery,
                 "Where messages are handled: 'inline' on the DDS thread that received them (one thread "
                 "wake-up less per message), 'queued' on the agent's own thread")
      ->check(CLI::IsMember({"inline", "queued"}))
      ->capture_default_str();
  cmd.add_flag("--exit-with-parent", o.exit_with_parent,
               "Stop (as on SIGTERM) when the process that started this one dies, e.g. a benchmark "
               "killed before it could stop its agents");
  cmd.add_flag("--json", o.json, "Print events (or the result) as JSON on stdout");
}

void add_layout_option(CLI::App& cmd, DdsCliOptions& o) {
  cmd.add_flag("--layout", o.layout,
               "Print this agent's DDS entity layout (readers, writers, topics) at start");
}

cnp::DdsSettings dds_settings(const DdsCliOptions& o) {
  return cnp::dds_settings(o.machining_domain, o.conveying_domain, o.partition, o.interface,
                           std::chrono::milliseconds{o.lease_ms});
}

void emit(json event) {
  event["t"] = std::chrono::duration_cast<std::chrono::nanoseconds>(
                   SteadyClock::instance().utc_now().time_since_epoch())
                   .count();
  std::cout << event.dump() << '\n' << std::flush;
}

void say(const std::string& line) {
  std::cout << line << '\n' << std::flush;
}

void print_layout(const std::vector<const dds::Participant*>& participants, bool as_json) {
  json all = json::array();
  for (const auto* p : participants) {
    auto layout = dds::inspect(*p);
    if (!layout) {
      std::cerr << "layout: " << layout.error().describe() << "\n";
      continue;
    }
    all.push_back(json::parse(dds::to_json(*layout)));
  }
  if (as_json) {
    emit(json{{"event", "layout"}, {"participants", all}});
    return;
  }
  for (const auto& p : all) {
    say(fmt::format("layout {} (domain {}): {} readers, {} writers", p["participant"].get<std::string>(),
                    p["domain"].get<unsigned>(), p["readers"].size(), p["writers"].size()));
  }
}

void exit_with_parent(const DdsCliOptions& o) {
  if (o.exit_with_parent) {
    const pid_t parent = getppid();
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) {  // died in between
      raise(SIGTERM);
    }
  }
}

cnp::RunOptions run_options(const DdsCliOptions& o) {
  return cnp::RunOptions{o.delivery == "inline"};
}

int run_until_stopped(dds::Executor& ex, cnp::Agent& agent, const DdsCliOptions& o) {
  install_stop_signals();
  cnp::run_agents(
      ex, SteadyClock::instance(), {&agent}, [] { return stop_requested(); }, run_options(o));
  return kExitOk;
}

}  // namespace sf::app::agents
