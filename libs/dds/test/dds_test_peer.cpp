// A DDS reader in a process of its own, for the tests that need a remote
// reader (Cyclone delivers to readers in the writer's process at once, without
// the network): it reads sf_ddstest_Reading on topic "Readings" and prints one
// line per event on stdout:
//   ready           a writer is matched
//   alive SENSOR    a sample of SENSOR's instance
//   disposed SENSOR SENSOR's instance was disposed
//   orphaned SENSOR SENSOR's instance has no writers left (unregistered without a dispose, or
//                   its writer went)
// It exits when stdin closes.
//
// Usage: dds_test_peer DOMAIN PARTITION
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <thread>

#include "dds_test_types.h"
#include "sf/dds/dds.hpp"

SF_DDS_TOPIC_TYPE(sf_ddstest_Reading);

namespace {

void say(const std::string& line) {
  std::fputs((line + "\n").c_str(), stdout);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace sf::dds;
  if (argc != 3) {
    std::fputs("usage: dds_test_peer DOMAIN PARTITION\n", stderr);
    return 2;
  }
  auto xml = cyclone_config_xml(loopback_network());
  if (!xml) {
    std::fprintf(stderr, "dds_test_peer: %s\n", xml.error().describe().c_str());
    return 1;
  }
  auto participant = Participant::create(static_cast<DomainId>(std::atoi(argv[1])), {*xml, "peer", argv[2]});
  if (!participant) {
    std::fprintf(stderr, "dds_test_peer: %s\n", participant.error().describe().c_str());
    return 1;
  }
  auto topic = Topic<sf_ddstest_Reading>::create(*participant, "Readings");
  if (!topic) {
    std::fprintf(stderr, "dds_test_peer: %s\n", topic.error().describe().c_str());
    return 1;
  }
  Executor executor;
  const Qos qos = QosBuilder{}.reliable().keep_last(8).build();
  auto reader = Reader<sf_ddstest_Reading>::create(
      *participant, *topic, qos, &executor,
      [](const sf_ddstest_Reading& r, const SampleInfo& info) {
        if (info.valid_data) {
          say(std::string{"alive "} + r.sensor);
        }
        if (info.instance_state == InstanceState::Disposed) {
          say(std::string{"disposed "} + r.sensor);
        } else if (info.instance_state == InstanceState::NoWriters) {
          say(std::string{"orphaned "} + r.sensor);
        }
      },
      ReaderListeners{[](const MatchedStatus& m) {
                        if (m.current_count > 0) {
                          say("ready");
                        }
                      },
                      {},
                      {}});
  if (!reader) {
    std::fprintf(stderr, "dds_test_peer: %s\n", reader.error().describe().c_str());
    return 1;
  }
  // Handlers run inline on the receive thread, as each sample arrives, so the lines come in the
  // order of the samples on the wire; another thread watches stdin so that the loop ends with it.
  executor.set_inline(true);
  std::atomic<bool> eof{false};
  std::thread stdin_watch{[&] {
    std::string line;
    while (std::getline(std::cin, line)) {
    }
    eof = true;
    executor.notify();
  }};
  while (!eof) {
    executor.wait_for(std::chrono::milliseconds{100});
    executor.run_pending();
  }
  stdin_watch.join();
  return 0;
}
