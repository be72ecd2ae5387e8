// RawSocketLink on a veth pair inside a private network namespace created for
// the test (lo does not reliably carry EtherType 0x88A4). Needs root.
#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "sf/ethercat/frame.hpp"
#include "sf/ethercat/link.hpp"

namespace sf::ethercat {
namespace {

using ::testing::HasSubstr;
using namespace std::chrono_literals;

bool run(const std::string& cmd) {
  return std::system((cmd + " >/dev/null 2>&1").c_str()) == 0;
}

// A network namespace holding a veth pair "<p>a" <-> "<p>b", removed on destruction.
class VethNamespace {
 public:
  VethNamespace() {
    const std::string id = std::to_string(::getpid() % 100000);
    ns_ = "sfcommon-" + id;
    a_ = "sfa" + id;
    b_ = "sfb" + id;
    ok_ = run("ip netns add " + ns_) &&
          run("ip link add " + a_ + " netns " + ns_ + " type veth peer name " + b_ + " netns " + ns_) &&
          run("ip -n " + ns_ + " link set " + a_ + " up") &&
          run("ip -n " + ns_ + " link set " + b_ + " up") && carrier_up(a_) && carrier_up(b_);
  }
  ~VethNamespace() { run("ip netns del " + ns_); }
  VethNamespace(const VethNamespace&) = delete;
  VethNamespace& operator=(const VethNamespace&) = delete;

  [[nodiscard]] bool ok() const { return ok_; }
  [[nodiscard]] const std::string& a() const { return a_; }
  [[nodiscard]] const std::string& b() const { return b_; }

  // Runs fn on a thread that has entered the namespace: sockets it creates
  // stay in the namespace after the thread ends.
  template <typename F>
  void inside(F&& fn) const {
    std::thread t([&] {
      const int fd = ::open(("/var/run/netns/" + ns_).c_str(), O_RDONLY | O_CLOEXEC);
      ASSERT_GE(fd, 0);
      ASSERT_EQ(::setns(fd, CLONE_NEWNET), 0);
      ::close(fd);
      fn();
    });
    t.join();
  }

 private:
  // A veth end reports its carrier some time after `link set up`, later on a loaded machine; a
  // frame sent before that is dropped without an error, so the test waits for operstate UP.
  [[nodiscard]] bool carrier_up(const std::string& dev) const {
    for (int i = 0; i < 250; ++i) {
      if (run("ip -n " + ns_ + " link show dev " + dev + " | grep -q 'state UP'")) {
        return true;
      }
      std::this_thread::sleep_for(20ms);
    }
    return false;
  }

  std::string ns_, a_, b_;
  bool ok_ = false;
};

Bytes ecat_frame(MacAddress src, std::uint8_t index) {
  Frame f;
  f.source = src;
  f.datagrams.push_back({Command::APRD, index, Datagram::physical(0, 0x0000), 0, false, Bytes(2), 0});
  return encode(f).value();
}

// Links on both ends of the pair (null if one could not be opened).
std::pair<std::unique_ptr<RawSocketLink>, std::unique_ptr<RawSocketLink>> open_pair(
    VethNamespace& ns, RawSocketOptions options_a, RawSocketOptions options_b) {
  std::pair<std::unique_ptr<RawSocketLink>, std::unique_ptr<RawSocketLink>> out;
  ns.inside([&] {
    auto a = RawSocketLink::open(ns.a(), options_a);
    auto b = RawSocketLink::open(ns.b(), options_b);
    EXPECT_TRUE(a) << a.error().describe();
    EXPECT_TRUE(b) << b.error().describe();
    if (a && b) {
      out = {std::move(*a), std::move(*b)};
    }
  });
  return out;
}

TEST(RawSocketLink, ExchangesFramesOverAVethPair) {
  if (::geteuid() != 0) {
    GTEST_SKIP() << "needs root (CAP_NET_ADMIN for ip netns, CAP_NET_RAW for AF_PACKET)";
  }
  VethNamespace ns;
  ASSERT_TRUE(ns.ok()) << "could not create netns/veth with ip(8)";
  auto [a, b] = open_pair(ns, {}, {});
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->name(), ns.a());
  EXPECT_GT(a->interface_index(), 0);
  EXPECT_NE(a->mac(), MacAddress{});

