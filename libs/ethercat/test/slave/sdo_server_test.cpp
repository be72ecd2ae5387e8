// CoE mailbox and SDO server: expedited, normal and segmented transfers,
// complete access, aborts, mailbox errors and the repeat procedure
// (ETG.1000.4 §5.6, ETG.1000.6 §5.6.2).
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "sf/ethercat/mailbox.hpp"
#include "sf/ethercat/sdo_abort_codes.hpp"
#include "sf/ethercat/sdo_info.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/standard_objects.hpp"
#include "slave_test_support.hpp"

namespace sf::ethercat::slave {
namespace {

using testing::Harness;

constexpr std::uint32_t sdo_code(SdoAbortCode c) {
  return static_cast<std::uint32_t>(c);
}

class SdoTest : public ::testing::Test {
 protected:
  SdoTest() : h("servo:1") {
    h.assign_stations();
    h.configure_mailbox(0);
    EXPECT_EQ(h.request(0, AlState::PreOp), AlStatus::of(AlState::PreOp));
  }

  // Writes a mailbox message into SM0 (padded to its size); returns the WKC.
  std::uint16_t send(const Bytes& message) {
    Bytes buffer = message;
    buffer.resize(kMailboxSize, 0);
    return h.run(Harness::physical(Command::FPWR, st, kMailboxOutStart, buffer)).wkc;
  }
  // Reads SM1 once; nullopt if the mailbox was empty (WKC 0).
  std::optional<Bytes> receive() {
    auto d = h.run(Harness::physical(Command::FPRD, st, kMailboxInStart, Bytes(kMailboxSize, 0)));
    if (d.wkc == 0)
      return std::nullopt;
    return d.data;
  }
  SdoResponse exchange(const SdoRequest& request) {
    auto message = make_sdo_request(request, counter_ = next_mailbox_counter(counter_));
    EXPECT_TRUE(message.ok());
    EXPECT_EQ(send(*message), 1);
    auto reply = receive();
    EXPECT_TRUE(reply.has_value());
    if (!reply)
      return SdoAbort{};
    auto coe = decode_coe(*reply);
    EXPECT_TRUE(coe.ok()) << (coe.ok() ? "" : coe.error().describe());
    if (!coe)
      return SdoAbort{};
    auto response = decode_sdo_response(coe->body);
    EXPECT_TRUE(response.ok());
    if (!response)
      return SdoAbort{};
    // Abort SDO Transfer is CoE service 2 (ETG.1000.6 §5.6.2.7.1), every
    // other answer service 3.
    const bool abort = std::holds_alternative<SdoAbort>(*response);
    EXPECT_EQ(coe->coe.service, abort ? CoeService::SdoRequest : CoeService::SdoResponse);
    return *response;
  }
  // An SDO Information request; the reassembled answer and how many
  // mailbox messages carried it.
  std::pair<std::optional<SdoInfoMessage>, int> info(const SdoInfoMessage& request) {
    EXPECT_EQ(send(make_sdo_info(request, counter_ = next_mailbox_counter(counter_))), 1);
    SdoInfoReassembly reassembly;
    for (int messages = 1; messages < 100; ++messages) {
      auto reply = receive();
      if (!reply)
        return {std::nullopt, messages};
      auto coe = decode_coe(*reply);
      EXPECT_TRUE(coe.ok());
      if (!coe)
        return {std::nullopt, messages};
      EXPECT_EQ(coe->coe.service, CoeService::SdoInformation);
      auto m = reassembly.add(coe->body);
      EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().describe());
      if (!m || m->has_value())
        return {m ? std::move(*m) : std::nullopt, messages};
    }
    return {std::nullopt, 100};
  }
  // A full upload, segmented if needed; aborts come back as their code.
  std::variant<Bytes, std::uint32_t> upload(std::uint16_t index, std::uint8_t sub, bool ca = false) {
    auto r = exchange(SdoInitiateUploadRequest{index, sub, ca});
    if (auto* a = std::get_if<SdoAbort>(&r))
      return a->code;
    auto init = std::get<SdoInitiateUploadResponse>(r);
    Bytes data = init.data;
    bool toggle = false;
    while (data.size() < init.complete_size) {
      auto s = exchange(SdoUploadSegmentRequest{toggle});
      if (auto* a = std::get_if<SdoAbort>(&s))
        return a->code;
      auto seg = std::get<SdoUploadSegmentResponse>(s);
      EXPECT_EQ(seg.toggle, toggle);
      data.insert(data.end(), seg.data.begin(), seg.data.end());
      toggle = !toggle;
      if (seg.last)
        break;
    }
    uploads_segmented_ += data.size() > init.data.size() ? 1 : 0;
    return data;
  }
  std::uint32_t download(std::uint16_t index, std::uint8_t sub, const Bytes& value, bool ca = false) {
    auto init = SdoInitiateDownloadRequest::make(index, sub, value, sdo_initiate_capacity(kMailboxSize), ca);
    auto r = exchange(init);
    if (auto* a = std::get_if<SdoAbort>(&r))
      return a->code;
    std::size_t sent = init.expedited ? value.size() : init.data.size();
    bool toggle = false;
    while (sent < value.size()) {
      const std::size_t n = std::min(sdo_segment_capacity(kMailboxSize), value.size() - sent);
      SdoDownloadSegmentRequest seg;
      seg.toggle = toggle;
      seg.data.assign(value.begin() + static_cast<std::ptrdiff_t>(sent),
                      value.begin() + static_cast<std::ptrdiff_t>(sent + n));
      sent += n;
      seg.last = sent == value.size();
      auto s = exchange(seg);
      if (auto* a = std::get_if<SdoAbort>(&s))
        return a->code;
      EXPECT_EQ(std::get<SdoDownloadSegmentResponse>(s).toggle, toggle);
      toggle = !toggle;
    }
    return 0;
  }

