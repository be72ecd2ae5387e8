// Encoder/Decoder state: limits, nesting depth and the first error with its path.
#include <limits>

#include <fmt/format.h>

#include "sf/opcua/binary.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {

namespace {
constexpr std::size_t kNoOffset = std::numeric_limits<std::size_t>::max();
}

// ---- CodecError -------------------------------------------------------------------------------

void CodecError::fail(StatusCode status, std::string message, std::size_t offset) {
  if (failed_) {
    return;
  }
  failed_ = true;
  status_ = status;
  message_ = std::move(message);
  offset_ = offset;
}

void CodecError::add_context(std::string_view segment) {
  if (failed_) {
    path_.emplace_back(segment);
  }
}

void CodecError::adopt(const CodecError& inner, std::size_t base_offset) {
  if (failed_ || !inner.failed_) {
    return;
  }
  failed_ = true;
  status_ = inner.status_;
  message_ = inner.message_;
  offset_ = inner.offset_ == kNoOffset ? kNoOffset : inner.offset_ + base_offset;
  path_ = inner.path_;
}

Error CodecError::to_error() const {
  std::string path;
  for (auto it = path_.rbegin(); it != path_.rend(); ++it) {
    const bool attached = it->starts_with('[') || it->starts_with('{');
    if (!path.empty() && !attached) {
      path += '.';
    }
    path += *it;
  }
  std::string text = path.empty() ? message_ : fmt::format("{}: {}", path, message_);
  if (offset_ != kNoOffset) {
    text += fmt::format(" (offset {})", offset_);
  }
  return status_error(status_, text);
}

// ---- Decoder ----------------------------------------------------------------------------------

Decoder::Decoder(ByteReader& reader, const DecodeOptions& options)
    : reader_(reader),
      options_(options),
      registry_(options.registry != nullptr ? options.registry : &ExtensionRegistry::standard()) {}

void Decoder::fail(StatusCode status, std::string message) {
  sync_truncation();
  error_.fail(status, std::move(message), reader_.position());
}

void Decoder::sync_truncation() {
  // A read past the end marks only the ByteReader; turn it into our error on first notice.
  if (!error_.failed() && !reader_.ok()) {
    error_.fail(status::BadDecodingError, reader_.error("truncated").message, kNoOffset);
  }
}

void Decoder::add_context(std::string_view segment) {
  sync_truncation();
  error_.add_context(segment);
}

Error Decoder::error() const {
  if (!error_.failed()) {
    if (!reader_.ok()) {
      return status_error(status::BadDecodingError, reader_.error("truncated").message);
    }
    return status_error(status::BadDecodingError, "decoding failed");
  }
  return error_.to_error();
}

const CodecError& Decoder::codec_error() {
  sync_truncation();
  return error_;
}

void Decoder::adopt(Decoder& inner, std::size_t base_offset) {
  sync_truncation();
  error_.adopt(inner.codec_error(), base_offset);
}

std::int64_t Decoder::read_length(std::string_view what, std::size_t min_element_size, std::size_t max) {
  const std::int32_t n = reader_.i32();
  if (!ok()) {
    return -2;
  }
  if (n == -1) {
    return -1;
  }
  if (n < 0) {
    fail(status::BadDecodingError, fmt::format("{} length {} is negative", what, n));
    return -2;
  }
  const auto length = static_cast<std::size_t>(n);
  if (length > max) {
    fail(status::BadEncodingLimitsExceeded,
         fmt::format("{} length {} exceeds the limit {}", what, length, max));
    return -2;
  }
  const std::size_t remaining = reader_.remaining();
  if (min_element_size != 0 && length > remaining / min_element_size) {
    fail(status::BadDecodingError, fmt::format("{} length {} needs at least {} bytes but {} remain", what,
                                               length, length * min_element_size, remaining));
    return -2;
  }
  return n;
}

bool Decoder::enter(std::string_view what) {
  if (depth_ >= options_.limits.max_depth) {
    fail(status::BadEncodingLimitsExceeded,
         fmt::format("{} nested deeper than the limit of {} levels", what, options_.limits.max_depth));
    return false;
  }
  ++depth_;
  return true;
}

Status check_trailing(const ByteReader& in, std::string_view what) {
  if (in.remaining() != 0) {
    return status_error(status::BadDecodingError, fmt::format("{} trailing byte(s) after the {} at offset {}",
                                                              in.remaining(), what, in.position()));
  }
  return {};
}

namespace detail {
std::string index_segment(std::size_t index) {
  return fmt::format("[{}]", index);
}
}  // namespace detail

// ---- Encoder ----------------------------------------------------------------------------------

Encoder::Encoder(ByteWriter& writer, std::size_t max_depth) : writer_(writer), max_depth_(max_depth) {}

void Encoder::fail(StatusCode status, std::string message) {
  error_.fail(status, std::move(message), kNoOffset);
}

void Encoder::add_context(std::string_view segment) {
  error_.add_context(segment);
}

bool Encoder::enter(std::string_view what) {
  if (depth_ >= max_depth_) {
    fail(status::BadEncodingLimitsExceeded,
         fmt::format("{} nested deeper than the limit of {} levels", what, max_depth_));
    return false;
  }
  ++depth_;
  return true;
}

void Encoder::write_length(std::size_t length, std::string_view what) {
  if (length > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
    fail(status::BadEncodingLimitsExceeded, fmt::format("{} length {} does not fit an Int32", what, length));
    writer_.i32(-1);
    return;
  }
  writer_.i32(static_cast<std::int32_t>(length));
}

}  // namespace sf::opcua
