// OPC UA security cost (OPC 10000-2 §4, OPC 10000-6 §6.7): secure channel + session set-up time and Read
// throughput under SignAndEncrypt relative to None, for our server next to a node-opcua server measured in
// the same run with the same client (sf::opcua::Client):
//
//   ours:       smartfactory opcua server --demo-model --security none,sign,encrypt --pki TMP/server
//   node-opcua: node tests/peers/opcua/node_server.mjs 0 --secure TMP/node
//
// Both trust the client's certificate (copied into their trusted/ folders); the client accepts
// theirs. While one server is measured the other is stopped (SIGSTOP). For None,
// Basic256Sha256 SignAndEncrypt and Aes256_Sha256_RsaPss SignAndEncrypt:
//   set-up  ms from connect() to an activated anonymous session, median and 90th percentile of
//           `--setups` (30) after 3 not counted, a new client each: a secured connection first
//           asks for the endpoints over a None channel (as node-opcua's client does), then opens
//           the channel with RSA, CreateSession (signed), ActivateSession;
//   reads   values/s of Demo.Temperature, one value per ReadRequest, `--depth` (8) requests kept
//           outstanding for `--read-seconds` (3) after a 0.5 s warm-up;
// each as ours, node-opcua and ours / node-opcua, and per server the ratio secured / None.
// A readable table on stdout (`--json`: one JSON object), progress on stderr; `--quick` is a short
// smoke run (8 set-ups, 1 s of reads). Figures in docs/performance.md.
//
//   build/release/bench/bench_opcua_security [--quick] [--json]
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "opcua_bench.hpp"
#include "sf/bench/percentile.hpp"
#include "sf/core/log.hpp"
#include "sf/opcua/security/pki.hpp"
#include "sf/opcua/security/policies.hpp"

