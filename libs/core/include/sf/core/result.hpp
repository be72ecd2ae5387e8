// Error and Result<T>: how smartfactory modules report failure without
// exceptions across module boundaries.
#pragma once

#include <cassert>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

namespace sf {

// Broad classes of failure; the message carries the specifics.
enum class Errc {
  invalid_argument,  // the caller passed something unusable
  malformed,         // input bytes/text do not follow the format
  out_of_range,      // a read or write past the end of a buffer
  not_found,         // a named thing does not exist
  unsupported,       // valid, but not implemented or not offered
  limit_exceeded,    // a configured limit would be exceeded
  timeout,           // a deadline passed
  io,                // the operating system refused (errno in message)
  state,             // the operation is not allowed in the current state
  remote,            // the peer reported an error
};

std::string_view to_string(Errc code);

// A code a protocol specification defines for a failure (an OPC UA StatusCode, OPC 10000-4
// §7.39), kept typed as the error travels through the modules: `table` names the code table (a
// constant of the protocol's module, static storage), `value` the code in it.
struct ProtocolCode {
  std::string_view table;
  std::uint32_t value = 0;
  friend bool operator==(const ProtocolCode&, const ProtocolCode&) = default;
};

struct Error {
  Errc code{};
  std::string message;
  std::optional<ProtocolCode> protocol_code;  // the protocol's own code, when it has one

  Error() = default;
  Error(Errc c, std::string msg) : code(c), message(std::move(msg)) {}
  Error(Errc c, std::string msg, ProtocolCode protocol)
      : code(c), message(std::move(msg)), protocol_code(protocol) {}

  // "malformed: datagram length 300 exceeds frame"
  [[nodiscard]] std::string describe() const;
  // Prefixes context: Error{...}.with_context("frame 7") → "frame 7: ..."; the codes stay.
  [[nodiscard]] Error with_context(std::string_view context) const;
};

// Result<T> holds a T or an Error. Small on purpose: ok(), value(), error().
template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::in_place_index<0>, std::move(value)) {}  // NOLINT(google-explicit-constructor)
  Result(Error error)
      : v_(std::in_place_index<1>, std::move(error)) {}  // NOLINT(google-explicit-constructor)

  [[nodiscard]] bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() & {
    assert(ok());
    return std::get<0>(v_);
  }
  const T& value() const& {
    assert(ok());
    return std::get<0>(v_);
  }
  T&& value() && {
    assert(ok());
    return std::get<0>(std::move(v_));
  }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T&& operator*() && { return std::move(*this).value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

  [[nodiscard]] const Error& error() const {
    assert(!ok());
    return std::get<1>(v_);
  }
  T value_or(T fallback) const { return ok() ? std::get<0>(v_) : std::move(fallback); }

 private:
  std::variant<T, Error> v_;
};

template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Error error) : error_(std::move(error)), ok_(false) {}  // NOLINT(google-explicit-constructor)

  [[nodiscard]] bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  [[nodiscard]] const Error& error() const {
    assert(!ok_);
    return error_;
  }

 private:
  Error error_;
  bool ok_ = true;
};

using Status = Result<void>;

inline Error make_error(Errc code, std::string message) {
  return Error{code, std::move(message)};
}

}  // namespace sf

// SF_TRY(expr): evaluate a Result<void>-like expression, return its error on failure.
#define SF_TRY(expr)                 \
  do {                               \
    auto sf_try_result_ = (expr);    \
    if (!sf_try_result_.ok()) {      \
      return sf_try_result_.error(); \
    }                                \
  } while (false)
