// Client: the seam between a Modbus client application (a legacy-machine gateway) and the
// device it talks to. TcpClient (tcp_client.hpp) speaks Modbus TCP through libmodbus;
// MemoryClient (memory_client.hpp) calls a Device in the same process with the server's exact
// semantics, for the deterministic simulation mode. Application code sees only this interface.
//
// Every call is one transaction (MB AP §6). Arguments are checked before anything is sent, the
// same way by every implementation: a quantity of 0 or above the function's limit is
// Errc::invalid_argument. Failures are ClientErrors:
//   Errc::remote    the device answered with a Modbus exception: `exception` holds its code;
//   Errc::timeout   no answer within the response timeout;
//   Errc::io        the connection could not be made or was lost;
//   Errc::malformed the answer did not fit the request.
// A Client is used by one thread at a time.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "sf/core/result.hpp"
#include "sf/modbus/protocol.hpp"

namespace sf::modbus {

// An sf::Error that keeps the Modbus exception code typed. It is an sf::Error, so it converts
// to one where the code does not matter (return it from a function returning sf::Status).
struct ClientError : Error {
  // The exception the device answered with (code == Errc::remote), if that is what failed.
  std::optional<ExceptionCode> exception;

  ClientError() = default;
  ClientError(Errc c, std::string msg) : Error(c, std::move(msg)) {}
  ClientError(Error error) : Error(std::move(error)) {}  // NOLINT(google-explicit-constructor)
  // "server_device_busy (0x06): read_holding_registers 0..9"
  static ClientError from_exception(ExceptionCode code, std::string_view context);
};

// sf::Result's shape with a ClientError: ok(), value(), error(), and a conversion to sf::Result.
template <typename T>
class [[nodiscard]] ClientResult {
 public:
  ClientResult(T value) : v_(std::in_place_index<0>, std::move(value)) {}            // NOLINT
  ClientResult(ClientError error) : v_(std::in_place_index<1>, std::move(error)) {}  // NOLINT

  [[nodiscard]] bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() & { return std::get<0>(v_); }
  const T& value() const& { return std::get<0>(v_); }
  T&& value() && { return std::get<0>(std::move(v_)); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  [[nodiscard]] const ClientError& error() const { return std::get<1>(v_); }

  operator Result<T>() const& {  // NOLINT(google-explicit-constructor)
    return ok() ? Result<T>(value()) : Result<T>(static_cast<const Error&>(error()));
  }

 private:
  std::variant<T, ClientError> v_;
};

template <>
class [[nodiscard]] ClientResult<void> {
 public:
  ClientResult() = default;
  ClientResult(ClientError error) : error_(std::move(error)) {}  // NOLINT

  [[nodiscard]] bool ok() const { return !error_; }
  explicit operator bool() const { return ok(); }
  [[nodiscard]] const ClientError& error() const { return *error_; }

  operator Status() const {  // NOLINT(google-explicit-constructor)
    return ok() ? Status{} : Status(static_cast<const Error&>(*error_));
  }

 private:
  std::optional<ClientError> error_;
};

using ClientStatus = ClientResult<void>;

class Client {
 public:
  Client() = default;
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;
  virtual ~Client() = default;

  ClientResult<std::vector<bool>> read_coils(std::uint16_t address, std::uint16_t count);
  ClientResult<std::vector<bool>> read_discrete_inputs(std::uint16_t address, std::uint16_t count);
  ClientResult<std::vector<std::uint16_t>> read_holding_registers(std::uint16_t address, std::uint16_t count);
  ClientResult<std::vector<std::uint16_t>> read_input_registers(std::uint16_t address, std::uint16_t count);
  ClientStatus write_single_coil(std::uint16_t address, bool value);
  ClientStatus write_single_register(std::uint16_t address, std::uint16_t value);
  ClientStatus write_multiple_coils(std::uint16_t address, const std::vector<bool>& values);
  ClientStatus write_multiple_registers(std::uint16_t address, std::span<const std::uint16_t> values);

  // What an implementation carries out: one function with its address, quantity and values
  // (already checked against the function's limits).
  struct Transaction {
    FunctionCode function = FunctionCode::read_coils;
    std::uint16_t address = 0;
    std::uint16_t count = 0;
    const std::vector<bool>* coils = nullptr;    // write_single_coil, write_multiple_coils
    std::span<const std::uint16_t> registers{};  // write_single_register, write_multiple_registers
  };
  // What a read brings back (the vector of its table's kind).
  struct Reply {
    std::vector<bool> bits;
    std::vector<std::uint16_t> registers;
  };

 protected:
  virtual ClientResult<Reply> transact(const Transaction& transaction) = 0;

 private:
  ClientResult<Reply> checked(const Transaction& transaction);
};

}  // namespace sf::modbus
