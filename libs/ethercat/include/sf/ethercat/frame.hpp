// EtherCAT frame and datagram codec (ETG.1000.4 §5.3/§5.4; ET1100 datasheet
// section I "EtherCAT frame structure"). EtherType 0x88A4; the EtherCAT header
// carries an 11-bit length and a 4-bit type (1 = EtherCAT commands); each
// datagram is a 10-byte header, data, and a 16-bit working counter (WKC).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"

namespace sf::ethercat {

inline constexpr std::uint16_t kEtherType = 0x88A4;
inline constexpr std::size_t kEthernetHeaderSize = 14;
inline constexpr std::size_t kEcatHeaderSize = 2;
inline constexpr std::size_t kDatagramHeaderSize = 10;
inline constexpr std::size_t kWkcSize = 2;
inline constexpr std::size_t kDatagramOverhead = kDatagramHeaderSize + kWkcSize;
inline constexpr std::size_t kMinFrameSize = 60;    // without FCS; shorter frames are padded
inline constexpr std::size_t kMaxFrameSize = 1514;  // without FCS
// Largest data of one datagram in a single-datagram frame.
inline constexpr std::size_t kMaxDatagramData =
    kMaxFrameSize - kEthernetHeaderSize - kEcatHeaderSize - kDatagramOverhead;
inline constexpr std::uint8_t kEcatTypeCommands = 1;
// Datagram and EtherCAT-header lengths are 11-bit fields.
inline constexpr std::size_t kMaxDatagramLength = 0x7FF;
// IEEE 802.1Q tag: ETG.1000.4 allows one VLAN tag before the EtherType.
inline constexpr std::uint16_t kVlanEtherType = 0x8100;
inline constexpr std::size_t kVlanTagSize = 4;

using MacAddress = std::array<std::uint8_t, 6>;
inline constexpr MacAddress kBroadcastMac{0xff, 0xff, 0xff, 0xff, 0xff, 0xff};

// ETG.1000.4 Table 12: command types.
enum class Command : std::uint8_t {
  NOP = 0,
  APRD = 1,  // auto-increment physical read
  APWR = 2,
  APRW = 3,
  FPRD = 4,  // configured-address physical read
  FPWR = 5,
  FPRW = 6,
  BRD = 7,  // broadcast read
  BWR = 8,
  BRW = 9,
  LRD = 10,  // logical read
  LWR = 11,
  LRW = 12,
  ARMW = 13,  // auto-increment read, multiple write
  FRMW = 14,  // configured read, multiple write
};

std::string_view to_string(Command c);
std::optional<Command> command_from_string(std::string_view name);

enum class Addressing { none, auto_increment, configured, broadcast, logical };
Addressing addressing_of(Command c);
bool reads(Command c);   // data flows slave → master
bool writes(Command c);  // data flows master → slave

// One datagram as a value. For physical addressing, `address` packs the
// 16-bit position/station address (ADP, low half) and the 16-bit register
// offset (ADO, high half) exactly as on the wire; for logical addressing it
// is the 32-bit logical address.
struct Datagram {
  Command command = Command::NOP;
  std::uint8_t index = 0;
  std::uint32_t address = 0;
  std::uint16_t irq = 0;
  bool circulating = false;  // C bit: the frame has passed the master once
  Bytes data;
  std::uint16_t wkc = 0;

