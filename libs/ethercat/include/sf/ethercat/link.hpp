// Link: how EtherCAT frames leave and enter the process. The master and the
// emulated segment never touch a socket directly (compare SOEM's oshw/nicdrv).
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/ethercat/frame.hpp"

namespace sf::ethercat {

class Link {
 public:
  virtual ~Link() = default;
  // Sends one complete Ethernet frame (header included, no FCS).
  virtual Status send(ByteSpan frame) = 0;
  // Receives one EtherCAT frame into buf, waiting up to timeout. Returns the
  // frame length, or 0 when the timeout passes first. Frames that are not
  // EtherCAT (EtherType 0x88A4) are skipped.
  virtual Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) = 0;
  [[nodiscard]] virtual MacAddress mac() const = 0;
  [[nodiscard]] virtual std::string name() const = 0;
};

// True if `frame` is an Ethernet frame carrying EtherType 0x88A4 (directly
// or behind one 802.1Q tag).
bool is_ethercat_frame(ByteSpan frame);

// ---------------------------------------------------------------------------
// In-memory link pair: what one end sends, the other receives. Each direction
// is a bounded queue; send() on a full queue fails (limit_exceeded) rather than
// blocking, so a stalled peer shows up as an error. Thread-safe: one thread
// may send while another receives. Destroying one end makes the other's
// receive() fail with Errc::state once its queue is drained.
// ---------------------------------------------------------------------------
struct MemoryLinkPair {
  std::unique_ptr<Link> a;
  std::unique_ptr<Link> b;
};
struct MemoryLinkOptions {
  std::size_t capacity = 256;  // frames queued per direction
  MacAddress mac_a{0x02, 0x00, 0x00, 0x00, 0x00, 0x01};
  MacAddress mac_b{0x02, 0x00, 0x00, 0x00, 0x00, 0x02};
  std::string name = "memory";  // ends are named "<name>:a" and "<name>:b"
};
MemoryLinkPair make_memory_link_pair(const MemoryLinkOptions& options = {});

// ---------------------------------------------------------------------------
// Raw Ethernet on a named interface (AF_PACKET, SOCK_RAW, bound to ETH_P_ECAT
// 0x88A4, promiscuous). Frames this socket sent itself (PACKET_OUTGOING) are
// ignored. Needs CAP_NET_RAW. Errors name the interface and errno.
// ---------------------------------------------------------------------------
struct RawSocketOptions {
  // receive() spins on non-blocking reads for up to this long before it
  // sleeps in ppoll(): a frame that comes back within it is taken without
  // waiting for the thread to be woken (the way SOEM's and KickCAT's receive
  // loops wait), at the price of a busy core meanwhile. 0: always sleep.
  std::chrono::nanoseconds busy_poll{0};
  // A frame that waited in the socket longer than this is dropped (stale()): a segment emulated in
  // a process answers only what a wire would have carried (src/link/arrival.hpp). 0: no limit.
  std::chrono::nanoseconds max_queue_age{0};
};

class RawSocketLink final : public Link {
 public:
  static Result<std::unique_ptr<RawSocketLink>> open(const std::string& interface,
                                                     RawSocketOptions options = {});
  ~RawSocketLink() override;
  RawSocketLink(const RawSocketLink&) = delete;
  RawSocketLink& operator=(const RawSocketLink&) = delete;

  Status send(ByteSpan frame) override;
  Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) override;
  [[nodiscard]] MacAddress mac() const override { return mac_; }
  [[nodiscard]] std::string name() const override { return interface_; }
  [[nodiscard]] int interface_index() const { return ifindex_; }
  // Frames dropped for their time in the socket (RawSocketOptions::max_queue_age).
  [[nodiscard]] std::uint64_t stale() const { return stale_.load(); }

 private:
  RawSocketLink(int fd, int ifindex, std::string interface, MacAddress mac, RawSocketOptions options)
      : fd_(fd), ifindex_(ifindex), interface_(std::move(interface)), mac_(mac), options_(options) {}
  // One non-blocking read: a frame's length, nothing (none waiting, or one
  // that is not for us), or an error.
  Result<std::optional<std::size_t>> read_frame(MutableByteSpan buf);

  int fd_;
  int ifindex_;
  std::string interface_;
  MacAddress mac_;
  RawSocketOptions options_;
  std::atomic<std::uint64_t> stale_{0};
};

// ---------------------------------------------------------------------------
// UdpLink: EtherCAT frames in UDP datagrams (IEC 61158-4-12 / ETG.1000.4
// "EtherCAT frame in UDP/IP": the EtherCAT header and its datagrams are the
// payload of a UDP datagram to port 0x88A4), so a master and an emulated
// segment in different processes meet on loopback without CAP_NET_RAW.
// The Link still carries whole Ethernet frames: send() strips the Ethernet
// header (and a VLAN tag), receive() puts a synthetic one back (destination
// this link's MAC, source the peer's, EtherType 0x88A4). Datagrams that are
// not EtherCAT (too short, header type not 1, length past the payload) are
// skipped and counted.
// ---------------------------------------------------------------------------
class UdpLink final : public Link {
 public:
  static constexpr std::uint16_t kPort = 0x88A4;  // 34980

  // Master side: sends to host:port and receives the replies from there.
  static Result<std::unique_ptr<UdpLink>> connect(const std::string& host, std::uint16_t port = kPort);
  // Segment side: listens on host:port (0 = a free port) and replies to
  // whoever sent the last frame. A frame that waited in the socket longer than
  // max_queue_age is dropped (stale(); src/link/arrival.hpp); 0: no limit.
  static Result<std::unique_ptr<UdpLink>> listen(const std::string& host, std::uint16_t port = kPort,
                                                 std::chrono::nanoseconds max_queue_age = {});
  ~UdpLink() override;
  UdpLink(const UdpLink&) = delete;
  UdpLink& operator=(const UdpLink&) = delete;

