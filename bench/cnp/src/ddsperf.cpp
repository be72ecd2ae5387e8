// ddsperf, Cyclone's own benchmark, as the peer of the Contract Net benchmark: its ping/pong round
// trip at the negotiation's fan-out, read from ping's output (FanOutRoundTrip).
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <regex>
#include <span>

#include <fmt/format.h>

#include "processes.hpp"
#include "sf/bench/cnp.hpp"
#include "sf/bench/percentile.hpp"
#include "sf/dds/config.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;
using detail::cpu_time_of;
using detail::microseconds;

constexpr dds::DomainId kDdsperfDomain = 231;

std::string temp_path(std::string_view tag) {
  return fmt::format("/tmp/sf-cnp-bench-{}-{}.log", ::getpid(), tag);
}

}  // namespace

// ddsperf at the negotiation's fan-out: one pong process per contractor. "ping" sends the next
// ping once every pong has answered, so one cycle is a round trip to all of them, as an
// ANNOUNCE/BID exchange is (FanOutRoundTrip: what ping prints and how it is read).
Result<DdsperfResult> run_ddsperf(const BenchOptions& options) {
  auto xml = dds::cyclone_config_xml(options.dds.network);
  if (!xml) {
    return xml.error();
  }
  const std::vector<std::string> env{"CYCLONEDDS_URI=" + *xml};
  const auto secs = options.ddsperf_duration.count();
  const auto domain = std::to_string(kDdsperfDomain);
  const std::size_t pongs = std::max<std::size_t>(1, options.contractors);
  std::vector<Process> pong_processes;
  for (std::size_t i = 0; i < pongs; ++i) {
    auto pong = detail::spawn_logged({options.ddsperf_binary, "-i", domain, "-D",
                                      std::to_string(secs + 40 + static_cast<long>(pongs)), "pong"},
                                     env, "/dev/null", options.contractor_scheduling);
    if (!pong) {
      return pong.error();
    }
    pong_processes.push_back(std::move(*pong));
  }
  const auto out = temp_path("ddsperf");
  // ping starts once it sees every pong's participant; many take a while to be discovered on a
  // busy host.
  const auto initwait = 20 + static_cast<long>(pongs);
  auto ping = detail::spawn_logged(
      {options.ddsperf_binary, "-i", domain, "-D", std::to_string(secs), "-Q",
       fmt::format("minmatch:{}", pongs), "-Q", fmt::format("initwait:{}", initwait), "ping"},
      env, out);
  if (!ping) {
    return ping.error();
  }
  std::vector<pid_t> pong_pids;
  for (const auto& pong : pong_processes) {
    pong_pids.push_back(pong.pid());
  }
  const auto pongs_cpu0 = cpu_time_of(pong_pids);
  const auto ping_status = ping->wait(std::chrono::seconds{secs + initwait + 10});
  const auto pongs_cpu1 = cpu_time_of(pong_pids);
  for (auto& pong : pong_processes) {
    pong.terminate(5s);
  }
  auto stats = parse_ddsperf_output(out);
  std::remove(out.c_str());
  if (!stats) {
    return Error{Errc::not_found, fmt::format("{} printed no round-trip statistics", options.ddsperf_binary)};
  }
  DdsperfResult result{*stats, std::nullopt};
  // The CPU time includes discovery and ping's initial wait, a small share of a run of seconds.
  const auto round_trips = static_cast<double>(stats->pings);
  if (pongs_cpu0 && pongs_cpu1 && ping_status && round_trips > 0) {
    result.cpu_us_per_round_trip =
        microseconds(*pongs_cpu1 - *pongs_cpu0 + ping_status->cpu_time) / round_trips;
  }
  return result;
}

std::optional<FanOutRoundTrip> parse_ddsperf_output(const std::string& path) {
  // "[pid] 2.000  host:pid size 12 mean 6.9us min 3.7us 50% 4.0us 90% 4.2us 99% 4.5us max 2743us cnt 71926"
  const std::regex line{R"(\] ([0-9.]+) .* mean [0-9.]+us min [0-9.]+us 50% ([0-9.]+)us .* cnt ([0-9]+))"};
  struct Report {
    double slowest_median = 0;  // half round trip, as printed
    double fewest = 0;          // the fewest answers of one pong: the pings all answered
    std::size_t pongs = 0;
  };
  std::map<double, Report> reports;  // by report time
  std::ifstream in{path};
  std::string text;
  while (std::getline(in, text)) {
    std::smatch m;
    if (!std::regex_search(text, m, line)) {
      continue;
    }
    const double answers = std::stod(m[3]);
    auto [it, first] = reports.try_emplace(std::stod(m[1]));
    Report& r = it->second;
    r.slowest_median = std::max(r.slowest_median, std::stod(m[2]));
    r.fewest = first ? answers : std::min(r.fewest, answers);
    ++r.pongs;
  }
  if (reports.empty()) {
    return std::nullopt;
  }
  std::size_t pongs = 0;
  for (const auto& [time, r] : reports) {
    pongs = std::max(pongs, r.pongs);
  }
  // A report without a line for some pong: that pong answered nothing, so no ping completed.
  const auto pings = [&](const Report& r) { return r.pongs == pongs ? r.fewest : 0.0; };
  std::vector<double> medians;
  double all_pings = 0;
  for (const auto& [time, r] : reports) {
    medians.push_back(2 * r.slowest_median);
    all_pings += pings(r);
  }
  std::sort(medians.begin(), medians.end());
  FanOutRoundTrip rt;
  rt.p50_us = bench::percentile_of_sorted(std::span<const double>(medians), 0.5);
  rt.pings = static_cast<std::size_t>(all_pings);
  // The first report's interval starts before the pings do: the cycle counts the others.
  const double cycles = all_pings - pings(reports.begin()->second);
  const double span_s = std::prev(reports.end())->first - reports.begin()->first;
  if (cycles > 0) {
    rt.mean_us = span_s * 1e6 / cycles;
  }
  return rt;
}

}  // namespace sf::negotiation
