// SII EEPROM access through the ESC's EEPROM interface (ET1100 datasheet II
// §9, registers 0x0500–0x050F): EtherCAT takes the EEPROM (0x0500 = 0), writes
// the word address (0x0504) and the read command (0x0502), polls until the
// busy bit clears, then reads 4 or 8 bytes from 0x0508 (0x0502 bit 6 says
// which).
#include <algorithm>
#include <array>

#include <fmt/format.h>

#include "poll.hpp"
#include "sf/ethercat/master/master.hpp"

namespace sf::ethercat::master {
namespace {

constexpr std::uint16_t kSiiErrors =
    reg::sii_control::kAcknowledgeError | reg::sii_control::kChecksumError | reg::sii_control::kLoadError;
// Upper bound of what we read: 64 KiB (a 512 KiBit EEPROM).
constexpr std::size_t kMaxSiiBytes = std::size_t{64} * 1024;
// Bytes read between two checks for the end of the category chain.
constexpr std::size_t kSiiChunkBytes = 128;

}  // namespace

Result<Bytes> Master::read_sii(std::size_t position, std::uint32_t word_address, std::size_t words) {
  if (position >= slaves_.size()) {
    return make_error(Errc::invalid_argument, fmt::format("no slave at position {}", position));
  }
  std::lock_guard lock(bus_.mutex());
  const std::uint16_t station = slaves_[position].station;
  SF_TRY(bus_.fpwr<std::uint8_t>(station, reg::kSiiConfiguration, 0));

  Bytes out;
  out.reserve(words * 2 + 8);
  std::uint16_t status = 0;
  auto not_busy = [&]() -> Result<bool> {
    auto s = bus_.fprd<std::uint16_t>(station, reg::kSiiControlStatus);
    if (!s) {
      return s.error();
    }
    status = *s;
    return (status & reg::sii_control::kBusy) == 0;
  };
  while (out.size() < words * 2) {
    SF_TRY(detail::poll_until(clock_, options_.eeprom_timeout, options_.poll_interval, "SII busy", not_busy));
    const auto address = static_cast<std::uint32_t>(word_address + out.size() / 2);
    // Address first, then the command (one frame, in this order): the ESC
    // starts the read on the command write.
    std::array<Datagram, 2> start{
        Datagram{Command::FPWR, 0, Datagram::physical(station, reg::kSiiAddress), 0, false, Bytes(4), 0},
        Datagram{Command::FPWR, 0, Datagram::physical(station, reg::kSiiControlStatus), 0, false, Bytes(2),
                 0}};
    store_le<std::uint32_t>(start[0].data.data(), address);
    store_le<std::uint16_t>(start[1].data.data(), reg::sii_control::kCommandRead);
    SF_TRY(bus_.transceive(start));
    if (start[0].wkc != 1 || start[1].wkc != 1) {
      return make_error(Errc::remote,
                        fmt::format("SII read at word 0x{:04x}: slave 0x{:04x} did not take the command",
                                    address, station));
    }
    SF_TRY(detail::poll_until(clock_, options_.eeprom_timeout, options_.poll_interval, "SII read", not_busy));
    if ((status & kSiiErrors) != 0) {
      return make_error(
          Errc::remote,
          fmt::format(
              "SII read at word 0x{:04x}: EEPROM status 0x{:04x}{}", address, status,
              (status & reg::sii_control::kAcknowledgeError) != 0 ? " (acknowledge/command error)" : ""));
    }
    const std::size_t chunk = (status & reg::sii_control::kRead8Bytes) != 0 ? 8 : 4;
    std::array<std::uint8_t, 8> data{};
    SF_TRY(bus_.read_one(Command::FPRD, station, reg::kSiiData, MutableByteSpan{data.data(), chunk}));
    out.insert(out.end(), data.begin(), data.begin() + static_cast<std::ptrdiff_t>(chunk));
  }
  out.resize(words * 2);
  return out;
}

Result<Bytes> Master::read_sii_image(std::size_t position) {
  auto image = read_sii(position, 0, sii::kFixedAreaBytes / 2);
  if (!image) {
    return image;
  }
  // Word 0x3E: EEPROM size in KiBit − 1; never read past it.
  const std::size_t eeprom_bytes = std::min(
      kMaxSiiBytes,
      (static_cast<std::size_t>(load_le<std::uint16_t>(&(*image)[std::size_t{2} * sii::kSize])) + 1) * 128);
  while (image->size() < eeprom_bytes) {
    auto length = sii_image_length(*image);
    if (!length) {
      return length.error().with_context("SII category chain");
    }
    if (length->has_value()) {
      image->resize(**length);
      return image;
    }
    const auto chunk = std::min(kSiiChunkBytes, eeprom_bytes - image->size());
    auto more = read_sii(position, static_cast<std::uint32_t>(image->size() / 2), chunk / 2);
    if (!more) {
      return more;
    }
    image->insert(image->end(), more->begin(), more->end());
  }
  // No end marker within the EEPROM: parse_sii accepts a partial chain.
  return image;
}

}  // namespace sf::ethercat::master
