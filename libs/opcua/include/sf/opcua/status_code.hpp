// StatusCode (OPC 10000-4 §7.39, OPC 10000-6 §5.2.2.11): a UInt32 whose top two bits give the
// severity (00 Good, 01 Uncertain, 1x Bad), bits 16..27 the sub-code and bits 0..15 info bits.
// The named constants (sf::opcua::status::BadDecodingError, ...) are generated from
// libs/opcua/schema/status_codes.csv into "sf/opcua/status_codes.hpp".
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sf/core/result.hpp"

namespace sf::opcua {

class StatusCode {
 public:
  constexpr StatusCode() = default;
  constexpr explicit StatusCode(std::uint32_t value) : value_(value) {}

  [[nodiscard]] constexpr std::uint32_t value() const { return value_; }
  // Severity and sub-code without the info bits: the key of the name table.
  [[nodiscard]] constexpr std::uint32_t code() const { return value_ & 0xFFFF0000U; }
  [[nodiscard]] constexpr bool is_good() const { return (value_ >> 30U) == 0U; }
  [[nodiscard]] constexpr bool is_uncertain() const { return (value_ >> 30U) == 1U; }
  [[nodiscard]] constexpr bool is_bad() const { return (value_ >> 31U) == 1U; }

  // "BadDecodingError"; empty for a code the schema does not know.
  [[nodiscard]] std::string_view name() const;
  [[nodiscard]] std::string_view description() const;

  constexpr bool operator==(const StatusCode&) const = default;

 private:
  std::uint32_t value_ = 0;
};

// "Good", "BadDecodingError", "BadDecodingError (0x80070400)" when info bits are set, or
// "0x81230000" for an unknown code.
std::string to_string(StatusCode code);

// Name/description tables (generated).
std::string_view status_code_name(std::uint32_t code);
std::string_view status_code_description(std::uint32_t code);
std::optional<StatusCode> status_code_from_name(std::string_view name);

// The table of Error::protocol_code that holds OPC UA StatusCodes.
inline constexpr std::string_view kStatusCodeTable = "OPC UA StatusCode";

// Errors of this module carry their StatusCode typed (Error::protocol_code), kept through
// with_context, and named at the start of the message for people:
// "BadDecodingError: ReadRequest.nodesToRead[2].indexRange: ...". status_error builds one
// (Errc chosen from the code) and status_of returns the code; errors from elsewhere map by Errc.
Error status_error(StatusCode code, std::string_view message);
StatusCode status_of(const Error& error);

}  // namespace sf::opcua
