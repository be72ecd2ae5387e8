// Little-endian byte reading and writing with bounds checks. EtherCAT,
// OPC UA binary and the DDS payloads are all little-endian on the wire.
//
// ByteReader is "sticky": a read past the end returns zero, marks the reader
// failed and every later read also fails, so a decoder can read a whole
// structure and check ok() once — no read ever touches memory past the span.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "sf/core/result.hpp"

namespace sf {

using Bytes = std::vector<std::uint8_t>;
using ByteSpan = std::span<const std::uint8_t>;
using MutableByteSpan = std::span<std::uint8_t>;

// Loads a little-endian integer or IEEE float from p (no alignment needed).
template <typename T>
requires std::is_arithmetic_v<T> T load_le(const std::uint8_t* p) {
  using U = std::conditional_t<
      sizeof(T) == 1, std::uint8_t,
      std::conditional_t<sizeof(T) == 2, std::uint16_t,
                         std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
  U u = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    u = static_cast<U>(u | static_cast<U>(static_cast<U>(p[i]) << (8U * i)));
  }
  return std::bit_cast<T>(u);
}

template <typename T>
requires std::is_arithmetic_v<T>
void store_le(std::uint8_t* p, T value) {
  using U = std::conditional_t<
      sizeof(T) == 1, std::uint8_t,
      std::conditional_t<sizeof(T) == 2, std::uint16_t,
                         std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;
  const U u = std::bit_cast<U>(value);
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    p[i] = static_cast<std::uint8_t>(u >> (8U * i));
  }
}

class ByteReader {
 public:
  explicit ByteReader(ByteSpan data) : data_(data) {}

  std::uint8_t u8() { return read<std::uint8_t>(); }
  std::uint16_t u16() { return read<std::uint16_t>(); }
  std::uint32_t u32() { return read<std::uint32_t>(); }
  std::uint64_t u64() { return read<std::uint64_t>(); }
  std::int8_t i8() { return read<std::int8_t>(); }
  std::int16_t i16() { return read<std::int16_t>(); }
  std::int32_t i32() { return read<std::int32_t>(); }
  std::int64_t i64() { return read<std::int64_t>(); }
  float f32() { return read<float>(); }
  double f64() { return read<double>(); }

  template <typename T>
  requires std::is_arithmetic_v<T> T read() {
    if (!take(sizeof(T))) {
      return T{};
    }
    return load_le<T>(data_.data() + pos_ - sizeof(T));
  }

  // The next n bytes as a view into the input (empty on overrun).
  ByteSpan bytes(std::size_t n);
  // Copies the next n bytes into out (zero-filled on overrun).
  void copy_to(MutableByteSpan out);
  void skip(std::size_t n) { (void)take(n); }
  // The next n bytes without consuming them (empty if fewer remain).
  [[nodiscard]] ByteSpan peek(std::size_t n) const;

  [[nodiscard]] bool ok() const { return !failed_; }
  [[nodiscard]] std::size_t position() const { return pos_; }
  [[nodiscard]] std::size_t remaining() const { return failed_ ? 0 : data_.size() - pos_; }
  [[nodiscard]] bool at_end() const { return remaining() == 0; }
  [[nodiscard]] ByteSpan rest() const { return failed_ ? ByteSpan{} : data_.subspan(pos_); }
  // Marks the reader failed (a decoder found an invalid value).
  void fail() { failed_ = true; }
  // Describes the first failure: where and how much was missing.
  [[nodiscard]] Error error(std::string_view what) const;

 private:
  bool take(std::size_t n);

  ByteSpan data_;
  std::size_t pos_ = 0;
  std::size_t wanted_at_fail_ = 0;
  bool failed_ = false;
};

// Appends little-endian values to a growable buffer.
class ByteWriter {
 public:
  ByteWriter() = default;
  explicit ByteWriter(Bytes& out) : out_(&out) {}

  void u8(std::uint8_t v) { write(v); }
  void u16(std::uint16_t v) { write(v); }
  void u32(std::uint32_t v) { write(v); }
  void u64(std::uint64_t v) { write(v); }
  void i8(std::int8_t v) { write(v); }
  void i16(std::int16_t v) { write(v); }
  void i32(std::int32_t v) { write(v); }
  void i64(std::int64_t v) { write(v); }
  void f32(float v) { write(v); }
  void f64(double v) { write(v); }
  void bytes(ByteSpan b) { buf().insert(buf().end(), b.begin(), b.end()); }
  void zeros(std::size_t n) { buf().resize(buf().size() + n, 0); }

  template <typename T>
  requires std::is_arithmetic_v<T>
  void write(T v) {
    const auto at = buf().size();
    buf().resize(at + sizeof(T));
    store_le<T>(buf().data() + at, v);
  }

  // Overwrites a value already written at offset (for length fields that are
  // known only after the body). Returns false if it would not fit.
  template <typename T>
  requires std::is_arithmetic_v<T>
  bool patch(std::size_t offset, T v) {
    if (offset > buf().size() || buf().size() - offset < sizeof(T)) {
      return false;
    }
    store_le<T>(buf().data() + offset, v);
    return true;
  }

  [[nodiscard]] std::size_t size() const { return out_ ? out_->size() : own_.size(); }
  [[nodiscard]] const Bytes& data() const { return out_ ? *out_ : own_; }
  Bytes take() { return out_ ? std::move(*out_) : std::move(own_); }

 private:
  Bytes& buf() { return out_ ? *out_ : own_; }

  Bytes own_;
  Bytes* out_ = nullptr;
};

// Writes into a fixed span (a frame being built in place); sticky overflow
// like ByteReader: a write that does not fit writes nothing and fails.
class SpanWriter {
 public:
  explicit SpanWriter(MutableByteSpan out) : out_(out) {}

  template <typename T>
  requires std::is_arithmetic_v<T>
  void write(T v) {
    if (!room(sizeof(T))) {
      return;
    }
    store_le<T>(out_.data() + pos_, v);
    pos_ += sizeof(T);
  }
  void u8(std::uint8_t v) { write(v); }
  void u16(std::uint16_t v) { write(v); }
  void u32(std::uint32_t v) { write(v); }
  void u64(std::uint64_t v) { write(v); }
  void bytes(ByteSpan b);
  void zeros(std::size_t n);

  [[nodiscard]] bool ok() const { return !failed_; }
  [[nodiscard]] std::size_t position() const { return pos_; }
  [[nodiscard]] std::size_t remaining() const { return out_.size() - pos_; }

 private:
  bool room(std::size_t n);

  MutableByteSpan out_;
  std::size_t pos_ = 0;
  bool failed_ = false;
};

// "01 a4 ff" — for logs and test failure messages.
std::string to_hex(ByteSpan data, std::size_t max_bytes = 64);
// Parses "01a4ff" or "01 a4 ff" (whitespace ignored); malformed → error.
Result<Bytes> from_hex(std::string_view hex);

}  // namespace sf
