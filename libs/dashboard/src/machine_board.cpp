// MachineBoard (machine_board.hpp): the machine models' variables (libs/factory
// machine_model.hpp, OPC 30050 PackML, OPC 40001-1 Machinery) read back by their browse paths.
#include "sf/dashboard/machine_board.hpp"

#include "json_values.hpp"
#include "sf/factory/packml.hpp"
#include "sf/line/ontology.hpp"

namespace sf::dashboard {

namespace {

constexpr std::string_view kMachines = "/Objects/Machines/";

// The PackML state's name for the Int32 StateCurrent (OPC 30050 §6.3.3, ISA-TR88 state numbers).
nlohmann::json state_name(const nlohmann::json& number) {
  if (!number.is_number_integer()) {
    return nullptr;
  }
  const auto n = number.get<std::int64_t>();
  if (n < 0 || n >= static_cast<std::int64_t>(factory::kPackMLStates)) {
    return nullptr;
  }
  return std::string(to_string(static_cast<factory::PackMLState>(n)));
}

nlohmann::json mode_name(const nlohmann::json& number) {
  if (!number.is_number_integer()) {
    return nullptr;
  }
  const auto n = number.get<std::int64_t>();
  if (n < 1 || n > 3) {
    return nullptr;
  }
  return std::string(to_string(static_cast<factory::PackMLMode>(n)));
}

}  // namespace

std::vector<MachineInfo> machines_of(const line::Layout& layout) {
  std::vector<MachineInfo> out;
  auto add = [&](const std::string& name, std::string kind, const std::string& label) {
    out.push_back({name, std::move(kind), label, line::iri_name(name)});
  };
  for (const auto& r : layout.robots) {
    add(r.name, std::string(to_string(r.kind)), r.label);
  }
  add(layout.uploader.name, "uploader", layout.uploader.label);
  add(layout.downloader.name, "downloader", layout.downloader.label);
  for (const auto& b : layout.belts) {
    add(b.name, "conveyor", b.label);
  }
  return out;
}

MachineBoard::MachineBoard(const line::Layout& layout) {
  for (auto& info : machines_of(layout)) {
    by_model_.emplace(info.model_name, entries_.size());
    entries_.push_back({std::move(info), {}, false, {}});
  }
}

std::optional<std::string> MachineBoard::on_value(const cloud::LiveUpdate& update) {
  if (update.series == nullptr) {
    return std::nullopt;
  }
  const std::string_view path = update.series->browse_path;
  if (!path.starts_with(kMachines)) {
    return std::nullopt;
  }
  const std::string_view rest = path.substr(kMachines.size());
  const auto slash = rest.find('/');
  if (slash == std::string_view::npos) {
    return std::nullopt;
  }
  std::lock_guard lock(mutex_);
  const auto found = by_model_.find(rest.substr(0, slash));
  if (found == by_model_.end()) {
    return std::nullopt;
  }
  Entry& e = entries_[found->second];
  e.server = update.series->server;
  if (auto s = servers_.find(e.server); s != servers_.end()) {
    e.connected = s->second;
  } else {
    e.connected = true;  // a value arrived: the gateway is connected to it
  }
  Current& current = e.values[std::string(rest.substr(slash + 1))];
  if (update.replayed && update.sample.source_time < current.time) {
    return std::nullopt;
  }
  current.value =
      historian::is_bad(update.sample.status) ? nlohmann::json(nullptr) : value_json(update.sample.value);
  current.time = update.sample.source_time;
  return e.info.name;
}

void MachineBoard::set_connected(const std::string& server, bool connected) {
  std::lock_guard lock(mutex_);
  servers_[server] = connected;
  for (auto& e : entries_) {
    if (e.server == server) {
      e.connected = connected;
    }
  }
}

bool MachineBoard::contains(std::string_view machine) const {
  std::lock_guard lock(mutex_);
  return std::any_of(entries_.begin(), entries_.end(),
                     [&](const Entry& e) { return e.info.name == machine; });
}

nlohmann::json MachineBoard::summary(const Entry& e, bool detail) const {
  auto value = [&](std::string_view path) -> nlohmann::json {
    const auto it = e.values.find(std::string(path));
    return it == e.values.end() ? nlohmann::json(nullptr) : it->second.value;
  };
  nlohmann::json m{
      {"name", e.info.name},
      {"kind", e.info.kind},
      {"label", e.info.label},
      {"server", e.server},
      {"connected", e.connected},
      {"state", state_name(value("PackML/Status/StateCurrent"))},
      {"mode", mode_name(value("PackML/Status/UnitModeCurrent"))},
      {"job",
       {{"id", value("Job/JobId")}, {"operation", value("Job/Operation")}, {"queued", value("Job/Queued")}}},
      {"processed", value("PackML/Admin/ProdProcessedCount")},
      {"defective", value("PackML/Admin/ProdDefectiveCount")},
      {"fault", value("Fault")}};
  if (detail) {
    nlohmann::json values = nlohmann::json::object();
    for (const auto& [path, current] : e.values) {
      values[path] = {{"value", current.value}, {"time", time_text(current.time)}};
    }
    m["values"] = std::move(values);
  }
  return m;
}

std::optional<nlohmann::json> MachineBoard::machine(std::string_view name, bool detail) const {
  std::lock_guard lock(mutex_);
  for (const auto& e : entries_) {
    if (e.info.name == name) {
      return summary(e, detail);
    }
  }
  return std::nullopt;
}

nlohmann::json MachineBoard::all() const {
  std::lock_guard lock(mutex_);
  nlohmann::json out = nlohmann::json::array();
  for (const auto& e : entries_) {
    out.push_back(summary(e, false));
  }
  return out;
}

std::optional<std::pair<std::string, std::string>> MachineBoard::address(std::string_view name) const {
  std::lock_guard lock(mutex_);
  for (const auto& e : entries_) {
    if (e.info.name == name && !e.server.empty()) {
      return std::pair(e.server, std::string(kMachines) + e.info.model_name);
    }
  }
  return std::nullopt;
}

}  // namespace sf::dashboard
