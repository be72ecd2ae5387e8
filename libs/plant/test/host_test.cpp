// The plant's faces served to other processes: Modbus TCP servers, an
// EtherCAT-in-UDP segment and the control port, with the physics running as
// fast as it can on a ManualClock. (No timing asserted: generous limits.)
#include "sf/plant/host.hpp"

#include <chrono>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sf/modbus/tcp_client.hpp"
#include "sf/plant/control.hpp"

namespace sf::plant {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

class HostTest : public ::testing::Test {
 protected:
  void SetUp() override {
    plant_ = std::make_unique<Plant>(*default_layout(), clock_);
    HostOptions options;
    options.ecat_port = 0;
    options.real_time = false;
    auto host = PlantHost::start(*plant_, clock_, options);
    ASSERT_TRUE(host) << host.error().describe();
    host_ = std::move(*host);
  }
  const Endpoint& endpoint(std::string_view machine) {
    for (const auto& e : host_->endpoints()) {
      if (e.machine == machine) {
        return e;
      }
    }
    static Endpoint none;
    ADD_FAILURE() << "no endpoint for " << machine;
    return none;
  }
  std::unique_ptr<modbus::TcpClient> client(std::string_view machine) {
    const std::string& address = endpoint(machine).address;
    modbus::TcpClientOptions o;
    o.host = address.substr(0, address.rfind(':'));
    o.port = static_cast<std::uint16_t>(std::stoi(address.substr(address.rfind(':') + 1)));
    o.response_timeout = 2s;
    return std::move(*modbus::TcpClient::create(o));
  }
  json control(const json& request) {
    const std::string& address = endpoint("plant").address;
    auto answer = control_request(
        "127.0.0.1", static_cast<std::uint16_t>(std::stoi(address.substr(address.rfind(':') + 1))),
        request.dump());
    EXPECT_TRUE(answer) << answer.error().describe();
    return answer ? json::parse(*answer) : json{};
  }