namespace {

using namespace opcua_bench;
namespace ua = sf::opcua;
namespace sec = sf::opcua::security;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr std::string_view kClientUri = "urn:smartfactory:bench:client";

struct Options : CommonOptions {
  Options() : CommonOptions(SF_BENCH_SOURCE_DIR) {}
  std::size_t setups = 30;
  std::size_t depth = 8;
  double read_seconds = 3;
};

struct Security {
  std::string name;
  std::string policy;
  ua::MessageSecurityMode mode;
};

const std::vector<Security>& securities() {
  static const std::vector<Security> all = {
      {"None", std::string(ua::kSecurityPolicyNoneUri), ua::MessageSecurityMode::None},
      {"Basic256Sha256 SignAndEncrypt", std::string(sec::kBasic256Sha256Uri),
       ua::MessageSecurityMode::SignAndEncrypt},
      {"Aes256_Sha256_RsaPss SignAndEncrypt", std::string(sec::kAes256Sha256RsaPssUri),
       ua::MessageSecurityMode::SignAndEncrypt},
  };
  return all;
}

void progress(const std::string& text) {
  std::fprintf(stderr, "bench_opcua_security: %s\n", text.c_str());
}

ua::ClientConfig client_config(const std::string& url, const Security& security,
                               const ua::SecurityCredentials& credentials) {
  ua::ClientConfig config;
  config.endpoint_url = url;
  config.application_uri = std::string(kClientUri);
  config.session_name = "bench_opcua_security";
  config.auto_reconnect = false;
  config.request_timeout = 20s;
  config.security.policy_uri = security.policy;
  config.security.mode = security.mode;
  config.security.credentials = credentials;
  return config;
}

// Median and 90th percentile of set-up times in ms (0 when nothing connected).
struct Setup {
  double median_ms = 0;
  double p90_ms = 0;
  std::size_t failed = 0;
};

Setup measure_setup(const std::string& url, const Security& security,
                    const ua::SecurityCredentials& credentials, std::size_t count) {
  std::vector<double> ms;
  Setup out;
  constexpr std::size_t kWarmUp = 3;  // not counted: node's JIT, both servers' first sessions
  for (std::size_t i = 0; i < kWarmUp + count; ++i) {
    ua::SyncClient client(client_config(url, security, credentials));
    const auto start = std::chrono::steady_clock::now();
    auto st = client.connect();
    const double elapsed = seconds_since(start) * 1000;
    if (!st) {
      ++out.failed;
      if (out.failed == 1) {
        progress(fmt::format("{} {}: {}", url, security.name, st.error().message));
      }
      continue;
    }
    if (i >= kWarmUp) {
      ms.push_back(elapsed);
    }
    client.disconnect();
  }
  out.median_ms = sf::bench::percentile(ms, 0.5);
  out.p90_ms = sf::bench::percentile(ms, 0.9);
  return out;
}

double measure_read_rate(const ServerProcess& server, const Security& security,
                         const ua::SecurityCredentials& credentials, const Options& o) {
  ua::SyncClient client(client_config(server.url(), security, credentials));
  if (auto st = client.connect(); !st) {
    progress(fmt::format("{} {}: {}", server.name(), security.name, st.error().message));
    return 0;
  }
  auto ns = client.namespace_index("urn:smartfactory:demo");
  if (!ns) {
    return 0;
  }
  const auto item = ua::value_of(ua::NodeId(*ns, ua::String("Demo.Temperature")));
  (void)measure_reads(server, client.client(), {item}, o.depth, 0.5);  // warm-up: node's JIT, buffers
  const ReadResult r = measure_reads(server, client.client(), {item}, o.depth, o.read_seconds);
  client.disconnect();
  return r.bad == 0 ? r.values_per_s : 0;
}

struct Row {
  std::string key;
  std::string label;
  std::string unit;
  double ours = 0;
  double node = 0;
  bool ratio = true;  // ours / node-opcua makes sense (not for the secured / None rows)
  bool higher_is_better = true;
};

// The client's certificate, trusted by both servers' PKI folders.
ua::SecurityCredentials provision(const fs::path& dir) {
  sec::CertificateRequest request;
  request.application_uri = std::string(kClientUri);
  request.common_name = "smartfactory bench client";
  request.dns_names = {"localhost"};
  request.ip_addresses = {"127.0.0.1"};
  auto client = sec::PkiStore(dir / "client").ensure_own(request);
  if (!client) {
    progress("cannot make the client certificate: " + client.error().message);
    return {};
  }
  for (const char* server : {"server", "node"}) {
    if (auto added = sec::PkiStore(dir / server).add(sec::PkiStore::Folder::Trusted, client->certificate);
        !added) {
      progress("cannot trust the client certificate: " + added.error().message);
    }
  }
  return *client;
}

std::string key_of(const Security& security) {
  std::string key;
  for (const char c : security.name) {
    key += c == ' ' ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return key;
}

void print(const std::vector<Row>& rows, const std::string& node_version, const Options& o) {
  std::string load;
  std::getline(std::ifstream("/proc/loadavg") >> std::ws, load);
  const unsigned cores = std::thread::hardware_concurrency();
  if (o.json) {
    nlohmann::json out;
    out["peer"] = "node-opcua " + node_version;
    out["cores"] = cores;
    out["loadavg"] = load;
    out["quick"] = o.quick;
    out["settings"] = {{"setups", o.setups}, {"read_seconds", o.read_seconds}, {"read_outstanding", o.depth}};
    for (const auto& r : rows) {
      out["metrics"][r.key] = {
          {"unit", r.unit},
          {"ours", r.ours},
          {"node_opcua", r.node},
          {"ratio", r.ratio && r.node > 0 ? nlohmann::json(r.ours / r.node) : nlohmann::json()},
          {"higher_is_better", r.higher_is_better}};
    }
    std::printf("%s\n", out.dump(2).c_str());
    return;
  }
  std::printf("OPC UA security: ours (smartfactory opcua server) vs node-opcua %s, same run, same client\n",
              node_version.c_str());
  std::printf(
      "%u cores, load average %s; set-up: median of %zu; reads %.0f s with %zu outstanding, 1 value each\n",
      cores, load.c_str(), o.setups, o.read_seconds, o.depth);
  std::printf("%-46s %-9s %10s %12s %8s\n", "metric", "unit", "ours", "node-opcua", "ratio");
  for (const auto& r : rows) {
    const bool ratio = r.ratio && r.node > 0;
    const std::string number = r.unit == "values/s" ? "{:.0f}" : "{:.2f}";
    std::printf("%-46s %-9s %10s %12s %8s%s\n", r.label.c_str(), r.unit.c_str(),
                fmt::format(fmt::runtime(number), r.ours).c_str(),
                fmt::format(fmt::runtime(number), r.node).c_str(),
                ratio ? fmt::format("{:.2f}x", r.ours / r.node).c_str() : "-",
                ratio && !r.higher_is_better ? " (lower is better)" : "");
  }
}

bool start_servers(ServerProcess& ours, ServerProcess& node, const fs::path& dir, const Options& o) {
  const fs::path& source = o.where.source_dir;
  if (!ours.start(
          our_server_command(o.where.smartfactory, {"--security", "none,sign,encrypt", "--pki",
                                                    (dir / "server").string(), "--anonymous", "operator"}),
          source, o.verbose, 60s)) {
    progress("our server did not start");
    return false;
  }
  if (!node.start(node_server_command(source, {"--secure", (dir / "node").string()}), source, o.verbose,
                  120s)) {
    progress("the node-opcua server did not start (node on PATH? npm ci?)");
    return false;
  }
  return true;
}

// Set-up and reads for every security, each server measured while the other one is stopped.
// Rows: set-ups (and relative to None), then reads (and relative to None).
std::vector<Row> measure(ServerProcess& ours, ServerProcess& node, const ua::SecurityCredentials& credentials,
                         const Options& o, std::size_t& failures) {
  std::vector<Row> setups;
  std::vector<Row> reads;
  for (const auto& security : securities()) {
    Row setup{"setup_ms_" + key_of(security), "Set-up, " + security.name, "ms median"};
    setup.higher_is_better = false;
    Row p90{setup.key + "_p90", "  90th percentile", "ms"};
    p90.higher_is_better = false;
    Row read{"reads_per_s_" + key_of(security), "Reads, " + security.name, "values/s"};
    for (ServerProcess* server : {&ours, &node}) {
      ServerProcess& other = server == &ours ? node : ours;
      other.pause();
      progress(fmt::format("{}: {}", server->name(), security.name));
      const Setup s = measure_setup(server->url(), security, credentials, o.setups);
      const double r = measure_read_rate(*server, security, credentials, o);
      other.resume();
      failures += s.failed + (r > 0 ? 0 : 1);
      (server == &ours ? setup.ours : setup.node) = s.median_ms;
      (server == &ours ? p90.ours : p90.node) = s.p90_ms;
      (server == &ours ? read.ours : read.node) = r;
    }
    setups.insert(setups.end(), {setup, p90});
    reads.push_back(read);
    if (security.mode != ua::MessageSecurityMode::None) {
      // Relative to None (the first row) on the same server.
      const Row& none_setup = setups.front();
      const Row& none_read = reads.front();
      setups.push_back(Row{setup.key + "_vs_none", "  relative to None", "x", setup.ours / none_setup.ours,
                           setup.node / none_setup.node, false, false});
      reads.push_back(Row{read.key + "_vs_none", "  relative to None", "x", read.ours / none_read.ours,
                          read.node / none_read.node, false});
    }
  }
  setups.insert(setups.end(), reads.begin(), reads.end());
  return setups;
}

int run(const Options& o) {
  const std::string node_version = node_opcua_version(o.where.source_dir);
  char pattern[] = "/tmp/sf-bench-security-XXXXXX";
  if (::mkdtemp(pattern) == nullptr) {
    progress("cannot make a folder in /tmp");
    return 1;
  }
  const fs::path dir(pattern);
  const ua::SecurityCredentials credentials = provision(dir);
  ServerProcess ours("ours");
  ServerProcess node("node-opcua");
  std::size_t failures = 0;
  const bool started = start_servers(ours, node, dir, o);
  const std::vector<Row> rows = started ? measure(ours, node, credentials, o, failures) : std::vector<Row>{};
  const bool both_alive = ours.running() && node.running();
  ours.stop();
  node.stop();
  std::error_code ec;
  fs::remove_all(dir, ec);
  if (!started) {
    return 1;
  }
  print(rows, node_version, o);
  if (failures > 0 || !both_alive) {
    progress(fmt::format("{} failed set-ups or read runs{}", failures, both_alive ? "" : "; a server died"));
    return 1;
  }
  return 0;
}

void usage() {
  std::fprintf(stderr,
               "usage: bench_opcua_security [--quick] [--json] [--verbose] [--setups N] [--depth N]\n"
               "                            [--read-seconds S] [--smartfactory PATH] [--source-dir DIR]\n"
               "Security set-up and read cost, ours next to node-opcua (see the top of the source).\n");
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  const auto own = [&o](std::string_view a, const OptionValue& value) {
    if (a == "--setups") {
      o.setups = std::max<std::size_t>(1, std::stoul(value()));
    } else if (a == "--depth") {
      o.depth = std::max<std::size_t>(1, std::stoul(value()));
    } else if (a == "--read-seconds") {
      o.read_seconds = std::stod(value());
    } else {
      return false;
    }
    return true;
  };
  if (const auto exit_status = parse_options(argc, argv, o, usage, own)) {
    return *exit_status;
  }
  if (o.quick) {
    o.setups = std::min<std::size_t>(o.setups, 8);
    o.read_seconds = std::min(o.read_seconds, 1.0);
  }
  // Not "warn": every connection to node-opcua would log that its certificate does not name
  // 127.0.0.1 (it names the machine), which the client tolerates.
  (void)sf::log::set_level(o.verbose ? "info" : "error");
  ::signal(SIGPIPE, SIG_IGN);
  return run(o);
}
