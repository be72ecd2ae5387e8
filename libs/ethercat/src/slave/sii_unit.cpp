#include "sii_unit.hpp"

#include <algorithm>

#include "sf/ethercat/registers.hpp"
#include "sf/ethercat/sii.hpp"

namespace sf::ethercat::slave::detail {

namespace sc = reg::sii_control;

void SiiUnit::load(Bytes image, bool read_8_bytes, SiiTiming timing) {
  // The size the EEPROM declares in word 0x3E (KiBit − 1), at least 1 KiBit;
  // doubled while the image would not fit.
  std::size_t size = 128;
  if (image.size() > 2U * sii::kSize + 1U) {
    size = std::max<std::size_t>(
        size, (std::size_t{load_le<std::uint16_t>(image.data() + 2U * sii::kSize)} + 1U) * 128U);
  }
  while (size < image.size()) {
    size *= 2;
  }
  image.resize(size, 0xFF);
  image_ = std::move(image);
  read8_ = read_8_bytes;
  timing_ = timing;
}

void SiiUnit::power_on(EscMemory& m) {
  busy_ = false;
  command_ = 0;
  std::fill(m.at(reg::kSiiConfiguration), m.at(reg::kSiiData + 8U), std::uint8_t{0});
  std::uint16_t status = 0;
  if (read8_) {
    status |= sc::kRead8Bytes;
  }
  if (image_.size() > 2048) {  // more than 16 KiBit: two address bytes (datasheet II 0x0502 bit 7)
    status |= sc::kTwoAddressBytes;
  }
  if (image_.size() < 16 || sii::checksum(ByteSpan(image_).first(14)) != image_[2U * sii::kChecksum]) {
    // ESC configuration area not loaded: "device information not available".
    status |= sc::kChecksumError | sc::kLoadError;
    m.put<std::uint16_t>(reg::kSiiControlStatus, status);
    return;
  }
  m.put<std::uint16_t>(reg::kSiiControlStatus, status);
  auto word = [&](std::uint16_t w) { return load_le<std::uint16_t>(image_.data() + 2U * w); };
  m.put<std::uint16_t>(reg::kPdiControl, word(sii::kPdiControl));
  m.put<std::uint16_t>(reg::kPdiConfiguration, word(sii::kPdiConfiguration));
  m.put<std::uint16_t>(reg::kPdiConfiguration + 2U, word(sii::kPdiConfiguration2));
  m.put<std::uint16_t>(reg::kDcPulseLength, word(sii::kSyncImpulseLength));
  m.put<std::uint16_t>(reg::kStationAlias, word(sii::kStationAlias));
}

void SiiUnit::set_status(EscMemory& m, std::uint16_t set, std::uint16_t clear) {
  auto v = m.get<std::uint16_t>(reg::kSiiControlStatus);
  v = static_cast<std::uint16_t>((v | set) & ~clear);
  m.put<std::uint16_t>(reg::kSiiControlStatus, v);
}

void SiiUnit::on_control_written(EscMemory& m, std::uint16_t written, std::int64_t now_ns) {
  // Write enable (bit 0) is self-clearing: it only counts together with the
  // write command in the same access.
  const bool write_enable = (written & sc::kWriteEnable) != 0;
  const auto command = static_cast<std::uint16_t>(written & sc::kCommandMask);
  set_status(m, 0, sc::kWriteEnable | sc::kCommandMask);
  switch (command) {
    case 0:  // "no command / EEPROM idle (clear error bits)"
      set_status(m, 0, sc::kAcknowledgeError | sc::kWriteEnableError);
      return;
    case sc::kCommandRead:
    case sc::kCommandWrite:
    case sc::kCommandReload:
      break;
    default:  // invalid command
      set_status(m, sc::kAcknowledgeError, 0);
      return;
  }
  set_status(m, 0, sc::kAcknowledgeError | sc::kWriteEnableError);
  if (command == sc::kCommandWrite && !write_enable) {
    set_status(m, sc::kWriteEnableError, 0);
    return;
  }
  address_ = m.get<std::uint32_t>(reg::kSiiAddress);
  if (command != sc::kCommandReload && address_ >= words()) {
    // The EEPROM does not acknowledge an address past its end.
    set_status(m, sc::kAcknowledgeError, 0);
    return;
  }
  command_ = command;
  write_word_ = m.get<std::uint16_t>(reg::kSiiData);
  busy_ = true;
  polls_ = 0;
  deadline_ns_ = now_ns + timing_.busy_time.count();
  set_status(m, static_cast<std::uint16_t>(sc::kBusy | command), 0);
}

void SiiUnit::before_read(EscMemory& m, std::int64_t now_ns, bool status_read) {
  if (!busy_) {
    return;
  }
  if (now_ns >= deadline_ns_ || (status_read && polls_ >= timing_.busy_polls)) {
    complete(m);
  } else if (status_read) {
    ++polls_;
  }
}

void SiiUnit::poll(EscMemory& m, std::int64_t now_ns) {
  if (busy_ && now_ns >= deadline_ns_) {
    complete(m);
  }
}

void SiiUnit::complete(EscMemory& m) {
  busy_ = false;
  if (command_ == sc::kCommandRead) {
    const std::size_t n = read8_ ? 8 : 4;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t at = 2U * address_ + i;
      // Reads wrap at the end of the EEPROM like the serial EEPROM's counter.
      *m.at(static_cast<std::uint32_t>(reg::kSiiData + i)) = image_[at % image_.size()];
    }
  } else if (command_ == sc::kCommandWrite) {
    store_le<std::uint16_t>(image_.data() + 2U * address_, write_word_);
  }
  // Reload: the configuration area is re-read, but alias and PDI control are
  // only taken at power-on (section I §11.2), so nothing changes here.
  set_status(m, 0, sc::kBusy | sc::kCommandMask);
  command_ = 0;
}

}  // namespace sf::ethercat::slave::detail
