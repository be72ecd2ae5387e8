// The request path against its reference: libmodbus's own modbus_reply. Every request of a grid
// (each function, addresses around each table's ends, quantities around each limit, coil
// values) is answered by modbus_reply from one bank and by check_request + apply from another;
// the exception codes, the data read and the banks afterwards must agree.
#include "request_path.hpp"

#include <modbus.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace sf::modbus::test {
namespace {

using detail::decode_request;

TEST(DecodeRequest, ReadsNameTheirTableAndRange) {
  const auto p = pdu(0x04, {2003, 5});
  const auto d = decode_request(9, p);
  ASSERT_FALSE(d.refusal);
  EXPECT_EQ(d.request.unit_id, 9);
  EXPECT_EQ(d.request.function, FunctionCode::read_input_registers);
  EXPECT_EQ(d.request.read, (Range{Table::input_registers, 2003, 5}));
  EXPECT_FALSE(d.request.writes());
}

TEST(DecodeRequest, WritesCarryTheirValues) {
  auto p = pdu(0x0F, {4, 10});
  p.insert(p.end(), {2, 0b0000'0101, 0b10});
  const auto d = decode_request(1, p);
  ASSERT_FALSE(d.refusal);
  EXPECT_EQ(d.request.write, (Range{Table::coils, 4, 10}));
  EXPECT_TRUE(d.request.coil_value(0));
  EXPECT_FALSE(d.request.coil_value(1));
  EXPECT_TRUE(d.request.coil_value(2));
  EXPECT_TRUE(d.request.coil_value(9));

  const auto single_pdu = pdu(0x05, {7, 0xFF00});  // the request's data points into it
  const auto single = decode_request(1, single_pdu);
  EXPECT_EQ(single.request.write, (Range{Table::coils, 7, 1}));
  EXPECT_TRUE(single.request.coil_value(0));

  const auto reg_pdu = pdu(0x06, {1001, 0x1234});
  const auto reg = decode_request(1, reg_pdu);
  EXPECT_EQ(reg.request.write, (Range{Table::holding_registers, 1001, 1}));
  EXPECT_EQ(reg.request.register_value(0), 0x1234);
}

TEST(DecodeRequest, ReadWriteMultipleHasBothRanges) {
  auto p = pdu(0x17, {1000, 3, 1010, 2});
  p.insert(p.end(), {4, 0, 1, 0, 2});
  const auto d = decode_request(1, p);
  ASSERT_FALSE(d.refusal);
  EXPECT_EQ(d.request.read, (Range{Table::holding_registers, 1000, 3}));
  EXPECT_EQ(d.request.write, (Range{Table::holding_registers, 1010, 2}));
  EXPECT_EQ(d.request.register_value(1), 2);
}

TEST(DecodeRequest, UnknownFunctionIsIllegalFunction) {
  for (std::uint8_t code :
       std::initializer_list<std::uint8_t>{0x00, 0x07, 0x08, 0x11, 0x2B, 0x41, 0x83, 0xFF}) {
    EXPECT_EQ(decode_request(1, pdu(code, {0, 1})).refusal, ExceptionCode::illegal_function) << int{code};
  }
}

TEST(DecodeRequest, LengthThatDoesNotFitTheFunctionIsIllegalDataValue) {
  EXPECT_EQ(decode_request(1, pdu(0x03, {0})).refusal, ExceptionCode::illegal_data_value);
  EXPECT_EQ(decode_request(1, pdu(0x03, {0, 1, 2})).refusal, ExceptionCode::illegal_data_value);
  EXPECT_EQ(decode_request(1, std::vector<std::uint8_t>{0x06}).refusal, ExceptionCode::illegal_data_value);
  auto short_values = pdu(0x10, {1000, 2});
  short_values.insert(short_values.end(), {4, 0, 1});  // byte count 4, three bytes follow
  EXPECT_EQ(decode_request(1, short_values).refusal, ExceptionCode::illegal_data_value);
  EXPECT_EQ(decode_request(1, pdu(0x16, {1000, 0xFF})).refusal, ExceptionCode::illegal_data_value);
}

TEST(CheckRequest, ByteCountMustMatchTheQuantity) {
  RegisterBank bank = make_bank();
  auto p = pdu(0x10, {1000, 2});
  p.insert(p.end(), {2, 0, 1});  // two registers announced, one sent
  const auto d = decode_request(1, p);
  ASSERT_FALSE(d.refusal);
  EXPECT_EQ(detail::check_request(bank, d.request), ExceptionCode::illegal_data_value);
}

// --- against libmodbus --------------------------------------------------------------------

const BankLayout kGridLayout{
    .coils = {10, 20},
    .discrete_inputs = {30, 20},
    .holding_registers = {40, 30},
    .input_registers = {0, 30},
};

// What modbus_reply answers: an exception code, or the response PDU after the function code.
struct Reference {
  std::optional<std::uint8_t> exception;
  std::vector<std::uint8_t> body;
};

class LibmodbusReply {
 public:
  LibmodbusReply() {
    EXPECT_EQ(::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds_), 0);
    ctx_ = modbus_new_tcp("127.0.0.1", 502);
    // modbus_reply sleeps for the response timeout before some exceptions; keep it short.
    modbus_set_response_timeout(ctx_, 0, 1);
    modbus_set_socket(ctx_, fds_[0]);
  }
  ~LibmodbusReply() {
    modbus_set_socket(ctx_, -1);
    modbus_free(ctx_);
    ::close(fds_[0]);
    ::close(fds_[1]);
  }
  LibmodbusReply(const LibmodbusReply&) = delete;
  LibmodbusReply& operator=(const LibmodbusReply&) = delete;

  Reference reply(const std::vector<std::uint8_t>& request_pdu, RegisterBank& bank) {
    const auto frame = adu(1, 1, request_pdu);
    EXPECT_GT(modbus_reply(ctx_, frame.data(), static_cast<int>(frame.size()), bank.mapping()), 0);
    RawConnection peer(::dup(fds_[1]));
    const auto response = peer.read_response(1000);
    EXPECT_TRUE(response);
    Reference out;
    if (response && response->is_exception()) {
      out.exception = response->exception_code();
    } else if (response) {
      out.body = response->body;
    }
    return out;
  }

 private:
  int fds_[2] = {-1, -1};
  modbus_t* ctx_ = nullptr;
};

void fill(RegisterBank& bank) {
  const BankLayout& l = bank.layout();
  for (std::uint16_t i = 0; i < l.coils.count; ++i) {
    bank.set_coil(static_cast<std::uint16_t>(l.coils.start + i), i % 3 == 0);
  }
  for (std::uint16_t i = 0; i < l.discrete_inputs.count; ++i) {
    bank.set_discrete_input(static_cast<std::uint16_t>(l.discrete_inputs.start + i), i % 2 == 1);
  }
  for (std::uint16_t i = 0; i < l.holding_registers.count; ++i) {
    bank.set_holding_register(static_cast<std::uint16_t>(l.holding_registers.start + i),
                              static_cast<std::uint16_t>(0x1000 + i));
  }
  for (std::uint16_t i = 0; i < l.input_registers.count; ++i) {
    bank.set_input_register(static_cast<std::uint16_t>(l.input_registers.start + i),
                            static_cast<std::uint16_t>(0x2000 + i));
  }
}

bool same_contents(const RegisterBank& a, const RegisterBank& b) {
  const BankLayout& l = a.layout();
  for (Table t : {Table::coils, Table::discrete_inputs}) {
    if (a.bits(t, l[t].start, l[t].count) != b.bits(t, l[t].start, l[t].count)) {
      return false;
    }
  }
  for (Table t : {Table::holding_registers, Table::input_registers}) {
    if (a.words(t, l[t].start, l[t].count) != b.words(t, l[t].start, l[t].count)) {
      return false;
    }
  }
  return true;
}

// The response body ours implies: byte count and values, or the echo of a write.
std::vector<std::uint8_t> expected_body(const Request& r, const Client::Reply& reply,
                                        const std::vector<std::uint8_t>& request_pdu) {
  if (!r.read) {
    // Writes echo address and quantity/value (§6.5, §6.6, §6.11, §6.12) or the whole request (§6.16).
    const std::size_t echoed = r.function == FunctionCode::mask_write_register ? 6 : 4;
    return {request_pdu.begin() + 1, request_pdu.begin() + 1 + static_cast<std::ptrdiff_t>(echoed)};
  }
  std::vector<std::uint8_t> body{0};
  if (!reply.bits.empty()) {
    for (std::size_t i = 0; i < reply.bits.size(); ++i) {
      if (i % 8 == 0) {
        body.push_back(0);
      }
      body.back() = static_cast<std::uint8_t>(body.back() | (reply.bits[i] ? 1U << (i % 8) : 0U));
    }
  }
  for (std::uint16_t v : reply.registers) {
    body.push_back(static_cast<std::uint8_t>(v >> 8));
    body.push_back(static_cast<std::uint8_t>(v & 0xFF));
  }
  body[0] = static_cast<std::uint8_t>(body.size() - 1);
  return body;
}

std::vector<std::vector<std::uint8_t>> request_grid() {
  std::vector<std::vector<std::uint8_t>> grid;
  const std::vector<std::uint16_t> addresses{0, 9, 10, 25, 29, 30, 39, 40, 65, 69, 70, 0xFFFF};
  for (std::uint8_t fc : std::initializer_list<std::uint8_t>{0x01, 0x02, 0x03, 0x04}) {
    for (std::uint16_t a : addresses) {
      for (std::uint16_t n :
           std::initializer_list<std::uint16_t>{0, 1, 5, 20, 30, 31, 125, 126, 2000, 2001, 0xFFFF}) {
        grid.push_back(pdu(fc, {a, n}));
      }
    }
  }
  for (std::uint16_t a : addresses) {
    for (std::uint16_t v : std::initializer_list<std::uint16_t>{0x0000, 0xFF00, 0x0001, 0x00FF, 0xFFFF}) {
      grid.push_back(pdu(0x05, {a, v}));
    }
    grid.push_back(pdu(0x06, {a, 0xABCD}));
    grid.push_back(pdu(0x16, {a, 0x00F2, 0x0025}));
    for (std::uint16_t n : std::initializer_list<std::uint16_t>{0, 1, 9, 20, 21, 1968, 1969}) {
      auto p = pdu(0x0F, {a, n});
      const std::size_t bytes = (n + 7U) / 8U;
      p.push_back(static_cast<std::uint8_t>(bytes));
      for (std::size_t i = 0; i < bytes; ++i) {
        p.push_back(static_cast<std::uint8_t>(0xA5 ^ i));
      }
      grid.push_back(p);
    }
    for (std::uint16_t n : std::initializer_list<std::uint16_t>{0, 1, 7, 30, 31, 123, 124}) {
      auto p = pdu(0x10, {a, n});
      p.push_back(static_cast<std::uint8_t>(2 * n));
      for (std::uint16_t i = 0; i < n; ++i) {
        p.push_back(static_cast<std::uint8_t>(i));
        p.push_back(0x5A);
      }
      grid.push_back(p);
    }
  }
  for (std::uint16_t read_at : std::initializer_list<std::uint16_t>{39, 40, 60}) {
    for (std::uint16_t write_at : std::initializer_list<std::uint16_t>{39, 40, 68}) {
      for (std::uint16_t rn : std::initializer_list<std::uint16_t>{0, 2, 11, 126}) {
        for (std::uint16_t wn : std::initializer_list<std::uint16_t>{0, 2, 3, 122}) {
          auto p = pdu(0x17, {read_at, rn, write_at, wn});
          p.push_back(static_cast<std::uint8_t>(2 * wn));
          for (std::uint16_t i = 0; i < wn; ++i) {
            p.push_back(0x77);
            p.push_back(static_cast<std::uint8_t>(i));
          }
          grid.push_back(p);
        }
      }
    }
  }
  return grid;
}

TEST(RequestPathAgainstLibmodbus, SameExceptionsDataAndBank) {
  LibmodbusReply libmodbus;
  std::size_t answered = 0;
  std::size_t refused = 0;
  for (const auto& request_pdu : request_grid()) {
    RegisterBank theirs = make_bank(kGridLayout);
    RegisterBank ours = make_bank(kGridLayout);
    fill(theirs);
    fill(ours);
    const Reference reference = libmodbus.reply(request_pdu, theirs);

    const auto decoded = decode_request(1, request_pdu);
    ASSERT_FALSE(decoded.refusal);
    const auto exception = detail::check_request(ours, decoded.request);
    const std::string what = decoded.request.describe();
    ASSERT_EQ(exception.has_value(), reference.exception.has_value()) << what;
    if (exception) {
      EXPECT_EQ(static_cast<std::uint8_t>(*exception), *reference.exception) << what;
      ++refused;
    } else {
      Client::Reply reply;
      detail::apply(ours, decoded.request, reply);
      EXPECT_EQ(expected_body(decoded.request, reply, request_pdu), reference.body) << what;
      ++answered;
    }
    EXPECT_TRUE(same_contents(ours, theirs)) << what;
  }
  // The grid reaches both outcomes often.
  EXPECT_GT(answered, 50U);
  EXPECT_GT(refused, 100U);
}

TEST(RequestPathAgainstLibmodbus, MaskWriteFollowsTheSpecExample) {
  // MB AP §6.16 example: current 0x12, AND 0xF2, OR 0x25 -> 0x17.
  RegisterBank bank = make_bank();
  bank.set_holding_register(1004, 0x12);
  const auto p = pdu(0x16, {1004, 0x00F2, 0x0025});
  const auto d = decode_request(1, p);
  ASSERT_FALSE(detail::check_request(bank, d.request));
  Client::Reply reply;
  detail::apply(bank, d.request, reply);
  EXPECT_EQ(bank.holding_register(1004), 0x17);
}

}  // namespace
}  // namespace sf::modbus::test
