// Frame codec: hand-assembled frames for every command, round trips, padding,
// the M-bit chain, and every way a frame can be truncated or inconsistent.
#include "sf/ethercat/frame.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace sf::ethercat {
namespace {

using ::testing::HasSubstr;

constexpr MacAddress kSrc{0x02, 0x11, 0x22, 0x33, 0x44, 0x55};

// Ethernet header (broadcast → kSrc, EtherType 0x88A4) + EtherCAT header.
Bytes ethernet_and_ecat_header(std::uint16_t ecat_length, std::uint8_t type = 1) {
  Bytes b(16);
  std::copy(kBroadcastMac.begin(), kBroadcastMac.end(), b.begin());
  std::copy(kSrc.begin(), kSrc.end(), b.begin() + 6);
  b[12] = 0x88;  // EtherType, big-endian
  b[13] = 0xA4;
  store_le<std::uint16_t>(b.data() + 14, static_cast<std::uint16_t>(ecat_length | (type << 12U)));
  return b;
}

// One datagram assembled byte by byte from ETG.1000.4 Table 13.
Bytes datagram_bytes(std::uint8_t cmd, std::uint8_t idx, std::array<std::uint8_t, 4> addr, ByteSpan data,
                     bool more, std::uint16_t wkc, bool circulating = false, std::uint16_t irq = 0) {
  Bytes b{cmd, idx, addr[0], addr[1], addr[2], addr[3]};
  const auto len =
      static_cast<std::uint16_t>(data.size() | (circulating ? 0x4000U : 0U) | (more ? 0x8000U : 0U));
  b.push_back(static_cast<std::uint8_t>(len & 0xFFU));
  b.push_back(static_cast<std::uint8_t>(len >> 8U));
  b.push_back(static_cast<std::uint8_t>(irq & 0xFFU));
  b.push_back(static_cast<std::uint8_t>(irq >> 8U));
  b.insert(b.end(), data.begin(), data.end());
  b.push_back(static_cast<std::uint8_t>(wkc & 0xFFU));
  b.push_back(static_cast<std::uint8_t>(wkc >> 8U));
  return b;
}

Bytes single_datagram_frame(std::uint8_t cmd, std::array<std::uint8_t, 4> addr, ByteSpan data,
                            std::uint16_t wkc) {
  Bytes f = ethernet_and_ecat_header(static_cast<std::uint16_t>(12 + data.size()));
  const Bytes d = datagram_bytes(cmd, 0x5A, addr, data, false, wkc);
  f.insert(f.end(), d.begin(), d.end());
  return f;
}

Frame one(Datagram d) {
  Frame f;
  f.source = kSrc;
  f.datagrams.push_back(std::move(d));
  return f;
}

// --- every command, hand-assembled --------------------------------------------

struct CommandCase {
  Command command;
  std::uint8_t code;
  const char* name;
  Addressing addressing;
  bool reads;
  bool writes;
};

class EveryCommand : public ::testing::TestWithParam<CommandCase> {};

TEST_P(EveryCommand, DecodesHandAssembledFrameAndEncodesItBack) {
  const auto& c = GetParam();
  const Bytes data{0xDE, 0xAD, 0xBE, 0xEF, 0x01};
  // ADP 0xFFFE (auto-increment position -2 / station 0xFFFE), ADO 0x0130;
  // for logical commands the same 4 bytes are logical address 0x0130FFFE.
  const Bytes wire = single_datagram_frame(c.code, {0xFE, 0xFF, 0x30, 0x01}, data, 0x0102);
  ASSERT_LT(wire.size(), kMinFrameSize);  // unpadded on purpose

  auto frame = decode(wire);
  ASSERT_TRUE(frame) << frame.error().describe();
  ASSERT_EQ(frame->datagrams.size(), 1U);
  const Datagram& d = frame->datagrams[0];
  EXPECT_EQ(d.command, c.command);
  EXPECT_EQ(d.index, 0x5A);
  EXPECT_EQ(d.address, 0x0130FFFEU);
  EXPECT_EQ(d.adp(), 0xFFFE);
  EXPECT_EQ(d.ado(), 0x0130);
  EXPECT_EQ(d.data, data);
  EXPECT_EQ(d.wkc, 0x0102);
  EXPECT_FALSE(d.circulating);
  EXPECT_EQ(frame->source, kSrc);
  EXPECT_EQ(frame->destination, kBroadcastMac);

  auto encoded = encode(*frame);
  ASSERT_TRUE(encoded) << encoded.error().describe();
  ASSERT_EQ(encoded->size(), kMinFrameSize);
  EXPECT_TRUE(std::equal(wire.begin(), wire.end(), encoded->begin()));
  EXPECT_TRUE(std::all_of(encoded->begin() + static_cast<std::ptrdiff_t>(wire.size()), encoded->end(),
                          [](std::uint8_t b) { return b == 0; }));

  EXPECT_EQ(to_string(c.command), c.name);
  EXPECT_EQ(command_from_string(c.name), c.command);
  EXPECT_EQ(addressing_of(c.command), c.addressing);
  EXPECT_EQ(reads(c.command), c.reads);
  EXPECT_EQ(writes(c.command), c.writes);
}

INSTANTIATE_TEST_SUITE_P(
    Etg1000_4_Table12, EveryCommand,
    ::testing::Values(CommandCase{Command::NOP, 0, "NOP", Addressing::none, false, false},
                      CommandCase{Command::APRD, 1, "APRD", Addressing::auto_increment, true, false},
                      CommandCase{Command::APWR, 2, "APWR", Addressing::auto_increment, false, true},
                      CommandCase{Command::APRW, 3, "APRW", Addressing::auto_increment, true, true},
                      CommandCase{Command::FPRD, 4, "FPRD", Addressing::configured, true, false},
                      CommandCase{Command::FPWR, 5, "FPWR", Addressing::configured, false, true},
                      CommandCase{Command::FPRW, 6, "FPRW", Addressing::configured, true, true},
                      CommandCase{Command::BRD, 7, "BRD", Addressing::broadcast, true, false},
                      CommandCase{Command::BWR, 8, "BWR", Addressing::broadcast, false, true},
                      CommandCase{Command::BRW, 9, "BRW", Addressing::broadcast, true, true},
                      CommandCase{Command::LRD, 10, "LRD", Addressing::logical, true, false},
                      CommandCase{Command::LWR, 11, "LWR", Addressing::logical, false, true},
                      CommandCase{Command::LRW, 12, "LRW", Addressing::logical, true, true},
                      CommandCase{Command::ARMW, 13, "ARMW", Addressing::auto_increment, true, true},
                      CommandCase{Command::FRMW, 14, "FRMW", Addressing::configured, true, true}),
    [](const auto& p) { return std::string(p.param.name); });

TEST(Command, NamesAreCaseInsensitiveAndUnknownNamesAreRejected) {
  EXPECT_EQ(command_from_string("lrw"), Command::LRW);
  EXPECT_EQ(command_from_string("Armw"), Command::ARMW);
  EXPECT_EQ(command_from_string("LRWX"), std::nullopt);
  EXPECT_EQ(command_from_string(""), std::nullopt);
  EXPECT_EQ(to_string(static_cast<Command>(15)), "INVALID");
  EXPECT_FALSE(reads(static_cast<Command>(200)));
  EXPECT_EQ(addressing_of(static_cast<Command>(200)), Addressing::none);
}

// --- encoding details ----------------------------------------------------------

TEST(Encode, ChainsDatagramsWithTheMoreBitAndSumsTheHeaderLength) {
  Frame f;
  f.datagrams.push_back({Command::BRD, 1, Datagram::physical(0, 0x0130), 0, false, Bytes(2), 0});
  f.datagrams.push_back({Command::LRW, 2, 0x00010000, 0x1234, true, Bytes{1, 2, 3}, 7});
  auto bytes = encode(f);
  ASSERT_TRUE(bytes);
  // EtherCAT header length = (12 + 2) + (12 + 3) = 29, type 1.
  EXPECT_EQ(load_le<std::uint16_t>(bytes->data() + 14), 29U | 0x1000U);
  // First datagram: M set; second: M clear, C set.
  EXPECT_EQ(load_le<std::uint16_t>(bytes->data() + 16 + 6), 2U | 0x8000U);
  EXPECT_EQ(load_le<std::uint16_t>(bytes->data() + 16 + 14 + 6), 3U | 0x4000U);
  EXPECT_EQ(load_le<std::uint16_t>(bytes->data() + 16 + 14 + 8), 0x1234U);  // IRQ

  auto back = decode(*bytes);
  ASSERT_TRUE(back) << back.error().describe();
  EXPECT_EQ(*back, f);
}

TEST(Encode, FrameSizeCountsHeadersAndDatagramOverhead) {
  const std::array<std::size_t, 2> lens{2, 3};
  EXPECT_EQ(frame_size(lens), 14U + 2U + 14U + 15U);
  EXPECT_EQ(frame_size({}), 16U);
  const std::array<std::size_t, 1> max{kMaxDatagramData};
  EXPECT_EQ(frame_size(max), kMaxFrameSize);
}

TEST(Encode, LargestSingleDatagramFitsExactly) {
  auto bytes = encode(one({Command::LRW, 0, 0, 0, false, Bytes(kMaxDatagramData, 0xAA), 0}));
  ASSERT_TRUE(bytes) << bytes.error().describe();
  EXPECT_EQ(bytes->size(), kMaxFrameSize);
  auto back = decode(*bytes);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->datagrams[0].data.size(), kMaxDatagramData);
}

