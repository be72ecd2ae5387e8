// The path every request takes through a Device (device.hpp), shared by the Server and the
// MemoryClient so the two cannot answer differently: decode the PDU, admit (fault, the checks of
// libmodbus's modbus_reply, before_request), then the bank answers.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

#include "sf/modbus/client.hpp"
#include "sf/modbus/device.hpp"
#include "sf/modbus/request.hpp"

namespace sf::modbus::detail {

// A PDU decoded into a Request, or the exception a server answers it with before looking
// further: illegal_function for a code we do not serve, illegal_data_value for a PDU whose
// length does not fit its function. `request.data` points into the PDU.
struct Decoded {
  Request request;
  std::optional<ExceptionCode> refusal;
};
Decoded decode_request(std::uint8_t unit_id, std::span<const std::uint8_t> pdu);

// The checks libmodbus's modbus_reply makes of a decoded request, in its order (quantity
// limits and byte counts: illegal_data_value; addresses: illegal_data_address; the value of
// write_single_coil: illegal_data_value). Nothing when the bank can answer it.
std::optional<ExceptionCode> check_request(const RegisterBank& bank, const Request& request);

// What the server does with a request; decided with the device's lock held (steps 1-3).
struct Verdict {
  enum class Kind : std::uint8_t { answer, exception, silent };
  Kind kind = Kind::answer;
  ExceptionCode exception = ExceptionCode::server_device_failure;
};
Verdict admit(Device& device, const Decoded& decoded);

// Step 4 without libmodbus, as modbus_reply does it: reads fill `reply`, writes change the bank
// (read_write_multiple_registers writes first, MB AP §6.17). The request must be admitted.
void apply(RegisterBank& bank, const Request& request, Client::Reply& reply);

// The request PDU a client sends for a transaction (MB AP §6); returns its length.
using PduBuffer = std::array<std::uint8_t, kMaxPduLength>;
std::size_t encode_request(const Client::Transaction& transaction, PduBuffer& pdu);

}  // namespace sf::modbus::detail
