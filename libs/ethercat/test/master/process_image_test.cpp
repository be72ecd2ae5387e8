#include "sf/ethercat/master/process_image.hpp"

#include <gtest/gtest.h>

namespace sf::ethercat::master {
namespace {

TEST(Bits, ReadWriteUnalignedFields) {
  Bytes data(4, 0);
  write_bits(data, 3, 5, 0x1F);
  EXPECT_EQ(data[0], 0xF8);
  write_bits(data, 6, 12, 0xABC);
  EXPECT_EQ(read_bits(data, 6, 12), 0xABCU);
  EXPECT_EQ(read_bits(data, 3, 3), 0x7U);  // untouched low bits of the first field
  write_bits(data, 8, 16, 0x1234);
  EXPECT_EQ(data[1], 0x34);
  EXPECT_EQ(data[2], 0x12);
}

TEST(Bits, OutOfRangeReadsZeroAndWritesNothing) {
  Bytes data(2, 0xFF);
  EXPECT_EQ(read_bits(data, 10, 8), 0U);
  EXPECT_EQ(read_bits(data, 0, 0), 0U);
  EXPECT_EQ(read_bits(data, 0, 65), 0U);
  write_bits(data, 12, 8, 0);
  EXPECT_EQ(data[0], 0xFF);
  EXPECT_EQ(data[1], 0xFF);
}

PdoMapping servo_like() {
  PdoMapping m;
  Pdo rx{0x1600, {{0x6040, 0, 16, 0}, {0x607A, 0, 32, 16}}, 48};
  Pdo tx{0x1A00, {{0x6041, 0, 16, 0}, {0x6064, 0, 32, 16}, {0, 0, 4, 48}, {0x6000, 1, 1, 52}}, 53};
  m.outputs.push_back(rx);
  m.inputs.push_back(tx);
  m.output_bits = 48;
  m.input_bits = 53;
  return m;
}

TEST(SlaveView, TypedAccessByOffsetIsBoundsChecked) {
  Bytes out(6, 0);
  Bytes in{0x37, 0x06, 0x10, 0x00, 0x00, 0x80, 0x00};
  const auto m = servo_like();
  SlaveView v(out, in, &m);
  v.set_output<std::uint16_t>(0, 0x000F);
  v.set_output<std::int32_t>(2, -5);
  EXPECT_EQ(out[0], 0x0F);
  EXPECT_EQ(v.output<std::int32_t>(2), -5);
  EXPECT_EQ(v.input<std::uint16_t>(0), 0x0637);
  EXPECT_EQ(v.input<std::int32_t>(2), static_cast<std::int32_t>(0x80000010U));
  // Past the end: zero, and no write.
  EXPECT_EQ(v.input<std::uint32_t>(5), 0U);
  const Bytes before = out;
  v.set_output<std::uint32_t>(4, 0x12345678);
  EXPECT_EQ(out, before);
}

TEST(SlaveView, EntriesResolveByIndexAndSignExtend) {
  Bytes out(6, 0);
  Bytes in(7, 0);
  const auto m = servo_like();
  SlaveView v(out, in, &m);
  auto target = v.entry(0x607A, 0);
  ASSERT_TRUE(target.ok());
  EXPECT_EQ(target->direction, PdoDirection::output);
  v.set<std::int32_t>(*target, -1000);
  EXPECT_EQ(v.output<std::int32_t>(2), -1000);
  EXPECT_EQ(v.get<std::int32_t>(*target), -1000);

  auto bit = v.entry(0x6000, 1);
  ASSERT_TRUE(bit.ok());
  EXPECT_EQ(bit->bit_offset, 52U);
  in[6] = 0x10;  // bit 52
  EXPECT_TRUE(v.get<bool>(*bit));
  // Writing an input entry does nothing.
  v.set<std::uint8_t>(*bit, 0);
  EXPECT_EQ(in[6], 0x10);

  auto missing = v.entry(0x1234, 5);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, Errc::not_found);
  EXPECT_NE(missing.error().message.find("0x1234:05"), std::string::npos);
}

TEST(SlaveView, EntryOutsideTheImageIsRejected) {
  Bytes out(2, 0);  // shorter than the mapping says
  Bytes in(7, 0);
  const auto m = servo_like();
  SlaveView v(out, in, &m);
  auto target = v.entry(0x607A, 0);
  ASSERT_FALSE(target.ok());
  EXPECT_EQ(target.error().code, Errc::out_of_range);
}

TEST(SlaveView, SignedNarrowEntries) {
  Bytes out(1, 0);
  Bytes in{0x0E};
  PdoMapping m;
  m.inputs.push_back(Pdo{0x1A00, {{0x7000, 1, 4, 0}}, 4});
  m.input_bits = 4;
  SlaveView v(out, in, &m);
  auto e = v.entry(0x7000, 1);
  ASSERT_TRUE(e.ok());
  EXPECT_EQ(v.get<std::int8_t>(*e), -2);  // 0b1110 as a 4-bit two's complement
  EXPECT_EQ(v.get<std::uint8_t>(*e), 14);
}

}  // namespace
}  // namespace sf::ethercat::master