TEST(Encode, RejectsOversizedAndEmptyFrames) {
  auto too_long = encode(one({Command::LWR, 0, 0, 0, false, Bytes(kMaxDatagramLength + 1), 0}));
  ASSERT_FALSE(too_long);
  EXPECT_EQ(too_long.error().code, Errc::invalid_argument);
  EXPECT_THAT(too_long.error().message, HasSubstr("11-bit"));

  Frame big;
  big.datagrams.assign(2, Datagram{Command::LRD, 0, 0, 0, false, Bytes(800), 0});
  auto too_big = encode(big);
  ASSERT_FALSE(too_big);
  EXPECT_EQ(too_big.error().code, Errc::limit_exceeded);

  EXPECT_FALSE(encode(Frame{}));
  EXPECT_FALSE(encode(one({static_cast<Command>(15), 0, 0, 0, false, {}, 0})));
}

TEST(Encode, IntoBufferChecksRoomAndPads) {
  const Frame f = one({Command::FPRD, 3, Datagram::physical(0x1001, 0x0130), 0, false, Bytes(2), 0});
  std::array<std::uint8_t, 59> small{};
  auto n = encode_into(f, small);
  ASSERT_FALSE(n);
  EXPECT_EQ(n.error().code, Errc::out_of_range);

  std::array<std::uint8_t, 100> buf;
  buf.fill(0xCC);
  n = encode_into(f, buf);
  ASSERT_TRUE(n);
  EXPECT_EQ(*n, kMinFrameSize);
  EXPECT_EQ(buf[59], 0);     // padding is zeroed
  EXPECT_EQ(buf[60], 0xCC);  // nothing written past the frame
}

