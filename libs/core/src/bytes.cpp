#include "sf/core/bytes.hpp"

#include <fmt/format.h>

namespace sf {

bool ByteReader::take(std::size_t n) {
  if (failed_ || n > data_.size() - pos_) {
    if (!failed_) {
      wanted_at_fail_ = n;
    }
    failed_ = true;
    return false;
  }
  pos_ += n;
  return true;
}

ByteSpan ByteReader::bytes(std::size_t n) {
  if (!take(n)) {
    return {};
  }
  return data_.subspan(pos_ - n, n);
}

void ByteReader::copy_to(MutableByteSpan out) {
  const ByteSpan in = bytes(out.size());
  if (in.size() == out.size() && !in.empty()) {
    std::memcpy(out.data(), in.data(), in.size());
  } else if (!ok()) {
    std::fill(out.begin(), out.end(), std::uint8_t{0});
  }
}

ByteSpan ByteReader::peek(std::size_t n) const {
  if (failed_ || n > data_.size() - pos_) {
    return {};
  }
  return data_.subspan(pos_, n);
}

Error ByteReader::error(std::string_view what) const {
  if (wanted_at_fail_ == 0) {
    return Error{Errc::malformed, fmt::format("{}: invalid value at offset {}", what, pos_)};
  }
  return Error{Errc::malformed, fmt::format("{}: needs {} more byte(s) at offset {} of {}", what,
                                            wanted_at_fail_, pos_, data_.size())};
}

bool SpanWriter::room(std::size_t n) {
  if (failed_ || n > out_.size() - pos_) {
    failed_ = true;
    return false;
  }
  return true;
}

void SpanWriter::bytes(ByteSpan b) {
  if (!room(b.size())) {
    return;
  }
  if (!b.empty()) {
    std::memcpy(out_.data() + pos_, b.data(), b.size());
  }
  pos_ += b.size();
}

void SpanWriter::zeros(std::size_t n) {
  if (!room(n)) {
    return;
  }
  std::memset(out_.data() + pos_, 0, n);
  pos_ += n;
}

std::string to_hex(ByteSpan data, std::size_t max_bytes) {
  std::string out;
  const std::size_t n = std::min(data.size(), max_bytes);
  out.reserve(n * 3 + 8);
  for (std::size_t i = 0; i < n; ++i) {
    if (i != 0) {
      out += ' ';
    }
    out += fmt::format("{:02x}", data[i]);
  }
  if (data.size() > n) {
    out += fmt::format(" ... ({} bytes)", data.size());
  }
  return out;
}

namespace {
int hex_digit(char c) {
  if (c >= '0' && c <= '9')
    return c - '0';
  if (c >= 'a' && c <= 'f')
    return c - 'a' + 10;
  if (c >= 'A' && c <= 'F')
    return c - 'A' + 10;
  return -1;
}
}  // namespace

Result<Bytes> from_hex(std::string_view hex) {
  Bytes out;
  int high = -1;
  for (std::size_t i = 0; i < hex.size(); ++i) {
    const char c = hex[i];
    if (c == ' ' || c == '\n' || c == '\t' || c == '\r') {
      continue;
    }
    const int d = hex_digit(c);
    if (d < 0) {
      return Error{Errc::malformed, fmt::format("hex: '{}' at position {} is not a hex digit", c, i)};
    }
    if (high < 0) {
      high = d;
    } else {
      out.push_back(static_cast<std::uint8_t>((high << 4) | d));
      high = -1;
    }
  }
  if (high >= 0) {
    return Error{Errc::malformed, "hex: odd number of digits"};
  }
  return out;
}

}  // namespace sf
