// The master against a segment across EtherCAT-in-UDP on loopback (UdpLink):
// what `smartfactory plant` serves and `--iface udp:HOST:PORT` reaches.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "sf/ethercat/master/master.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/segment.hpp"

namespace sf::ethercat::master::test {
namespace {

TEST(UdpSegment, AMasterBringsASegmentBehindUdpToOp) {
  auto& clock = SteadyClock::instance();
  auto segment = slave::Segment::create("smart-controller:1,digital-io:1", clock);
  ASSERT_TRUE(segment.ok());
  auto server_link = UdpLink::listen("127.0.0.1", 0);
  ASSERT_TRUE(server_link) << server_link.error().describe();
  ASSERT_NE((*server_link)->local_port(), 0);
  slave::SegmentRunner server(**segment, **server_link, std::chrono::microseconds{200});
  ASSERT_TRUE(server.start().ok());

  auto link = open_link("udp:127.0.0.1:" + std::to_string((*server_link)->local_port()));
  ASSERT_TRUE(link) << link.error().describe();
  MasterOptions o;
  o.bus.frame_timeout =
      std::chrono::milliseconds{500};  // a loaded machine may not run the segment's thread for a while
  o.dc_static_drift_frames = 100;
  o.dc_static_drift_interval = std::chrono::microseconds{10};
  Master master(**link, clock, o);
  ASSERT_EQ(*master.scan(), 2U);
  auto st = master.bring_up();
  ASSERT_TRUE(st.ok()) << st.error().describe();
  auto out = master.slave(1).entry(0x7000, 0);
  ASSERT_TRUE(out.ok());
  master.slave(1).set<std::uint8_t>(*out, 0xA5);
  bool delivered = false;
  for (int i = 0; i < 200 && !delivered; ++i) {
    delivered = master.exchange().ok();
  }
  EXPECT_TRUE(delivered);
  server.stop();
  auto lock = (*segment)->lock();
  EXPECT_EQ((*segment)->device<slave::DigitalIo>(1)->outputs(), 0xA5);
  EXPECT_EQ((*segment)->slave(0).state(), AlState::Op);
}

TEST(UdpSegment, DatagramsThatAreNotEtherCatAreSkipped) {
  auto link = UdpLink::listen("127.0.0.1", 0);
  ASSERT_TRUE(link);
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons((*link)->local_port());
  ::inet_pton(AF_INET, "127.0.0.1", &to.sin_addr);
  const std::uint8_t junk[][4] = {{0x01}, {0x10, 0x20, 0x00, 0x00}, {0xff, 0x17, 0x00, 0x00}};
  const std::size_t sizes[] = {1, 4, 4};  // too short; type 2; length past the payload
  for (std::size_t i = 0; i < 3; ++i) {
    ::sendto(fd, junk[i], sizes[i], 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);  // NOLINT
  }
  ::close(fd);
  std::array<std::uint8_t, kMaxFrameSize> buf{};
  auto n = (*link)->receive(buf, std::chrono::milliseconds{200});
  ASSERT_TRUE(n);
  EXPECT_EQ(*n, 0U);
  EXPECT_EQ((*link)->skipped(), 3U);
  // Nobody has sent a frame: the segment side has nobody to answer.
  EXPECT_FALSE((*link)->send(std::vector<std::uint8_t>(60, 0)));
}

// A frame that waited in the segment's socket longer than its maximum queue age is dropped, as a
// wire would have lost it; a fresh one is answered (src/link/arrival.hpp).
TEST(UdpSegment, AFrameThatWaitedLongerThanTheMaximumQueueAgeIsDropped) {
  auto segment_side = UdpLink::listen("127.0.0.1", 0, std::chrono::milliseconds{5});
  ASSERT_TRUE(segment_side) << segment_side.error().describe();
  auto master_side = UdpLink::connect("127.0.0.1", (*segment_side)->local_port());
  ASSERT_TRUE(master_side);
  Frame frame;
  frame.datagrams.push_back(Datagram{});
  frame.datagrams.back().command = Command::BRD;
  frame.datagrams.back().data.assign(2, 0);
  auto bytes = encode(frame);
  ASSERT_TRUE(bytes);
  std::array<std::uint8_t, kMaxFrameSize> buf{};

  // The segment's process not scheduled for 50 ms while a frame waits. The kernel turns arrival
  // stamps on a moment after the first socket asks (net_enable_timestamp() defers it), and a
  // datagram that came before is stamped when read: the first frames may pass.
  for (int i = 0; i < 40 && (*segment_side)->stale() == 0; ++i) {
    ASSERT_TRUE((*master_side)->send(*bytes));
    ::usleep(50'000);
    auto n = (*segment_side)->receive(buf, std::chrono::milliseconds{20});
    ASSERT_TRUE(n);
  }
  EXPECT_EQ((*segment_side)->stale(), 1U);

  ASSERT_TRUE((*master_side)->send(*bytes));
  auto n = (*segment_side)->receive(buf, std::chrono::seconds{5});
  ASSERT_TRUE(n);
  EXPECT_EQ(*n, bytes->size());
  EXPECT_EQ((*segment_side)->stale(), 1U);
  auto back = decode(ByteSpan{buf.data(), *n});
  ASSERT_TRUE(back);
  EXPECT_EQ(back->datagrams.size(), 1U);
}

TEST(UdpSegment, BadLinkSpecsAreRefused) {
  EXPECT_FALSE(open_link("udp:localhost:34980"));  // numeric addresses only
  EXPECT_FALSE(open_link("udp:127.0.0.1:0"));
  EXPECT_FALSE(open_link("udp:127.0.0.1:http"));
  EXPECT_FALSE(open_link("no-such-interface0"));
}

}  // namespace
}  // namespace sf::ethercat::master::test