// --- decoding of wire variations ----------------------------------------------

TEST(Decode, IgnoresEthernetPadding) {
  Bytes wire = single_datagram_frame(4, {0x01, 0x10, 0x30, 0x01}, Bytes{0x02, 0x00}, 1);
  wire.resize(kMinFrameSize, 0x00);
  auto f = decode(wire);
  ASSERT_TRUE(f) << f.error().describe();
  EXPECT_EQ(f->datagrams[0].data, (Bytes{0x02, 0x00}));
}

TEST(Decode, AcceptsOneVlanTag) {
  Bytes wire = single_datagram_frame(7, {0, 0, 0, 0}, Bytes{0, 0}, 3);
  const Bytes tag{0x81, 0x00, 0x20, 0x05};
  wire.insert(wire.begin() + 12, tag.begin(), tag.end());
  auto f = decode(wire);
  ASSERT_TRUE(f) << f.error().describe();
  EXPECT_EQ(f->datagrams[0].command, Command::BRD);
  EXPECT_EQ(f->datagrams[0].wkc, 3);
}

TEST(Decode, KeepsCirculatingBitAndIrq) {
  Bytes f = ethernet_and_ecat_header(14);
  const Bytes d = datagram_bytes(1, 9, {0, 0, 0x10, 0}, Bytes{0xAB, 0xCD}, false, 0, true, 0x0204);
  f.insert(f.end(), d.begin(), d.end());
  auto frame = decode(f);
  ASSERT_TRUE(frame);
  EXPECT_TRUE(frame->datagrams[0].circulating);
  EXPECT_EQ(frame->datagrams[0].irq, 0x0204);
}

TEST(Decode, ParsesAChainOfThreeDatagrams) {
  Bytes f = ethernet_and_ecat_header(12 * 3 + 1 + 0 + 4);
  for (const Bytes& d : {datagram_bytes(7, 1, {0, 0, 0x30, 1}, Bytes{0x11}, true, 5),
                         datagram_bytes(0, 2, {0, 0, 0, 0}, Bytes{}, true, 0),
                         datagram_bytes(12, 3, {0, 0, 1, 0}, Bytes{1, 2, 3, 4}, false, 9)}) {
    f.insert(f.end(), d.begin(), d.end());
  }
  auto frame = decode(f);
  ASSERT_TRUE(frame) << frame.error().describe();
  ASSERT_EQ(frame->datagrams.size(), 3U);
  EXPECT_EQ(frame->datagrams[1].command, Command::NOP);
  EXPECT_TRUE(frame->datagrams[1].data.empty());
  EXPECT_EQ(frame->datagrams[2].wkc, 9);
}

