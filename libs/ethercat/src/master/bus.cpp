#include "sf/ethercat/master/bus.hpp"

#include <algorithm>
#include <array>

#include <fmt/format.h>

namespace sf::ethercat::master {
namespace {

// A link that keeps delivering stale frames must not keep us waiting forever.
constexpr int kMaxDiscardsPerWait = 16;

std::string describe(const Datagram& d) {
  if (addressing_of(d.command) == Addressing::logical) {
    return fmt::format("{} 0x{:08x}", to_string(d.command), d.address);
  }
  return fmt::format("{} 0x{:04x}:0x{:04x}", to_string(d.command), d.adp(), d.ado());
}

}  // namespace

Bus::Bus(Link& link, Clock& clock, BusOptions options)
    : link_(link), clock_(clock), options_(options), rx_(kMaxFrameSize + 64) {}

Status Bus::transceive(std::span<Datagram> datagrams, int retries) {
  if (datagrams.empty()) {
    return make_error(Errc::invalid_argument, "transceive: no datagrams");
  }
  std::lock_guard lock(mutex_);
  for (int attempt = 0; attempt <= retries; ++attempt) {
    bool lost = false;
    auto st = transceive_once(datagrams, lost);
    if (!lost) {
      return st;
    }
  }
  return make_error(Errc::timeout,
                    fmt::format("frame with {} lost {} times", describe(datagrams.front()), retries + 1));
}

Status Bus::transceive_once(std::span<Datagram> datagrams, bool& lost) {
  Frame frame;
  frame.source = link_.mac();
  frame.datagrams.assign(datagrams.begin(), datagrams.end());
  const std::uint8_t index = next_index();
  for (auto& d : frame.datagrams) {
    d.index = index;
  }
  auto encoded = encode(frame);
  if (!encoded) {
    return encoded.error();
  }
  SF_TRY(send_raw(*encoded));
  auto n = receive_raw(rx_, index);
  if (!n) {
    return n.error();
  }
  if (*n == 0) {
    lost = true;
    return {};
  }
  auto back = decode(ByteSpan{rx_.data(), *n});
  if (!back) {
    return back.error().with_context("returned frame");
  }
  if (back->datagrams.size() != datagrams.size()) {
    return make_error(Errc::malformed, fmt::format("returned frame has {} datagrams, sent {}",
                                                   back->datagrams.size(), datagrams.size()));
  }
  for (std::size_t i = 0; i < datagrams.size(); ++i) {
    auto& got = back->datagrams[i];
    if (got.command != datagrams[i].command || got.data.size() != datagrams[i].data.size()) {
      return make_error(Errc::malformed,
                        fmt::format("returned datagram {} does not match {}", i, describe(datagrams[i])));
    }
    datagrams[i].data = std::move(got.data);
    datagrams[i].wkc = got.wkc;
  }
  return {};
}

Result<std::uint16_t> Bus::read(Command command, std::uint32_t address, MutableByteSpan out) {
  Datagram d;
  d.command = command;
  d.address = address;
  d.data.assign(out.size(), 0);
  std::array<Datagram, 1> one{std::move(d)};
  SF_TRY(transceive(one));
  std::copy(one[0].data.begin(), one[0].data.end(), out.begin());
  return one[0].wkc;
}

Result<std::uint16_t> Bus::write(Command command, std::uint32_t address, ByteSpan data) {
  Datagram d;
  d.command = command;
  d.address = address;
  d.data.assign(data.begin(), data.end());
  std::array<Datagram, 1> one{std::move(d)};
  SF_TRY(transceive(one));
  return one[0].wkc;
}

Status Bus::read_one(Command command, std::uint16_t adp, std::uint16_t ado, MutableByteSpan out) {
  auto wkc = read(command, Datagram::physical(adp, ado), out);
  if (!wkc) {
    return wkc.error();
  }
  if (*wkc != 1) {
    return make_error(Errc::remote, fmt::format("{} slave 0x{:04x} register 0x{:04x}: WKC {} (expected 1)",
                                                to_string(command), adp, ado, *wkc));
  }
  return {};
}

Status Bus::write_one(Command command, std::uint16_t adp, std::uint16_t ado, ByteSpan data) {
  auto wkc = write(command, Datagram::physical(adp, ado), data);
  if (!wkc) {
    return wkc.error();
  }
  if (*wkc != 1) {
    return make_error(Errc::remote, fmt::format("{} slave 0x{:04x} register 0x{:04x}: WKC {} (expected 1)",
                                                to_string(command), adp, ado, *wkc));
  }
  return {};
}

Status Bus::send_raw(ByteSpan frame) {
  ++counters_.frames_sent;
  return link_.send(frame);
}

Result<std::size_t> Bus::receive_raw(MutableByteSpan buf, std::uint8_t index) {
  for (int i = 0; i < kMaxDiscardsPerWait; ++i) {
    auto n = link_.receive(buf, options_.frame_timeout);
    if (!n) {
      return n.error();
    }
    if (*n == 0) {
      ++counters_.frames_lost;
      return std::size_t{0};
    }
    if (*n > kFirstIndexOffset && buf[kFirstIndexOffset] == index) {
      return *n;
    }
    ++counters_.frames_discarded;
  }
  ++counters_.frames_lost;
  return std::size_t{0};
}

}  // namespace sf::ethercat::master
