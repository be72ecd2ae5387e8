// NodeSet2 files on the command line: `opcua server --nodeset FILE` and `opcua nodeset`.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "sf/opcua/server/server.hpp"

namespace sf::app {

// Imports each file into the running server's address space, in order; prints a summary line
// per file (and its warnings) to stderr. Stops at the first file that fails, naming it.
Status load_nodesets(opcua::server::Server& server, const std::vector<std::string>& files);

// `opcua nodeset FILE... [--demo-model] [--export OUT --namespace URI...]`.
void register_opcua_nodeset(CLI::App& group, CommandResult& result);

}  // namespace sf::app