// --- malformed frames --------------------------------------------------------

Error decode_error(const Bytes& wire) {
  auto f = decode(wire);
  EXPECT_FALSE(f);
  return f ? Error{} : f.error();
}

TEST(DecodeErrors, TooShortForHeaders) {
  const Bytes full = ethernet_and_ecat_header(12);
  for (std::size_t n = 0; n <= full.size(); ++n) {
    const Bytes wire(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n));
    EXPECT_EQ(decode_error(wire).code, Errc::malformed) << n;
  }
}

TEST(DecodeErrors, WrongEtherTypeAndHeaderType) {
  Bytes wire = single_datagram_frame(1, {0, 0, 0, 0}, Bytes(2), 0);
  Bytes ipv4 = wire;
  ipv4[12] = 0x08;
  ipv4[13] = 0x00;
  EXPECT_THAT(decode_error(ipv4).message, HasSubstr("0x0800"));

  Bytes mailbox_gateway = wire;
  mailbox_gateway[15] = static_cast<std::uint8_t>((mailbox_gateway[15] & 0x0FU) | 0x50U);
  const Error e = decode_error(mailbox_gateway);
  EXPECT_EQ(e.code, Errc::unsupported);
  EXPECT_THAT(e.message, HasSubstr("type 5"));
}

TEST(DecodeErrors, HeaderLengthBeyondFrame) {
  Bytes wire = single_datagram_frame(1, {0, 0, 0, 0}, Bytes(2), 0);
  wire[14] = 15;  // one more than the 14 bytes present
  EXPECT_THAT(decode_error(wire).message, HasSubstr("exceeds"));
}

TEST(DecodeErrors, ZeroHeaderLength) {
  Bytes wire = single_datagram_frame(1, {0, 0, 0, 0}, Bytes(2), 0);
  wire[14] = 0;
  EXPECT_THAT(decode_error(wire).message, HasSubstr("no datagrams"));
}

TEST(DecodeErrors, TruncatedDatagramDataNamesTheDatagram) {
  Bytes f = ethernet_and_ecat_header(12 + 2 + 12 + 4);
  for (const Bytes& d : {datagram_bytes(7, 1, {0, 0, 0, 0}, Bytes(2), true, 0),
                         datagram_bytes(4, 2, {0, 0, 0, 0}, Bytes(4), false, 0)}) {
    f.insert(f.end(), d.begin(), d.end());
  }
  f[16 + 14 + 6] = 40;  // datagram 1 claims 40 data bytes
  const Error e = decode_error(f);
  EXPECT_THAT(e.message, HasSubstr("datagram 1 (FPRD)"));
  EXPECT_THAT(e.message, HasSubstr("data length 40"));
}

TEST(DecodeErrors, MoreBitWithNothingAfter) {
  Bytes f = ethernet_and_ecat_header(14);
  const Bytes d = datagram_bytes(7, 1, {0, 0, 0, 0}, Bytes(2), true, 0);
  f.insert(f.end(), d.begin(), d.end());
  EXPECT_THAT(decode_error(f).message, HasSubstr("M (more) bit"));
}

TEST(DecodeErrors, MoreBitIntoPaddingIsNotADatagram) {
  // M is set but the EtherCAT length covers only the first datagram: the
  // padding after it must not be parsed as a second datagram.
  Bytes f = ethernet_and_ecat_header(14);
  const Bytes d = datagram_bytes(7, 1, {0, 0, 0, 0}, Bytes(2), true, 0);
  f.insert(f.end(), d.begin(), d.end());
  f.resize(kMinFrameSize, 0);
  EXPECT_THAT(decode_error(f).message, HasSubstr("M (more) bit"));
}

TEST(DecodeErrors, HeaderLengthLongerThanTheChain) {
  Bytes f = ethernet_and_ecat_header(14 + 12);
  const Bytes d = datagram_bytes(7, 1, {0, 0, 0, 0}, Bytes(2), false, 0);
  f.insert(f.end(), d.begin(), d.end());
  f.resize(f.size() + 12, 0);
  EXPECT_THAT(decode_error(f).message, HasSubstr("no M bit"));
}

