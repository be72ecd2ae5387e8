// CoE SDO client against the emulated slaves' SDO server.
#include <numeric>

#include <gtest/gtest.h>

#include "segment_bench.hpp"
#include "sf/ethercat/sdo_abort_codes.hpp"
#include "sf/ethercat/slave/devices.hpp"
#include "sf/ethercat/slave/standard_objects.hpp"

namespace sf::ethercat::master::test {
namespace {

class Coe : public ::testing::Test {
 protected:
  void SetUp() override {
    // Objects big enough for normal and segmented transfers (the mailbox
    // holds 128 bytes: 112 in an initiate message, 119 per segment).
    auto& od = b.segment->slave(0).objects();
    od.add_string(0x2000, "Small blob", std::string(60, '\0'), slave::access::kRW,
                  slave::DataType::OctetString);
    od.add_string(0x2001, "Large blob", std::string(1000, '\0'), slave::access::kRW,
                  slave::DataType::OctetString);
    ASSERT_TRUE(b.master->scan().ok());
    auto st = b.master->request_state(AlState::PreOp);
    ASSERT_TRUE(st.ok()) << st.error().describe();
  }
  Bytes device_value(std::uint16_t index, std::uint8_t subindex) {
    const auto* e = b.segment->slave(0).objects().find(index, subindex);
    return e != nullptr ? e->value : Bytes{};
  }

  Bench b{"servo:1,digital-io:1"};
};

TEST_F(Coe, ExpeditedUpload) {
  auto vendor = b.master->sdo_read<std::uint32_t>(0, 0x1018, 1);
  ASSERT_TRUE(vendor.ok()) << vendor.error().describe();
  EXPECT_EQ(*vendor, slave::kVendorId);
  auto product = b.master->sdo_upload(0, 0x1018, 2);
  ASSERT_TRUE(product.ok());
  ASSERT_EQ(product->size(), 4U);
  EXPECT_EQ(load_le<std::uint32_t>(product->data()), slave::kServoProductCode);
}

TEST_F(Coe, ExpeditedDownloadReachesTheDevice) {
  ASSERT_TRUE(b.master->sdo_write<std::uint32_t>(0, 0x607F, 0, 123456).ok());
  EXPECT_EQ(load_le<std::uint32_t>(device_value(0x607F, 0).data()), 123456U);
  auto back = b.master->sdo_read<std::uint32_t>(0, 0x607F, 0);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(*back, 123456U);
}

TEST_F(Coe, NormalUploadOfTheDeviceName) {
  auto name = b.master->sdo_upload(0, 0x1008, 0);
  ASSERT_TRUE(name.ok()) << name.error().describe();
  EXPECT_GT(name->size(), 4U);  // more than fits an expedited transfer
  EXPECT_EQ(std::string(name->begin(), name->end()), b.master->slave_info(0).sii.name());
}

TEST_F(Coe, NormalDownloadAndUpload) {
  Bytes data(60);
  std::iota(data.begin(), data.end(), std::uint8_t{1});
  auto st = b.master->sdo_download(0, 0x2000, 0, data);
  ASSERT_TRUE(st.ok()) << st.error().describe();
  EXPECT_EQ(device_value(0x2000, 0), data);
  auto back = b.master->sdo_upload(0, 0x2000, 0);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(*back, data);
}

TEST_F(Coe, SegmentedDownloadAndUpload) {
  Bytes data(1000);
  for (std::size_t i = 0; i < data.size(); ++i) {
    data[i] = static_cast<std::uint8_t>(i * 37U + 11U);
  }
  auto st = b.master->sdo_download(0, 0x2001, 0, data);
  ASSERT_TRUE(st.ok()) << st.error().describe();
  EXPECT_EQ(device_value(0x2001, 0), data);
  // Change it on the device side, then read it back in segments.
  data[500] = 0xEE;
  auto* e = b.segment->slave(0).objects().find(0x2001, 0);
  ASSERT_NE(e, nullptr);
  e->value = data;
  auto back = b.master->sdo_upload(0, 0x2001, 0);
  ASSERT_TRUE(back.ok()) << back.error().describe();
  EXPECT_EQ(*back, data);
}

TEST_F(Coe, CompleteAccessUpload) {
  auto identity = b.master->sdo_upload(0, 0x1018, 0, true);
  ASSERT_TRUE(identity.ok()) << identity.error().describe();
  // Subindex 0 as 16 bits, then four UNSIGNED32 (ETG.1000.6 §5.6.2.1.1).
  ASSERT_GE(identity->size(), 2U + 8U);
  EXPECT_EQ(load_le<std::uint32_t>(identity->data() + 2), slave::kVendorId);
}

TEST_F(Coe, AbortForAMissingObjectCarriesCodeAndText) {
  auto missing = b.master->sdo_upload(0, 0x5555, 0);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().code, Errc::remote);
  EXPECT_NE(missing.error().message.find("06020000"), std::string::npos) << missing.error().message;
  EXPECT_NE(missing.error().message.find("not exist"), std::string::npos) << missing.error().message;
  EXPECT_EQ(missing.error().protocol_code, (ProtocolCode{kSdoAbortTable, 0x06020000U}));
  // The mailbox is still usable afterwards.
  EXPECT_TRUE(b.master->sdo_read<std::uint32_t>(0, 0x1018, 1).ok());
}

TEST_F(Coe, AbortForAWriteToAReadOnlyObject) {
  auto st = b.master->sdo_write<std::uint32_t>(0, 0x1018, 1, 42);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().code, Errc::remote);
  EXPECT_NE(st.error().message.find("06010002"), std::string::npos) << st.error().message;
}

