#include "sf/modbus/tcp_client.hpp"

#include <arpa/inet.h>
#include <modbus.h>
#include <poll.h>
#include <sys/socket.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "address.hpp"

namespace sf::modbus {

void TcpClient::ContextFree::operator()(_modbus* ctx) const {
  modbus_close(ctx);
  modbus_free(ctx);
}

namespace {

using detail::is_ipv4;

// The plain IPv4 back end takes dotted quads only; the protocol-independent one resolves names
// and IPv6 addresses.
modbus_t* new_context(const TcpClientOptions& options) {
  if (is_ipv4(options.host)) {
    return modbus_new_tcp(options.host.c_str(), options.port);
  }
  return modbus_new_tcp_pi(options.host.c_str(), std::to_string(options.port).c_str());
}

Status configure(modbus_t* ctx, const TcpClientOptions& options) {
  // libmodbus accepts unit ids 0..247 and 0xFF on TCP (modbus_set_slave).
  if (modbus_set_slave(ctx, options.unit_id) != 0) {
    return make_error(Errc::invalid_argument,
                      fmt::format("unit id {}: {}", options.unit_id, modbus_strerror(errno)));
  }
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(options.response_timeout).count();
  if (us <= 0) {
    return make_error(Errc::invalid_argument, "response timeout must be positive");
  }
  (void)modbus_set_response_timeout(ctx, static_cast<std::uint32_t>(us / 1'000'000),
                                    static_cast<std::uint32_t>(us % 1'000'000));
  return {};
}

bool is_exception(int err) {
  return err > MODBUS_ENOBASE && err < MODBUS_ENOBASE + MODBUS_EXCEPTION_MAX;
}

bool is_bad_response(int err) {
  return err == EMBBADDATA || err == EMBBADEXC || err == EMBUNKEXC || err == EMBMDATA || err == EMBBADSLAVE ||
         err == EMBBADCRC;
}

}  // namespace

Result<std::unique_ptr<TcpClient>> TcpClient::create(const TcpClientOptions& options) {
  modbus_t* ctx = new_context(options);
  if (ctx == nullptr) {
    return make_error(Errc::invalid_argument, fmt::format("Modbus TCP endpoint {}:{}: {}", options.host,
                                                          options.port, modbus_strerror(errno)));
  }
  std::unique_ptr<TcpClient> client(new TcpClient(options, ctx));
  SF_TRY(configure(ctx, options));
  return client;
}

TcpClient::TcpClient(const TcpClientOptions& options, _modbus* ctx) : options_(options), ctx_(ctx) {}

TcpClient::~TcpClient() = default;

std::string TcpClient::endpoint() const {
  if (options_.host.find(':') != std::string::npos) {
    return fmt::format("[{}]:{}", options_.host, options_.port);
  }
  return fmt::format("{}:{}", options_.host, options_.port);
}

Status TcpClient::connect() {
  if (connected()) {
    return {};
  }
  if (modbus_connect(ctx_.get()) != 0) {
    const int err = errno;
    modbus_close(ctx_.get());
    return make_error(Errc::io, fmt::format("connect to {}: {}", endpoint(), modbus_strerror(err)));
  }
  return {};
}

void TcpClient::close() {
  modbus_close(ctx_.get());
}

bool TcpClient::connected() const {
  return modbus_get_socket(ctx_.get()) >= 0;
}

// A connection with something to read before a request was sent is stale: the server closed it
// (end of stream) or a response arrived after its request had timed out.
bool TcpClient::connection_closed_by_peer() const {
  pollfd p{modbus_get_socket(ctx_.get()), POLLIN, 0};
  return ::poll(&p, 1, 0) != 0;
}

ClientError TcpClient::failure(const Transaction& t, int err) {
  const std::string context =
      fmt::format("{} {} x{} at {}", to_string(t.function), t.address, t.count, endpoint());
  if (is_exception(err)) {
    return ClientError::from_exception(static_cast<ExceptionCode>(err - MODBUS_ENOBASE), context);
  }
  // The connection's state is unknown (a late response may still come): start afresh next time.
  close();
  if (err == ETIMEDOUT) {
    return ClientError(Errc::timeout, fmt::format("{}: no response within {} ms", context,
                                                  options_.response_timeout.count()));
  }
  if (is_bad_response(err)) {
    return ClientError(Errc::malformed, fmt::format("{}: {}", context, modbus_strerror(err)));
  }
  return ClientError(Errc::io, fmt::format("{}: connection lost: {}", context, modbus_strerror(err)));
}

namespace {

std::vector<bool> to_bits(const std::vector<std::uint8_t>& bytes) {
  std::vector<bool> out(bytes.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    out[i] = bytes[i] != 0;
  }
  return out;
}

int read(modbus_t* ctx, const Client::Transaction& t, Client::Reply& reply) {
  std::vector<std::uint8_t> bits(
      t.function == FunctionCode::read_coils || t.function == FunctionCode::read_discrete_inputs ? t.count
                                                                                                 : 0);
  int rc = -1;
  switch (t.function) {
    case FunctionCode::read_coils:
      rc = modbus_read_bits(ctx, t.address, t.count, bits.data());
      reply.bits = to_bits(bits);
      break;
    case FunctionCode::read_discrete_inputs:
      rc = modbus_read_input_bits(ctx, t.address, t.count, bits.data());
      reply.bits = to_bits(bits);
      break;
    case FunctionCode::read_input_registers:
      reply.registers.resize(t.count);
      rc = modbus_read_input_registers(ctx, t.address, t.count, reply.registers.data());
      break;
    default:
      reply.registers.resize(t.count);
      rc = modbus_read_registers(ctx, t.address, t.count, reply.registers.data());
  }
  return rc;
}

int write(modbus_t* ctx, const Client::Transaction& t) {
  switch (t.function) {
    case FunctionCode::write_single_coil:
      return modbus_write_bit(ctx, t.address, (*t.coils)[0] ? 1 : 0);
    case FunctionCode::write_single_register:
      return modbus_write_register(ctx, t.address, t.registers[0]);
    case FunctionCode::write_multiple_coils: {
      std::vector<std::uint8_t> bits(t.coils->begin(), t.coils->end());
      return modbus_write_bits(ctx, t.address, t.count, bits.data());
    }
    default:
      return modbus_write_registers(ctx, t.address, t.count, t.registers.data());
  }
}

bool is_read(FunctionCode function) {
  return static_cast<std::uint8_t>(function) <= static_cast<std::uint8_t>(FunctionCode::read_input_registers);
}

}  // namespace

ClientResult<Client::Reply> TcpClient::transact(const Transaction& transaction) {
  if (connected() && connection_closed_by_peer()) {
    close();
  }
  if (auto st = connect(); !st) {
    return ClientError(st.error());
  }
  Reply reply;
  const int rc =
      is_read(transaction.function) ? read(ctx_.get(), transaction, reply) : write(ctx_.get(), transaction);
  if (rc == -1) {
    return failure(transaction, errno);
  }
  return reply;
}

}  // namespace sf::modbus