TEST(DecodeErrors, DatagramHeaderCutShort) {
  Bytes f = ethernet_and_ecat_header(14 + 8);
  const Bytes d = datagram_bytes(7, 1, {0, 0, 0, 0}, Bytes(2), true, 0);
  f.insert(f.end(), d.begin(), d.end());
  f.resize(f.size() + 8, 0);
  EXPECT_THAT(decode_error(f).message, HasSubstr("datagram 1: header and WKC need 12 bytes, only 8"));
}

TEST(DecodeErrors, UnknownCommand) {
  const Bytes wire = single_datagram_frame(0x20, {0, 0, 0, 0}, Bytes(2), 0);
  EXPECT_THAT(decode_error(wire).message, HasSubstr("unknown command 32"));
}

// --- in-place views --------------------------------------------------------------

TEST(DatagramViews, ExposeAndModifyTheFrameInPlace) {
  Frame f;
  f.datagrams.push_back({Command::APRD, 1, Datagram::physical(0, 0x0000), 0, false, Bytes(2), 0});
  f.datagrams.push_back({Command::LRW, 2, 0x00010000, 0, false, Bytes{1, 2, 3}, 0});
  Bytes wire = encode(f).value();

  auto views = datagram_views(wire);
  ASSERT_TRUE(views) << views.error().describe();
  ASSERT_EQ(views->size(), 2U);
  DatagramView& aprd = (*views)[0];
  EXPECT_EQ(aprd.command(), Command::APRD);
  EXPECT_TRUE(aprd.more());
  EXPECT_FALSE((*views)[1].more());
  // What an ESC does: increment ADP, insert data, bump the WKC.
  aprd.set_adp(static_cast<std::uint16_t>(aprd.adp() + 1));
  aprd.data()[0] = 0x11;
  aprd.add_wkc(1);
  (*views)[1].data()[2] = 0x33;
  (*views)[1].add_wkc(3);

  auto back = decode(wire);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->datagrams[0].adp(), 1);
  EXPECT_EQ(back->datagrams[0].data, (Bytes{0x11, 0}));
  EXPECT_EQ(back->datagrams[0].wkc, 1);
  EXPECT_EQ(back->datagrams[1].data, (Bytes{1, 2, 0x33}));
  EXPECT_EQ(back->datagrams[1].wkc, 3);
}

// The shared walk: datagrams in order with their places, the chain's bounds, trailing bytes
// inside the EtherCAT length visible to callers (the codec refuses them, an ESC ignores them).
TEST(ForEachDatagram, VisitsEveryDatagramInOrderAndReportsTheChain) {
  Bytes wire = ethernet_and_ecat_header(12 + 2 + 12 + 3 + 4);  // two datagrams and 4 bytes more
  const Bytes first = datagram_bytes(7, 1, {0, 0, 0, 0}, Bytes(2), true, 0);
  const Bytes second = datagram_bytes(12, 2, {0, 0, 1, 0}, Bytes{1, 2, 3}, false, 0);
  wire.insert(wire.end(), first.begin(), first.end());
  wire.insert(wire.end(), second.begin(), second.end());
  wire.insert(wire.end(), {0, 0, 0, 0});
  std::vector<std::pair<std::size_t, std::size_t>> seen;
  auto chain = for_each_datagram(wire, [&](const DatagramSpan& d) { seen.emplace_back(d.offset, d.length); });
  ASSERT_TRUE(chain) << chain.error().describe();
  EXPECT_EQ(seen, (std::vector<std::pair<std::size_t, std::size_t>>{{16, 2}, {30, 3}}));
  EXPECT_EQ(chain->count, 2U);
  EXPECT_EQ(chain->body, 16U);
  EXPECT_EQ(chain->end, 45U);
  EXPECT_EQ(chain->declared, 33U);
  EXPECT_FALSE(decode(wire));  // the codec wants the length filled exactly

  wire[16 + 6] = 100;  // the first datagram now claims more data than there is
  seen.clear();
  auto bad = for_each_datagram(wire, [&](const DatagramSpan& d) { seen.emplace_back(d.offset, d.length); });
  ASSERT_FALSE(bad);
  EXPECT_THAT(bad.error().message, HasSubstr("datagram 0"));
  EXPECT_TRUE(seen.empty());
}

TEST(DatagramViews, RejectMalformedFramesWithoutTouchingThem) {
  Bytes wire = single_datagram_frame(1, {0, 0, 0, 0}, Bytes(2), 0);
  wire[16 + 6] = 100;
  const Bytes before = wire;
  auto views = datagram_views(wire);
  ASSERT_FALSE(views);
  EXPECT_THAT(views.error().message, HasSubstr("datagram 0"));
  EXPECT_EQ(wire, before);
}

}  // namespace
}  // namespace sf::ethercat
