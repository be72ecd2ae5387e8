// EtherCAT frame codec: ETG.1000.4 §5.3 (frame structure) and §5.4
// (datagram structure); ET1100 datasheet section I §2 "EtherCAT protocol".
#include "sf/ethercat/frame.hpp"

#include <algorithm>
#include <array>
#include <cctype>

#include <fmt/format.h>

namespace sf::ethercat {
namespace {

// Datagram header byte offsets (ETG.1000.4 Table 13).
constexpr std::size_t kLenOffset = 6;
constexpr std::uint16_t kLenMask = 0x07FF;
constexpr std::uint16_t kCirculatingBit = 0x4000;
constexpr std::uint16_t kMoreBit = 0x8000;
// EtherCAT header (ETG.1000.4 Table 11): length bits 10:0, reserved bit 11, type bits 15:12.
constexpr unsigned kEcatTypeShift = 12;

struct CommandInfo {
  Command command;
  std::string_view name;
  Addressing addressing;
  bool reads;
  bool writes;
};

// ETG.1000.4 Table 12; ARMW/FRMW read at one slave and write at the others,
// so they count as both.
constexpr std::array<CommandInfo, 15> kCommands{{
    {Command::NOP, "NOP", Addressing::none, false, false},
    {Command::APRD, "APRD", Addressing::auto_increment, true, false},
    {Command::APWR, "APWR", Addressing::auto_increment, false, true},
    {Command::APRW, "APRW", Addressing::auto_increment, true, true},
    {Command::FPRD, "FPRD", Addressing::configured, true, false},
    {Command::FPWR, "FPWR", Addressing::configured, false, true},
    {Command::FPRW, "FPRW", Addressing::configured, true, true},
    {Command::BRD, "BRD", Addressing::broadcast, true, false},
    {Command::BWR, "BWR", Addressing::broadcast, false, true},
    {Command::BRW, "BRW", Addressing::broadcast, true, true},
    {Command::LRD, "LRD", Addressing::logical, true, false},
    {Command::LWR, "LWR", Addressing::logical, false, true},
    {Command::LRW, "LRW", Addressing::logical, true, true},
    {Command::ARMW, "ARMW", Addressing::auto_increment, true, true},
    {Command::FRMW, "FRMW", Addressing::configured, true, true},
}};

const CommandInfo* info(Command c) {
  const auto i = static_cast<std::size_t>(c);
  return i < kCommands.size() ? &kCommands[i] : nullptr;
}

// Checks that the datagrams fill the EtherCAT length exactly (ETG.1000.4 §5.3): the codec
// accepts no trailing bytes inside it.
Result<DatagramChain> walk_datagrams(ByteSpan bytes) {
  auto chain = for_each_datagram(bytes, [](const DatagramSpan&) {});
  if (chain && chain->end != chain->body + chain->declared) {
    return make_error(Errc::malformed,
                      fmt::format("datagrams end at byte {} (last datagram {} has no M bit) but "
                                  "the EtherCAT length says {}",
                                  chain->end - chain->body, chain->count - 1, chain->declared));
  }
  return chain;
}

Status check_encodable(const Frame& frame) {
  if (frame.datagrams.empty()) {
    return make_error(Errc::invalid_argument, "frame has no datagrams");
  }
  std::size_t total = kEthernetHeaderSize + kEcatHeaderSize;
  for (std::size_t i = 0; i < frame.datagrams.size(); ++i) {
    const auto& d = frame.datagrams[i];
    if (d.data.size() > kMaxDatagramLength) {
      return make_error(Errc::invalid_argument, fmt::format("datagram {}: {} data bytes exceed the 11-bit "
                                                            "length field (max {})",
                                                            i, d.data.size(), kMaxDatagramLength));
    }
    if (info(d.command) == nullptr) {
      return make_error(Errc::invalid_argument, fmt::format("datagram {}: command {} is not defined", i,
                                                            static_cast<unsigned>(d.command)));
    }
    total += kDatagramOverhead + d.data.size();
  }
  if (total > kMaxFrameSize) {
    return make_error(
        Errc::limit_exceeded,
        fmt::format("frame of {} bytes exceeds the Ethernet maximum of {}", total, kMaxFrameSize));
  }
  return {};
}

void write_frame(const Frame& frame, SpanWriter& w, std::size_t body_length) {
  w.bytes(frame.destination);
  w.bytes(frame.source);
  w.u8(static_cast<std::uint8_t>(kEtherType >> 8U));  // EtherType is big-endian
  w.u8(static_cast<std::uint8_t>(kEtherType & 0xFFU));
  w.u16(
      static_cast<std::uint16_t>(body_length | (static_cast<unsigned>(kEcatTypeCommands) << kEcatTypeShift)));
  for (std::size_t i = 0; i < frame.datagrams.size(); ++i) {
    const auto& d = frame.datagrams[i];
    const bool more = i + 1 < frame.datagrams.size();
    auto len = static_cast<std::uint16_t>(d.data.size());
    len = static_cast<std::uint16_t>(len | (d.circulating ? kCirculatingBit : 0U) | (more ? kMoreBit : 0U));
    w.u8(static_cast<std::uint8_t>(d.command));
    w.u8(d.index);
    w.u32(d.address);
    w.u16(len);
    w.u16(d.irq);
    w.bytes(d.data);
    w.u16(d.wkc);
  }
}

}  // namespace

Result<EcatHeader> ecat_header(ByteSpan bytes) {
  if (bytes.size() < kEthernetHeaderSize + kEcatHeaderSize) {
    return make_error(Errc::malformed, fmt::format("frame of {} bytes is shorter than the Ethernet and "
                                                   "EtherCAT headers ({} bytes)",
                                                   bytes.size(), kEthernetHeaderSize + kEcatHeaderSize));
  }
  std::size_t type_at = 12;
  std::uint16_t ethertype = static_cast<std::uint16_t>((bytes[12] << 8U) | bytes[13]);
  if (ethertype == kVlanEtherType) {
    type_at += kVlanTagSize;
    if (bytes.size() < type_at + 2 + kEcatHeaderSize) {
      return make_error(Errc::malformed, "VLAN-tagged frame truncated before the EtherCAT header");
    }
    ethertype = static_cast<std::uint16_t>((bytes[type_at] << 8U) | bytes[type_at + 1]);
  }
  if (ethertype != kEtherType) {
    return make_error(Errc::malformed, fmt::format("EtherType 0x{:04X} is not EtherCAT (0x88A4)", ethertype));
  }
  return EcatHeader{type_at + 2, load_le<std::uint16_t>(bytes.data() + type_at + 2)};
}

namespace detail {

Result<DatagramChain> chain_start(ByteSpan bytes) {
  auto header = ecat_header(bytes);
  if (!header) {
    return header.error();
  }
  if (header->type() != kEcatTypeCommands) {
    return make_error(Errc::unsupported,
                      fmt::format("EtherCAT header type {} is not 1 (EtherCAT commands)", header->type()));
  }
  DatagramChain chain;
  chain.body = header->offset + kEcatHeaderSize;
  chain.declared = header->length();
  if (chain.declared > bytes.size() - chain.body) {
    return make_error(Errc::malformed, fmt::format("EtherCAT header length {} exceeds the {} bytes after it",
                                                   chain.declared, bytes.size() - chain.body));
  }
  if (chain.declared == 0) {
    return make_error(Errc::malformed, "EtherCAT header length is 0: no datagrams");
  }
  return chain;
}

Result<DatagramSpan> datagram_at(ByteSpan bytes, std::size_t pos, const DatagramChain& chain) {
  const std::size_t end = chain.body + chain.declared;
  const std::size_t n = chain.count;
  if (end - pos < kDatagramOverhead) {
    return make_error(Errc::malformed,
                      fmt::format("datagram {}: header and WKC need {} bytes, only {} left of the "
                                  "EtherCAT length {}",
                                  n, kDatagramOverhead, end - pos, chain.declared));
  }
  const auto len_field = load_le<std::uint16_t>(bytes.data() + pos + kLenOffset);
  const std::size_t len = len_field & kLenMask;
  if (len > end - pos - kDatagramOverhead) {
    return make_error(Errc::malformed,
                      fmt::format("datagram {} ({}): data length {} exceeds the {} bytes left of the "
                                  "EtherCAT length {}",
                                  n, to_string(static_cast<Command>(bytes[pos])), len,
                                  end - pos - kDatagramOverhead, chain.declared));
  }
  const bool more = (len_field & kMoreBit) != 0;
  if (more && pos + kDatagramOverhead + len == end) {
    return make_error(Errc::malformed, fmt::format("datagram {}: M (more) bit set but the EtherCAT length "
                                                   "{} ends after it",
                                                   n, chain.declared));
  }
  return DatagramSpan{pos, len, more};
}

}  // namespace detail

std::string_view to_string(Command c) {
  const CommandInfo* i = info(c);
  return i != nullptr ? i->name : "INVALID";
}

std::optional<Command> command_from_string(std::string_view name) {
  for (const auto& i : kCommands) {
    if (std::equal(name.begin(), name.end(), i.name.begin(), i.name.end(), [](char a, char b) {
          return std::toupper(static_cast<unsigned char>(a)) == static_cast<unsigned char>(b);
        })) {
      return i.command;
    }
  }
  return std::nullopt;
}

Addressing addressing_of(Command c) {
  const CommandInfo* i = info(c);
  return i != nullptr ? i->addressing : Addressing::none;
}

bool reads(Command c) {
  const CommandInfo* i = info(c);
  return i != nullptr && i->reads;
}

bool writes(Command c) {
  const CommandInfo* i = info(c);
  return i != nullptr && i->writes;
}

std::size_t frame_size(std::span<const std::size_t> data_lengths) {
  std::size_t total = kEthernetHeaderSize + kEcatHeaderSize;
  for (const std::size_t n : data_lengths) {
    total += kDatagramOverhead + n;
  }
  return total;
}

Result<std::size_t> encode_into(const Frame& frame, MutableByteSpan out) {
  SF_TRY(check_encodable(frame));
  std::size_t body = 0;
  for (const auto& d : frame.datagrams) {
    body += kDatagramOverhead + d.data.size();
  }
  const std::size_t size = std::max(kEthernetHeaderSize + kEcatHeaderSize + body, kMinFrameSize);
  if (out.size() < size) {
    return make_error(Errc::out_of_range,
                      fmt::format("buffer of {} bytes too small for a frame of {} bytes", out.size(), size));
  }
  SpanWriter w(out.first(size));
  write_frame(frame, w, body);
  w.zeros(size - w.position());  // Ethernet padding
  return size;
}

Result<Bytes> encode(const Frame& frame) {
  Bytes out(kMaxFrameSize);
  auto n = encode_into(frame, out);
  if (!n) {
    return n.error();
  }
  out.resize(*n);
  return out;
}

Result<Frame> decode(ByteSpan bytes) {
  auto chain = walk_datagrams(bytes);
  if (!chain) {
    return chain.error().with_context("EtherCAT frame");
  }
  Frame frame;
  std::copy_n(bytes.begin(), 6, frame.destination.begin());
  std::copy_n(bytes.begin() + 6, 6, frame.source.begin());
  frame.datagrams.reserve(chain->count);
  std::optional<Error> unknown;  // the first datagram with an undefined command
  (void)for_each_datagram(bytes, [&](const DatagramSpan& s) {
    ByteReader r(bytes.subspan(s.offset, kDatagramOverhead + s.length));
    const std::uint8_t cmd = r.u8();
    if (info(static_cast<Command>(cmd)) == nullptr) {
      if (!unknown) {
        unknown = make_error(Errc::malformed, fmt::format("EtherCAT frame: datagram {}: unknown command {}",
                                                          frame.datagrams.size(), cmd));
      }
      return;
    }
    Datagram& d = frame.datagrams.emplace_back();
    d.command = static_cast<Command>(cmd);
    d.index = r.u8();
    d.address = r.u32();
    d.circulating = (r.u16() & kCirculatingBit) != 0;
    d.irq = r.u16();
    const ByteSpan data = r.bytes(s.length);
    d.data.assign(data.begin(), data.end());
    d.wkc = r.u16();
  });
  if (unknown) {
    return *unknown;
  }
  return frame;
}

Result<std::vector<DatagramView>> datagram_views(MutableByteSpan frame) {
  auto chain = walk_datagrams(frame);
  if (!chain) {
    return chain.error().with_context("EtherCAT frame");
  }
  std::vector<DatagramView> views;
  views.reserve(chain->count);
  (void)for_each_datagram(
      frame, [&](const DatagramSpan& s) { views.emplace_back(frame.data() + s.offset, s.length); });
  return views;
}

}  // namespace sf::ethercat
