// The master's SDO Information client and read_dictionary against the
// emulated slaves' dictionaries.
#include <gtest/gtest.h>

#include "segment_bench.hpp"
#include "sf/ethercat/master/dictionary.hpp"
#include "sf/ethercat/sdo_abort_codes.hpp"
#include "sf/ethercat/slave/devices.hpp"

namespace sf::ethercat::master::test {
namespace {

class SdoInfo : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(b.master->scan().ok());
    auto st = b.master->request_state(AlState::PreOp);
    ASSERT_TRUE(st.ok()) << st.error().describe();
  }
  Bench b{"smart-controller:1,digital-io:1"};
};

TEST_F(SdoInfo, ReadsTheWholeDictionaryOverFragmentedLists) {
  const auto& od = b.segment->slave(0).objects();
  // The smart controller's list needs several 128-byte mailbox messages.
  ASSERT_GT(2 + 2 * od.objects().size(), 116U);
  auto dictionary = read_dictionary(*b.master, 0, true);
  ASSERT_TRUE(dictionary.ok()) << dictionary.error().describe();
  ASSERT_EQ(dictionary->size(), od.objects().size());
  for (const auto& object : *dictionary) {
    const auto* expected = od.find(object.description.index);
    ASSERT_NE(expected, nullptr);
    EXPECT_EQ(object.description.name, expected->name());
    EXPECT_EQ(object.description.object_code, static_cast<std::uint8_t>(expected->code()));
    ASSERT_EQ(object.entries.size(), expected->entries().size()) << object.description.name;
    for (std::size_t i = 0; i < object.entries.size(); ++i) {
      const auto& got = object.entries[i];
      const auto& want = expected->entries()[i];
      EXPECT_EQ(got.description.subindex, want.subindex);
      EXPECT_EQ(got.description.name, want.name);
      EXPECT_EQ(got.description.data_type, static_cast<std::uint16_t>(want.type));
      EXPECT_EQ(got.description.object_access, want.access);
      ASSERT_TRUE(got.value.has_value());
      ASSERT_TRUE(std::holds_alternative<Bytes>(*got.value));
      EXPECT_EQ(std::get<Bytes>(*got.value), want.value);
    }
  }
}

TEST_F(SdoInfo, RefusalsAreTheSlavesAbort) {
  auto missing = b.master->sdo_info_object(0, 0x5555);
  ASSERT_TRUE(missing.ok()) << missing.error().describe();
  ASSERT_TRUE(std::holds_alternative<SdoAbort>(*missing));
  EXPECT_EQ(std::get<SdoAbort>(*missing).code, static_cast<std::uint32_t>(SdoAbortCode::ObjectDoesNotExist));
  EXPECT_EQ(std::get<SdoAbort>(*missing).index, 0x5555);
  auto entry = b.master->sdo_info_entry(0, 0x1018, 1);
  ASSERT_TRUE(entry.ok()) << entry.error().describe();
  EXPECT_EQ(std::get<EntryDescription>(*entry).data_type, data_type::kUnsigned32);
  // No mailbox, no service.
  auto io = b.master->sdo_info_od_list(1);
  ASSERT_FALSE(io.ok());
  EXPECT_EQ(io.error().code, Errc::unsupported);
}

}  // namespace
}  // namespace sf::ethercat::master::test
