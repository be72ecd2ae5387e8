// Command groups of the smartfactory CLI. Each group's file registers its
// subcommands on the app; the group's module does the work. A group is
// registered only when its module has something real behind it.
#pragma once

#include <atomic>

#include <CLI/CLI.hpp>
#include <filesystem>

namespace sf::app {

// Exit codes shared by all commands.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// Where a subcommand's callback leaves its exit code for main().
struct CommandResult {
  int exit_code = kExitOk;
};

// Installs SIGINT/SIGTERM handlers that set stop_requested(); commands that
// run "until signalled" poll it.
void install_stop_signals();
bool stop_requested();

// Puts the calling thread (and the threads it starts afterwards) on SCHED_FIFO
// with locked memory when the system allows it; returns whether it did.
bool try_realtime(int priority);

// `--tls-cert FILE --tls-key FILE` (both or neither): the dashboard over HTTPS and WSS only
// (cloud, and passed to it by line and demo).
inline void add_tls_options(CLI::App* cmd, std::filesystem::path& cert, std::filesystem::path& key) {
  auto* c = cmd->add_option("--tls-cert", cert,
                            "Serve the dashboard over HTTPS and WSS only (TLS 1.2 or 1.3): the certificate "
                            "chain, PEM (the server's certificate first, then its issuers). The session "
                            "cookie gets Secure, every response Strict-Transport-Security");
  auto* k = cmd->add_option("--tls-key", key, "The private key of --tls-cert: PEM, unencrypted");
  c->needs(k);
  k->needs(c);
}

void register_ecat(CLI::App& app, CommandResult& result);
// `agent machine|conveyor|product` and `cnp bench` (negotiation module).
void register_agent(CLI::App& app, CommandResult& result);
void register_cnp(CLI::App& app, CommandResult& result);
// `opcua server|browse|read|write|call|subscribe` (opcua module).
void register_opcua(CLI::App& app, CommandResult& result);
// `cloud --config cloud.yaml` (cloud module).
void register_cloud(CLI::App& app, CommandResult& result);
// `kb reason|to-nodeset|generate` (knowledge module).
void register_kb(CLI::App& app, CommandResult& result);

// `plant [check|registers|ontology|faults|snapshot|events]` (plant module).
void register_plant(CLI::App& app, CommandResult& result);

// `machine --config FILE` (factory module): the smart robot's IPC.
void register_machine(CLI::App& app, CommandResult& result);

// `history query|series|events|retention|write` (historian module).
void register_history(CLI::App& app, CommandResult& result);

// `gateway --config FILE` (factory module): a legacy machine's gateway.
void register_gateway(CLI::App& app, CommandResult& result);

// `orders --config FILE` and `order ...` (factory module): the order service and its client.
void register_orders(CLI::App& app, CommandResult& result);

// `line --layout FILE` (factory module): the line's processes, supervised.
void register_line(CLI::App& app, CommandResult& result);

// `demo` (factory module): the candy factory as processes, fed generated orders.
void register_demo(CLI::App& app, CommandResult& result);

// `simulate` (simulation module): the factory in its deterministic mode.
void register_simulate(CLI::App& app, CommandResult& result);

}  // namespace sf::app
