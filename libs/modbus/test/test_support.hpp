// Shared pieces of the modbus tests: a device that records its hooks, a raw Modbus TCP
// connection for bytes no client would send, and ADU builders.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "sf/modbus/device.hpp"

namespace sf::modbus::test {

// Every table starts elsewhere, so start addresses matter in every test.
inline const BankLayout kLayout{
    .coils = {0, 32},
    .discrete_inputs = {100, 16},
    .holding_registers = {1000, 100},
    .input_registers = {2000, 20},
};

inline RegisterBank make_bank(const BankLayout& layout = kLayout) {
  auto bank = RegisterBank::create(layout);
  EXPECT_TRUE(bank.ok());
  return std::move(bank).value();
}

// Records what its hooks see (guarded by mutex()) and refuses requests when told to.
class RecordingDevice final : public Device {
 public:
  explicit RecordingDevice(const BankLayout& layout = kLayout) : bank_(make_bank(layout)) {}
  RegisterBank& bank() override { return bank_; }

  std::optional<ExceptionCode> before_request(const Request& request) override {
    before.push_back(request);
    before.back().data = {};  // valid only during the hook
    return refuse;
  }
  void after_write(const Request& request) override {
    after.push_back(request);
    written_values.clear();
    for (std::size_t i = 0; i < request.write->count; ++i) {
      written_values.push_back(request.write->table == Table::coils ? request.coil_value(i)
                                                                    : request.register_value(i));
    }
    after.back().data = {};
  }

  std::vector<Request> before;
  std::vector<Request> after;
  std::vector<std::uint16_t> written_values;  // the last write's values, as after_write saw them
  std::optional<ExceptionCode> refuse;

 private:
  RegisterBank bank_;
};

// An ADU: MBAP header (MB TCP §3.1.3) + PDU; `length` overrides the header's length field.
inline std::vector<std::uint8_t> adu(std::uint16_t transaction, std::uint8_t unit,
                                     const std::vector<std::uint8_t>& pdu,
                                     std::optional<std::uint16_t> length = std::nullopt,
                                     std::uint16_t protocol = 0) {
  const auto len = length.value_or(static_cast<std::uint16_t>(pdu.size() + 1));
  std::vector<std::uint8_t> out{static_cast<std::uint8_t>(transaction >> 8),
                                static_cast<std::uint8_t>(transaction & 0xFF),
                                static_cast<std::uint8_t>(protocol >> 8),
                                static_cast<std::uint8_t>(protocol & 0xFF),
                                static_cast<std::uint8_t>(len >> 8),
                                static_cast<std::uint8_t>(len & 0xFF),
                                unit};
  out.insert(out.end(), pdu.begin(), pdu.end());
  return out;
}

// A PDU with a function code and 16-bit fields.
inline std::vector<std::uint8_t> pdu(std::uint8_t function, std::initializer_list<std::uint16_t> fields) {
  std::vector<std::uint8_t> out{function};
  for (std::uint16_t f : fields) {
    out.push_back(static_cast<std::uint8_t>(f >> 8));
    out.push_back(static_cast<std::uint8_t>(f & 0xFF));
  }
  return out;
}

// A response as read back: its transaction id, function code and PDU bytes after the code.
struct Response {
  std::uint16_t transaction = 0;
  std::uint8_t unit = 0;
  std::uint8_t function = 0;
  std::vector<std::uint8_t> body;

  [[nodiscard]] bool is_exception() const { return (function & 0x80U) != 0; }
  [[nodiscard]] std::uint8_t exception_code() const { return body.empty() ? 0 : body[0]; }
};

// A blocking TCP connection to 127.0.0.1:port that sends raw bytes. Reads wait at most
// `patience` for a server on another thread (a bound against hanging, not a measurement).
class RawConnection {
 public:
  explicit RawConnection(std::uint16_t port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port);
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;  // NOLINT
    // Requests leave at once, as libmodbus's own client sends them (no Nagle wait for an ACK).
    const int one = 1;
    (void)::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  }
  explicit RawConnection(int fd) : fd_(fd), connected_(true) {}
  ~RawConnection() {
    if (fd_ >= 0) {
      ::close(fd_);
    }
  }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;

  [[nodiscard]] bool connected() const { return connected_; }
  bool send(const std::vector<std::uint8_t>& bytes) {
    return ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
  }
  // One response frame, or nothing when the connection closed (or nothing came in time).
  std::optional<Response> read_response(int patience_ms = 5000) {
    std::vector<std::uint8_t> header(7);
    if (!read_exactly(header, patience_ms)) {
      return std::nullopt;
    }
    const std::size_t length = (static_cast<std::size_t>(header[4]) << 8U) | header[5];
    std::vector<std::uint8_t> rest(length > 0 ? length - 1 : 0);
    if (!read_exactly(rest, patience_ms) || rest.empty()) {
      return std::nullopt;
    }
    Response r;
    r.transaction = static_cast<std::uint16_t>((header[0] << 8U) | header[1]);
    r.unit = header[6];
    r.function = rest[0];
    r.body.assign(rest.begin() + 1, rest.end());
    return r;
  }
  // True when the server closed the connection (end of stream or reset) within the patience.
  bool closed_by_peer(int patience_ms = 5000) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, patience_ms) <= 0) {
      return false;
    }
    std::uint8_t byte = 0;
    return ::recv(fd_, &byte, 1, 0) <= 0;
  }
  [[nodiscard]] int fd() const { return fd_; }

 private:
  bool read_exactly(std::vector<std::uint8_t>& out, int patience_ms) {
    std::size_t got = 0;
    while (got < out.size()) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, patience_ms) <= 0) {
        return false;
      }
      const ssize_t n = ::recv(fd_, out.data() + got, out.size() - got, 0);
      if (n <= 0) {
        return false;
      }
      got += static_cast<std::size_t>(n);
    }
    return true;
  }

  int fd_ = -1;
  bool connected_ = false;
};

}  // namespace sf::modbus::test
