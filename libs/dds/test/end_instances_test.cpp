// Writer under Cyclone's write batching (Internal/WriteBatch, on in the
// generated configuration), with a reader in another process (dds_test_peer):
// every write still leaves at once, end_instances ends many instances with one
// flush. The writer's heartbeat interval is an hour: with Cyclone's default
// (100 ms), the first write after a quiet spell asks for an acknowledgement,
// which sends the batch, and heartbeats announce what stayed behind, so a
// Writer that did not flush would still pass. (The interval also slows the
// recovery of lost discovery messages; on loopback none are lost.)
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "dds_test_support.hpp"
#include "sf/core/process.hpp"

namespace sf::dds {
namespace {

using namespace std::chrono_literals;
using test::reading;

class RemoteReader : public ::testing::Test {
 protected:
  void SetUp() override {
    auto network = loopback_network();
    network.heartbeat_interval = std::chrono::hours{1};
    participant.emplace(test::make_participant("writer", partition, network));
    topic.emplace(Topic<sf_ddstest_Reading>::create(*participant, "Readings").value());
    writer.emplace(
        Writer<sf_ddstest_Reading>::create(*participant, *topic, QosBuilder{}.reliable().keep_last(8).build())
            .value());
    ProcessOptions o;
    o.argv = {SF_DDS_TEST_PEER, std::to_string(test::kTestDomain), partition};
    o.in = Stdio::pipe();  // the peer ends when its stdin does
    o.out = Stdio::pipe();
    auto started = Process::spawn(std::move(o));
    ASSERT_TRUE(started.ok()) << started.error().describe();
    peer = std::move(*started);
    ASSERT_TRUE(peer.wait_for_line([](const std::string& l) { return l == "ready"; }, 30s).ok());
    // Discovery is not symmetric: the writer must know the reader too before it writes.
    const auto end = std::chrono::steady_clock::now() + 30s;
    while (writer->publication_matched().value().current_count == 0) {
      ASSERT_LT(std::chrono::steady_clock::now(), end) << "the writer never matched the peer's reader";
      std::this_thread::sleep_for(10ms);
    }
  }
  void TearDown() override { peer.close_and_wait(10s); }

  // Reads the peer's lines until `line` (true) or `bound` passes (false).
  bool peer_says(const std::string& line, std::chrono::milliseconds bound = 20s) {
    return peer.wait_for_line([&](const std::string& l) { return l == line; }, bound).ok();
  }
  // The peer's next `n` lines (fewer if it stops talking for 20 s).
  std::vector<std::string> peer_lines(std::size_t n) {
    std::vector<std::string> lines;
    (void)peer.wait_for_line(
        [&](const std::string& l) {
          lines.push_back(l);
          return lines.size() == n;
        },
        20s);
    return lines;
  }

  const std::string partition = test::private_partition("remote");
  std::optional<Participant> participant;
  std::optional<Topic<sf_ddstest_Reading>> topic;
  std::optional<Writer<sf_ddstest_Reading>> writer;
  Process peer;
};

// A write waits in the batch only until its flush, which Writer does at once: the
// peer would never see the samples otherwise.
TEST_F(RemoteReader, EveryWriteLeavesAtOnceUnderWriteBatch) {
  ASSERT_TRUE(writer->write(reading("a", 1)).ok());
  ASSERT_TRUE(writer->write(reading("b", 1)).ok());
  EXPECT_EQ(peer_lines(2), (std::vector<std::string>{"alive a", "alive b"}));
  ASSERT_TRUE(writer->dispose_and_unregister(reading("a", 0)).ok());
  EXPECT_TRUE(peer_says("disposed a"));
}

TEST_F(RemoteReader, EndInstancesEndsThemAll) {
  ASSERT_TRUE(writer->write(reading("d", 1)).ok());
  ASSERT_TRUE(writer->write(reading("e", 1)).ok());
  ASSERT_EQ(peer_lines(2), (std::vector<std::string>{"alive d", "alive e"}));
  const std::vector<sf_ddstest_Reading> ended{reading("d", 0), reading("e", 0)};
  ASSERT_TRUE(writer->end_instances(ended).ok());
  EXPECT_EQ(peer_lines(2), (std::vector<std::string>{"disposed d", "disposed e"}));
}

// Ending no instance sends nothing and ends nothing: the writes around it arrive as they are.
TEST_F(RemoteReader, NoEndsIsNothing) {
  ASSERT_TRUE(writer->write(reading("g", 1)).ok());
  EXPECT_TRUE(writer->end_instances({}).ok());
  ASSERT_TRUE(writer->write(reading("h", 1)).ok());
  EXPECT_EQ(peer_lines(2), (std::vector<std::string>{"alive g", "alive h"}));
}

}  // namespace
}  // namespace sf::dds