  std::array<std::uint8_t, kMaxFrameSize> buf{};
  for (std::uint8_t i = 0; i < 3; ++i) {
    const Bytes sent = ecat_frame(a->mac(), i);
    ASSERT_TRUE(a->send(sent));
    auto n = b->receive(buf, 2s);
    ASSERT_TRUE(n) << n.error().describe();
    ASSERT_EQ(*n, sent.size());
    EXPECT_EQ(Bytes(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(*n)), sent);
  }
  // The sender does not see its own frames (PACKET_OUTGOING is skipped).
  auto own = a->receive(buf, 50ms);
  ASSERT_TRUE(own);
  EXPECT_EQ(*own, 0U);

  // And back the other way, the way a slave segment answers.
  ASSERT_TRUE(b->send(ecat_frame(b->mac(), 9)));
  auto back = a->receive(buf, 2s);
  ASSERT_TRUE(back);
  EXPECT_EQ(buf[17], 9);

  // A receive buffer too small for the frame is an error, not a silent cut.
  ASSERT_TRUE(a->send(ecat_frame(a->mac(), 1)));
  std::array<std::uint8_t, 20> small{};
  auto cut = b->receive(small, 2s);
  ASSERT_FALSE(cut);
  EXPECT_EQ(cut.error().code, Errc::out_of_range);
}

TEST(RawSocketLink, BusyPollReceivesAndStillTimesOut) {
  if (::geteuid() != 0) {
    GTEST_SKIP() << "needs root (CAP_NET_ADMIN for ip netns, CAP_NET_RAW for AF_PACKET)";
  }
  VethNamespace ns;
  ASSERT_TRUE(ns.ok()) << "could not create netns/veth with ip(8)";
  // a spins longer than its receive timeouts, b only briefly.
  auto [a, b] = open_pair(ns, RawSocketOptions{std::chrono::milliseconds{100}},
                          RawSocketOptions{std::chrono::microseconds{20}});
  ASSERT_TRUE(a && b);
  std::array<std::uint8_t, kMaxFrameSize> buf{};
  ASSERT_TRUE(b->send(ecat_frame(b->mac(), 5)));
  auto got = a->receive(buf, 2s);
  ASSERT_TRUE(got) << got.error().describe();
  EXPECT_EQ(buf[17], 5);
  // Nothing more comes: 0 after the timeout, spinning or sleeping.
  auto none = a->receive(buf, 5ms);
  ASSERT_TRUE(none);
  EXPECT_EQ(*none, 0U);
  ASSERT_TRUE(a->send(ecat_frame(a->mac(), 6)));
  auto later = b->receive(buf, 2s);  // past its spin: from ppoll
  ASSERT_TRUE(later);
  EXPECT_EQ(buf[17], 6);
  // Its own frames stay invisible to the sender while it spins.
  auto own = a->receive(buf, 5ms);
  ASSERT_TRUE(own);
  EXPECT_EQ(*own, 0U);
}

TEST(RawSocketLink, ErrorsNameTheInterface) {
  auto missing = RawSocketLink::open("sf-no-such-if");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().code, Errc::io);
  EXPECT_THAT(missing.error().message, HasSubstr("'sf-no-such-if'"));
  EXPECT_THAT(missing.error().message, HasSubstr("errno"));
  EXPECT_FALSE(RawSocketLink::open(""));
  EXPECT_FALSE(RawSocketLink::open("an-interface-name-that-is-too-long"));
}

}  // namespace
}  // namespace sf::ethercat
