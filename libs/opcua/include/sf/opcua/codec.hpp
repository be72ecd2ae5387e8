// The state every OPC UA Binary encoder and decoder carries (OPC 10000-6 §5.2): limits, nesting
// depth, the ExtensionObject registry and the first error with its StatusCode, byte offset and
// field path, e.g.
//   "BadDecodingError: ReadRequest.nodesToRead[2].indexRange: String length 1000 needs at least
//    1000 bytes but 12 remain (offset 57)".
// Errors are sticky as in ByteReader: after the first one every read is a no-op, so decoders
// check ok() where they must and once at the end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "sf/core/bytes.hpp"
#include "sf/core/result.hpp"
#include "sf/opcua/status_code.hpp"

namespace sf::opcua {

class ExtensionRegistry;

struct DecodeLimits {
  // Bytes of one String, ByteString or XmlElement.
  std::size_t max_string_length = 16U * 1024U * 1024U;
  // Elements of one array (structure fields, Variant arrays, matrix dimensions).
  std::size_t max_array_length = 1U << 20U;
  // Nesting of Variants, DiagnosticInfos and decoded ExtensionObject bodies (a DataValue nests
  // through its Variant); OPC 10000-6 §5.1.5 asks decoders to support at least 100 levels and
  // to report an error beyond their limit.
  std::size_t max_depth = 100;
};

struct DecodeOptions {
  DecodeLimits limits;
  // Decodes known ExtensionObject bodies into typed values; nullptr means
  // ExtensionRegistry::standard(). An empty registry keeps every body opaque.
  const ExtensionRegistry* registry = nullptr;
};

// Where and why encoding or decoding stopped; shared by Encoder and Decoder.
class CodecError {
 public:
  [[nodiscard]] bool failed() const { return failed_; }
  [[nodiscard]] StatusCode status() const { return status_; }
  // Records the first failure; later ones are ignored.
  void fail(StatusCode status, std::string message, std::size_t offset);
  // Adds one path segment while the failure unwinds ("nodesToRead", "[2]", "{ReadValueId}").
  void add_context(std::string_view segment);
  // "BadDecodingError: ReadRequest.nodesToRead[2]: ... (offset 57)".
  [[nodiscard]] Error to_error() const;
  // Takes over a nested codec's failure (an ExtensionObject body), shifting its offset.
  void adopt(const CodecError& inner, std::size_t base_offset);

 private:
  StatusCode status_;
  std::string message_;
  std::vector<std::string> path_;  // innermost first
  std::size_t offset_ = 0;
  bool failed_ = false;
};

class Decoder {
 public:
  explicit Decoder(ByteReader& reader, const DecodeOptions& options = {});

  [[nodiscard]] bool ok() const { return !error_.failed() && reader_.ok(); }
  ByteReader& reader() { return reader_; }
  [[nodiscard]] const DecodeLimits& limits() const { return options_.limits; }
  [[nodiscard]] const ExtensionRegistry& registry() const { return *registry_; }
  [[nodiscard]] const DecodeOptions& options() const { return options_; }

  void fail(StatusCode status, std::string message);
  // Adds a path segment, but only when decoding has failed (so callers may call it freely).
  void add_context(std::string_view segment);
  // The failure, or a generic error if none was recorded.
  [[nodiscard]] Error error() const;
  // The failure as a CodecError.
  const CodecError& codec_error();
  // Takes over the failure of a decoder that read a nested part (an ExtensionObject body)
  // starting at base_offset of this decoder's input.
  void adopt(Decoder& inner, std::size_t base_offset);

  // Reads an Int32 length prefix. Returns -1 for null, the length otherwise, or -2 after
  // recording an error: negative lengths other than -1, lengths above `max`, and lengths whose
  // `min_element_size` bytes per element exceed the remaining input.
  std::int64_t read_length(std::string_view what, std::size_t min_element_size, std::size_t max);

  // Nesting guard for recursive types: enter() fails with BadEncodingLimitsExceeded past
  // max_depth. Prefer DepthGuard.
  bool enter(std::string_view what);
  void leave() { --depth_; }
  [[nodiscard]] std::size_t depth() const { return depth_; }
  void set_depth(std::size_t depth) { depth_ = depth; }

 private:
  void sync_truncation();

  ByteReader& reader_;
  DecodeOptions options_;
  const ExtensionRegistry* registry_;
  CodecError error_;
  std::size_t depth_ = 0;
};

class Encoder {
 public:
  explicit Encoder(ByteWriter& writer, std::size_t max_depth = DecodeLimits{}.max_depth);

  [[nodiscard]] bool ok() const { return !error_.failed(); }
  ByteWriter& writer() { return writer_; }
  void fail(StatusCode status, std::string message);
  void add_context(std::string_view segment);
  [[nodiscard]] Error error() const { return error_.to_error(); }
  [[nodiscard]] const CodecError& codec_error() const { return error_; }
  bool enter(std::string_view what);
  void leave() { --depth_; }

  // Writes an Int32 length prefix; BadEncodingLimitsExceeded above INT32_MAX.
  void write_length(std::size_t length, std::string_view what);

 private:
  ByteWriter& writer_;
  CodecError error_;
  std::size_t max_depth_;
  std::size_t depth_ = 0;
};

// RAII for Decoder::enter/leave and Encoder::enter/leave.
template <typename Codec>
class DepthGuard {
 public:
  DepthGuard(Codec& codec, std::string_view what) : codec_(codec), entered_(codec.enter(what)) {}
  DepthGuard(const DepthGuard&) = delete;
  DepthGuard& operator=(const DepthGuard&) = delete;
  ~DepthGuard() {
    if (entered_) {
      codec_.leave();
    }
  }
  explicit operator bool() const { return entered_; }

 private:
  Codec& codec_;
  bool entered_;
};

}  // namespace sf::opcua
