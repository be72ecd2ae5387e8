// Helpers shared by the opcua tests.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <gtest/gtest.h>

#include "sf/core/bytes.hpp"
#include "sf/opcua/binary.hpp"
#include "sf/opcua/status_codes.hpp"
#include "sf/opcua/transport/tcp_messages.hpp"

namespace sf::opcua::test {

inline Bytes hex(std::string_view text) {
  auto bytes = from_hex(text);
  EXPECT_TRUE(bytes.ok()) << text;
  return bytes.ok() ? *bytes : Bytes{};
}

// The encoding of value; fails the test if encoding fails.
template <typename T>
Bytes encoded(const T& value) {
  auto bytes = encode(value);
  EXPECT_TRUE(bytes.ok()) << (bytes.ok() ? "" : bytes.error().describe());
  return bytes.ok() ? *bytes : Bytes{};
}

// Encodes, decodes and checks that the decoded value re-encodes to the same bytes.
template <typename T>
T round_trip(const T& value, const DecodeOptions& options = {}) {
  const Bytes bytes = encoded(value);
  auto decoded = decode<T>(bytes, options);
  EXPECT_TRUE(decoded.ok()) << (decoded.ok() ? "" : decoded.error().describe());
  if (!decoded.ok()) {
    return T{};
  }
  EXPECT_EQ(encoded(*decoded), bytes) << "re-encoding differs";
  return *decoded;
}

// The StatusCode and message of a failed decode of T from bytes.
template <typename T>
Error decode_error(const Bytes& bytes, const DecodeOptions& options = {}) {
  auto decoded = decode<T>(bytes, options);
  EXPECT_FALSE(decoded.ok()) << "decoding unexpectedly succeeded";
  return decoded.ok() ? Error{} : decoded.error();
}

// The status of the ERR message bytes start with (OPC 10000-6 §7.1.2.5); nullopt for anything else.
inline std::optional<StatusCode> error_status(ByteSpan bytes) {
  auto header = decode_header(bytes);
  if (!header || header->type != MessageType::Error || bytes.size() < 8) {
    return std::nullopt;
  }
  auto err = decode_error_body(bytes.subspan(8));
  return err ? std::optional<StatusCode>(err->error) : std::nullopt;
}

inline std::string status_name(const Error& e) {
  return to_string(status_of(e));
}

}  // namespace sf::opcua::test
