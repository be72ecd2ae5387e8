// Test helpers for the OPC UA client: the node-opcua test server
// (tests/peers/opcua/node_server.mjs) as a child process, and a thread-safe collector for
// values that callbacks deliver on the loop thread.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "../collector.hpp"
#include "sf/core/process.hpp"
#include "sf/testing/node_peer.hpp"

namespace sf::opcua::test {

using sf::testing::find_node;
using sf::testing::node_unavailable;
using sf::testing::source_dir;

// One node-opcua server process. It exits when its stdin closes (stop) or on SIGKILL (kill).
class NodeServer {
 public:
  // Starts the server on port (0 = a free one) and waits for "READY <port>".
  bool start(std::uint16_t port = 0, std::chrono::seconds timeout = std::chrono::seconds(90)) {
    const auto node = find_node();
    if (!node) {
      return false;
    }
    const std::string script = (source_dir() / "tests" / "peers" / "opcua" / "node_server.mjs").string();
    ProcessOptions o;
    o.argv = {node->string(), script, std::to_string(port)};
    o.cwd = source_dir();
    o.in = Stdio::pipe();
    o.out = Stdio::pipe();
    o.err = std::getenv("SF_NODE_SERVER_LOG") != nullptr ? Stdio::inherit() : Stdio::null();
    auto started = Process::spawn(std::move(o));
    if (!started) {
      return false;
    }
    process_ = std::move(*started);
    return process_
        .wait_for_line(
            [this](const std::string& line) {
              const auto at = line.find("READY ");
              if (at != std::string::npos) {
                port_ = static_cast<std::uint16_t>(std::stoul(line.substr(at + 6)));
              }
              return at != std::string::npos;
            },
            timeout)
        .ok();
  }

  // Closes stdin (an orderly shutdown); SIGKILL if it is not gone within a few seconds.
  void stop() { process_.close_and_wait(std::chrono::seconds(10)); }
  // The server dies at once (no CloseSession, no CLO): the connection just drops.
  void kill() { process_.kill(); }

  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] std::string url() const { return "opc.tcp://127.0.0.1:" + std::to_string(port_); }

 private:
  Process process_;
  std::uint16_t port_ = 0;
};

}  // namespace sf::opcua::test
