// In-memory link pair, PcapTap and LossyLink.
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "sf/ethercat/frame.hpp"
#include "sf/ethercat/link.hpp"

namespace sf::ethercat {
namespace {

using ::testing::HasSubstr;
using namespace std::chrono_literals;

Bytes ecat_frame(std::uint8_t index, std::size_t data = 2) {
  Frame f;
  f.datagrams.push_back(
      {Command::BRD, index, Datagram::physical(0, 0x0130), 0, false, Bytes(data, index), 0});
  return encode(f).value();
}

Bytes ipv4_frame() {
  Bytes b(60, 0);
  b[12] = 0x08;
  return b;
}

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()));
}

// --- MemoryLinkPair -------------------------------------------------------------

TEST(MemoryLink, DeliversFramesToThePeerInOrder) {
  auto [a, b] = make_memory_link_pair();
  EXPECT_EQ(a->name(), "memory:a");
  EXPECT_EQ(b->name(), "memory:b");
  EXPECT_NE(a->mac(), b->mac());
  ASSERT_TRUE(a->send(ecat_frame(1)));
  ASSERT_TRUE(a->send(ecat_frame(2)));
  std::array<std::uint8_t, kMaxFrameSize> buf{};
  for (std::uint8_t i = 1; i <= 2; ++i) {
    auto n = b->receive(buf, 1s);
    ASSERT_TRUE(n);
    EXPECT_EQ(Bytes(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(*n)), ecat_frame(i));
  }
  // Nothing came back to the sender.
  auto none = a->receive(buf, 0ns);
  ASSERT_TRUE(none);
  EXPECT_EQ(*none, 0U);
}

TEST(MemoryLink, TimeoutReturnsZero) {
  auto pair = make_memory_link_pair();
  std::array<std::uint8_t, kMaxFrameSize> buf{};
  auto n = pair.b->receive(buf, 1ms);
  ASSERT_TRUE(n);
  EXPECT_EQ(*n, 0U);
}

TEST(MemoryLink, SkipsFramesThatAreNotEtherCat) {
  auto pair = make_memory_link_pair();
  ASSERT_TRUE(pair.a->send(ipv4_frame()));
  ASSERT_TRUE(pair.a->send(ecat_frame(7)));
  std::array<std::uint8_t, kMaxFrameSize> buf{};
  auto n = pair.b->receive(buf, 1s);
  ASSERT_TRUE(n);
  EXPECT_EQ(buf[17], 7);  // the EtherCAT frame's datagram index
}

TEST(MemoryLink, BoundedQueueRejectsWhenFull) {
  auto pair = make_memory_link_pair({.capacity = 2});
  ASSERT_TRUE(pair.a->send(ecat_frame(1)));
  ASSERT_TRUE(pair.a->send(ecat_frame(2)));
  auto full = pair.a->send(ecat_frame(3));
  ASSERT_FALSE(full);
  EXPECT_EQ(full.error().code, Errc::limit_exceeded);
  EXPECT_THAT(full.error().message, HasSubstr("full (2 frames)"));
  // The other direction is independent.
  EXPECT_TRUE(pair.b->send(ecat_frame(4)));
}

TEST(MemoryLink, RejectsBadSizesAndSmallBuffers) {
  auto pair = make_memory_link_pair();
  EXPECT_FALSE(pair.a->send(Bytes(13)));
  EXPECT_FALSE(pair.a->send(Bytes(kMaxFrameSize + 1)));
  ASSERT_TRUE(pair.a->send(ecat_frame(1, 100)));
  std::array<std::uint8_t, 64> small{};
  auto n = pair.b->receive(small, 1s);
  ASSERT_FALSE(n);
  EXPECT_EQ(n.error().code, Errc::out_of_range);
}

TEST(MemoryLink, ClosedPeerIsAnErrorAfterTheQueueDrains) {
  auto pair = make_memory_link_pair();
  ASSERT_TRUE(pair.a->send(ecat_frame(1)));
  pair.a.reset();
  std::array<std::uint8_t, kMaxFrameSize> buf{};
  auto first = pair.b->receive(buf, 1s);
  ASSERT_TRUE(first);
  EXPECT_GT(*first, 0U);
  auto closed = pair.b->receive(buf, 1s);
  ASSERT_FALSE(closed);
  EXPECT_EQ(closed.error().code, Errc::state);
  EXPECT_FALSE(pair.b->send(ecat_frame(2)));
}

