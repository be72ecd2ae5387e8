// The control side of the plant's multi-namespace test (plant_netns_test.py):
// in its own network namespace, our EtherCAT master on the smart robot's
// wire and Modbus TCP clients of the plant's PLCs run the scripted line
// (sf/line/testing/line_script.hpp) in real time — the sequence the plant's
// unit tests run on a ManualClock. It links the line's description and the
// protocol libraries, never the plant.
//   plant_driver ENDPOINTS_JSON ECAT_LINK
// ENDPOINTS_JSON is `smartfactory plant --json`'s first line; ECAT_LINK an
// interface or udp:HOST:PORT. Prints {"box": ID} on success, exits 1 with
// the failed step on stderr otherwise.
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "sf/core/clock.hpp"
#include "sf/ethercat/link.hpp"
#include "sf/line/testing/line_script.hpp"
#include "sf/modbus/tcp_client.hpp"

namespace {

using namespace std::chrono_literals;

class RealLine final : public sf::line::testing::LineIo {
 public:
  explicit RealLine(sf::line::Layout layout) : layout_(std::move(layout)), next_(clock_.now()) {}

  sf::Status add_plc(const std::string& machine, const std::string& address) {
    sf::modbus::TcpClientOptions o;
    o.host = address.substr(0, address.rfind(':'));
    o.port = static_cast<std::uint16_t>(std::stoi(address.substr(address.rfind(':') + 1)));
    o.response_timeout = 1s;
    auto client = sf::modbus::TcpClient::create(o);
    if (!client) {
      return client.error();
    }
    clients_[machine] = std::move(*client);
    return {};
  }
  [[nodiscard]] const sf::line::Layout& layout() const override { return layout_; }
  sf::modbus::Client& plc(const std::string& machine) override { return *clients_.at(machine); }
  void step() override {
    next_ += 1ms;
    clock_.sleep_until(next_);
    run_cycle();
  }
  [[nodiscard]] int poll_steps() const override { return 20; }  // a gateway's poll period
  sf::Clock& clock() { return clock_; }

 private:
  sf::line::Layout layout_;
  sf::SteadyClock clock_;
  sf::Clock::time_point next_;
  std::map<std::string, std::unique_ptr<sf::modbus::TcpClient>> clients_;
};

int fail(const std::string& message) {
  std::fprintf(stderr, "plant_driver: %s\n", message.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    return fail("usage: plant_driver ENDPOINTS_JSON ECAT_LINK");
  }
  const auto endpoints = nlohmann::json::parse(argv[1], nullptr, false);
  if (endpoints.is_discarded() || !endpoints.contains("endpoints")) {
    return fail("ENDPOINTS_JSON is not `plant --json` output");
  }
  auto layout = sf::line::default_layout();
  if (!layout) {
    return fail(layout.error().describe());
  }
  RealLine line(*layout);
  for (const auto& e : endpoints["endpoints"]) {
    if (e["protocol"] == "modbus-tcp") {
      if (auto st = line.add_plc(e["machine"], e["address"]); !st) {
        return fail(st.error().describe());
      }
    }
  }
  auto link = sf::ethercat::open_link(argv[2]);
  if (!link) {
    return fail(link.error().describe());
  }
  sf::ethercat::master::Master master(**link, line.clock());
  sf::line::testing::SmartArm arm(line, master, "scara-robot-1");
  if (auto st = arm.start(); !st) {
    return fail(st.error().describe());
  }
  auto box = sf::line::testing::pack_one_box(line, arm);
  if (!box) {
    return fail(box.error().describe());
  }
  std::printf("%s\n", nlohmann::json{{"box", *box}}.dump().c_str());
  return 0;
}
