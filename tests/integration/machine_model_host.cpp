// The OPC UA model of a machine controller (libs/factory machine_model.hpp) served for
// machine_model_test.py: serve_machine with the test PackML controller
// (sf/factory/testing/packml_machine.hpp) on its controller thread, on loopback, as the `machine`
// and `gateway` processes serve theirs, until SIGTERM or SIGINT.
//   machine_model_host --pki DIR [--users FILE] [--anonymous ROLE] [--modes none] [--nodeset FILE]...
// Prints "listening on <endpoint URL>" when clients may connect.
#include <pthread.h>

#include <csignal>
#include <cstdio>
#include <stop_token>
#include <string>
#include <thread>
#include <vector>

#include "sf/factory/machine_host.hpp"
#include "sf/factory/testing/packml_machine.hpp"
#include "sf/opcua/server/security_setup.hpp"

namespace {

struct Options {
  sf::opcua::server::ServerSecuritySettings security;
  std::vector<std::string> nodesets;
};

bool parse(int argc, char** argv, Options& o) {
  o.security.modes = "none";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    const std::string value = argv[i + 1];
    if (flag == "--pki") {
      o.security.pki = value;
    } else if (flag == "--users") {
      o.security.users = value;
    } else if (flag == "--anonymous") {
      o.security.anonymous = value;
    } else if (flag == "--modes") {
      o.security.modes = value;
    } else if (flag == "--nodeset") {
      o.nodesets.push_back(value);
    } else {
      std::fprintf(stderr, "unknown option %s\n", flag.c_str());
      return false;
    }
  }
  return argc % 2 == 1 && !o.security.pki.empty();
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  if (!parse(argc, argv, options)) {
    std::fprintf(
        stderr,
        "usage: machine_model_host --pki DIR [--users FILE] [--anonymous ROLE] [--nodeset FILE]...\n");
    return 2;
  }
  sf::factory::MachineServerConfig config;
  config.thread.realtime = false;
  config.server.transport.host = "127.0.0.1";
  config.server.transport.port = 0;
  config.server.advertised_host = "127.0.0.1";
  config.nodesets = options.nodesets;
  auto security = sf::opcua::server::configure_server_security(options.security, false, config.server);
  if (!security) {
    std::fprintf(stderr, "security: %s\n", security.error().message.c_str());
    return 1;
  }
  std::fprintf(stderr, "%s\n", security->c_str());

  // Signals are taken by one thread (sigwait), which asks the poll loop to stop.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::stop_source stop;
  std::thread([signals, stop]() mutable {
    int signal = 0;
    sigwait(&signals, &signal);
    stop.request_stop();
  }).detach();

  sf::factory::testing::PackMLMachine machine(sf::SteadyClock::instance());
  const auto st =
      sf::factory::serve_machine(machine, config, sf::SteadyClock::instance(), stop.get_token(),
                                 [](const sf::opcua::server::Server& server, sf::factory::ControllerThread&) {
                                   std::printf("listening on %s\n", server.endpoint_url().c_str());
                                   std::fflush(stdout);
                                 });
  if (!st) {
    std::fprintf(stderr, "machine_model_host: %s\n", st.error().describe().c_str());
    return 1;
  }
  return 0;
}
