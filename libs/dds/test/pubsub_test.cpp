#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <vector>

#include "dds_test_support.hpp"

namespace sf::dds {
namespace {

using namespace std::chrono_literals;
using test::pump_until;
using test::reading;

Qos endpoint_qos() {
  return QosBuilder{}
      .reliable()
      .durability(Durability::TransientLocal)
      .keep_last(8)
      .liveliness(Liveliness::Automatic, 2s)
      .build();
}

struct Received {
  std::string sensor;
  std::int64_t value = 0;
  std::vector<double> samples;
  SampleInfo info;
};

Received copy_of(const sf_ddstest_Reading& r, const SampleInfo& info) {
  Received out{r.sensor, r.value, {}, info};
  for (std::uint32_t i = 0; i < r.samples._length && i < r.samples._maximum; ++i) {
    out.samples.push_back(r.samples._buffer[i]);
  }
  return out;
}

class PubSub : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto partition =
        test::private_partition(::testing::UnitTest::GetInstance()->current_test_info()->name());
    pub_participant.emplace(test::make_participant("publisher", partition));
    sub_participant.emplace(test::make_participant("subscriber", partition));
    pub_topic.emplace(Topic<sf_ddstest_Reading>::create(*pub_participant, "Readings").value());
    sub_topic.emplace(Topic<sf_ddstest_Reading>::create(*sub_participant, "Readings").value());
  }

  Reader<sf_ddstest_Reading> make_reader(ReaderListeners listeners = {}) {
    auto r = Reader<sf_ddstest_Reading>::create(
        *sub_participant, *sub_topic, endpoint_qos(), &executor,
        [this](const sf_ddstest_Reading& s, const SampleInfo& i) { received.push_back(copy_of(s, i)); },
        std::move(listeners));
    EXPECT_TRUE(r.ok()) << r.error().describe();
    return std::move(*r);
  }

  Writer<sf_ddstest_Reading> make_writer(WriterListeners listeners = {}) {
    auto w = Writer<sf_ddstest_Reading>::create(*pub_participant, *pub_topic, endpoint_qos(), &executor,
                                                std::move(listeners));
    EXPECT_TRUE(w.ok()) << w.error().describe();
    return std::move(*w);
  }

  bool wait_matched(const Writer<sf_ddstest_Reading>& w, std::uint32_t n) {
    return pump_until(executor, [&] {
      auto m = w.publication_matched();
      return m.ok() && m->current_count >= n;
    });
  }

  Executor executor;
  std::optional<Participant> pub_participant;
  std::optional<Participant> sub_participant;
  std::optional<Topic<sf_ddstest_Reading>> pub_topic;
  std::optional<Topic<sf_ddstest_Reading>> sub_topic;
  std::vector<Received> received;
};

TEST_F(PubSub, TypedSamplesArriveOnTheExecutorWithTheirSequence) {
  auto reader = make_reader();
  auto writer = make_writer();
  ASSERT_TRUE(wait_matched(writer, 1));
  auto r = reading("temp-1", 42);
  double values[3] = {1.5, 2.5, 3.5};
  r.samples._buffer = values;
  r.samples._length = 3;
  r.samples._maximum = 3;
  ASSERT_TRUE(writer.write(r).ok());
  ASSERT_TRUE(pump_until(executor, [&] { return !received.empty(); }));
  ASSERT_EQ(received.size(), 1U);
  EXPECT_EQ(received[0].sensor, "temp-1");
  EXPECT_EQ(received[0].value, 42);
  EXPECT_EQ(received[0].samples, (std::vector<double>{1.5, 2.5, 3.5}));
  EXPECT_TRUE(received[0].info.valid_data);
  EXPECT_EQ(received[0].info.instance_state, InstanceState::Alive);
  EXPECT_NE(received[0].info.publication_handle, 0U);
}

