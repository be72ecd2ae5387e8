// Bus against a scripted link: every frame sent comes back with each
// datagram's WKC set to 1 and its data filled with 0xAB, unless the script
// says to lose it, to deliver a stale frame first, or to mangle it.
#include "sf/ethercat/master/bus.hpp"

#include <deque>
#include <random>

#include <gtest/gtest.h>

namespace sf::ethercat::master {
namespace {

class ScriptedLink final : public Link {
 public:
  int lose_next = 0;                // frames swallowed
  bool stale_first = false;         // deliver an old frame before the answer
  bool truncate = false;            // answer with a cut frame
  std::mt19937* garbage = nullptr;  // answer with random bytes
  std::size_t sent = 0;

  Status send(ByteSpan frame) override {
    ++sent;
    if (lose_next > 0) {
      --lose_next;
      return {};
    }
    if (garbage != nullptr) {
      Bytes junk(std::uniform_int_distribution<std::size_t>(0, 1600)((*garbage)));
      for (auto& byte : junk) {
        byte = static_cast<std::uint8_t>((*garbage)());
      }
      // Keep the index byte sometimes, so the junk gets past the matching.
      if (junk.size() > Bus::kFirstIndexOffset && ((*garbage)() & 1U) != 0) {
        junk[Bus::kFirstIndexOffset] = frame[Bus::kFirstIndexOffset];
      }
      queue_.push_back(std::move(junk));
      return {};
    }
    auto decoded = decode(frame);
    if (!decoded) {
      return decoded.error();
    }
    auto answer = *decoded;
    for (auto& d : answer.datagrams) {
      std::fill(d.data.begin(), d.data.end(), 0xAB);
      d.wkc = 1;
    }
    if (stale_first) {
      auto stale = answer;
      stale.datagrams[0].index = static_cast<std::uint8_t>(stale.datagrams[0].index - 1);
      queue_.push_back(*encode(stale));
      stale_first = false;
    }
    auto bytes = *encode(answer);
    if (truncate) {
      bytes.resize(kEthernetHeaderSize + kEcatHeaderSize + 4);
    }
    queue_.push_back(std::move(bytes));
    return {};
  }
  Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds) override {
    if (queue_.empty()) {
      return std::size_t{0};
    }
    auto f = std::move(queue_.front());
    queue_.pop_front();
    const auto n = std::min(f.size(), buf.size());  // a link never writes past buf
    std::copy_n(f.begin(), n, buf.begin());
    return n;
  }
  [[nodiscard]] MacAddress mac() const override { return {2, 0, 0, 0, 0, 1}; }
  [[nodiscard]] std::string name() const override { return "scripted"; }

 private:
  std::deque<Bytes> queue_;
};

class BusTest : public ::testing::Test {
 protected:
  ScriptedLink link;
  ManualClock clock;
  Bus bus{link, clock, BusOptions{std::chrono::milliseconds{1}, 2}};
};

TEST_F(BusTest, ReadReturnsDataAndWkc) {
  std::array<std::uint8_t, 4> out{};
  auto wkc = bus.read(Command::FPRD, Datagram::physical(0x1001, 0x0130), out);
  ASSERT_TRUE(wkc.ok()) << wkc.error().describe();
  EXPECT_EQ(*wkc, 1);
  EXPECT_EQ(out[0], 0xAB);
  auto v = bus.fprd<std::uint16_t>(0x1001, 0x0130);
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(*v, 0xABAB);
}

TEST_F(BusTest, LostFrameIsResent) {
  link.lose_next = 2;
  std::array<std::uint8_t, 2> out{};
  auto wkc = bus.read(Command::BRD, 0, out);
  ASSERT_TRUE(wkc.ok()) << wkc.error().describe();
  EXPECT_EQ(link.sent, 3U);
  EXPECT_EQ(bus.counters().frames_lost, 2U);
}

TEST_F(BusTest, FrameLostMoreThanRetriesIsATimeout) {
  link.lose_next = 3;
  std::array<std::uint8_t, 2> out{};
  auto wkc = bus.read(Command::BRD, 0, out);
  ASSERT_FALSE(wkc.ok());
  EXPECT_EQ(wkc.error().code, Errc::timeout);
  EXPECT_NE(wkc.error().message.find("BRD"), std::string::npos) << wkc.error().message;
}

TEST_F(BusTest, StaleFrameIsSkipped) {
  link.stale_first = true;
  std::array<std::uint8_t, 2> out{};
  auto wkc = bus.read(Command::BRD, 0, out);
  ASSERT_TRUE(wkc.ok());
  EXPECT_EQ(bus.counters().frames_discarded, 1U);
  EXPECT_EQ(link.sent, 1U);
}

TEST_F(BusTest, TruncatedAnswerIsAnErrorNotACrash) {
  link.truncate = true;
  std::array<std::uint8_t, 8> out{};
  auto wkc = bus.read(Command::FPRD, Datagram::physical(0x1001, 0x0000), out);
  ASSERT_FALSE(wkc.ok());
}

TEST_F(BusTest, SeveralDatagramsShareOneFrame) {
  std::array<Datagram, 2> two{
      Datagram{Command::FPRD, 0, Datagram::physical(0x1001, 0x10), 0, false, Bytes(2), 0},
      Datagram{Command::FPRD, 0, Datagram::physical(0x1002, 0x10), 0, false, Bytes(2), 0}};
  ASSERT_TRUE(bus.transceive(two).ok());
  EXPECT_EQ(link.sent, 1U);
  EXPECT_EQ(two[0].wkc, 1);
  EXPECT_EQ(two[1].data[1], 0xAB);
}

TEST_F(BusTest, ReadOneInsistsOnOneAnswer) {
  link.lose_next = 0;
  std::array<std::uint8_t, 2> data{};
  // The scripted link answers every datagram with WKC 1: a read_one passes...
  EXPECT_TRUE(bus.read_one(Command::FPRD, 0x1001, 0x0010, data).ok());
  // ...and an empty datagram list is refused up front.
  EXPECT_FALSE(bus.transceive(std::span<Datagram>{}).ok());
}

TEST_F(BusTest, GarbageAnswersAreErrorsNeverCrashes) {
  std::mt19937 rng(42);
  link.garbage = &rng;
  int failures = 0;
  for (int i = 0; i < 2000; ++i) {
    std::array<std::uint8_t, 16> out{};
    auto wkc = bus.read(Command::FPRD, Datagram::physical(0x1001, 0x0130), out);
    failures += wkc.ok() ? 0 : 1;
  }
  EXPECT_EQ(failures, 2000);
}

}  // namespace
}  // namespace sf::ethercat::master
