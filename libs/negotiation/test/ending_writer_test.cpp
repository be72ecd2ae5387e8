// EndingWriter: conversation ends wait for kEndDelay on the injected clock and
// leave together; a full batch and the destructor send at once. The reader is
// in this process, where Cyclone delivers every operation when it leaves the
// writer, so what the reader sees is what was sent.
#include <gtest/gtest.h>
#include <unistd.h>

#include <map>
#include <set>
#include <string>

#include <fmt/format.h>

#include "dds_common.hpp"

namespace sf::negotiation {
namespace {

using namespace std::chrono_literals;
using detail::EndingWriter;
using detail::kEndDelay;
using detail::kMaxEndBatch;

class EndingWriterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    settings.machining_domain = 77;
    settings.partition = fmt::format("sf-ending-{}-{}", ::getpid(),
                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    participant.emplace(detail::join(settings, settings.machining_domain, "ending-writer-test").value());
    topic.emplace(dds::Topic<sf_cnp_ContractorMessage>::create(*participant, bid_topic("OP1")).value());
    reader.emplace(
        dds::Reader<sf_cnp_ContractorMessage>::create(*participant, *topic, detail::reader_qos(settings))
            .value());
    writer.emplace(
        dds::Writer<sf_cnp_ContractorMessage>::create(*participant, *topic, detail::writer_qos(settings))
            .value(),
        clock);
  }

  void bid(const std::string& conversation) {
    const ContractorMessage m{conversation, "M1", "OP1", 1, Bid{}};
    names[codec::key_hash(conversation)] = conversation;
    codec::ParamStorage storage;
    ASSERT_TRUE(writer->write(codec::encode(m, storage).value()).ok());
  }
  Status end(const std::string& conversation) {
    return writer->end_later(codec::contractor_key(conversation, "M1"));
  }
  // The conversations whose instance the reader saw disposed since the last call (an instance
  // whose writer went without disposing it is NoWriters, not counted). An end carries the key
  // hash only: the name is the one bid() wrote with it.
  std::set<std::string> ended() {
    std::set<std::string> out;
    EXPECT_TRUE(reader
                    ->take([&](const sf_cnp_ContractorMessage& s, const dds::SampleInfo& info) {
                      if (info.instance_state == dds::InstanceState::Disposed) {
                        const auto it = names.find(s.conversation_hash);
                        out.insert(it != names.end() ? it->second : "?");
                      }
                    })
                    .ok());
    return out;
  }

  DdsSettings settings;
  ManualClock clock;
  std::map<std::uint64_t, std::string> names;  // by key hash
  std::optional<dds::Participant> participant;
  std::optional<dds::Topic<sf_cnp_ContractorMessage>> topic;
  std::optional<dds::Reader<sf_cnp_ContractorMessage>> reader;
  std::optional<EndingWriter<sf_cnp_ContractorMessage>> writer;
};

TEST_F(EndingWriterTest, EndsWaitForTheDelayThenLeaveTogether) {
  bid("c1");
  bid("c2");
  EXPECT_TRUE(ended().empty());
  EXPECT_FALSE(writer->ends_due());
  const auto t0 = clock.now();
  ASSERT_TRUE(end("c1").ok());
  clock.advance(1ms);
  ASSERT_TRUE(end("c2").ok());
  EXPECT_EQ(writer->waiting(), 2u);
  // Due when the oldest has waited kEndDelay.
  EXPECT_EQ(writer->ends_due(), t0 + kEndDelay);
  ASSERT_TRUE(writer->flush_ended(t0 + kEndDelay - 1us).ok());
  EXPECT_TRUE(ended().empty());
  ASSERT_TRUE(writer->flush_ended(t0 + kEndDelay).ok());
  EXPECT_EQ(ended(), (std::set<std::string>{"c1", "c2"}));
  EXPECT_EQ(writer->waiting(), 0u);
  EXPECT_FALSE(writer->ends_due());
}

TEST_F(EndingWriterTest, TheNextBatchIsTimedFromItsOwnFirstEnd) {
  bid("c1");
  bid("c2");
  ASSERT_TRUE(end("c1").ok());
  clock.advance(kEndDelay);
  ASSERT_TRUE(writer->flush_ended(clock.now()).ok());
  EXPECT_EQ(ended(), (std::set<std::string>{"c1"}));
  clock.advance(1ms);
  ASSERT_TRUE(end("c2").ok());
  EXPECT_EQ(writer->ends_due(), clock.now() + kEndDelay);
  ASSERT_TRUE(writer->flush_ended(clock.now()).ok());
  EXPECT_TRUE(ended().empty());
}

TEST_F(EndingWriterTest, AFullBatchLeavesAtOnce) {
  std::set<std::string> all;
  for (std::size_t i = 0; i < kMaxEndBatch; ++i) {
    const auto c = fmt::format("c{}", i);
    bid(c);
    all.insert(c);
  }
  (void)ended();
  for (std::size_t i = 0; i + 1 < kMaxEndBatch; ++i) {
    ASSERT_TRUE(end(fmt::format("c{}", i)).ok());
  }
  EXPECT_TRUE(ended().empty());
  ASSERT_TRUE(end(fmt::format("c{}", kMaxEndBatch - 1)).ok());
  EXPECT_EQ(ended(), all);
  EXPECT_EQ(writer->waiting(), 0u);
}

// Without autodispose, deleting the DDS writer alone leaves the instance NoWriters: only the
// ends the EndingWriter sends on its way out dispose it.
TEST_F(EndingWriterTest, WaitingEndsLeaveWhenTheWriterGoes) {
  writer.reset();
  const auto qos = dds::QosBuilder{}
                       .reliable(1s)
                       .durability(dds::Durability::TransientLocal)
                       .keep_last(settings.history_depth)
                       .autodispose_unregistered_instances(false)
                       .build();
  writer.emplace(dds::Writer<sf_cnp_ContractorMessage>::create(*participant, *topic, qos).value(), clock);
  bid("c1");
  bid("c2");
  (void)ended();
  ASSERT_TRUE(end("c1").ok());
  EXPECT_TRUE(ended().empty());
  writer.reset();
  EXPECT_EQ(ended(), (std::set<std::string>{"c1"}));
}

}  // namespace
}  // namespace sf::negotiation
