// `smartfactory cloud --config cloud.yaml`: the cloud gateway (paper §V.B, Fig. 6) — an OPC UA
// client of every shop-floor server writing to the historian, with an aggregating OPC UA server
// for history — and the dashboard's web server on top of it (libs/dashboard). Runs until
// signalled and shows a status line; the cloud and dashboard modules do the work.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <thread>

#include <fmt/format.h>

#include "commands.hpp"
#include "opcua_security.hpp"
#include "sf/cloud/config.hpp"
#include "sf/cloud/gateway.hpp"
#include "sf/line/layout.hpp"
#ifdef SF_HAVE_DASHBOARD
#include "sf/dashboard/dashboard.hpp"
#endif

namespace sf::app {
namespace {

using namespace std::chrono_literals;

struct CloudOptions {
  std::string config;
  double status_interval_s = 5;
  double duration_s = 0;
  int aggregating_port = -1;  // -1: as the config says
  int http_port = 8080;       // -1: no web server
  std::string http_host = "127.0.0.1";
  std::string web_users;  // empty: the aggregating server's users file
  std::string web_root = SF_WEB_ROOT;
  std::filesystem::path tls_cert;  // both set: HTTPS and WSS only
  std::filesystem::path tls_key;
};

#ifdef SF_HAVE_DASHBOARD
// The dashboard on the gateway (its layout: the knowledge loop's, else the built-in one); null
// when it is off or cannot start (said on stderr).
Result<std::unique_ptr<dashboard::Dashboard>> start_dashboard(const CloudOptions& o, cloud::Gateway& gateway,
                                                              const line::Layout& layout,
                                                              const std::string& users) {
  if (o.http_port < 0) {
    return std::unique_ptr<dashboard::Dashboard>{};
  }
  if (users.empty()) {
    std::fprintf(stderr,
                 "cloud: web dashboard off: no users file (--web-users FILE, or aggregating_server.users)\n");
    return std::unique_ptr<dashboard::Dashboard>{};
  }
  dashboard::DashboardConfig c;
  c.http.host = o.http_host;
  c.http.port = static_cast<std::uint16_t>(o.http_port);
  c.http.threads = 2;
  c.http.static_root = o.web_root;
  if (!o.tls_cert.empty()) {
    c.http.tls = web::TlsConfig{o.tls_cert, o.tls_key};
  }
  c.users = users;
  auto d = dashboard::Dashboard::create(gateway, layout, std::move(c));
  if (!d) {
    return d.error();
  }
  auto port = (*d)->start();
  if (!port) {
    return Error(port.error()).with_context(fmt::format("web server on {}:{}", o.http_host, o.http_port));
  }
  std::printf("dashboard on %s://%s:%u/\n", o.tls_cert.empty() ? "http" : "https", o.http_host.c_str(),
              *port);
  return d;
}
#endif

std::string status_line(const cloud::GatewayStatus& s, double samples_per_s) {
  std::size_t connected = 0;
  std::size_t series = 0;
  for (const auto& server : s.servers) {
    connected += server.connected ? 1 : 0;
    series += server.series;
  }
  return fmt::format(
      "cloud: {}/{} servers connected, {} series, {:.0f} samples/s, {} written ({} failed), "
      "{} queued, {} buffered, database {}",
      connected, s.servers.size(), series, samples_per_s, s.samples_written, s.samples_failed, s.queued,
      s.buffer.buffered_records, s.buffer.database_up ? "up" : "away");
}

void print_problems(const cloud::GatewayStatus& s) {
  if (s.discovery && !s.discovery->last_error.empty()) {
    std::fprintf(stderr, "cloud: discovery %s: %s\n", s.discovery->url.c_str(),
                 s.discovery->last_error.c_str());
  }
  for (const auto& server : s.servers) {
    if (!server.connected && !server.last_error.empty()) {
      std::fprintf(stderr, "cloud: %s (%s): %s: %s\n", server.name.c_str(), server.url.c_str(),
                   server.phase.c_str(), server.last_error.c_str());
    }
  }
}

// Security as the opcua commands apply it (opcua_security.hpp): one PKI folder for the gateway's
// client certificate, the servers it trusts and the aggregating server's certificate.
cloud::GatewayOptions security_hooks(const std::string& pki) {
  const std::string folder = pki.empty() ? opcua::security::default_pki_dir() : pki;
  cloud::GatewayOptions options;
  options.configure_client = [folder](const cloud::ServerConfig& server, opcua::ClientConfig& client) {
    ClientSecurityOptions o;
    o.pki = folder;
    o.security = server.security.security;
    o.user = server.security.user;
    o.password_file = server.security.password_file;
    o.user_certificate = server.security.user_certificate;
    o.user_key = server.security.user_key;
    return apply_client_security(o, client);
  };
  options.configure_aggregating_server = [folder](const cloud::AggregatingServerConfig& aggregating,
                                                  opcua::server::ServerConfig& server) -> Status {
    ServerSecurityOptions o;
    o.pki = folder;
    o.modes = aggregating.security;
    if (!aggregating.policies.empty()) {
      o.policies = aggregating.policies;
    }
    o.users = aggregating.users;
    o.anonymous = aggregating.anonymous;
    auto applied = apply_server_security(o, false, server);
    if (!applied) {
      return applied.error();
    }
    std::fprintf(stderr, "cloud: aggregating server %s\n", applied->c_str());
    return {};
  };
  return options;
}

int run_cloud(const CloudOptions& o) {
  auto config = cloud::load_gateway_config(o.config);
  if (!config) {
    std::cerr << "cloud: " << config.error().message << "\n";
    return kExitUsage;
  }
  if (o.aggregating_port >= 0) {
    config->aggregating_server.enabled = true;
    config->aggregating_server.port = static_cast<std::uint16_t>(o.aggregating_port);
  }
  const std::string pki = config->pki;
  const std::string users = o.web_users.empty() ? config->aggregating_server.users : o.web_users;
  auto layout = config->knowledge && !config->knowledge->layout.empty()
                    ? line::load_layout(config->knowledge->layout)
                    : line::default_layout();
  if (!layout) {
    std::cerr << "cloud: layout: " << layout.error().describe() << "\n";
    return kExitUsage;
  }
  auto gateway = cloud::Gateway::create(std::move(*config), security_hooks(pki));
  if (!gateway) {
    std::cerr << "cloud: " << gateway.error().describe() << "\n";
    return kExitFailure;
  }
  if (auto st = (*gateway)->start(); !st) {
    std::cerr << "cloud: " << st.error().describe() << "\n";
    return kExitFailure;
  }
  install_stop_signals();
  // The first stdout line says where the aggregating server listens (scripts wait for it).
  const auto first = (*gateway)->status();
  if (first.aggregating_port != 0) {
    std::printf("aggregating server on port %u\n", first.aggregating_port);
  } else {
    std::printf("gateway running\n");
  }
#ifdef SF_HAVE_DASHBOARD
  auto web = start_dashboard(o, **gateway, *layout, users);
  if (!web) {
    std::cerr << "cloud: " << web.error().describe() << "\n";
    (*gateway)->stop();
    return kExitFailure;
  }
#endif
  std::fflush(stdout);
  const auto start = std::chrono::steady_clock::now();
  auto last = start;
  std::uint64_t last_received = 0;
  while (!stop_requested()) {
    std::this_thread::sleep_for(50ms);
    const auto now = std::chrono::steady_clock::now();
    if (o.duration_s > 0 && now - start >= std::chrono::duration<double>(o.duration_s)) {
      break;
    }
    if (o.status_interval_s > 0 && now - last >= std::chrono::duration<double>(o.status_interval_s)) {
      const auto s = (*gateway)->status();
      const double seconds = std::chrono::duration<double>(now - last).count();
      std::string line = status_line(s, static_cast<double>(s.samples_received - last_received) / seconds);
      if (const auto* knowledge = (*gateway)->knowledge(); knowledge != nullptr) {
        const auto k = knowledge->status();
        line += fmt::format(", knowledge: {} alarms, {} boxes, {} triples", k.active_alarms, k.inspections,
                            k.triples);
      }
      std::fprintf(stderr, "%s\n", line.c_str());
      print_problems(s);
      last_received = s.samples_received;
      last = now;
    }
  }
#ifdef SF_HAVE_DASHBOARD
  if (*web) {
    (*web)->stop();
  }
#endif
  (*gateway)->stop();
  const auto s = (*gateway)->status();
  std::fprintf(stderr, "cloud: stopped; %llu samples received, %llu written, %llu buffered records left\n",
               static_cast<unsigned long long>(s.samples_received),
               static_cast<unsigned long long>(s.samples_written),
               static_cast<unsigned long long>(s.buffer.buffered_records));
  return kExitOk;
}

}  // namespace

void register_cloud(CLI::App& app, CommandResult& result) {
  auto o = std::make_shared<CloudOptions>();
  auto* cmd = app.add_subcommand("cloud",
                                 "Cloud gateway: OPC UA client of the shop-floor servers → historian "
                                 "(SQLite/PostgreSQL, store-and-forward), "
                                 "with an aggregating OPC UA server for history");
  cmd->add_option("--config", o->config, "The gateway's YAML file (servers, subscribe rules, historian)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--status-interval", o->status_interval_s,
                  "Seconds between status lines on stderr (0 = none)")
      ->capture_default_str();
  cmd->add_option("--duration", o->duration_s, "Stop after this many seconds (0 = until signalled)")
      ->capture_default_str();
  cmd->add_option(
      "--aggregating-port", o->aggregating_port,
      "Run the aggregating OPC UA server on this port (0 = any free port) whatever the config says");
#ifdef SF_HAVE_DASHBOARD
  cmd->add_option("--http", o->http_port,
                  "The dashboard's web server (REST API, live WebSocket, pages) on this port; 0 = any free "
                  "port, -1 = off. The URL is printed on stdout")
      ->capture_default_str();
  cmd->add_option("--http-host", o->http_host, "Address the web server listens on")->capture_default_str();
  cmd->add_option(
      "--web-users", o->web_users,
      "Users of the dashboard (`smartfactory opcua users` file; roles consumer, viewer, operator, "
      "engineer, admin); default: the aggregating server's users file");
  cmd->add_option("--web-root", o->web_root, "Directory of the dashboard's pages")->capture_default_str();
  add_tls_options(cmd, o->tls_cert, o->tls_key);
#endif
  cmd->footer(
      "cloud.yaml:\n"
      "  historian: {url: 'sqlite:history.db', buffer: history.buffer}\n"
      "  servers:\n"
      "    - name: line-1\n"
      "      url: opc.tcp://localhost:4840\n"
      "      subscribe: [{browse_path: /Objects/Demo}]\n"
      "      security: auto              # or Basic256Sha256:SignAndEncrypt, none\n"
      "  discovery: {url: 'opc.tcp://lds:4840', subscribe: [{browse_path: /Objects}]}\n"
      "  aggregating_server: {port: 4850, security: 'sign,encrypt'}\n"
      "  pki: DIR                         # default: the one `opcua pki` uses\n"
      "  knowledge: {due_after_s: 900}    # alarms from the rules (built-in ontology, rules, layout)\n"
      "See docs/cloud.md for every setting; docs/dashboard.md for the web API "
      "(libs/dashboard/openapi.yaml).");
  cmd->callback([o, &result] { result.exit_code = run_cloud(*o); });
}

}  // namespace sf::app