// A filter on the reader's topic: refused samples never reach the reader (no handler call, no
// instance); accepted ones arrive as usual. Cyclone filters samples with data only: the filter
// never sees a key-only end, which reaches the reader even for an instance it kept out.
TEST_F(PubSub, AFilteredTopicsReaderTakesOnlyTheSamplesTheFilterAccepts) {
  std::vector<std::int64_t> offered;
  ASSERT_TRUE(sub_topic
                  ->set_filter([&](const sf_ddstest_Reading& r) {
                    offered.push_back(r.value);
                    return r.value % 2 == 0;
                  })
                  .ok());
  auto reader = make_reader();
  auto writer = make_writer();
  ASSERT_TRUE(wait_matched(writer, 1));
  for (const auto& [sensor, value] :
       std::vector<std::pair<std::string, std::int64_t>>{{"a", 1}, {"b", 2}, {"c", 3}, {"d", 4}}) {
    ASSERT_TRUE(writer.write(reading(sensor, value)).ok());
  }
  ASSERT_TRUE(writer.dispose_and_unregister(reading("a", 1)).ok());
  ASSERT_TRUE(writer.dispose_and_unregister(reading("b", 2)).ok());
  ASSERT_TRUE(writer.write(reading("z", 100)).ok());  // the last: all before it were delivered
  ASSERT_TRUE(pump_until(executor, [&] { return !received.empty() && received.back().sensor == "z"; }));
  std::vector<std::string> valid;
  std::vector<std::string> ended;
  for (const auto& r : received) {
    if (r.info.valid_data) {
      valid.push_back(r.sensor);
    }
    if (r.info.instance_state != InstanceState::Alive) {
      ended.push_back(r.sensor);
    }
  }
  EXPECT_EQ(valid, (std::vector<std::string>{"b", "d", "z"}));
  std::sort(ended.begin(), ended.end());  // b's end may come with its data or after it
  EXPECT_EQ(ended, (std::vector<std::string>{"a", "b"}));
  std::sort(offered.begin(), offered.end());
  offered.erase(std::unique(offered.begin(), offered.end()), offered.end());
  EXPECT_EQ(offered, (std::vector<std::int64_t>{1, 2, 3, 4, 100}));
}

TEST_F(PubSub, LateReaderGetsTransientLocalHistory) {
  auto writer = make_writer();
  ASSERT_TRUE(writer.write(reading("a", 1)).ok());
  ASSERT_TRUE(writer.write(reading("b", 2)).ok());
  auto reader = make_reader();
  ASSERT_TRUE(pump_until(executor, [&] { return received.size() >= 2; }));
  EXPECT_EQ(received.size(), 2U);
}

TEST_F(PubSub, DisposeAndUnregisterReachTheReaderAsInstanceStates) {
  auto reader = make_reader();
  auto writer = make_writer();
  ASSERT_TRUE(wait_matched(writer, 1));
  ASSERT_TRUE(writer.write(reading("x", 7)).ok());
  ASSERT_TRUE(writer.dispose_and_unregister(reading("x", 0)).ok());
  ASSERT_TRUE(pump_until(executor, [&] {
    return std::any_of(received.begin(), received.end(),
                       [](const Received& r) { return r.info.instance_state == InstanceState::Disposed; });
  }));
  // Either the data sample itself carries the new state (not yet taken when
  // the dispose arrived) or an invalid sample does; the key is valid in both.
  const auto& last = received.back();
  EXPECT_EQ(last.sensor, "x");
  EXPECT_EQ(last.info.instance_state, InstanceState::Disposed);
}

TEST_F(PubSub, WithoutAutodisposeDisposeAndUnregisterStillDisposes) {
  auto reader = make_reader();
  auto qos = QosBuilder{}
                 .reliable()
                 .durability(Durability::TransientLocal)
                 .keep_last(8)
                 .liveliness(Liveliness::Automatic, 2s)
                 .autodispose_unregistered_instances(false)
                 .build();
  EXPECT_EQ(read_settings(qos).autodispose_unregistered_instances, false);
  auto writer = Writer<sf_ddstest_Reading>::create(*pub_participant, *pub_topic, qos);
  ASSERT_TRUE(writer.ok());
  EXPECT_FALSE(writer->autodispose());
  EXPECT_TRUE(make_writer().autodispose());  // the policy's default
  ASSERT_TRUE(wait_matched(*writer, 1));
  ASSERT_TRUE(writer->write(reading("y", 3)).ok());
  ASSERT_TRUE(writer->dispose_and_unregister(reading("y", 0)).ok());
  ASSERT_TRUE(pump_until(executor, [&] {
    return !received.empty() && received.back().info.instance_state == InstanceState::Disposed;
  }));
  EXPECT_EQ(received.back().sensor, "y");
}

