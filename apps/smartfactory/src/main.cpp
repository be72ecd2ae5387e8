// smartfactory: one binary, many roles. Command groups are registered by the
// modules that have something real behind them (see commands.hpp).
#include <cstdlib>
#include <iostream>
#include <string>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "sf/core/log.hpp"
#include "version.hpp"

namespace {

constexpr const char* kDescription =
    "smartfactory - EtherCAT inside machines, DDS between machines, OPC UA to the\n"
    "cloud, and a cloud that stores, reasons and shows: a smart factory on one\n"
    "Ethernet. Each command group runs one component; see `smartfactory GROUP --help`.\n"
    "Logging: --log-level or SF_LOG, e.g. \"info,ethercat=debug\".";

}  // namespace

int main(int argc, char** argv) {
  sf::log::init_from_env();
  CLI::App app{kDescription, "smartfactory"};
  app.set_version_flag("--version",
                       fmt::format("smartfactory {} ({})", sf::app::kVersion, sf::app::kGitDescribe));
  app.require_subcommand(0, 1);
  std::string log_level;
  app.add_option("--log-level", log_level,
                 "trace|debug|info|warn|error|off, optionally per module: info,opcua=debug")
      ->envname("SF_LOG");
  app.parse_complete_callback([&] {
    if (!log_level.empty()) {
      if (auto st = sf::log::set_level(log_level); !st) {
        throw CLI::ValidationError("--log-level", st.error().message);
      }
    }
  });

  sf::app::CommandResult result;
#ifdef SF_HAVE_ECAT
  sf::app::register_ecat(app, result);
#endif
#ifdef SF_HAVE_AGENT
  sf::app::register_agent(app, result);
  sf::app::register_cnp(app, result);
#endif
#ifdef SF_HAVE_OPCUA
  sf::app::register_opcua(app, result);
#endif
#ifdef SF_HAVE_CLOUD
  sf::app::register_cloud(app, result);
#endif
#ifdef SF_HAVE_HISTORY
  sf::app::register_history(app, result);
#endif
#ifdef SF_HAVE_PLANT
  sf::app::register_plant(app, result);
#endif
#ifdef SF_HAVE_KB
  sf::app::register_kb(app, result);
#endif
#ifdef SF_HAVE_FACTORY
  sf::app::register_machine(app, result);
  sf::app::register_gateway(app, result);
  sf::app::register_line(app, result);
#ifdef SF_HAVE_OPCUA
  sf::app::register_orders(app, result);
  sf::app::register_demo(app, result);
#endif
#endif
#ifdef SF_HAVE_SIMULATION
  sf::app::register_simulate(app, result);
#endif

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  if (app.get_subcommands().empty()) {
    std::cout << app.help();
    return sf::app::kExitOk;
  }
  return result.exit_code;
}