  [[nodiscard]] std::uint16_t adp() const { return static_cast<std::uint16_t>(address & 0xffffU); }
  [[nodiscard]] std::uint16_t ado() const { return static_cast<std::uint16_t>(address >> 16U); }
  static std::uint32_t physical(std::uint16_t adp, std::uint16_t ado) {
    return static_cast<std::uint32_t>(adp) | (static_cast<std::uint32_t>(ado) << 16U);
  }
  bool operator==(const Datagram&) const = default;
};

struct Frame {
  MacAddress destination = kBroadcastMac;
  MacAddress source{};
  std::vector<Datagram> datagrams;
  bool operator==(const Frame&) const = default;
};

// Size on the wire of a frame holding datagrams with these data lengths,
// before padding to kMinFrameSize.
std::size_t frame_size(std::span<const std::size_t> data_lengths);

// Encodes a frame (padded to 60 bytes). Fails if it exceeds kMaxFrameSize or
// a datagram exceeds 2047 bytes of data. The M (more) bit of every datagram
// but the last is set; EtherType, EtherCAT header length and type are filled in.
Result<Bytes> encode(const Frame& frame);
// The same into a caller's buffer (no allocation, for cyclic exchange);
// returns the number of bytes written (padded to kMinFrameSize).
Result<std::size_t> encode_into(const Frame& frame, MutableByteSpan out);
// Decodes a frame by its length fields; trailing padding is ignored, a
// truncated or inconsistent frame is an error that says where.
Result<Frame> decode(ByteSpan bytes);

// A zero-copy view of the datagrams inside a frame buffer, for code that must
// process a frame in place as an ESC does (read commands, insert data, bump
// WKCs) without decoding it.
class DatagramView {
 public:
  DatagramView(std::uint8_t* header, std::size_t length) : p_(header), len_(length) {}
  [[nodiscard]] Command command() const { return static_cast<Command>(p_[0]); }
  [[nodiscard]] std::uint8_t index() const { return p_[1]; }
  [[nodiscard]] std::uint32_t address() const { return load_le<std::uint32_t>(p_ + 2); }
  void set_address(std::uint32_t a) { store_le<std::uint32_t>(p_ + 2, a); }
  [[nodiscard]] std::uint16_t adp() const { return load_le<std::uint16_t>(p_ + 2); }
  void set_adp(std::uint16_t a) { store_le<std::uint16_t>(p_ + 2, a); }
  [[nodiscard]] std::uint16_t ado() const { return load_le<std::uint16_t>(p_ + 4); }
  [[nodiscard]] bool circulating() const { return (p_[7] & 0x40U) != 0; }
  [[nodiscard]] bool more() const { return (p_[7] & 0x80U) != 0; }
  [[nodiscard]] std::uint16_t irq() const { return load_le<std::uint16_t>(p_ + 8); }
  [[nodiscard]] MutableByteSpan data() const { return {p_ + kDatagramHeaderSize, len_}; }
  [[nodiscard]] std::uint16_t wkc() const { return load_le<std::uint16_t>(p_ + kDatagramHeaderSize + len_); }
  void set_wkc(std::uint16_t w) { store_le<std::uint16_t>(p_ + kDatagramHeaderSize + len_, w); }
  void add_wkc(std::uint16_t n) { set_wkc(static_cast<std::uint16_t>(wkc() + n)); }

 private:
  std::uint8_t* p_;
  std::size_t len_;
};

// Splits a frame buffer into datagram views, validating every length field
// first; nothing is modified. Errors say which datagram is wrong and why.
Result<std::vector<DatagramView>> datagram_views(MutableByteSpan frame);

// Where one datagram sits in a frame buffer (ETG.1000.4 §5.4): the offset of its header, its
// data length and its M (more) bit.
struct DatagramSpan {
  std::size_t offset = 0;
  std::size_t length = 0;
  bool more = false;
};

// A frame's datagram chain: where the datagrams start (after the EtherCAT header), the EtherCAT
// header's length, where the last datagram ends and how many there are. A frame whose datagrams
// end before the EtherCAT length (end < body + declared) carries trailing bytes.
struct DatagramChain {
  std::size_t body = 0;
  std::size_t declared = 0;
  std::size_t end = 0;
  std::size_t count = 0;
};

// The EtherCAT header of a frame: its offset (after the MAC addresses, an optional 802.1Q tag and
// EtherType 0x88A4, which is checked) and its value (length 10:0, type 15:12; ETG.1000.4 §5.3).
struct EcatHeader {
  std::size_t offset = 0;
  std::uint16_t value = 0;
  [[nodiscard]] std::size_t length() const { return value & 0x07FFU; }
  [[nodiscard]] unsigned type() const { return static_cast<unsigned>(value >> 12U); }
};
Result<EcatHeader> ecat_header(ByteSpan frame);

namespace detail {
// The chain's start and EtherCAT length, checked: EtherCAT commands, not empty, within `frame`.
Result<DatagramChain> chain_start(ByteSpan frame);
// Datagram number `index` whose header is at `pos`, checked against the chain's end.
Result<DatagramSpan> datagram_at(ByteSpan frame, std::size_t pos, const DatagramChain& chain);
}  // namespace detail

// Walks the datagram chain of a frame by the M bits and calls visit(const DatagramSpan&) for
// each in order, checking every length against the EtherCAT length and the buffer. Reads no
// byte outside `frame` and allocates nothing: the codec, the master and the emulated ESCs share
// it. An error may come after some datagrams were visited, so code that must not act on part
// of a malformed frame walks it once without acting first. Errors say which datagram is wrong.
template <typename Visit>
Result<DatagramChain> for_each_datagram(ByteSpan frame, Visit&& visit) {
  auto chain = detail::chain_start(frame);
  if (!chain) {
    return chain.error();
  }
  std::size_t pos = chain->body;
  for (bool more = true; more;) {
    auto datagram = detail::datagram_at(frame, pos, *chain);
    if (!datagram) {
      return datagram.error();
    }
    visit(static_cast<const DatagramSpan&>(*datagram));
    ++chain->count;
    more = datagram->more;
    pos = datagram->offset + kDatagramOverhead + datagram->length;
  }
  chain->end = pos;
  return chain;
}

}  // namespace sf::ethercat
