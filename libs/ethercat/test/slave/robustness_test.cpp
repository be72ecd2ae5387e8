// Bad input must give a clear error or be ignored, never crash or touch
// memory out of bounds: random frames, random mailbox messages, datagrams at
// the edges of the address space. (Run under the asan preset to catch reads.)
#include <gtest/gtest.h>

#include <random>

#include "sf/ethercat/slave/devices.hpp"
#include "slave_test_support.hpp"

namespace sf::ethercat::slave {
namespace {

using testing::Harness;

TEST(Robustness, RandomFramesNeitherCrashNorBreakTheSegment) {
  Harness h("servo:1,digital-io:1,smart-controller:1");
  std::mt19937 rng(1234);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<std::size_t> length(0, kMaxFrameSize + 4);
  for (int i = 0; i < 3000; ++i) {
    Bytes frame(length(rng));
    for (auto& b : frame)
      b = static_cast<std::uint8_t>(byte(rng));
    if (frame.size() >= 16 && i % 2 == 0) {
      // Make half of them EtherCAT with a random header, so datagram parsing runs.
      frame[12] = 0x88;
      frame[13] = 0xA4;
      frame[15] = static_cast<std::uint8_t>((frame[15] & 0x07) | 0x10);
    }
    (void)h.segment->process(frame);
  }
  // Still a working segment.
  EXPECT_EQ(h.run(Harness::physical(Command::BRD, 0, reg::kType, Bytes(1))).wkc, 3);
}

TEST(Robustness, DatagramsAtTheEndOfTheAddressSpace) {
  Harness h("servo:1");
  h.assign_stations();
  auto d = h.fprd(Harness::station(0), 0xFFF0, 64);
  EXPECT_EQ(d.wkc, 1);
  EXPECT_EQ(d.data, Bytes(64, 0));
  EXPECT_EQ(h.fpwr(Harness::station(0), 0xFFF0, Bytes(64, 0xAB)), 1);
  // Logical access that maps past 0xFFFF.
  FmmuConfig c = FmmuConfig::bytes(0, 0xFFF8, 16, kFmmuRead | kFmmuWrite);
  const auto bytes = c.encode();
  ASSERT_EQ(h.fpwr(Harness::station(0), reg::fmmu(0), Bytes(bytes.begin(), bytes.end())), 1);
  EXPECT_EQ(h.run(Harness::make(Command::LRW, 0, Bytes(16, 1))).wkc, 3);
  // A bit-wise FMMU at the very last bit.
  c = FmmuConfig{};
  c.logical_start = 0x100;
  c.length = 2;
  c.logical_start_bit = 7;
  c.logical_stop_bit = 0;
  c.physical_start = 0xFFFF;
  c.physical_start_bit = 7;
  c.type = kFmmuRead | kFmmuWrite;
  c.active = true;
  const auto bits = c.encode();
  ASSERT_EQ(h.fpwr(Harness::station(0), reg::fmmu(1), Bytes(bits.begin(), bits.end())), 1);
  (void)h.run(Harness::make(Command::LRW, 0x100, Bytes(2, 0xFF)));
  // Mailbox and 3-buffer SMs at the end of memory.
  h.write_sm(0, 6, 0xFFF0, 0x100, 0x04);
  (void)h.fpwr(Harness::station(0), 0xFFF0, Bytes(16, 1));
  (void)h.fprd(Harness::station(0), 0xFFF0, 16);
}

TEST(Robustness, RandomMailboxMessagesGetAnswersOrErrors) {
  Harness h("servo:1");
  h.assign_stations();
  h.configure_mailbox(0);
  ASSERT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::PreOp));
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> byte(0, 255);
  int answered = 0;
  for (int i = 0; i < 2000; ++i) {
    Bytes m(kMailboxSize);
    for (auto& b : m)
      b = static_cast<std::uint8_t>(byte(rng));
    if (i % 2 == 0) {
      // A plausible header: CoE, length within the mailbox, SDO request service.
      store_le<std::uint16_t>(&m[0], static_cast<std::uint16_t>(m[0] % (kMailboxSize - 6)));
      m[5] = 0x03;
      m[7] = static_cast<std::uint8_t>((m[7] & 0x0F) | 0x20);
    }
    ASSERT_EQ(h.fpwr(Harness::station(0), kMailboxOutStart, m), 1) << i;
    while (h.run(Harness::physical(Command::FPRD, Harness::station(0), kMailboxInStart, Bytes(kMailboxSize)))
               .wkc == 1) {
      ++answered;
    }
  }
  EXPECT_GT(answered, 1000);
  // The SDO server still works.
  auto msg = *make_sdo_request(SdoInitiateUploadRequest{0x1000, 0, false}, 1);
  msg.resize(kMailboxSize);
  ASSERT_EQ(h.fpwr(Harness::station(0), kMailboxOutStart, msg), 1);
  auto reply =
      h.run(Harness::physical(Command::FPRD, Harness::station(0), kMailboxInStart, Bytes(kMailboxSize)));
  ASSERT_EQ(reply.wkc, 1);
  auto coe = decode_coe(reply.data);
  ASSERT_TRUE(coe.ok());
  auto response = decode_sdo_response(coe->body);
  ASSERT_TRUE(response.ok());
  EXPECT_TRUE(std::holds_alternative<SdoInitiateUploadResponse>(*response));
}

}  // namespace
}  // namespace sf::ethercat::slave