  Harness h;
  std::uint16_t st = Harness::station(0);
  std::uint8_t counter_ = 0;
  int uploads_segmented_ = 0;
};

TEST_F(SdoTest, ExpeditedUploadOfIdentity) {
  auto v = upload(0x1018, 2);
  ASSERT_TRUE(std::holds_alternative<Bytes>(v));
  EXPECT_EQ(load_le<std::uint32_t>(std::get<Bytes>(v).data()), kServoProductCode);
  EXPECT_EQ(load_le<std::uint32_t>(std::get<Bytes>(upload(0x1000, 0)).data()), 0x00020192u);
}

TEST_F(SdoTest, NormalUploadOfTheDeviceName) {
  auto v = upload(0x1008, 0);
  ASSERT_TRUE(std::holds_alternative<Bytes>(v));
  const Bytes& b = std::get<Bytes>(v);
  EXPECT_EQ(std::string(b.begin(), b.end()), "Servo drive (1 axis)");
}

TEST_F(SdoTest, ExpeditedDownloadThenReadBack) {
  EXPECT_EQ(download(0x6065, 0, Harness::le<std::uint32_t>(4321)), 0u);
  EXPECT_EQ(load_le<std::uint32_t>(std::get<Bytes>(upload(0x6065, 0)).data()), 4321u);
}

TEST_F(SdoTest, SegmentedTransfersBothWays) {
  // A writable string longer than one mailbox: segmented download and upload.
  auto& od = h.segment->slave(0).objects();
  od.add_string(0x2000, "Notes", "", access::kRW);
  od.find(0x2000, 0)->bit_length = 8 * 400;
  Bytes text(300);
  for (std::size_t i = 0; i < text.size(); ++i)
    text[i] = static_cast<std::uint8_t>('a' + i % 26);
  EXPECT_EQ(download(0x2000, 0, text), 0u);
  auto back = upload(0x2000, 0);
  ASSERT_TRUE(std::holds_alternative<Bytes>(back));
  EXPECT_EQ(std::get<Bytes>(back), text);
  EXPECT_EQ(uploads_segmented_, 1);
}

TEST_F(SdoTest, AbortsForMissingReadOnlyAndWrongLength) {
  EXPECT_EQ(std::get<std::uint32_t>(upload(0x2345, 0)), sdo_code(SdoAbortCode::ObjectDoesNotExist));
  EXPECT_EQ(std::get<std::uint32_t>(upload(0x1018, 9)), sdo_code(SdoAbortCode::SubindexDoesNotExist));
  EXPECT_EQ(download(0x1018, 1, Harness::le<std::uint32_t>(1)), sdo_code(SdoAbortCode::ReadOnly));
  EXPECT_EQ(download(0x6065, 0, Harness::le<std::uint16_t>(1)), sdo_code(SdoAbortCode::LengthMismatch));
  EXPECT_EQ(download(0x6060, 0, Bytes{3}), sdo_code(SdoAbortCode::ValueRangeExceeded));  // only CSP
}

TEST_F(SdoTest, MappingIsWritableInPreOpOnlyAndFollowsTheSubindexZeroRule) {
  // Entries may only change while subindex 0 is 0.
  EXPECT_EQ(download(0x1A00, 3, Harness::le<std::uint32_t>(0x606C0020)),
            sdo_code(SdoAbortCode::SubindexCannotBeWritten));
  EXPECT_EQ(download(0x1A00, 0, Bytes{0}), 0u);
  EXPECT_EQ(download(0x1A00, 1, Harness::le<std::uint32_t>(0x60410010)), 0u);
  EXPECT_EQ(download(0x1A00, 2, Harness::le<std::uint32_t>(0x60640020)), 0u);
  // 0x6040 is an RxPDO object: it cannot go into a TxPDO.
  EXPECT_EQ(download(0x1A00, 3, Harness::le<std::uint32_t>(0x60400010)),
            sdo_code(SdoAbortCode::CannotBeMapped));
  EXPECT_EQ(download(0x1A00, 3, Harness::le<std::uint32_t>(0x60F40020)), 0u);  // following error actual
  EXPECT_EQ(download(0x1A00, 0, Bytes{3}), 0u);
  // Going to SAFEOP with the new 10-byte TxPDO and reading it back via complete access.
  auto ca = upload(0x1A00, 0, true);
  ASSERT_TRUE(std::holds_alternative<Bytes>(ca));
  const Bytes& b = std::get<Bytes>(ca);
  ASSERT_GE(b.size(), 2u + 3u * 4u);
  EXPECT_EQ(b[0], 3);
  EXPECT_EQ(load_le<std::uint32_t>(&b[2 + 8]), 0x60F40020u);
  h.write_sm(0, 2, kOutputsStart, 6, 0x64);
  h.write_sm(0, 3, kInputsStart, 10, 0x20);
  ASSERT_EQ(h.request(0, AlState::SafeOp), AlStatus::of(AlState::SafeOp));
  EXPECT_EQ(download(0x1A00, 0, Bytes{0}), sdo_code(SdoAbortCode::CannotTransferDeviceState));
}

TEST_F(SdoTest, CompleteAccessDownloadOfTheAssignment) {
  // 0x1C13 := { 0x1A00 } with subindex 0 padded to 16 bits.
  const Bytes ca = {1, 0, 0x00, 0x1A};
  EXPECT_EQ(download(0x1C13, 0, ca, true), 0u);
  auto back = upload(0x1C13, 0, true);
  ASSERT_TRUE(std::holds_alternative<Bytes>(back));
  EXPECT_EQ(std::get<Bytes>(back), (Bytes{1, 0, 0x00, 0x1A}));
  // A PDO index outside the TxPDO range is refused.
  EXPECT_EQ(download(0x1C13, 0, Bytes{1, 0, 0x00, 0x16}, true), sdo_code(SdoAbortCode::ValueRangeExceeded));
}

TEST_F(SdoTest, SegmentToggleErrorAbortsTheTransfer) {
  auto& od = h.segment->slave(0).objects();
  od.add_string(0x2001, "Long", "", access::kRW);
  od.find(0x2001, 0)->bit_length = 8 * 400;
  Bytes value(200, 'x');
  auto init = SdoInitiateDownloadRequest::make(0x2001, 0, value, sdo_initiate_capacity(kMailboxSize));
  ASSERT_TRUE(std::holds_alternative<SdoInitiateDownloadResponse>(exchange(init)));
  SdoDownloadSegmentRequest seg;
  seg.toggle = true;  // must start with 0
  seg.data = Bytes(10, 'y');
  auto r = exchange(seg);
  ASSERT_TRUE(std::holds_alternative<SdoAbort>(r));
  EXPECT_EQ(std::get<SdoAbort>(r).code, sdo_code(SdoAbortCode::ToggleBitNotChanged));
  // A segment without a transfer in progress.
  r = exchange(SdoUploadSegmentRequest{false});
  EXPECT_EQ(std::get<SdoAbort>(r).code, sdo_code(SdoAbortCode::InvalidCommandSpecifier));
}

TEST_F(SdoTest, UnsupportedProtocolsGetAMailboxError) {
  MailboxHeader header;
  header.type = MailboxType::FoE;
  header.counter = 1;
  ASSERT_EQ(send(encode_mailbox(header, Bytes(6, 0))), 1);
  auto reply = receive();
  ASSERT_TRUE(reply.has_value());
  auto message = decode_mailbox(*reply);
  ASSERT_TRUE(message.ok());
  EXPECT_EQ(message->header.type, MailboxType::Err);
  EXPECT_EQ(decode_mailbox_error(message->data).value(), MailboxError::UnsupportedProtocol);
}

TEST_F(SdoTest, MailboxFullAndEmptyDenyAccess) {
  // Empty read mailbox: WKC 0.
  EXPECT_FALSE(receive().has_value());
  EXPECT_EQ(h.fprd(st, reg::sync_manager(1) + reg::kSmStatus, 1).data[0] & sm::kStatusMailboxFull, 0);
  // A request: the reply sits in SM1 (status full) until read.
  auto message = make_sdo_request(SdoInitiateUploadRequest{0x1000, 0, false}, 1);
  ASSERT_EQ(send(*message), 1);
  EXPECT_NE(h.fprd(st, reg::sync_manager(1) + reg::kSmStatus, 1).data[0] & sm::kStatusMailboxFull, 0);
  // Second request before the reply is read: its reply waits in the queue.
  ASSERT_EQ(send(*make_sdo_request(SdoInitiateUploadRequest{0x1018, 1, false}, 2)), 1);
  auto first = receive();
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(load_le<std::uint32_t>(&(*first)[6 + 2 + 4]), 0x00020192u);
  auto second = receive();
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(load_le<std::uint32_t>(&(*second)[6 + 2 + 4]), kVendorId);
  EXPECT_FALSE(receive().has_value());
}

TEST_F(SdoTest, RepeatRequestResendsTheLastReply) {
  ASSERT_EQ(send(*make_sdo_request(SdoInitiateUploadRequest{0x1018, 2, false}, 1)), 1);
  auto lost = receive();  // "lost on the way back"
  ASSERT_TRUE(lost.has_value());
  EXPECT_FALSE(receive().has_value());
  // Toggle the repeat request (SM1 activate bit 1): the reply comes again and
  // PDI control bit 1 follows.
  ASSERT_EQ(h.fpwr(st, reg::sync_manager(1) + reg::kSmActivate, Bytes{0x03}), 1);
  EXPECT_EQ(h.fprd(st, reg::sync_manager(1) + reg::kSmPdiControl, 1).data[0] & sm::kPdiRepeatAck,
            sm::kPdiRepeatAck);
  auto again = receive();
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(*again, *lost);
}

TEST_F(SdoTest, ASecondRepeatBeforeTheFirstWasReadDoesNotDuplicate) {
  ASSERT_EQ(send(*make_sdo_request(SdoInitiateUploadRequest{0x1018, 2, false}, 1)), 1);
  auto lost = receive();
  ASSERT_TRUE(lost.has_value());
  ASSERT_EQ(h.fpwr(st, reg::sync_manager(1) + reg::kSmActivate, Bytes{0x03}), 1);
  ASSERT_EQ(h.fpwr(st, reg::sync_manager(1) + reg::kSmActivate, Bytes{0x01}), 1);
  EXPECT_EQ(h.fprd(st, reg::sync_manager(1) + reg::kSmPdiControl, 1).data[0] & sm::kPdiRepeatAck, 0);
  auto again = receive();
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(*again, *lost);
  EXPECT_FALSE(receive().has_value());
}

TEST_F(SdoTest, RepeatWhileANewerReplyIsUnreadKeepsIt) {
  // The master's read of reply 2 was lost before it reached the slave: the
  // repeat brings reply 1 again, reply 2 follows.
  ASSERT_EQ(send(*make_sdo_request(SdoInitiateUploadRequest{0x1018, 1, false}, 1)), 1);
  auto first = receive();
  ASSERT_TRUE(first.has_value());
  ASSERT_EQ(send(*make_sdo_request(SdoInitiateUploadRequest{0x1018, 2, false}, 2)), 1);
  ASSERT_EQ(h.fpwr(st, reg::sync_manager(1) + reg::kSmActivate, Bytes{0x03}), 1);
  auto repeated = receive();
  ASSERT_TRUE(repeated.has_value());
  EXPECT_EQ(*repeated, *first);
  auto second = receive();
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(load_le<std::uint32_t>(&(*second)[12]), kServoProductCode);
}

TEST_F(SdoTest, ARepeatedWriteWithTheSameCounterIsNotServedTwice) {
  // The master repeats a mailbox write whose frame was lost on the way back.
  const Bytes message = *make_sdo_request(SdoInitiateUploadRequest{0x1000, 0, false}, 5);
  ASSERT_EQ(send(message), 1);
  ASSERT_EQ(send(message), 1);
  EXPECT_TRUE(receive().has_value());
  EXPECT_FALSE(receive().has_value());
  // A new counter is a new request; counter 0 is never treated as a repeat.
  ASSERT_EQ(send(*make_sdo_request(SdoInitiateUploadRequest{0x1000, 0, false}, 6)), 1);
  EXPECT_TRUE(receive().has_value());
  const Bytes unchecked = *make_sdo_request(SdoInitiateUploadRequest{0x1000, 0, false}, 0);
  ASSERT_EQ(send(unchecked), 1);
  ASSERT_EQ(send(unchecked), 1);
  EXPECT_TRUE(receive().has_value());
  EXPECT_TRUE(receive().has_value());
}

TEST_F(SdoTest, EmergencyOnAxisFault) {
  // Following error: enable the axis, then jump the target far away.
  auto* servo = h.segment->device<Servo>(0);
  ASSERT_NE(servo, nullptr);
  EXPECT_EQ(download(0x6040, 0, Harness::le<std::uint16_t>(0x0006)), 0u);
  EXPECT_EQ(download(0x6040, 0, Harness::le<std::uint16_t>(0x000F)), 0u);
  h.clock.advance(std::chrono::milliseconds{1});
  h.segment->poll();
  ASSERT_EQ(servo->axis(0).state(), Cia402State::OperationEnabled);
  EXPECT_EQ(download(0x607A, 0, Harness::le<std::int32_t>(50'000'000)), 0u);
  for (int i = 0; i < 30; ++i) {
    h.clock.advance(std::chrono::milliseconds{1});
    h.segment->poll();
  }
  EXPECT_EQ(servo->axis(0).state(), Cia402State::Fault);
  auto reply = receive();
  ASSERT_TRUE(reply.has_value());
  auto coe = decode_coe(*reply);
  ASSERT_TRUE(coe.ok());
  ASSERT_EQ(coe->coe.service, CoeService::Emergency);
  EXPECT_EQ(CoeEmergency::decode(coe->body)->error_code, kErrorFollowing);
}

}  // namespace
}  // namespace sf::ethercat::slave

