// The line as the integration drivers reach it from their own network
// namespace: Modbus TCP clients of the plant's PLCs (from `smartfactory plant
// --json`'s endpoints line) and one millisecond per step in real time, for
// the scripted sequences of sf/line/testing/line_script.hpp.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "sf/core/clock.hpp"
#include "sf/line/testing/line_script.hpp"
#include "sf/modbus/tcp_client.hpp"

namespace sf::integration {

class RealLine final : public line::testing::LineIo {
 public:
  explicit RealLine(line::Layout layout) : layout_(std::move(layout)), next_(clock_.now()) {}

  // Every Modbus TCP endpoint of `plant --json`'s endpoints line.
  Status connect(const nlohmann::json& endpoints) {
    for (const auto& e : endpoints["endpoints"]) {
      if (e["protocol"] == "modbus-tcp") {
        SF_TRY(add_plc(e["machine"], e["address"]));
      }
    }
    return {};
  }
  [[nodiscard]] const line::Layout& layout() const override { return layout_; }
  modbus::Client& plc(const std::string& machine) override { return *clients_.at(machine); }
  void step() override {
    next_ += std::chrono::milliseconds{1};
    clock_.sleep_until(next_);
    run_cycle();
  }
  [[nodiscard]] int poll_steps() const override { return 20; }  // a gateway's poll period
  Clock& clock() { return clock_; }

 private:
  Status add_plc(const std::string& machine, const std::string& address) {
    modbus::TcpClientOptions o;
    o.host = address.substr(0, address.rfind(':'));
    o.port = static_cast<std::uint16_t>(std::stoi(address.substr(address.rfind(':') + 1)));
    o.response_timeout = std::chrono::seconds{1};
    auto client = modbus::TcpClient::create(o);
    if (!client) {
      return client.error();
    }
    clients_[machine] = std::move(*client);
    return {};
  }

  line::Layout layout_;
  SteadyClock clock_;
  Clock::time_point next_;
  std::map<std::string, std::unique_ptr<modbus::TcpClient>> clients_;
};

}  // namespace sf::integration
