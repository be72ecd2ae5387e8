#include "sf/opcua/status_code.hpp"

#include <fmt/format.h>

#include "sf/opcua/status_codes.hpp"

namespace sf::opcua {

std::string_view StatusCode::name() const {
  return status_code_name(code());
}
std::string_view StatusCode::description() const {
  return status_code_description(code());
}

std::string to_string(StatusCode code) {
  const std::string_view name = code.name();
  if (name.empty()) {
    return fmt::format("0x{:08X}", code.value());
  }
  if (code.value() != code.code()) {
    return fmt::format("{} (0x{:08X})", name, code.value());
  }
  return std::string(name);
}

namespace {

Errc errc_of(StatusCode code) {
  switch (code.code()) {
    case status::BadDecodingError.value():
      return Errc::malformed;
    case status::BadEncodingLimitsExceeded.value():
    case status::BadRequestTooLarge.value():
    case status::BadResponseTooLarge.value():
    case status::BadTcpMessageTooLarge.value():
      return Errc::limit_exceeded;
    case status::BadEncodingError.value():
    case status::BadInvalidArgument.value():
      return Errc::invalid_argument;
    case status::BadDataTypeIdUnknown.value():
    case status::BadNodeIdUnknown.value():
    case status::BadNotFound.value():
      return Errc::not_found;
    case status::BadNotSupported.value():
    case status::BadNotImplemented.value():
    case status::BadServiceUnsupported.value():
      return Errc::unsupported;
    case status::BadTimeout.value():
    case status::BadRequestTimeout.value():
      return Errc::timeout;
    case status::BadInvalidState.value():
      return Errc::state;
    case status::BadCommunicationError.value():
    case status::BadConnectionClosed.value():
      return Errc::io;
    default:
      return Errc::remote;
  }
}

StatusCode status_of_errc(Errc code) {
  switch (code) {
    case Errc::malformed:
    case Errc::out_of_range:
      return status::BadDecodingError;
    case Errc::limit_exceeded:
      return status::BadEncodingLimitsExceeded;
    case Errc::invalid_argument:
      return status::BadInvalidArgument;
    case Errc::not_found:
      return status::BadNotFound;
    case Errc::unsupported:
      return status::BadNotSupported;
    case Errc::timeout:
      return status::BadTimeout;
    case Errc::io:
      return status::BadCommunicationError;
    case Errc::state:
      return status::BadInvalidState;
    case Errc::remote:
      break;
  }
  return status::BadUnexpectedError;
}

}  // namespace

Error status_error(StatusCode code, std::string_view message) {
  return Error{errc_of(code), fmt::format("{}: {}", to_string(code), message),
               ProtocolCode{kStatusCodeTable, code.value()}};
}

StatusCode status_of(const Error& error) {
  if (error.protocol_code && error.protocol_code->table == kStatusCodeTable) {
    return StatusCode(error.protocol_code->value);
  }
  return status_of_errc(error.code);
}

}  // namespace sf::opcua
