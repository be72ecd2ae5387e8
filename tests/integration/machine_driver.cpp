// The product side of the smart robot's multi-namespace test
// (machine_netns_test.py): in the machine's network namespace it brings a box
// to SCARA Robot 1's station the way the line's gateways will (the uploader's
// job handshake and the belts over Modbus TCP), then negotiates "load COUNT
// gummies into slots 0.. of that box" as a Contract Net manager over DDS on
// loopback, and waits for the robot's INFORM-DONE (or FAILURE).
//   machine_driver ENDPOINTS_JSON PARTITION COUNT
// Prints {"box": ID, "done": true|false, "contractor": NAME}; exits 1 with the
// failed step on stderr when the box cannot be brought or nobody answers.
#include <chrono>
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "real_line.hpp"
#include "sf/dds/executor.hpp"
#include "sf/negotiation/dds_transport.hpp"
#include "sf/negotiation/manager.hpp"

namespace {

using namespace std::chrono_literals;
using sf::integration::RealLine;
namespace ln = sf::line;
namespace cnp = sf::negotiation;

int fail(const std::string& message) {
  std::fprintf(stderr, "machine_driver: %s\n", message.c_str());
  return 1;
}

// The uploader puts a small box on conveyor1; the belts carry it to SCARA Robot 1.
sf::Result<std::uint16_t> bring_box(RealLine& line) {
  const auto& uploader = line.layout().uploader.name;
  const auto type = static_cast<std::uint16_t>(*line.layout().catalog.box_index("small-box") + 1);
  SF_TRY(ln::testing::hr(line, uploader, ln::transfer_plc::kBoxType, type));
  auto uploaded = ln::testing::run_job(line, uploader);
  if (!uploaded || *uploaded != ln::FaultCode::none) {
    return uploaded ? sf::make_error(sf::Errc::remote, "the uploader faulted")
                    : sf::Result<std::uint16_t>(uploaded.error());
  }
  auto id = ln::testing::ir(line, uploader, ln::transfer_plc::kBoxId);
  if (!id) {
    return id.error();
  }
  SF_TRY(ln::testing::convey(line, {"conveyor1", "conveyor2"}, 0));
  return *id;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    return fail("usage: machine_driver ENDPOINTS_JSON PARTITION COUNT");
  }
  const auto endpoints = nlohmann::json::parse(argv[1], nullptr, false);
  if (endpoints.is_discarded() || !endpoints.contains("endpoints")) {
    return fail("ENDPOINTS_JSON is not `plant --json` output");
  }
  auto layout = ln::default_layout();
  if (!layout) {
    return fail(layout.error().describe());
  }
  RealLine line(*layout);
  if (auto st = line.connect(endpoints); !st) {
    return fail(st.error().describe());
  }
  auto box = bring_box(line);
  if (!box) {
    return fail(box.error().describe());
  }

  sf::Clock& clock = line.clock();
  sf::dds::Executor executor;
  const auto settings = cnp::dds_settings(10, 11, argv[2], "lo", 1s);
  auto endpoints_dds =
      cnp::ProductEndpoints::create(settings, "box-driver", {"load"}, executor, clock, false);
  if (!endpoints_dds) {
    return fail(endpoints_dds.error().describe());
  }
  cnp::Manager manager(**endpoints_dds, clock);
  (*endpoints_dds)->bind(static_cast<cnp::ManagerInbox&>(manager));
  const auto discovery_end = clock.now() + 20s;
  while ((*endpoints_dds)->bidders("load") == 0 && clock.now() < discovery_end) {
    executor.wait_for(10ms);
    executor.run_pending();
  }
  if ((*endpoints_dds)->bidders("load") == 0) {
    return fail("no machine offers 'load' on DDS");
  }
  const double candy = static_cast<double>(*layout->catalog.candy_index("gummy"));
  const double box_type = static_cast<double>(*layout->catalog.box_index("small-box"));
  bool done = false;
  bool failed = false;
  std::string contractor;
  cnp::ConversationEvents events;
  events.on_confirmed = [&](const cnp::Conversation& c) { contractor = c.contractor; };
  events.on_done = [&](const cnp::Conversation&) { done = true; };
  events.on_failed = [&](const cnp::Conversation&) { failed = true; };
  auto id = manager.negotiate({"box-" + std::to_string(*box),
                               "load",
                               {{"candy", candy},
                                {"count", std::stod(argv[3])},
                                {"box", static_cast<double>(*box)},
                                {"slot", 0},
                                {"box_type", box_type}},
                               ""},
                              std::move(events));
  if (!id) {
    return fail(id.error().describe());
  }
  const auto end = clock.now() + 90s;
  while (!done && !failed && clock.now() < end) {
    executor.wait_for(5ms);
    executor.run_pending();
    manager.tick();
    (*endpoints_dds)->flush_ended();
  }
  if (!done && !failed) {
    return fail("no INFORM-DONE or FAILURE within 90 s");
  }
  std::printf("%s\n",
              nlohmann::json{{"box", *box}, {"done", done}, {"contractor", contractor}}.dump().c_str());
  return 0;
}
