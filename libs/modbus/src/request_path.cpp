#include "request_path.hpp"

#include "wire.hpp"

namespace sf::modbus::detail {

namespace {

using wire::load_be16;
using wire::store_be16;

Table read_table(FunctionCode function) {
  switch (function) {
    case FunctionCode::read_coils:
      return Table::coils;
    case FunctionCode::read_discrete_inputs:
      return Table::discrete_inputs;
    case FunctionCode::read_input_registers:
      return Table::input_registers;
    default:
      return Table::holding_registers;
  }
}

// Address and quantity (or value) of the four-byte bodies of §6.1-§6.6.
bool decode_fixed(Request& request, std::span<const std::uint8_t> body) {
  if (body.size() != 4) {
    return false;
  }
  const std::uint16_t address = load_be16(&body[0]);
  switch (request.function) {
    case FunctionCode::write_single_coil:
      request.write = Range{Table::coils, address, 1};
      request.data = body.subspan(2);
      break;
    case FunctionCode::write_single_register:
      request.write = Range{Table::holding_registers, address, 1};
      request.data = body.subspan(2);
      break;
    default:
      request.read = Range{read_table(request.function), address, load_be16(&body[2])};
  }
  return true;
}

// §6.11, §6.12: address, quantity, byte count, values.
bool decode_write_multiple(Request& request, std::span<const std::uint8_t> body, Table table) {
  if (body.size() < 5 || body.size() != 5U + body[4]) {
    return false;
  }
  request.write = Range{table, load_be16(&body[0]), load_be16(&body[2])};
  request.data = body.subspan(5);
  return true;
}

// §6.17: read address, read quantity, write address, write quantity, byte count, values.
bool decode_read_write(Request& request, std::span<const std::uint8_t> body) {
  if (body.size() < 9 || body.size() != 9U + body[8]) {
    return false;
  }
  request.read = Range{Table::holding_registers, load_be16(&body[0]), load_be16(&body[2])};
  request.write = Range{Table::holding_registers, load_be16(&body[4]), load_be16(&body[6])};
  request.data = body.subspan(9);
  return true;
}

bool decode_body(Request& request, std::span<const std::uint8_t> body) {
  switch (request.function) {
    case FunctionCode::write_multiple_coils:
      return decode_write_multiple(request, body, Table::coils);
    case FunctionCode::write_multiple_registers:
      return decode_write_multiple(request, body, Table::holding_registers);
    case FunctionCode::mask_write_register:  // §6.16: address, AND mask, OR mask
      if (body.size() != 6) {
        return false;
      }
      request.write = Range{Table::holding_registers, load_be16(&body[0]), 1};
      request.data = body.subspan(2);
      return true;
    case FunctionCode::read_write_multiple_registers:
      return decode_read_write(request, body);
    default:
      return decode_fixed(request, body);
  }
}

bool quantity_in(std::uint16_t count, std::uint16_t max) {
  return count >= 1 && count <= max;
}

bool fits(const RegisterBank& bank, const Range& range) {
  return bank.contains(range.table, range.address, range.count);
}

}  // namespace

Decoded decode_request(std::uint8_t unit_id, std::span<const std::uint8_t> pdu) {
  Decoded decoded;
  decoded.request.unit_id = unit_id;
  const std::uint8_t code = pdu.empty() ? 0 : pdu[0];
  decoded.request.function = static_cast<FunctionCode>(code);
  if (!is_served(code)) {
    decoded.refusal = ExceptionCode::illegal_function;
  } else if (!decode_body(decoded.request, pdu.subspan(1))) {
    decoded.refusal = ExceptionCode::illegal_data_value;
  }
  return decoded;
}

std::optional<ExceptionCode> check_request(const RegisterBank& bank, const Request& r) {
  constexpr auto kValue = ExceptionCode::illegal_data_value;
  constexpr auto kAddress = ExceptionCode::illegal_data_address;
  switch (r.function) {
    case FunctionCode::read_coils:
    case FunctionCode::read_discrete_inputs:
      if (!quantity_in(r.read->count, kMaxReadBits)) {
        return kValue;
      }
      return fits(bank, *r.read) ? std::nullopt : std::optional{kAddress};
    case FunctionCode::read_holding_registers:
    case FunctionCode::read_input_registers:
      if (!quantity_in(r.read->count, kMaxReadRegisters)) {
        return kValue;
      }
      return fits(bank, *r.read) ? std::nullopt : std::optional{kAddress};
    case FunctionCode::write_single_coil:
      if (!fits(bank, *r.write)) {
        return kAddress;
      }
      if (const auto v = r.register_value(0); v != wire::kCoilOn && v != wire::kCoilOff) {
        return kValue;
      }
      return std::nullopt;
    case FunctionCode::write_single_register:
    case FunctionCode::mask_write_register:
      return fits(bank, *r.write) ? std::nullopt : std::optional{kAddress};
    case FunctionCode::write_multiple_coils:
      if (!quantity_in(r.write->count, kMaxWriteBits) || r.data.size() != (r.write->count + 7U) / 8U) {
        return kValue;
      }
      return fits(bank, *r.write) ? std::nullopt : std::optional{kAddress};
    case FunctionCode::write_multiple_registers:
      if (!quantity_in(r.write->count, kMaxWriteRegisters) ||
          r.data.size() != std::size_t{2} * r.write->count) {
        return kValue;
      }
      return fits(bank, *r.write) ? std::nullopt : std::optional{kAddress};
    case FunctionCode::read_write_multiple_registers:
      if (!quantity_in(r.write->count, kMaxReadWriteRegisters) ||
          !quantity_in(r.read->count, kMaxReadRegisters) ||
          r.data.size() != std::size_t{2} * r.write->count) {
        return kValue;
      }
      return fits(bank, *r.read) && fits(bank, *r.write) ? std::nullopt : std::optional{kAddress};
  }
  return ExceptionCode::illegal_function;
}

Verdict admit(Device& device, const Decoded& decoded) {
  const Fault fault = device.fault();
  if (fault.kind == Fault::Kind::unreachable) {
    return Verdict{Verdict::Kind::silent};
  }
  if (fault.kind == Fault::Kind::exception) {
    return Verdict{Verdict::Kind::exception, fault.exception};
  }
  std::optional<ExceptionCode> refusal = decoded.refusal;
  if (!refusal) {
    refusal = check_request(device.bank(), decoded.request);
  }
  if (!refusal) {
    refusal = device.before_request(decoded.request);
  }
  if (refusal) {
    return Verdict{Verdict::Kind::exception, *refusal};
  }
  return Verdict{};
}

namespace {

void write_values(RegisterBank& bank, const Request& r) {
  const Range& w = *r.write;
  for (std::uint16_t i = 0; i < w.count; ++i) {
    const auto address = static_cast<std::uint16_t>(w.address + i);
    if (w.table == Table::coils) {
      bank.set_coil(address, r.coil_value(i));
    } else {
      bank.set_holding_register(address, r.register_value(i));
    }
  }
}

// §6.16: Result = (Current AND And_Mask) OR (Or_Mask AND (NOT And_Mask)).
void mask_write(RegisterBank& bank, const Request& r) {
  const std::uint16_t current = bank.holding_register(r.write->address);
  const std::uint16_t and_mask = r.register_value(0);
  const std::uint16_t or_mask = r.register_value(1);
  bank.set_holding_register(r.write->address,
                            static_cast<std::uint16_t>((current & and_mask) | (or_mask & ~and_mask)));
}

}  // namespace

void apply(RegisterBank& bank, const Request& r, Client::Reply& reply) {
  if (r.function == FunctionCode::mask_write_register) {
    mask_write(bank, r);
  } else if (r.write) {
    write_values(bank, r);
  }
  if (r.read) {
    const Range& range = *r.read;
    if (range.table == Table::coils || range.table == Table::discrete_inputs) {
      reply.bits = bank.bits(range.table, range.address, range.count);
    } else {
      reply.registers = bank.words(range.table, range.address, range.count);
    }
  }
}

namespace {

std::size_t encode_coils(const std::vector<bool>& coils, std::uint8_t* out) {
  const std::size_t bytes = (coils.size() + 7) / 8;
  for (std::size_t i = 0; i < bytes; ++i) {
    out[i] = 0;
  }
  for (std::size_t i = 0; i < coils.size(); ++i) {
    if (coils[i]) {
      out[i / 8] = static_cast<std::uint8_t>(out[i / 8] | (1U << (i % 8)));
    }
  }
  return bytes;
}

}  // namespace

std::size_t encode_request(const Client::Transaction& t, PduBuffer& pdu) {
  pdu[0] = static_cast<std::uint8_t>(t.function);
  store_be16(&pdu[1], t.address);
  switch (t.function) {
    case FunctionCode::write_single_coil:
      store_be16(&pdu[3], (*t.coils)[0] ? wire::kCoilOn : wire::kCoilOff);
      return 5;
    case FunctionCode::write_single_register:
      store_be16(&pdu[3], t.registers[0]);
      return 5;
    case FunctionCode::write_multiple_coils: {
      store_be16(&pdu[3], t.count);
      const std::size_t bytes = encode_coils(*t.coils, &pdu[6]);
      pdu[5] = static_cast<std::uint8_t>(bytes);
      return 6 + bytes;
    }
    case FunctionCode::write_multiple_registers:
      store_be16(&pdu[3], t.count);
      pdu[5] = static_cast<std::uint8_t>(2 * t.count);
      for (std::size_t i = 0; i < t.count; ++i) {
        store_be16(&pdu[6 + 2 * i], t.registers[i]);
      }
      return 6 + 2U * t.count;
    default:
      store_be16(&pdu[3], t.count);
      return 5;
  }
}

}  // namespace sf::modbus::detail
