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
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "real_line.hpp"
#include "sf/ethercat/link.hpp"

namespace {

using sf::integration::RealLine;

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
  if (auto st = line.connect(endpoints); !st) {
    return fail(st.error().describe());
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
