#include "sf/core/bytes.hpp"

#include <gtest/gtest.h>

namespace sf {
namespace {

TEST(ByteWriter, WritesLittleEndian) {
  ByteWriter w;
  w.u8(0x01);
  w.u16(0x0302);
  w.u32(0x07060504);
  w.u64(0x0f0e0d0c0b0a0908ULL);
  w.i16(-2);
  const Bytes expect{0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09,
                     0x0a, 0x0b, 0x0c, 0x0d, 0x0e, 0x0f, 0xfe, 0xff};
  EXPECT_EQ(w.data(), expect);
}

TEST(ByteReader, RoundTripsEveryWidth) {
  ByteWriter w;
  w.u8(200);
  w.i8(-100);
  w.u16(65000);
  w.i16(-32000);
  w.u32(4'000'000'000U);
  w.i32(-2'000'000'000);
  w.u64(18'000'000'000'000'000'000ULL);
  w.i64(-9'000'000'000'000'000'000LL);
  w.f32(1.5F);
  w.f64(-2.25e300);
  ByteReader r{w.data()};
  EXPECT_EQ(r.u8(), 200);
  EXPECT_EQ(r.i8(), -100);
  EXPECT_EQ(r.u16(), 65000);
  EXPECT_EQ(r.i16(), -32000);
  EXPECT_EQ(r.u32(), 4'000'000'000U);
  EXPECT_EQ(r.i32(), -2'000'000'000);
  EXPECT_EQ(r.u64(), 18'000'000'000'000'000'000ULL);
  EXPECT_EQ(r.i64(), -9'000'000'000'000'000'000LL);
  EXPECT_EQ(r.f32(), 1.5F);
  EXPECT_EQ(r.f64(), -2.25e300);
  EXPECT_TRUE(r.ok());
  EXPECT_TRUE(r.at_end());
}

TEST(ByteReader, OverrunIsStickyAndReadsNothing) {
  const Bytes data{0x01, 0x02, 0x03};
  ByteReader r{data};
  EXPECT_EQ(r.u16(), 0x0201);
  EXPECT_EQ(r.u16(), 0);  // only one byte left
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.u8(), 0);  // sticky: even a fitting read fails now
  EXPECT_EQ(r.remaining(), 0U);
  EXPECT_NE(r.error("test").message.find("needs 2 more byte(s) at offset 2 of 3"), std::string::npos);
}

TEST(ByteReader, BytesViewAndPeek) {
  const Bytes data{1, 2, 3, 4, 5};
  ByteReader r{data};
  r.skip(1);
  EXPECT_EQ(r.peek(2).size(), 2U);
  const auto b = r.bytes(3);
  ASSERT_EQ(b.size(), 3U);
  EXPECT_EQ(b[0], 2);
  EXPECT_EQ(r.rest().size(), 1U);
  EXPECT_TRUE(r.bytes(2).empty());
  EXPECT_FALSE(r.ok());
}

TEST(ByteReader, CopyToZeroFillsOnOverrun) {
  const Bytes data{9, 9};
  ByteReader r{data};
  std::uint8_t out[4] = {7, 7, 7, 7};
  r.copy_to(out);
  EXPECT_FALSE(r.ok());
  for (auto b : out)
    EXPECT_EQ(b, 0);
}

TEST(ByteWriter, PatchOverwritesOnlyInside) {
  ByteWriter w;
  w.u16(0);
  w.u8(0xAA);
  EXPECT_TRUE(w.patch<std::uint16_t>(0, 0x1234));
  EXPECT_FALSE(w.patch<std::uint32_t>(1, 1));
  EXPECT_EQ(w.data(), (Bytes{0x34, 0x12, 0xAA}));
}

TEST(SpanWriter, RefusesToOverflow) {
  std::uint8_t buf[3] = {};
  SpanWriter w{buf};
  w.u16(0xBEEF);
  EXPECT_TRUE(w.ok());
  w.u16(0x1111);
  EXPECT_FALSE(w.ok());
  EXPECT_EQ(buf[2], 0);
  EXPECT_EQ(w.position(), 2U);
}

TEST(Hex, RoundTripAndErrors) {
  const Bytes data{0x00, 0xa4, 0x88, 0xff};
  EXPECT_EQ(to_hex(data), "00 a4 88 ff");
  auto parsed = from_hex("00a4 88FF");
  ASSERT_TRUE(parsed.ok());
  EXPECT_EQ(*parsed, data);
  EXPECT_FALSE(from_hex("0g").ok());
  EXPECT_FALSE(from_hex("abc").ok());
}

}  // namespace
}  // namespace sf
