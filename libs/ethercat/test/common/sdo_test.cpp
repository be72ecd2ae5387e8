// SDO services of ETG.1000.6 §5.6.2: command bytes as on the wire (the
// classic CiA 301 values 0x23/0x2B/0x2F, 0x43/0x4B/0x4F, 0x60, 0x80...), round
// trips of every request and response, and malformed bodies.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "sf/ethercat/mailbox.hpp"
#include "sf/ethercat/sdo_abort_codes.hpp"

namespace sf::ethercat {
namespace {

using ::testing::HasSubstr;

constexpr std::size_t kMailbox = 128;

Bytes body_of(const Result<Bytes>& r) {
  EXPECT_TRUE(r) << r.error().describe();
  return r ? *r : Bytes{};
}

TEST(SdoDownload, ExpeditedCommandBytesBySize) {
  const Bytes object{0x0F, 0x00, 0x11, 0x22};
  const std::array<std::uint8_t, 4> expected_cmd{0x2F, 0x2B, 0x27, 0x23};
  for (std::size_t n = 1; n <= 4; ++n) {
    const auto req = SdoInitiateDownloadRequest::make(0x6040, 0x00, ByteSpan(object).first(n), 100);
    EXPECT_TRUE(req.expedited);
    const Bytes body = body_of(encode_sdo_request(req));
    ASSERT_EQ(body.size(), 8U);
    EXPECT_EQ(body[0], expected_cmd[n - 1]) << n;
    EXPECT_EQ(body[1], 0x40);
    EXPECT_EQ(body[2], 0x60);
    EXPECT_EQ(body[3], 0x00);
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_EQ(body[4 + i], i < n ? object[i] : 0) << n << "/" << i;
    }
  }
}

TEST(SdoDownload, CompleteMailboxMessage) {
  // Controlword 0x6040:00 = 0x000F, mailbox counter 1, from the master.
  const Bytes value{0x0F, 0x00};
  auto msg = make_sdo_request(SdoInitiateDownloadRequest::make(0x6040, 0, value, 100), 1);
  ASSERT_TRUE(msg);
  EXPECT_EQ(*msg, (Bytes{0x0A, 0x00, 0x00, 0x00, 0x00, 0x13, 0x00, 0x20, 0x2B, 0x40, 0x60, 0x00, 0x0F, 0x00,
                         0x00, 0x00}));
  auto coe = decode_coe(*msg);
  ASSERT_TRUE(coe);
  EXPECT_EQ(coe->coe.service, CoeService::SdoRequest);
  auto req = decode_sdo_request(coe->body);
  ASSERT_TRUE(req) << req.error().describe();
  const auto& d = std::get<SdoInitiateDownloadRequest>(*req);
  EXPECT_EQ(d.index, 0x6040);
  EXPECT_EQ(d.data, value);
  EXPECT_EQ(d.complete_size, 2U);
}

TEST(SdoDownload, NormalTransferWithSegments) {
  Bytes object(20);
  for (std::size_t i = 0; i < object.size(); ++i) {
    object[i] = static_cast<std::uint8_t>(i + 1);
  }
  // A tiny capacity forces segmentation: 8 bytes in the initiate request.
  const auto init = SdoInitiateDownloadRequest::make(0x8000, 0x01, object, 8, true);
  EXPECT_FALSE(init.expedited);
  EXPECT_EQ(init.complete_size, 20U);
  EXPECT_EQ(init.data.size(), 8U);
  const Bytes body = body_of(encode_sdo_request(init));
  ASSERT_EQ(body.size(), 16U);
  EXPECT_EQ(body[0], 0x31);  // ccs 1, complete access, size indicated, normal
  EXPECT_EQ(load_le<std::uint32_t>(body.data() + 4), 20U);

  // 12 bytes remain: one full segment of 7, then a last one of 5 (2 unused).
  const SdoDownloadSegmentRequest seg1{false, false, Bytes(object.begin() + 8, object.begin() + 15)};
  const SdoDownloadSegmentRequest seg2{true, true, Bytes(object.begin() + 15, object.end())};
  const Bytes b1 = body_of(encode_sdo_request(seg1));
  const Bytes b2 = body_of(encode_sdo_request(seg2));
  EXPECT_EQ(b1.size(), 8U);
  EXPECT_EQ(b1[0], 0x00);
  ASSERT_EQ(b2.size(), 8U);
  EXPECT_EQ(b2[0], 0x10U | (2U << 1U) | 0x01U);  // toggle, 2 unused bytes, last
  EXPECT_EQ(b2[6], 0);                           // padding

  Bytes reassembled;
  for (const Bytes* b : {&body, &b1, &b2}) {
    auto req = decode_sdo_request(*b);
    ASSERT_TRUE(req) << req.error().describe();
    std::visit(
        [&](const auto& m) {
          if constexpr (requires { m.data; }) {
            reassembled.insert(reassembled.end(), m.data.begin(), m.data.end());
          }
        },
        *req);
  }
  EXPECT_EQ(reassembled, object);
}

TEST(SdoDownload, LongSegmentsCarryMoreThanSevenBytes) {
  const SdoDownloadSegmentRequest seg{true, false, Bytes(100, 0x5A)};
  const Bytes body = body_of(encode_sdo_request(seg));
  EXPECT_EQ(body.size(), 101U);
  EXPECT_EQ(body[0], 0x10);
  auto back = decode_sdo_request(body);
  ASSERT_TRUE(back);
  EXPECT_EQ(std::get<SdoDownloadSegmentRequest>(*back), seg);
  EXPECT_EQ(sdo_segment_capacity(kMailbox), 119U);
  EXPECT_EQ(sdo_initiate_capacity(kMailbox), 112U);
  EXPECT_EQ(sdo_initiate_capacity(10), 0U);
}

TEST(SdoDownload, EmptyObjectIsANormalTransferOfSizeZero) {
  const auto req = SdoInitiateDownloadRequest::make(0x2000, 1, {}, 100);
  EXPECT_FALSE(req.expedited);
  const Bytes body = body_of(encode_sdo_request(req));
  EXPECT_EQ(body.size(), 8U);
  auto back = decode_sdo_request(body);
  ASSERT_TRUE(back);
  EXPECT_EQ(std::get<SdoInitiateDownloadRequest>(*back), req);
}

TEST(SdoUpload, RequestAndExpeditedResponses) {
  const Bytes req = body_of(encode_sdo_request(SdoInitiateUploadRequest{0x1018, 0x01, false}));
  EXPECT_EQ(req, (Bytes{0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0}));
  const Bytes req_ca = body_of(encode_sdo_request(SdoInitiateUploadRequest{0x1C12, 0x00, true}));
  EXPECT_EQ(req_ca[0], 0x50);

  const Bytes vendor{0x9A, 0x02, 0x00, 0x00};
  const std::array<std::uint8_t, 4> expected_cmd{0x4F, 0x4B, 0x47, 0x43};
  for (std::size_t n = 1; n <= 4; ++n) {
    const auto resp = SdoInitiateUploadResponse::make(0x1018, 0x01, ByteSpan(vendor).first(n), 100);
    const Bytes body = body_of(encode_sdo_response(resp));
    EXPECT_EQ(body[0], expected_cmd[n - 1]);
    auto back = decode_sdo_response(body);
    ASSERT_TRUE(back);
    EXPECT_EQ(std::get<SdoInitiateUploadResponse>(*back), resp);
  }
}

TEST(SdoUpload, NormalResponseThenSegments) {
  const std::string name = "smartfactory servo drive";
  const ByteSpan object(reinterpret_cast<const std::uint8_t*>(name.data()), name.size());  // NOLINT
  const auto resp = SdoInitiateUploadResponse::make(0x1008, 0x00, object, 10);
  EXPECT_FALSE(resp.expedited);
  EXPECT_EQ(resp.complete_size, name.size());
  const Bytes body = body_of(encode_sdo_response(resp));
  EXPECT_EQ(body[0], 0x41);
  auto back = decode_sdo_response(body);
  ASSERT_TRUE(back);
  EXPECT_EQ(std::get<SdoInitiateUploadResponse>(*back), resp);

  EXPECT_EQ(body_of(encode_sdo_request(SdoUploadSegmentRequest{false})), (Bytes{0x60, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(body_of(encode_sdo_request(SdoUploadSegmentRequest{true}))[0], 0x70);
  const SdoUploadSegmentResponse last{true, true, Bytes(object.begin() + 10, object.end())};
  const Bytes seg = body_of(encode_sdo_response(last));
  EXPECT_EQ(seg[0], 0x11);  // toggle, 14 bytes (no unused), last
  auto seg_back = decode_sdo_response(seg);
  ASSERT_TRUE(seg_back);
  EXPECT_EQ(std::get<SdoUploadSegmentResponse>(*seg_back), last);
}

TEST(SdoResponses, AcknowledgementsAndAbort) {
  EXPECT_EQ(body_of(encode_sdo_response(SdoInitiateDownloadResponse{0x6040, 0})),
            (Bytes{0x60, 0x40, 0x60, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(body_of(encode_sdo_response(SdoDownloadSegmentResponse{true}))[0], 0x30);
  EXPECT_EQ(body_of(encode_sdo_response(SdoDownloadSegmentResponse{false}))[0], 0x20);

  const SdoAbort abort{0x6041, 0x00, static_cast<std::uint32_t>(SdoAbortCode::ReadOnly)};
  const Bytes a = body_of(encode_sdo_response(abort));
  EXPECT_EQ(a, (Bytes{0x80, 0x41, 0x60, 0x00, 0x02, 0x00, 0x01, 0x06}));
  EXPECT_EQ(std::get<SdoAbort>(decode_sdo_response(a).value()), abort);
  EXPECT_EQ(std::get<SdoAbort>(decode_sdo_request(a).value()), abort);  // either side may abort
  EXPECT_EQ(describe(abort), "SDO abort 0x06010002 (Attempt to write a read-only object) at 0x6041:00");
}

TEST(SdoResponses, AbortFromTheServerTravelsAsAnSdoRequest) {
  // ETG.1000.6 §5.6.2.7.1: Abort SDO Transfer has CoE service 2 from either
  // side; the CoE header is the 16-bit word after the 6-byte mailbox header.
  auto msg = make_sdo_response(SdoAbort{0x5555, 0, 0x06020000}, 2, 0x1001);
  ASSERT_TRUE(msg);
  EXPECT_EQ((*msg)[7] >> 4U, 2) << "CoE service bits 15:12";
  auto coe = decode_coe(*msg);
  ASSERT_TRUE(coe);
  EXPECT_EQ(coe->coe.service, CoeService::SdoRequest);
  EXPECT_EQ(std::get<SdoAbort>(decode_sdo_request(coe->body).value()).code, 0x06020000U);
}

TEST(Sdo, EveryVariantRoundTrips) {
  const std::vector<SdoRequest> requests{SdoInitiateDownloadRequest::make(0x7000, 2, Bytes{1, 2, 3}, 100),
                                         SdoInitiateDownloadRequest::make(0x7000, 0, Bytes(50, 7), 30, true),
                                         SdoDownloadSegmentRequest{true, true, Bytes{1}},
                                         SdoDownloadSegmentRequest{false, false, Bytes{}},
                                         SdoInitiateUploadRequest{0x1A00, 0, true},
                                         SdoUploadSegmentRequest{true},
                                         SdoAbort{0x1000, 0, 0x08000000}};
  for (const auto& r : requests) {
    auto msg = make_sdo_request(r, 3, 0);
    ASSERT_TRUE(msg);
    auto coe = decode_coe(*msg);
    ASSERT_TRUE(coe);
    auto back = decode_sdo_request(coe->body);
    ASSERT_TRUE(back) << back.error().describe();
    EXPECT_EQ(*back, r) << "variant " << r.index();
  }
  const std::vector<SdoResponse> responses{
      SdoInitiateDownloadResponse{0x7000, 2},
      SdoDownloadSegmentResponse{true},
      SdoInitiateUploadResponse::make(0x1018, 2, Bytes{1, 2}, 100),
      SdoInitiateUploadResponse::make(0x1018, 0, Bytes(300, 1), 112, true),
      SdoUploadSegmentResponse{false, true, Bytes{1, 2, 3, 4, 5, 6, 7, 8}},
      SdoAbort{0x1018, 5, 0x06090011}};
  for (const auto& r : responses) {
    auto msg = make_sdo_response(r, 4, 0x1001);
    ASSERT_TRUE(msg);
    auto coe = decode_coe(*msg);
    ASSERT_TRUE(coe);
    EXPECT_EQ(coe->mailbox.address, 0x1001);
    const bool abort = std::holds_alternative<SdoAbort>(r);
    EXPECT_EQ(coe->coe.service, abort ? CoeService::SdoRequest : CoeService::SdoResponse);
    auto back = decode_sdo_response(coe->body);
    ASSERT_TRUE(back) << back.error().describe();
    EXPECT_EQ(*back, r) << "variant " << r.index();
  }
}

TEST(SdoEncodeErrors, InvalidFieldCombinations) {
  SdoInitiateDownloadRequest empty_expedited{};
  empty_expedited.expedited = true;
  auto e = encode_sdo_request(empty_expedited);
  ASSERT_FALSE(e);
  EXPECT_THAT(e.error().message, HasSubstr("1-4 data bytes"));

  SdoInitiateDownloadRequest five{};
  five.data = Bytes(5);
  EXPECT_FALSE(encode_sdo_request(five));

  SdoInitiateUploadResponse too_much{};
  too_much.expedited = false;
  too_much.complete_size = 2;
  too_much.data = Bytes(3);
  auto t = encode_sdo_response(too_much);
  ASSERT_FALSE(t);
  EXPECT_THAT(t.error().message, HasSubstr("exceed the complete size"));
  EXPECT_FALSE(make_sdo_response(too_much, 1));
}

TEST(SdoDecodeErrors, MalformedBodies) {
  auto short_body = decode_sdo_request(Bytes{0x40, 0x00, 0x10, 0x00, 0, 0, 0});
  ASSERT_FALSE(short_body);
  EXPECT_THAT(short_body.error().message, HasSubstr("shorter than the minimum 8"));
  EXPECT_FALSE(decode_sdo_response(Bytes{}));

  auto block = decode_sdo_request(Bytes{0xC0, 0, 0x10, 0, 0, 0, 0, 0});
  ASSERT_FALSE(block);
  EXPECT_EQ(block.error().code, Errc::unsupported);
  EXPECT_THAT(block.error().message, HasSubstr("specifier 6"));
  EXPECT_FALSE(decode_sdo_response(Bytes{0xA0, 0, 0x10, 0, 0, 0, 0, 0}));

  auto no_size = decode_sdo_request(Bytes{0x20, 0x00, 0x20, 0x01, 4, 0, 0, 0, 1, 2, 3, 4});
  ASSERT_FALSE(no_size);
  EXPECT_THAT(no_size.error().message, HasSubstr("0x2000:01: normal transfer without size indicator"));

  auto oversize = decode_sdo_response(Bytes{0x41, 0x00, 0x20, 0x01, 2, 0, 0, 0, 1, 2, 3});
  ASSERT_FALSE(oversize);
  EXPECT_THAT(oversize.error().message, HasSubstr("3 data bytes exceed the complete size 2"));
}

TEST(SdoDecode, ExpeditedWithoutSizeIndicatorCarriesFourBytes) {
  auto r = decode_sdo_request(Bytes{0x22, 0x00, 0x70, 0x01, 1, 2, 3, 4});
  ASSERT_TRUE(r);
  const auto& d = std::get<SdoInitiateDownloadRequest>(*r);
  EXPECT_TRUE(d.expedited);
  EXPECT_FALSE(d.size_indicated);
  EXPECT_EQ(d.data, (Bytes{1, 2, 3, 4}));
  EXPECT_EQ(body_of(encode_sdo_request(d)), (Bytes{0x22, 0x00, 0x70, 0x01, 1, 2, 3, 4}));
}

}  // namespace
}  // namespace sf::ethercat