TEST_F(PubSub, InlineHandlersMayWriteToReadersOfTheirOwnProcess) {
  // A handler run inline writes; Cyclone delivers that write to a reader of
  // this process on the same thread, whose listener posts back into the
  // executor. The post is queued for the application thread, never run nested
  // in the handler, and nothing deadlocks.
  auto echo_topic = Topic<sf_ddstest_Reading>::create(*sub_participant, "Echoes");
  auto echo_topic_pub = Topic<sf_ddstest_Reading>::create(*pub_participant, "Echoes");
  ASSERT_TRUE(echo_topic.ok() && echo_topic_pub.ok());
  auto echo_writer = Writer<sf_ddstest_Reading>::create(*sub_participant, *echo_topic, endpoint_qos());
  ASSERT_TRUE(echo_writer.ok());
  int depth = 0;
  int max_depth = 0;
  int nested_echoes = 0;
  int handled = 0;
  std::vector<std::int64_t> echoed;
  auto echo_reader =
      Reader<sf_ddstest_Reading>::create(*pub_participant, *echo_topic_pub, endpoint_qos(), &executor,
                                         [&](const sf_ddstest_Reading& r, const SampleInfo& i) {
                                           // Run inside the handler whose write it is?
                                           nested_echoes += depth > 0 ? 1 : 0;
                                           if (i.valid_data) {
                                             echoed.push_back(r.value);
                                           }
                                         });
  ASSERT_TRUE(echo_reader.ok());
  auto reader = Reader<sf_ddstest_Reading>::create(
      *sub_participant, *sub_topic, endpoint_qos(), &executor,
      [&](const sf_ddstest_Reading& r, const SampleInfo& i) {
        max_depth = std::max(max_depth, ++depth);
        ++handled;
        if (i.valid_data) {
          EXPECT_TRUE(echo_writer->write(reading("echo" + std::to_string(r.value), r.value * 10)).ok());
        }
        --depth;
      });
  ASSERT_TRUE(reader.ok());
  auto writer = make_writer();
  ASSERT_TRUE(wait_matched(writer, 1));
  ASSERT_TRUE(pump_until(executor, [&] {
    auto m = echo_writer->publication_matched();
    return m.ok() && m->current_count >= 1;
  }));
  {
    const auto strand = executor.hold();
    executor.set_inline(true);
  }
  for (std::int64_t v = 1; v <= 50; ++v) {  // one instance each: KEEP_LAST(8) drops none
    ASSERT_TRUE(writer.write(reading("x" + std::to_string(v), v)).ok());
  }
  const auto all_echoed = [&] {
    const auto strand = executor.hold();
    return echoed.size() >= 50;
  };
  ASSERT_TRUE(pump_until(executor, all_echoed)) << echoed.size() << " echoed of " << handled << " handled";
  {
    const auto strand = executor.hold();
    executor.set_inline(false);
  }
  EXPECT_EQ(max_depth, 1);
  EXPECT_EQ(nested_echoes, 0);
  EXPECT_EQ(handled, 50);
  ASSERT_EQ(echoed.size(), 50U);
  for (std::int64_t v = 1; v <= 50; ++v) {
    EXPECT_EQ(echoed[static_cast<std::size_t>(v - 1)], v * 10);
  }
}

TEST_F(PubSub, PartitionsKeepRunsApart) {
  auto reader = make_reader();
  auto stranger = test::make_participant("stranger", test::private_partition("elsewhere"));
  auto topic = Topic<sf_ddstest_Reading>::create(stranger, "Readings");
  ASSERT_TRUE(topic.ok());
  auto foreign = Writer<sf_ddstest_Reading>::create(stranger, *topic, endpoint_qos());
  ASSERT_TRUE(foreign.ok());
  auto writer = make_writer();
  ASSERT_TRUE(wait_matched(writer, 1));
  ASSERT_TRUE(foreign->write(reading("foreign", 1)).ok());
  ASSERT_TRUE(writer.write(reading("ours", 2)).ok());
  ASSERT_TRUE(pump_until(executor, [&] { return !received.empty(); }));
  auto m = foreign->publication_matched();
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(m->current_count, 0U);
  for (const auto& r : received) {
    EXPECT_EQ(r.sensor, "ours");
  }
}

TEST_F(PubSub, MatchedListenersReportTheRemoteEndpoint) {
  std::optional<MatchedStatus> pub_matched;
  std::optional<MatchedStatus> sub_matched;
  auto reader = make_reader(ReaderListeners{[&](const MatchedStatus& s) { sub_matched = s; }, {}, {}});
  auto writer = make_writer(WriterListeners{[&](const MatchedStatus& s) { pub_matched = s; }, {}, {}});
  ASSERT_TRUE(pump_until(executor, [&] { return pub_matched && sub_matched; }));
  EXPECT_EQ(pub_matched->current_count, 1U);
  EXPECT_EQ(sub_matched->current_count, 1U);
  EXPECT_NE(sub_matched->last_handle, 0U);
}

TEST_F(PubSub, WriterGoneIsReportedAsLivelinessChangeOfThatWriter) {
  std::vector<LivelinessChangedStatus> changes;
  auto reader =
      make_reader(ReaderListeners{{}, [&](const LivelinessChangedStatus& s) { changes.push_back(s); }, {}});
  std::optional<Writer<sf_ddstest_Reading>> writer{make_writer()};
  ASSERT_TRUE(wait_matched(*writer, 1));
  ASSERT_TRUE(writer->write(reading("w", 1)).ok());
  ASSERT_TRUE(pump_until(executor, [&] { return !received.empty(); }));
  const auto writer_handle = received[0].info.publication_handle;
  writer.reset();
  ASSERT_TRUE(pump_until(executor, [&] {
    return std::any_of(changes.begin(), changes.end(),
                       [](const auto& c) { return c.alive_count_change < 0; });
  }));
  const auto lost =
      std::find_if(changes.begin(), changes.end(), [](const auto& c) { return c.alive_count_change < 0; });
  EXPECT_EQ(lost->last_publication_handle, writer_handle);
  EXPECT_EQ(lost->alive_count, 0U);
}