TEST(MemoryLink, WakesAWaitingReceiverFromAnotherThread) {
  auto pair = make_memory_link_pair({.capacity = 8});
  constexpr int kFrames = 500;
  std::thread producer([&] {
    for (int i = 0; i < kFrames; ++i) {
      while (!pair.a->send(ecat_frame(static_cast<std::uint8_t>(i)))) {
        std::this_thread::yield();  // queue full: wait for the consumer
      }
    }
  });
  std::array<std::uint8_t, kMaxFrameSize> buf{};
  int received = 0;
  while (received < kFrames) {
    auto n = pair.b->receive(buf, 5s);
    ASSERT_TRUE(n);
    ASSERT_GT(*n, 0U) << "timed out after " << received;
    EXPECT_EQ(buf[17], static_cast<std::uint8_t>(received));
    ++received;
  }
  producer.join();
}

// --- PcapTap ----------------------------------------------------------------------

TEST(PcapTap, RecordsSentAndReceivedFramesWithClockTimestamps) {
  const auto file = temp_file("sf-pcap-ns");
  ManualClock clock;  // UTC 1'700'000'000 s at start
  auto pair = make_memory_link_pair();
  auto tap = PcapTap::open(std::move(pair.a), file, clock);
  ASSERT_TRUE(tap) << tap.error().describe();
  clock.advance(1'500ns);
  ASSERT_TRUE((*tap)->send(ecat_frame(1)));
  ASSERT_TRUE(pair.b->send(ecat_frame(2, 20)));
  clock.advance(2s);
  std::array<std::uint8_t, kMaxFrameSize> buf{};
  ASSERT_EQ((*tap)->receive(buf, 1s).value(), kMinFrameSize);
  EXPECT_EQ((*tap)->frames_written(), 2U);
  EXPECT_EQ((*tap)->name(), "memory:a");

  auto pcap = read_pcap(file);
  ASSERT_TRUE(pcap) << pcap.error().describe();
  EXPECT_EQ(pcap->linktype, 1U);
  EXPECT_EQ(pcap->resolution, PcapResolution::nanoseconds);
  ASSERT_EQ(pcap->records.size(), 2U);
  EXPECT_EQ(pcap->records[0].data, ecat_frame(1));
  EXPECT_EQ(pcap->records[1].data, ecat_frame(2, 20));
  const auto t0 = Clock::utc_time{std::chrono::seconds{1'700'000'000}};
  EXPECT_EQ(pcap->records[0].timestamp - t0, 1'500ns);
  EXPECT_EQ(pcap->records[1].timestamp - t0, 2s + 1'500ns);
  EXPECT_EQ(pcap->records[0].original_length, kMinFrameSize);
  std::filesystem::remove(file);
}

TEST(PcapTap, MicrosecondResolutionTruncates) {
  const auto file = temp_file("sf-pcap-us");
  ManualClock clock;
  auto pair = make_memory_link_pair();
  auto tap = PcapTap::open(std::move(pair.a), file, clock, PcapResolution::microseconds);
  ASSERT_TRUE(tap);
  clock.advance(2'999ns);
  ASSERT_TRUE((*tap)->send(ecat_frame(1)));
  tap->reset();  // closes the file
  auto pcap = read_pcap(file);
  ASSERT_TRUE(pcap);
  EXPECT_EQ(pcap->resolution, PcapResolution::microseconds);
  ASSERT_EQ(pcap->records.size(), 1U);
  EXPECT_EQ(pcap->records[0].timestamp - Clock::utc_time{std::chrono::seconds{1'700'000'000}}, 2us);
  std::filesystem::remove(file);
}

TEST(PcapTap, WiresharkDissectsTheFileAsEtherCat) {
  if (std::system("command -v tshark >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "tshark not installed";
  }
  const auto file = temp_file("sf-pcap-tshark");
  const auto out = temp_file("sf-pcap-tshark-out");
  ManualClock clock;
  auto pair = make_memory_link_pair();
  {
    auto tap = PcapTap::open(std::move(pair.a), file, clock);
    ASSERT_TRUE(tap);
    ASSERT_TRUE((*tap)->send(ecat_frame(1)));
    ASSERT_TRUE((*tap)->send(ecat_frame(2)));
  }
  const std::string cmd =
      "tshark -r " + file.string() + " -Y ecat -T fields -e ecat.cmd > " + out.string() + " 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream in(out);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  // Two BRD (0x07) frames dissected.
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2);
  EXPECT_THAT(text, HasSubstr("7"));
  std::filesystem::remove(file);
  std::filesystem::remove(out);
}

TEST(PcapTap, ErrorsNameTheFile) {
  ManualClock clock;
  auto pair = make_memory_link_pair();
  auto tap = PcapTap::open(std::move(pair.a), "/nonexistent-dir/x.pcap", clock);
  ASSERT_FALSE(tap);
  EXPECT_EQ(tap.error().code, Errc::io);
  EXPECT_THAT(tap.error().message, HasSubstr("/nonexistent-dir/x.pcap"));
  EXPECT_FALSE(PcapTap::open(nullptr, temp_file("sf-null"), clock));
}

TEST(ReadPcap, RejectsMissingBadAndTruncatedFiles) {
  EXPECT_FALSE(read_pcap("/nonexistent-dir/x.pcap"));
  const auto file = temp_file("sf-pcap-bad");
  {
    std::ofstream out(file, std::ios::binary);
    out << "not a pcap file at all, but long enough";
  }
  auto bad = read_pcap(file);
  ASSERT_FALSE(bad);
  EXPECT_THAT(bad.error().message, HasSubstr("not a classic pcap"));

  ManualClock clock;
  auto pair = make_memory_link_pair();
  {
    auto tap = PcapTap::open(std::move(pair.a), file, clock);
    ASSERT_TRUE(tap);
    ASSERT_TRUE((*tap)->send(ecat_frame(1)));
  }
  std::filesystem::resize_file(file, std::filesystem::file_size(file) - 5);
  auto truncated = read_pcap(file);
  ASSERT_FALSE(truncated);
  EXPECT_THAT(truncated.error().message, HasSubstr("record 0"));
  std::filesystem::remove(file);
}

// --- LossyLink ----------------------------------------------------------------------

std::uint64_t delivered(double p, std::uint64_t seed, int frames, std::vector<bool>* pattern = nullptr) {
  auto pair = make_memory_link_pair({.capacity = 2000});
  LossyLink lossy(std::move(pair.a), p, seed);
  std::array<std::uint8_t, kMaxFrameSize> buf{};
  std::uint64_t got = 0;
  for (int i = 0; i < frames; ++i) {
    EXPECT_TRUE(lossy.send(ecat_frame(static_cast<std::uint8_t>(i))));
    const bool arrived = pair.b->receive(buf, 0ns).value() > 0;
    got += arrived ? 1U : 0U;
    if (pattern != nullptr) {
      pattern->push_back(arrived);
    }
  }
  EXPECT_EQ(lossy.dropped_sent() + got, static_cast<std::uint64_t>(frames));
  return got;
}

TEST(LossyLink, ProbabilityZeroAndOne) {
  EXPECT_EQ(delivered(0.0, 1, 100), 100U);
  EXPECT_EQ(delivered(1.0, 1, 100), 0U);
  EXPECT_EQ(delivered(7.0, 1, 10), 0U);    // clamped to 1
  EXPECT_EQ(delivered(-1.0, 1, 10), 10U);  // clamped to 0
}

TEST(LossyLink, SeededDropsAreRepeatable) {
  std::vector<bool> first;
  std::vector<bool> second;
  std::vector<bool> other_seed;
  const auto n = delivered(0.3, 42, 1000, &first);
  delivered(0.3, 42, 1000, &second);
  delivered(0.3, 43, 1000, &other_seed);
  EXPECT_EQ(first, second);
  EXPECT_NE(first, other_seed);
  // With seed 42 the generator is fixed, so this bound cannot flake; it
  // checks that the probability is applied at all.
  EXPECT_GT(n, 600U);
  EXPECT_LT(n, 800U);
}

TEST(LossyLink, DropsOnReceiveAndKeepsWaiting) {
  auto pair = make_memory_link_pair();
  LossyLink lossy(std::move(pair.b), LossyLinkOptions{0.0, 1.0, 5});
  for (std::uint8_t i = 0; i < 3; ++i) {
    ASSERT_TRUE(pair.a->send(ecat_frame(i)));
  }
  std::array<std::uint8_t, kMaxFrameSize> buf{};
  auto n = lossy.receive(buf, 1ms);
  ASSERT_TRUE(n);
  EXPECT_EQ(*n, 0U);
  EXPECT_EQ(lossy.dropped_received(), 3U);
  EXPECT_EQ(lossy.dropped(), 3U);
  EXPECT_EQ(lossy.name(), "memory:b");
}

}  // namespace
}  // namespace sf::ethercat
