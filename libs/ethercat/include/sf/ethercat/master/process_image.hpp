// The process image: one logical address space holding, slave after slave,
// each slave's outputs (RxPDOs, master → slave), inputs (TxPDOs, slave →
// master) and a status byte. FMMUs map these logical ranges onto the slaves'
// SyncManager buffers (ETG.1000.4 §6.6 "FMMU"); one LRW per cycle moves them.
//
// SlaveView gives typed access to one slave's part, by byte offset or by PDO
// entry (index/subindex), with bounds checks: an offset outside the slave's
// area reads as zero and writes nothing.
#pragma once

#include <bit>
#include <cstdint>
#include <optional>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"

namespace sf::ethercat::master {

// RxPDOs are outputs (master writes, SM2), TxPDOs inputs (master reads, SM3).
enum class PdoDirection : std::uint8_t { output, input };

struct PdoEntry {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint8_t bit_length = 0;
  std::uint32_t bit_offset = 0;  // from the start of the slave's outputs or inputs
};

struct Pdo {
  std::uint16_t index = 0;  // 0x16xx (RxPDO) or 0x1Axx (TxPDO)
  std::vector<PdoEntry> entries;
  std::uint32_t bit_length = 0;
};

// A slave's PDO mapping and where it came from.
struct PdoMapping {
  enum class Source : std::uint8_t { none, coe, sii };
  Source source = Source::none;
  std::vector<Pdo> outputs;  // RxPDOs assigned to SM2 (0x1C12)
  std::vector<Pdo> inputs;   // TxPDOs assigned to SM3 (0x1C13)
  std::uint32_t output_bits = 0;
  std::uint32_t input_bits = 0;

  [[nodiscard]] std::uint32_t output_bytes() const { return (output_bits + 7) / 8; }
  [[nodiscard]] std::uint32_t input_bytes() const { return (input_bits + 7) / 8; }
  // The entry with this index/subindex, searching outputs then inputs.
  [[nodiscard]] std::optional<std::pair<PdoDirection, PdoEntry>> find(std::uint16_t index,
                                                                      std::uint8_t subindex) const;
};

// A byte range of the process image (offset from its start).
struct ImageRegion {
  std::uint32_t offset = 0;
  std::uint32_t size = 0;
  [[nodiscard]] std::uint32_t end() const { return offset + size; }
};

// Where one slave's data sits in the image.
struct SlaveImage {
  ImageRegion outputs;
  ImageRegion inputs;
  ImageRegion status;  // watchdog status byte (ET1100 0x0440) if mapped, else empty
  [[nodiscard]] std::uint32_t begin() const { return outputs.offset; }
  [[nodiscard]] std::uint32_t end() const { return status.size ? status.end() : inputs.end(); }
};

// Reads/writes an unsigned field of up to 64 bits at any bit offset
// (little-endian bit order as on the wire). Out-of-range → 0 / no write.
std::uint64_t read_bits(ByteSpan data, std::size_t bit_offset, std::size_t bit_length);
void write_bits(MutableByteSpan data, std::size_t bit_offset, std::size_t bit_length, std::uint64_t value);

// A resolved PDO entry: direction, bit position and width, checked once.
struct EntryRef {
  PdoDirection direction = PdoDirection::input;
  std::uint32_t bit_offset = 0;
  std::uint8_t bit_length = 0;
};

class SlaveView {
 public:
  SlaveView(MutableByteSpan outputs, ByteSpan inputs, const PdoMapping* mapping)
      : outputs_(outputs), inputs_(inputs), mapping_(mapping) {}

  template <typename T>
  requires std::is_arithmetic_v<T>
  [[nodiscard]] T input(std::size_t byte_offset) const { return load<T>(inputs_, byte_offset); }
  template <typename T>
  requires std::is_arithmetic_v<T>
  [[nodiscard]] T output(std::size_t byte_offset) const { return load<T>(outputs_, byte_offset); }
  template <typename T>
  requires std::is_arithmetic_v<T>
  void set_output(std::size_t byte_offset, T value) {
    if (byte_offset <= outputs_.size() && outputs_.size() - byte_offset >= sizeof(T)) {
      store_le<T>(outputs_.data() + byte_offset, value);
    }
  }
  [[nodiscard]] bool input_bit(std::size_t bit) const { return read_bits(inputs_, bit, 1) != 0; }
  [[nodiscard]] bool output_bit(std::size_t bit) const { return read_bits(outputs_, bit, 1) != 0; }
  void set_output_bit(std::size_t bit, bool on) { write_bits(outputs_, bit, 1, on ? 1U : 0U); }

  // Resolves a PDO entry (e.g. 0x6041:00) of this slave's mapping.
  [[nodiscard]] Result<EntryRef> entry(std::uint16_t index, std::uint8_t subindex) const;

  // Reads an entry (inputs or outputs); signed types are sign-extended.
  template <typename T>
  requires std::is_arithmetic_v<T>
  [[nodiscard]] T get(const EntryRef& e) const {
    const auto raw = read_bits(e.direction == PdoDirection::input ? inputs_ : ByteSpan{outputs_},
                               e.bit_offset, e.bit_length);
    return from_raw<T>(raw, e.bit_length);
  }
  // Writes an output entry; writing an input entry does nothing.
  template <typename T>
  requires std::is_arithmetic_v<T>
  void set(const EntryRef& e, T value) {
    if (e.direction == PdoDirection::output) {
      write_bits(outputs_, e.bit_offset, e.bit_length, to_raw(value));
    }
  }

  [[nodiscard]] MutableByteSpan outputs() const { return outputs_; }
  [[nodiscard]] ByteSpan inputs() const { return inputs_; }
  [[nodiscard]] const PdoMapping* mapping() const { return mapping_; }

 private:
  template <typename T>
  static T load(ByteSpan area, std::size_t byte_offset) {
    if (byte_offset > area.size() || area.size() - byte_offset < sizeof(T)) {
      return T{};
    }
    return load_le<T>(area.data() + byte_offset);
  }
  template <typename T>
  static T from_raw(std::uint64_t raw, std::uint8_t bits) {
    if constexpr (std::is_floating_point_v<T>) {
      using U = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
      return std::bit_cast<T>(static_cast<U>(raw));
    } else if constexpr (std::is_signed_v<T>) {
      if (bits > 0 && bits < 64 && ((raw >> (bits - 1U)) & 1U) != 0) {
        raw |= ~((std::uint64_t{1} << bits) - 1U);  // sign-extend
      }
      return static_cast<T>(static_cast<std::int64_t>(raw));
    } else {
      return static_cast<T>(raw);
    }
  }
  template <typename T>
  static std::uint64_t to_raw(T value) {
    if constexpr (std::is_floating_point_v<T>) {
      using U = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
      return std::bit_cast<U>(value);
    } else if constexpr (std::is_signed_v<T>) {
      return static_cast<std::uint64_t>(static_cast<std::int64_t>(value));
    } else {
      return static_cast<std::uint64_t>(value);
    }
  }

  MutableByteSpan outputs_;
  ByteSpan inputs_;
  const PdoMapping* mapping_;
};

}  // namespace sf::ethercat::master
