#include "sf/core/result.hpp"

namespace sf {

std::string_view to_string(Errc code) {
  switch (code) {
    case Errc::invalid_argument:
      return "invalid argument";
    case Errc::malformed:
      return "malformed";
    case Errc::out_of_range:
      return "out of range";
    case Errc::not_found:
      return "not found";
    case Errc::unsupported:
      return "unsupported";
    case Errc::limit_exceeded:
      return "limit exceeded";
    case Errc::timeout:
      return "timeout";
    case Errc::io:
      return "i/o error";
    case Errc::state:
      return "wrong state";
    case Errc::remote:
      return "remote error";
  }
  return "unknown error";
}

std::string Error::describe() const {
  std::string out{to_string(code)};
  if (!message.empty()) {
    out += ": ";
    out += message;
  }
  return out;
}

Error Error::with_context(std::string_view context) const {
  std::string msg{context};
  msg += ": ";
  msg += message;
  Error out{code, std::move(msg)};
  out.protocol_code = protocol_code;
  return out;
}

}  // namespace sf
