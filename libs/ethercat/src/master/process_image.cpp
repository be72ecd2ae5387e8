#include "sf/ethercat/master/process_image.hpp"

#include <fmt/format.h>

namespace sf::ethercat::master {
namespace {

bool bits_in_range(std::size_t size_bytes, std::size_t bit_offset, std::size_t bit_length) {
  return bit_length > 0 && bit_length <= 64 && bit_offset <= size_bytes * 8 &&
         size_bytes * 8 - bit_offset >= bit_length;
}

}  // namespace

std::uint64_t read_bits(ByteSpan data, std::size_t bit_offset, std::size_t bit_length) {
  if (!bits_in_range(data.size(), bit_offset, bit_length)) {
    return 0;
  }
  if (bit_offset % 8 == 0 && bit_length % 8 == 0) {
    std::uint64_t v = 0;
    const std::size_t first = bit_offset / 8;
    for (std::size_t i = 0; i < bit_length / 8; ++i) {
      v |= static_cast<std::uint64_t>(data[first + i]) << (8 * i);
    }
    return v;
  }
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < bit_length; ++i) {
    const std::size_t b = bit_offset + i;
    if (((unsigned{data[b / 8]} >> (b % 8)) & 1U) != 0) {
      v |= std::uint64_t{1} << i;
    }
  }
  return v;
}

void write_bits(MutableByteSpan data, std::size_t bit_offset, std::size_t bit_length, std::uint64_t value) {
  if (!bits_in_range(data.size(), bit_offset, bit_length)) {
    return;
  }
  if (bit_offset % 8 == 0 && bit_length % 8 == 0) {
    const std::size_t first = bit_offset / 8;
    for (std::size_t i = 0; i < bit_length / 8; ++i) {
      data[first + i] = static_cast<std::uint8_t>(value >> (8 * i));
    }
    return;
  }
  for (std::size_t i = 0; i < bit_length; ++i) {
    const std::size_t b = bit_offset + i;
    const auto mask = static_cast<std::uint8_t>(1U << (b % 8));
    if (((value >> i) & 1U) != 0) {
      data[b / 8] = static_cast<std::uint8_t>(data[b / 8] | mask);
    } else {
      data[b / 8] = static_cast<std::uint8_t>(data[b / 8] & ~mask);
    }
  }
}

std::optional<std::pair<PdoDirection, PdoEntry>> PdoMapping::find(std::uint16_t index,
                                                                  std::uint8_t subindex) const {
  for (const auto& [direction, pdos] :
       {std::pair{PdoDirection::output, &outputs}, std::pair{PdoDirection::input, &inputs}}) {
    for (const auto& pdo : *pdos) {
      for (const auto& e : pdo.entries) {
        // Index 0 entries are padding gaps, never a real object.
        if (e.index != 0 && e.index == index && e.subindex == subindex) {
          return std::pair{direction, e};
        }
      }
    }
  }
  return std::nullopt;
}

Result<EntryRef> SlaveView::entry(std::uint16_t index, std::uint8_t subindex) const {
  if (mapping_ == nullptr) {
    return make_error(Errc::not_found, "slave has no PDO mapping");
  }
  auto found = mapping_->find(index, subindex);
  if (!found) {
    return make_error(Errc::not_found,
                      fmt::format("PDO entry 0x{:04x}:{:02x} is not mapped", index, subindex));
  }
  const auto& [direction, e] = *found;
  const auto area_bytes = direction == PdoDirection::input ? inputs_.size() : outputs_.size();
  if (!bits_in_range(area_bytes, e.bit_offset, e.bit_length)) {
    return make_error(Errc::out_of_range,
                      fmt::format("PDO entry 0x{:04x}:{:02x} ({} bits at bit {}) lies outside the image",
                                  index, subindex, e.bit_length, e.bit_offset));
  }
  return EntryRef{direction, e.bit_offset, e.bit_length};
}

}  // namespace sf::ethercat::master