namespace sf::ethercat::slave {
namespace {

TEST_F(SdoTest, SdoInfoListsEveryObject) {
  const auto& od = h.segment->slave(0).objects();
  auto [all, messages] = info(OdListRequest{OdListType::All});
  ASSERT_TRUE(all.has_value());
  const auto& indices = std::get<OdListResponse>(*all).indices;
  ASSERT_EQ(indices.size(), od.objects().size());
  EXPECT_EQ(indices.front(), 0x1000);
  EXPECT_EQ(messages, 1);
  auto [lengths, _] = info(OdListRequest{OdListType::Lengths});
  ASSERT_TRUE(lengths.has_value());
  const auto& n = std::get<OdListResponse>(*lengths).indices;
  ASSERT_EQ(n.size(), 5U);
  EXPECT_EQ(n[0], od.objects().size());
  auto [rx, rx_messages] = info(OdListRequest{OdListType::RxPdoMappable});
  ASSERT_TRUE(rx.has_value());
  const auto& rx_list = std::get<OdListResponse>(*rx).indices;
  EXPECT_EQ(rx_list.size(), n[1]);
  EXPECT_NE(std::find(rx_list.begin(), rx_list.end(), 0x6040), rx_list.end()) << "controlword";
  EXPECT_EQ(std::find(rx_list.begin(), rx_list.end(), 0x6041), rx_list.end()) << "statusword is an input";
}

TEST_F(SdoTest, SdoInfoDescribesObjectsAndEntries) {
  auto [object, m1] = info(ObjectDescriptionRequest{0x1018});
  ASSERT_TRUE(object.has_value());
  const auto& o = std::get<ObjectDescription>(*object);
  EXPECT_EQ(o.index, 0x1018);
  EXPECT_EQ(o.object_code, 9);  // RECORD
  EXPECT_EQ(o.max_subindex, 4);
  EXPECT_EQ(o.name, h.segment->slave(0).objects().find(0x1018)->name());
  auto [entry, m2] = info(EntryDescriptionRequest{0x1018, 1, 0});
  ASSERT_TRUE(entry.has_value());
  const auto& e = std::get<EntryDescription>(*entry);
  EXPECT_EQ(e.data_type, data_type::kUnsigned32);
  EXPECT_EQ(e.bit_length, 32);
  EXPECT_EQ(e.object_access, access::kRO);
  EXPECT_EQ(e.name, h.segment->slave(0).objects().find(0x1018, 1)->name);
  auto [cw, m3] = info(EntryDescriptionRequest{0x6040, 0, value_info::kDefault});
  ASSERT_TRUE(cw.has_value());
  EXPECT_EQ(std::get<EntryDescription>(*cw).value_info, 0) << "no default value is offered";
  EXPECT_NE(std::get<EntryDescription>(*cw).object_access & access::kRxPdo, 0);
}

TEST_F(SdoTest, SdoInfoErrorsCarryAnAbortCode) {
  const auto error_of = [&](const SdoInfoMessage& request) -> std::uint32_t {
    auto [m, _] = info(request);
    if (!m || !std::holds_alternative<SdoInfoError>(*m))
      return 0;
    return std::get<SdoInfoError>(*m).code;
  };
  EXPECT_EQ(error_of(ObjectDescriptionRequest{0x5555}), sdo_code(SdoAbortCode::ObjectDoesNotExist));
  EXPECT_EQ(error_of(EntryDescriptionRequest{0x1018, 9, 0}), sdo_code(SdoAbortCode::SubindexDoesNotExist));
  EXPECT_EQ(error_of(OdListRequest{static_cast<OdListType>(6)}), sdo_code(SdoAbortCode::UnsupportedAccess));
  // A response or error opcode from the client, or an opcode that does not
  // exist: "command specifier not valid", not a mailbox error.
  EXPECT_EQ(error_of(SdoInfoError{0}), sdo_code(SdoAbortCode::InvalidCommandSpecifier));
  EXPECT_EQ(error_of(OdListResponse{}), sdo_code(SdoAbortCode::InvalidCommandSpecifier));
  const Bytes unknown{0x0F, 0x00, 0x00, 0x00, 0x00, 0x00};
  ASSERT_EQ(
      send(encode_coe(MailboxHeader{0, 0, 0, 0, MailboxType::CoE, counter_ = next_mailbox_counter(counter_)},
                      CoeHeader{0, CoeService::SdoInformation}, unknown)),
      1);
  auto reply = receive();
  ASSERT_TRUE(reply.has_value());
  auto coe = decode_coe(*reply);
  ASSERT_TRUE(coe.ok());
  EXPECT_EQ(coe->body[0], 7) << "SDO Info Error request";
  EXPECT_EQ(load_le<std::uint32_t>(coe->body.data() + 4), sdo_code(SdoAbortCode::InvalidCommandSpecifier));
}

TEST_F(SdoTest, SdoInfoFragmentsComeOneAfterTheOther) {
  // 200 more objects: 2 + 2 * 225 bytes of indices, 116 per 128-byte mailbox.
  auto& od = h.segment->slave(0).objects();
  for (std::uint16_t i = 0; i < 200; ++i) {
    od.add_var(static_cast<std::uint16_t>(0x3000 + i), "Filler", DataType::Unsigned8, access::kRO);
  }
  auto [all, messages] = info(OdListRequest{OdListType::All});
  ASSERT_TRUE(all.has_value());
  EXPECT_EQ(std::get<OdListResponse>(*all).indices.size(), od.objects().size());
  EXPECT_EQ(messages, static_cast<int>((2 + 2 * od.objects().size() + 115) / 116));
  EXPECT_FALSE(receive().has_value()) << "nothing after the last fragment";
  // The mailbox serves SDO right afterwards.
  EXPECT_EQ(std::get<Bytes>(upload(0x1018, 1)), Harness::le<std::uint32_t>(kVendorId));
}

TEST_F(SdoTest, CoeServicesNotOfferedGetAMailboxError) {
  // A TxPDO by mailbox (CoE service 4): ETG.1000.4 Table 30 "service not supported".
  ASSERT_EQ(
      send(encode_coe(MailboxHeader{0, 0, 0, 0, MailboxType::CoE, counter_ = next_mailbox_counter(counter_)},
                      CoeHeader{0, CoeService::TxPdo}, Bytes(8, 0))),
      1);
  auto reply = receive();
  ASSERT_TRUE(reply.has_value());
  auto message = decode_mailbox(*reply);
  ASSERT_TRUE(message.ok());
  EXPECT_EQ(message->header.type, MailboxType::Err);
  EXPECT_EQ(decode_mailbox_error(message->data).value(), MailboxError::ServiceNotSupported);
}

}  // namespace
}  // namespace sf::ethercat::slave