  Status send(ByteSpan frame) override;
  Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) override;
  [[nodiscard]] MacAddress mac() const override { return mac_; }
  [[nodiscard]] std::string name() const override;
  [[nodiscard]] std::uint16_t local_port() const { return local_port_; }
  [[nodiscard]] std::uint64_t skipped() const { return skipped_.load(); }
  [[nodiscard]] std::uint64_t stale() const { return stale_.load(); }

 private:
  struct Peer;
  UdpLink(int fd, bool listening, std::uint16_t local_port, std::string name);

  int fd_;
  bool listening_;
  std::uint16_t local_port_;
  std::string name_;
  MacAddress mac_;
  std::unique_ptr<Peer> peer_;
  std::mutex peer_mutex_;
  std::chrono::nanoseconds max_queue_age_{0};
  std::atomic<std::uint64_t> skipped_{0};
  std::atomic<std::uint64_t> stale_{0};
};

// A link from a command-line spec: "udp:HOST:PORT" (a UdpLink to a segment
// listening there; PORT defaults to 0x88A4) or an interface name (a
// RawSocketLink with `raw_options`).
Result<std::unique_ptr<Link>> open_link(const std::string& spec, RawSocketOptions raw_options = {});

// ---------------------------------------------------------------------------
// PcapTap: a Link decorator that records every frame sent and received into a
// classic pcap file (LINKTYPE_ETHERNET = 1) readable by Wireshark/tshark.
// Timestamps come from clock.utc_now(), so tests with a ManualClock produce
// reproducible files. Each record is flushed as it is written.
// ---------------------------------------------------------------------------
enum class PcapResolution { microseconds, nanoseconds };

class PcapTap final : public Link {
 public:
  static Result<std::unique_ptr<PcapTap>> open(std::unique_ptr<Link> inner, const std::filesystem::path& file,
                                               const Clock& clock,
                                               PcapResolution resolution = PcapResolution::nanoseconds);
  ~PcapTap() override;
  PcapTap(const PcapTap&) = delete;
  PcapTap& operator=(const PcapTap&) = delete;

  Status send(ByteSpan frame) override;
  Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) override;
  [[nodiscard]] MacAddress mac() const override { return inner_->mac(); }
  [[nodiscard]] std::string name() const override { return inner_->name(); }

  [[nodiscard]] Link& inner() { return *inner_; }
  [[nodiscard]] std::uint64_t frames_written() const { return frames_written_.load(); }

 private:
  PcapTap(std::unique_ptr<Link> inner, std::FILE* file, const Clock& clock, PcapResolution resolution)
      : inner_(std::move(inner)), file_(file), clock_(&clock), resolution_(resolution) {}
  Status record(ByteSpan frame);

  std::unique_ptr<Link> inner_;
  std::FILE* file_;
  const Clock* clock_;
  PcapResolution resolution_;
  std::mutex mutex_;
  std::atomic<std::uint64_t> frames_written_{0};
};

// One record of a pcap file, as read back by read_pcap().
struct PcapRecord {
  Clock::utc_time timestamp;
  std::uint32_t original_length = 0;
  Bytes data;
};
struct PcapFile {
  PcapResolution resolution = PcapResolution::microseconds;
  std::uint32_t linktype = 0;
  std::uint32_t snaplen = 0;
  std::vector<PcapRecord> records;
};
// Reads a classic pcap file (either resolution, little- or big-endian).
Result<PcapFile> read_pcap(const std::filesystem::path& file);

// ---------------------------------------------------------------------------
// LossyLink: a decorator that drops frames with a given probability, from a
// seeded generator so a test's losses are repeatable. Dropped sends report
// success (the frame is "lost on the wire"); dropped receives are discarded
// and receive() keeps waiting for the rest of its timeout.
// ---------------------------------------------------------------------------
struct LossyLinkOptions {
  double send_drop_probability = 0.0;
  double receive_drop_probability = 0.0;
  std::uint64_t seed = 1;
};

class LossyLink final : public Link {
 public:
  LossyLink(std::unique_ptr<Link> inner, LossyLinkOptions options);
  // Drops in both directions with the same probability.
  LossyLink(std::unique_ptr<Link> inner, double drop_probability, std::uint64_t seed)
      : LossyLink(std::move(inner), LossyLinkOptions{drop_probability, drop_probability, seed}) {}

  Status send(ByteSpan frame) override;
  Result<std::size_t> receive(MutableByteSpan buf, std::chrono::nanoseconds timeout) override;
  [[nodiscard]] MacAddress mac() const override { return inner_->mac(); }
  [[nodiscard]] std::string name() const override { return inner_->name(); }

  [[nodiscard]] Link& inner() { return *inner_; }
  [[nodiscard]] std::uint64_t dropped_sent() const { return dropped_sent_.load(); }
  [[nodiscard]] std::uint64_t dropped_received() const { return dropped_received_.load(); }
  [[nodiscard]] std::uint64_t dropped() const { return dropped_sent() + dropped_received(); }

 private:
  bool drop(double probability);

  std::unique_ptr<Link> inner_;
  LossyLinkOptions options_;
  std::mutex mutex_;
  std::mt19937_64 rng_;
  std::atomic<std::uint64_t> dropped_sent_{0};
  std::atomic<std::uint64_t> dropped_received_{0};
};

}  // namespace sf::ethercat