TEST_F(Coe, RejectedDownloadIsReportedAsTheSlavesAbort) {
  // 0x1018:01 is read-only: the slave answers Abort SDO Transfer (CoE
  // service 2), which the client must take as the answer.
  auto answer = b.master->sdo_download_answer(0, 0x1018, 1, Bytes{1, 2, 3, 4});
  ASSERT_TRUE(answer.ok()) << answer.error().describe();
  ASSERT_TRUE(answer->has_value()) << "the write was refused";
  EXPECT_EQ((*answer)->code, static_cast<std::uint32_t>(SdoAbortCode::ReadOnly));
  EXPECT_EQ((*answer)->index, 0x1018);
  EXPECT_EQ((*answer)->subindex, 1);
  // A segmented download refused at its start: the abort, not a timeout.
  auto big = b.master->sdo_download_answer(0, 0x1008, 0, Bytes(300, 'x'));
  ASSERT_TRUE(big.ok()) << big.error().describe();
  ASSERT_TRUE(big->has_value());
  EXPECT_EQ((*big)->code, static_cast<std::uint32_t>(SdoAbortCode::ReadOnly));
  auto upload = b.master->sdo_upload_answer(0, 0x5555, 0);
  ASSERT_TRUE(upload.ok()) << upload.error().describe();
  ASSERT_TRUE(std::holds_alternative<SdoAbort>(*upload));
  EXPECT_EQ(std::get<SdoAbort>(*upload).code, static_cast<std::uint32_t>(SdoAbortCode::ObjectDoesNotExist));
}

TEST_F(Coe, SlaveWithoutMailboxIsRefused) {
  auto r = b.master->sdo_upload(1, 0x1018, 1);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::unsupported);
}

TEST(CoeLossy, TransfersSurviveFrameLoss) {
  // 15 % of all frames lost, before or after the slaves saw them: lost
  // requests are sent again, lost answers fetched again (repeat request),
  // and nothing reaches the SDO server twice.
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    slave::SegmentOptions so;
    so.seed = seed;
    Bench b("servo:1", quick_options(), so);
    b.segment->slave(0).objects().add_string(0x2001, "Large blob", std::string(300, '\0'), slave::access::kRW,
                                             slave::DataType::OctetString);
    ASSERT_TRUE(b.master->scan().ok());
    ASSERT_TRUE(b.master->request_state(AlState::PreOp).ok());
    b.segment->set_drop_probability(0.15);
    Bytes data(300);
    for (int round = 0; round < 100; ++round) {
      for (std::size_t i = 0; i < data.size(); ++i) {
        data[i] = static_cast<std::uint8_t>(i + static_cast<std::size_t>(round));
      }
      auto st = b.master->sdo_download(0, 0x2001, 0, data);
      ASSERT_TRUE(st.ok()) << "seed " << seed << " round " << round << ": " << st.error().describe();
      auto back = b.master->sdo_upload(0, 0x2001, 0);
      ASSERT_TRUE(back.ok()) << "seed " << seed << " round " << round << ": " << back.error().describe();
      ASSERT_EQ(*back, data);
    }
    b.segment->set_drop_probability(0.0);
    EXPECT_GT(b.master->mailbox_repeats(), 0U);
    EXPECT_GT(b.master->bus().counters().frames_lost, 0U);
  }
}

}  // namespace
}  // namespace sf::ethercat::master::test
