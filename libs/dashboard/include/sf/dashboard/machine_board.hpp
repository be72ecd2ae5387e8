// The machine board: the current state of every machine and conveyor of the line, from the
// values the gateway receives (the machines' OPC UA models of libs/factory, below
// /Objects/Machines/<model name>): PackML state and mode, job, Admin counters, fault, tags, and
// which gateway server it is on (for its commands). Thread-safe.
#pragma once

#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "sf/cloud/live_bus.hpp"
#include "sf/line/layout.hpp"

namespace sf::dashboard {

struct MachineInfo {
  std::string name;  // the layout's name ("scara-robot-1")
  std::string kind;  // smart-scara, legacy-scara, legacy-articulated, uploader, downloader, conveyor
  std::string label;
  std::string model_name;  // its object below /Objects/Machines (line::iri_name)
};

// Every machine of the layout: robots, uploader, downloader, belts (conveyors).
std::vector<MachineInfo> machines_of(const line::Layout& layout);

class MachineBoard {
 public:
  explicit MachineBoard(const line::Layout& layout);

  // A value of the gateway: the machine (layout name) it changed, if it is one of the line's.
  // Values read back from history (replayed) older than the current one are left out.
  std::optional<std::string> on_value(const cloud::LiveUpdate& update);
  // The gateway's connection state of each server (the machines on it are connected or not).
  void set_connected(const std::string& server, bool connected);

  [[nodiscard]] bool contains(std::string_view machine) const;
  // The Machine object of openapi.yaml: state, mode, job, counters, fault; `values`: every
  // current value by its path below the machine (detail only).
  [[nodiscard]] std::optional<nlohmann::json> machine(std::string_view name, bool detail) const;
  [[nodiscard]] nlohmann::json all() const;
  // The gateway server and browse path of a machine's object, once a value of it arrived.
  [[nodiscard]] std::optional<std::pair<std::string, std::string>> address(std::string_view name) const;

 private:
  struct Current {
    nlohmann::json value;
    historian::Timestamp time{};
  };
  struct Entry {
    MachineInfo info;
    std::string server;
    bool connected = false;
    std::map<std::string, Current> values;  // "PackML/Status/StateCurrent" → value
  };
  [[nodiscard]] nlohmann::json summary(const Entry& e, bool detail) const;

  mutable std::mutex mutex_;
  std::vector<Entry> entries_;
  std::map<std::string, std::size_t, std::less<>> by_model_;  // model name → entry
  std::map<std::string, bool> servers_;
};

}  // namespace sf::dashboard
