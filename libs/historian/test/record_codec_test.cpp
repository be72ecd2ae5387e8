#include <gtest/gtest.h>

#include "sf/historian/buffer_records.hpp"

namespace sf::historian {
namespace {

const Timestamp kT = from_micros(1'700'000'000'123'456);

TEST(RecordCodec, SamplesRoundTripEveryValueType) {
  const std::vector<Sample> in = {
      {1, kT, kT, 0, kGood, Value{}},
      {2, kT, kT, 1, 0x40000000, Value{true}},
      {3, kT, kT, 2, kGood, Value{std::int64_t{-5}}},
      {4, kT, kT, 3, kGood, Value{~std::uint64_t{0}}},
      {5, kT, kT, 4, kGood, Value{2.5}},
      {6, kT, kT, 5, kGood, Value{std::string{"text\0with nul", 13}}},
      {7, kT, kT, 6, kGood, Value{Bytes{0, 1, 2}}},
  };
  auto out = decode_samples(encode_samples(in));
  ASSERT_TRUE(out.ok()) << out.error().describe();
  EXPECT_EQ(*out, in);
}

TEST(RecordCodec, SeriesAndEventsRoundTrip) {
  const SeriesInfo info{"opc.tcp://a", "ns=1;i=7", "/Objects/A", DataType::string, "m/s"};
  EXPECT_EQ(decode_series(encode_series(info)).value_or(SeriesInfo{}), info);
  const std::vector<Event> events = {
      {"opc.tcp://a", Bytes{9, 9}, kT, kT, "i=2041", "i=85", "Root", 100, "m", "{}"}};
  EXPECT_EQ(decode_events(encode_events(events)).value_or({}), events);
}

TEST(RecordCodec, TruncatedOrPaddedPayloadsAreMalformed) {
  const std::vector<Sample> in = {{1, kT, kT, 0, kGood, Value{std::string{"hello"}}}};
  const auto bytes = encode_samples(in);
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    EXPECT_FALSE(decode_samples(ByteSpan{bytes}.first(n)).ok()) << n;
  }
  auto padded = bytes;
  padded.push_back(0);
  EXPECT_EQ(decode_samples(padded).error().code, Errc::malformed);
}

TEST(RecordCodec, AnImpossibleCountIsRefusedBeforeAllocating) {
  Bytes b = {1, 0xff, 0xff, 0xff, 0xff};
  auto out = decode_samples(b);
  ASSERT_FALSE(out.ok());
  EXPECT_NE(out.error().message.find("does not fit"), std::string::npos);
}

TEST(RecordCodec, AnotherFormatVersionIsUnsupported) {
  auto bytes = encode_samples({});
  bytes[0] = 2;
  EXPECT_EQ(decode_samples(bytes).error().code, Errc::unsupported);
}

}  // namespace
}  // namespace sf::historian