  ManualClock clock_;
  std::unique_ptr<Plant> plant_;
  std::unique_ptr<PlantHost> host_;
};

TEST_F(HostTest, EveryFaceHasAnEndpoint) {
  std::size_t modbus = 0;
  std::size_t ethercat = 0;
  for (const auto& e : host_->endpoints()) {
    modbus += e.protocol == "modbus-tcp" ? 1U : 0U;
    ethercat += e.protocol == "ethercat-udp" ? 1U : 0U;
  }
  EXPECT_EQ(modbus, 9U);  // five conveyors, uploader, downloader, two legacy robots
  EXPECT_EQ(ethercat, 1U);
  EXPECT_EQ(endpoint("plant").protocol, "control");
}

TEST_F(HostTest, AnUploadOverModbusTcpShowsInTheSnapshot) {
  auto uploader = client("uploader");
  ASSERT_TRUE(uploader->write_single_register(transfer_plc::kBoxType, 2));
  ASSERT_TRUE(uploader->write_single_coil(transfer_plc::kStart, true));
  bool done = false;
  for (int i = 0; i < 1000 && !done; ++i) {
    auto inputs = uploader->read_discrete_inputs(0, 4);
    ASSERT_TRUE(inputs) << inputs.error().describe();
    done = (*inputs)[transfer_plc::kDone];
    std::this_thread::sleep_for(5ms);
  }
  ASSERT_TRUE(done);
  const json reply = control({{"op", "snapshot"}});
  ASSERT_TRUE(reply["ok"].get<bool>());
  ASSERT_EQ(reply["snapshot"]["boxes"].size(), 1U);
  EXPECT_EQ(reply["snapshot"]["boxes"][0]["type"], "large-box");
  EXPECT_EQ(reply["snapshot"]["boxes"][0]["station"], "conveyor1/upload");
  const json events = control({{"op", "events"}, {"since", 0}});
  EXPECT_GE(events["events"].size(), 3U);
  EXPECT_EQ(events["next"].get<std::uint64_t>(), events["events"].size());
}

TEST_F(HostTest, FaultsThroughTheControlPortReachTheModbusFace) {
  EXPECT_TRUE(control({{"op", "inject"}, {"fault", "plc-exception:conveyor3:6"}})["ok"].get<bool>());
  EXPECT_EQ(control({{"op", "faults"}})["faults"], json::array({"plc-exception:conveyor3:6"}));
  auto conveyor = client("conveyor3");
  auto read = conveyor->read_input_registers(0, 4);
  ASSERT_FALSE(read);
  ASSERT_TRUE(read.error().exception.has_value());
  EXPECT_EQ(*read.error().exception, modbus::ExceptionCode::server_device_busy);
  EXPECT_TRUE(control({{"op", "clear"}, {"fault", "plc-exception:conveyor3"}})["ok"].get<bool>());
  EXPECT_TRUE(conveyor->read_input_registers(0, 4));
}

TEST_F(HostTest, BadControlRequestsGetAnErrorAndTheConnectionStays) {
  for (const char* bad :
       {"not json", "[1,2]", R"({"op": 3})", R"({"op": "explode"})",
        R"({"op": "inject", "fault": "jam:conveyor9"})", R"({"op": "inject", "fault": "jam"})",
        R"({"op": "inject", "fault": "jam:conveyor1", "at": "soon"})", R"({"op": "events", "since": -4})"}) {
    const std::string& address = endpoint("plant").address;
    auto answer = control_request(
        "127.0.0.1", static_cast<std::uint16_t>(std::stoi(address.substr(address.rfind(':') + 1))), bad);
    ASSERT_TRUE(answer) << bad;
    const json reply = json::parse(*answer);
    EXPECT_FALSE(reply["ok"].get<bool>()) << bad;
    EXPECT_FALSE(reply["error"].get<std::string>().empty()) << bad;
  }
  EXPECT_TRUE(control({{"op", "faults"}})["ok"].get<bool>());
}

TEST(ControlRequest, OneAnswerPerLineWithoutANetwork) {
  ManualClock clock;
  Plant plant(*default_layout(), clock);
  EXPECT_EQ(json::parse(handle_control_request(
                plant, R"({"op":"inject","fault":"jam:conveyor2","at":1,"for":1})"))["ok"],
            true);
  EXPECT_TRUE(plant.active_faults().empty());  // not yet: at 1 s
  {
    auto lock = plant.lock();
    plant.advance(1500ms);
  }
  EXPECT_EQ(plant.active_faults().size(), 1U);
  {
    auto lock = plant.lock();
    plant.advance(1s);
  }
  EXPECT_TRUE(plant.active_faults().empty());
  const json snapshot = json::parse(handle_control_request(plant, R"({"op":"snapshot"})"));
  EXPECT_EQ(snapshot["snapshot"]["belts"].size(), 5U);
}

TEST(ControlRequest, AMixupIsInjectedListedAndClearedByRequest) {
  ManualClock clock;
  Plant plant(*default_layout(), clock);
  const auto d =
      static_cast<std::size_t>(plant.layout().dispenser("denso-lollipop") - plant.layout().dispensers.data());
  const auto ask = [&](std::string_view line) { return json::parse(handle_control_request(plant, line)); };
  EXPECT_EQ(ask(R"({"op":"inject","fault":"mixup:denso-lollipop"})")["ok"], true);
  EXPECT_TRUE(plant.world().mixed_up(d));
  EXPECT_EQ(plant.world().dispensed_candy(d), *plant.layout().catalog.candy_index("toffee"));
  EXPECT_EQ(ask(R"({"op":"faults"})")["faults"], json::array({"mixup:denso-lollipop"}));
  const json unknown = ask(R"({"op":"inject","fault":"mixup:denso-mint"})");
  EXPECT_EQ(unknown["ok"], false);
  EXPECT_NE(unknown["error"].get<std::string>().find("no dispenser 'denso-mint'"), std::string::npos)
      << unknown;
  EXPECT_EQ(ask(R"({"op":"inject","fault":"mixup"})")["ok"], false);
  EXPECT_EQ(ask(R"({"op":"clear","fault":"mixup:denso-lollipop"})")["ok"], true);
  EXPECT_FALSE(plant.world().mixed_up(d));
  EXPECT_EQ(ask(R"({"op":"faults"})")["faults"], json::array());
  const json events = ask(R"({"op":"events","since":0})")["events"];
  ASSERT_EQ(events.size(), 2U);
  EXPECT_EQ(events[0]["kind"], "fault_raised");
  EXPECT_EQ(events[0]["where"], "denso-lollipop");
  EXPECT_EQ(events[1]["kind"], "fault_cleared");
}

}  // namespace
}  // namespace sf::plant