TEST_F(PubSub, RequestedDeadlineMissedIsReported) {
  int missed = 0;
  const Qos qos = QosBuilder{}.reliable().keep_last(1).deadline(50ms).build();
  auto reader = Reader<sf_ddstest_Reading>::create(
      *sub_participant, *sub_topic, qos, &executor, {},
      ReaderListeners{{}, {}, [&](const DeadlineMissedStatus&) { ++missed; }});
  ASSERT_TRUE(reader.ok()) << reader.error().describe();
  auto writer = Writer<sf_ddstest_Reading>::create(*pub_participant, *pub_topic, qos);
  ASSERT_TRUE(writer.ok());
  ASSERT_TRUE(pump_until(executor, [&] { return writer->publication_matched()->current_count == 1; }));
  ASSERT_TRUE(writer->write(reading("slow", 1)).ok());
  // The instance is not updated again, so its deadline passes.
  EXPECT_TRUE(pump_until(executor, [&] { return missed > 0; }));
}

TEST_F(PubSub, NoCallbackAfterTheReaderIsDestroyed) {
  std::optional<Reader<sf_ddstest_Reading>> reader{make_reader()};
  auto writer = make_writer();
  ASSERT_TRUE(wait_matched(writer, 1));
  executor.run_pending();
  ASSERT_TRUE(writer.write(reading("late", 1)).ok());
  // Wait (without running it) until the delivery task is queued.
  const auto end = std::chrono::steady_clock::now() + 20s;
  while (executor.pending() == 0 && std::chrono::steady_clock::now() < end) {
    executor.wait_for(10ms);
  }
  ASSERT_GT(executor.pending(), 0U);
  reader.reset();
  executor.run_pending();
  EXPECT_TRUE(received.empty());
}

TEST_F(PubSub, ReaderWithoutExecutorIsPolled) {
  auto polled = Reader<sf_ddstest_Reading>::create(*sub_participant, *sub_topic, endpoint_qos());
  ASSERT_TRUE(polled.ok());
  auto writer = make_writer();
  ASSERT_TRUE(wait_matched(writer, 1));
  ASSERT_TRUE(writer.write(reading("p", 5)).ok());
  std::vector<std::int64_t> values;
  ASSERT_TRUE(pump_until(executor, [&] {
    (void)polled->take([&](const sf_ddstest_Reading& s, const SampleInfo& i) {
      if (i.valid_data) {
        values.push_back(s.value);
      }
    });
    return !values.empty();
  }));
  EXPECT_EQ(values, std::vector<std::int64_t>{5});
  // Callbacks without an executor are a usage error, reported as such.
  auto bad = Reader<sf_ddstest_Reading>::create(*sub_participant, *sub_topic, endpoint_qos(), nullptr,
                                                [](const sf_ddstest_Reading&, const SampleInfo&) {});
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().code, Errc::invalid_argument);
}

TEST_F(PubSub, IntrospectionShowsLocalAndDiscoveredLayout) {
  auto reader = make_reader();
  auto writer = make_writer();
  auto second_writer = make_writer();
  auto local = inspect(*pub_participant);
  ASSERT_TRUE(local.ok()) << local.error().describe();
  EXPECT_EQ(local->participant, "publisher");
  EXPECT_EQ(local->writers_on("Readings"), 2U);
  EXPECT_TRUE(local->readers.empty());
  EXPECT_EQ(local->writers[0].type, "sf_ddstest::Reading");

  auto found = discover(*sub_participant, SteadyClock::instance(), 500ms, pub_participant->partition());
  ASSERT_TRUE(found.ok()) << found.error().describe();
  const auto pub =
      std::find_if(found->begin(), found->end(), [](const auto& l) { return l.participant == "publisher"; });
  const auto sub =
      std::find_if(found->begin(), found->end(), [](const auto& l) { return l.participant == "subscriber"; });
  ASSERT_NE(pub, found->end());
  ASSERT_NE(sub, found->end());
  EXPECT_EQ(pub->key, local->key);
  EXPECT_EQ(pub->writer_topics(), (std::vector<std::string>{"Readings", "Readings"}));
  EXPECT_EQ(sub->reader_topics(), (std::vector<std::string>{"Readings"}));
  EXPECT_TRUE(sub->writers.empty());
  EXPECT_NE(to_json(*local).find("\"writers\":[{\"topic\":\"Readings\""), std::string::npos);
}

}  // namespace
}  // namespace sf::dds
