// SII EEPROM image: checksum, fixed-area word addresses, category round trips,
// tolerance of unknown categories and strictness on truncated ones.
#include "sf/ethercat/sii.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace sf::ethercat {
namespace {

using ::testing::HasSubstr;

std::uint16_t word(const Bytes& image, std::uint16_t address) {
  return load_le<std::uint16_t>(image.data() + 2U * address);
}
std::uint32_t dword(const Bytes& image, std::uint16_t address) {
  return load_le<std::uint32_t>(image.data() + 2U * address);
}

// A servo drive much like the one the slave emulator will model.
SiiInfo servo() {
  SiiInfo info;
  info.pdi_control = 0x0C80;
  info.pdi_configuration = 0x6E00;
  info.station_alias = 0x0042;
  info.identity = {0x00000ACE, 0x00010402, 0x00000003, 0x12345678};
  info.bootstrap_mailbox = {0x1000, 0x0200, 0x1200, 0x0200};
  info.standard_mailbox = {0x1000, 0x0080, 0x1080, 0x0080};
  info.mailbox_protocols = sii::protocol::kCoE | sii::protocol::kFoE;
  info.size = 7;
  info.version = 1;
  info.strings = {"Servo drive", "Drives", "SF-SERVO-1"};
  SiiGeneral g;
  g.group = "Drives";
  g.order = "SF-SERVO-1";
  g.name = "Servo drive";
  g.image = "";
  g.coe_details = sii::coe_details::kSdo | sii::coe_details::kSdoInfo | sii::coe_details::kPdoAssign |
                  sii::coe_details::kSdoCompleteAccess;
  g.foe_details = 1;
  g.flags = 0x01;
  g.current_on_ebus = -200;
  g.physical_port = 0x0011;
  info.general = g;
  info.fmmus = {SiiFmmuUsage::outputs, SiiFmmuUsage::inputs, SiiFmmuUsage::sm_status};
  info.sync_managers = {{0x1000, 0x80, 0x26, 0, 1, SiiSyncManagerType::mailbox_out},
                        {0x1080, 0x80, 0x22, 0, 1, SiiSyncManagerType::mailbox_in},
                        {0x1100, 0x06, 0x64, 0, 1, SiiSyncManagerType::outputs},
                        {0x1180, 0x0A, 0x20, 0, 1, SiiSyncManagerType::inputs}};
  info.rx_pdos = {{0x1600,
                   2,
                   0,
                   "RxPDO 1",
                   0,
                   {{0x6040, 0, "Controlword", 0x06, 16, 0}, {0x607A, 0, "Target position", 0x04, 32, 0}}}};
  info.tx_pdos = {{0x1A00,
                   3,
                   0,
                   "TxPDO 1",
                   0,
                   {{0x6041, 0, "Statusword", 0x06, 16, 0},
                    {0x6064, 0, "Position actual value", 0x04, 32, 0},
                    {0x60FD, 0, "Digital inputs", 0x07, 32, 0}}}};
  info.dc_modes = {{1000000, 0, 0, 0, 0x0300, 1, "DC-Synchron", "SYNC0 each cycle"},
                   {0, 0, 0, 0, 0x0000, 0, "FreeRun", ""}};
  return info;
}

TEST(SiiChecksum, Crc8Poly07InitFF) {
  // Check value of this CRC-8 variant (x^8+x^2+x+1, init 0xFF, not reflected)
  // over "123456789", computed with an independent bit-serial implementation.
  const std::string check = "123456789";
  // Only 14 bytes take part; "123456789" is shorter, so feed it whole.
  EXPECT_EQ(
      sii::checksum(ByteSpan(reinterpret_cast<const std::uint8_t*>(check.data()), check.size())),  // NOLINT
      0xFB);
  EXPECT_EQ(sii::checksum(Bytes(14, 0)), 0x30);
  // Bytes past the 14th are not covered.
  Bytes longer(14, 0);
  longer.push_back(0xAA);
  EXPECT_EQ(sii::checksum(longer), 0x30);
}

TEST(SiiEncode, FixedAreaWordAddresses) {
  const Bytes image = encode_sii(servo()).value();
  EXPECT_EQ(word(image, sii::kPdiControl), 0x0C80);
  EXPECT_EQ(word(image, sii::kPdiConfiguration), 0x6E00);
  EXPECT_EQ(word(image, sii::kStationAlias), 0x0042);
  EXPECT_EQ(word(image, sii::kChecksum), sii::checksum(image));
  EXPECT_EQ(word(image, sii::kChecksum) >> 8U, 0U);
  EXPECT_EQ(dword(image, sii::kVendorId), 0x00000ACEU);
  EXPECT_EQ(dword(image, sii::kProductCode), 0x00010402U);
  EXPECT_EQ(dword(image, sii::kRevisionNumber), 3U);
  EXPECT_EQ(dword(image, sii::kSerialNumber), 0x12345678U);
  EXPECT_EQ(word(image, sii::kBootstrapRxMailboxSize), 0x0200);
  EXPECT_EQ(word(image, sii::kStandardRxMailboxOffset), 0x1000);
  EXPECT_EQ(word(image, sii::kStandardRxMailboxSize), 0x0080);
  EXPECT_EQ(word(image, sii::kStandardTxMailboxOffset), 0x1080);
  EXPECT_EQ(word(image, sii::kStandardTxMailboxSize), 0x0080);
  EXPECT_EQ(word(image, sii::kMailboxProtocol), 0x000C);
  EXPECT_EQ(word(image, sii::kSize), 7);
  EXPECT_EQ(word(image, sii::kVersion), 1);
  // The first category is Strings at word 0x40: the 3 given strings plus the
  // 10 PDO, entry and DC names appended; then "Servo drive" (11 bytes).
  EXPECT_EQ(word(image, 0x40), 10);
  EXPECT_EQ(image[2 * 0x42], 13);
  EXPECT_EQ(image[2 * 0x42 + 1], 11);
  EXPECT_EQ(image[2 * 0x42 + 2], 'S');
  EXPECT_EQ(image.size() % 2, 0U);
  // Ends with the End category.
  EXPECT_EQ(load_le<std::uint16_t>(image.data() + image.size() - 4), 0xFFFF);
}

TEST(SiiRoundTrip, EveryCategory) {
  const SiiInfo info = servo();
  auto image = encode_sii(info);
  ASSERT_TRUE(image) << image.error().describe();
  auto back = parse_sii(*image);
  ASSERT_TRUE(back) << back.error().describe();
  EXPECT_EQ(back->identity, info.identity);
  EXPECT_EQ(back->general, info.general);
  EXPECT_EQ(back->fmmus, info.fmmus);
  EXPECT_EQ(back->sync_managers, info.sync_managers);
  EXPECT_EQ(back->rx_pdos, info.rx_pdos);
  EXPECT_EQ(back->tx_pdos, info.tx_pdos);
  EXPECT_EQ(back->dc_modes, info.dc_modes);
  // Names not in the initial table were appended in order of use.
  ASSERT_GE(back->strings.size(), 3U);
  EXPECT_EQ(std::vector<std::string>(back->strings.begin(), back->strings.begin() + 3), info.strings);
  // Re-encoding the parsed value gives the same bytes.
  EXPECT_EQ(encode_sii(*back).value(), *image);
  EXPECT_TRUE(back->supports_dc());
  EXPECT_EQ(back->name(), "Servo drive");
  EXPECT_EQ(back->tx_pdos[0].bit_length(), 80U);
}

TEST(SiiEncode, DeviceNameIsStringOne) {
  // Masters that do not follow the General category's NameIdx show string 1
  // as the slave's name: it must be the name, not the group.
  SiiInfo info = servo();
  info.strings.clear();
  info.general->group = "smartfactory";
  auto image = encode_sii(info);
  ASSERT_TRUE(image) << image.error().describe();
  auto back = parse_sii(*image);
  ASSERT_TRUE(back) << back.error().describe();
  ASSERT_FALSE(back->strings.empty());
  EXPECT_EQ(back->strings[0], "Servo drive");
  EXPECT_EQ(back->name(), "Servo drive");
  EXPECT_EQ(back->general->group, "smartfactory");
  EXPECT_EQ(back->general->order, "SF-SERVO-1");
}

TEST(SiiRoundTrip, MinimalDeviceWithoutCategories) {
  SiiInfo info;
  info.identity.vendor_id = 0x1;
  info.size = 1;
  auto image = encode_sii(info);
  ASSERT_TRUE(image);
  EXPECT_EQ(image->size(), 128U + 4U);
  auto back = parse_sii(*image);
  ASSERT_TRUE(back);
  EXPECT_EQ(*back, info);
  EXPECT_FALSE(back->supports_dc());
  EXPECT_EQ(back->name(), "");
}

TEST(SiiEncode, DerivesTheSizeWordWhenZero) {
  SiiInfo info = servo();
  info.size = 0;
  const Bytes image = encode_sii(info).value();
  // size word = KiBit − 1, 1 KiBit = 128 bytes.
  EXPECT_EQ(word(image, sii::kSize), (image.size() + 127) / 128 - 1);
}

TEST(SiiEncode, OddFmmuCountIsPaddedWithNotUsed) {
  SiiInfo info;
  info.fmmus = {SiiFmmuUsage::outputs};
  const Bytes image = encode_sii(info).value();
  EXPECT_EQ(word(image, 0x40), 40);
  EXPECT_EQ(word(image, 0x41), 1);
  EXPECT_EQ(image[2 * 0x42 + 1], 0xFF);
  EXPECT_EQ(parse_sii(image)->fmmus, info.fmmus);
}

TEST(SiiEncode, RejectsWhatDoesNotFitItsField) {
  SiiInfo many_strings;
  for (int i = 0; i < 256; ++i) {
    many_strings.strings.push_back("s" + std::to_string(i));
  }
  EXPECT_FALSE(encode_sii(many_strings));

  SiiInfo long_string;
  long_string.strings = {std::string(256, 'x')};
  auto r = encode_sii(long_string);
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().message, HasSubstr("256 bytes"));

  SiiInfo many_entries;
  many_entries.tx_pdos = {{0x1A00, 3, 0, "", 0, std::vector<SiiPdoEntry>(256)}};
  EXPECT_FALSE(encode_sii(many_entries));
}

// Inserts a category before the End marker of an image.
Bytes with_category(Bytes image, std::uint16_t type, const Bytes& data) {
  const auto end = image.end() - 4;
  Bytes c{static_cast<std::uint8_t>(type & 0xFFU), static_cast<std::uint8_t>(type >> 8U),
          static_cast<std::uint8_t>(data.size() / 2), 0};
  c.insert(c.end(), data.begin(), data.end());
  image.insert(end, c.begin(), c.end());
  return image;
}

TEST(SiiParse, SkipsUnknownAndVendorCategories) {
  const Bytes base = encode_sii(servo()).value();
  Bytes image = with_category(base, 0x0800, Bytes{1, 2, 3, 4});  // unknown
  image = with_category(image, 0x8001, Bytes{5, 6});             // vendor specific (bit 15)
  image = with_category(image, 20, Bytes{});                     // DataTypes, empty
  auto back = parse_sii(image);
  ASSERT_TRUE(back) << back.error().describe();
  EXPECT_EQ(back->tx_pdos, servo().tx_pdos);
}

TEST(SiiParse, StringsMayComeAfterTheCategoriesUsingThem) {
  const Bytes general_first = [] {
    SiiInfo i;
    i.size = 1;
    return encode_sii(i).value();
  }();
  Bytes g(32, 0);
  g[3] = 1;  // name = string 1
  Bytes image = with_category(general_first, 30, g);
  image = with_category(image, 10, Bytes{1, 4, 'A', 'x', 'i', 's'});
  auto back = parse_sii(image);
  ASSERT_TRUE(back) << back.error().describe();
  EXPECT_EQ(back->name(), "Axis");
}

TEST(SiiParse, DanglingStringIndexReadsAsEmpty) {
  Bytes g(32, 0);
  g[3] = 9;
  SiiInfo info;
  info.size = 1;
  auto back = parse_sii(with_category(encode_sii(info).value(), 30, g));
  ASSERT_TRUE(back);
  EXPECT_EQ(back->name(), "");
}

TEST(SiiParse, AcceptsAPartialReadEndingBetweenCategories) {
  const Bytes full = encode_sii(servo()).value();
  // Cut after the Strings category: header 4 + data.
  const std::size_t strings_end = 128 + 4 + 2U * word(full, 0x41);
  auto back = parse_sii(ByteSpan(full).first(strings_end));
  ASSERT_TRUE(back) << back.error().describe();
  EXPECT_EQ(back->strings.size(), 13U);
  EXPECT_FALSE(back->general);
}

TEST(SiiParseErrors, ShortImageAndBadChecksum) {
  const Bytes full = encode_sii(servo()).value();
  auto short_image = parse_sii(ByteSpan(full).first(127));
  ASSERT_FALSE(short_image);
  EXPECT_THAT(short_image.error().message, HasSubstr("128-byte fixed area"));

  Bytes tampered = full;
  tampered[2 * sii::kStationAlias] ^= 0x01;
  auto bad = parse_sii(tampered);
  ASSERT_FALSE(bad);
  EXPECT_THAT(bad.error().message, HasSubstr("checksum"));
  EXPECT_TRUE(parse_sii(tampered, SiiParseOptions{false}));
}

TEST(SiiParseErrors, CategoryRunningPastTheData) {
  const Bytes full = encode_sii(servo()).value();
  for (std::size_t cut : {std::size_t{128 + 3}, std::size_t{128 + 10}, full.size() - 10}) {
    auto r = parse_sii(ByteSpan(full).first(cut));
    ASSERT_FALSE(r) << cut;
    EXPECT_EQ(r.error().code, Errc::malformed);
    EXPECT_THAT(r.error().message, HasSubstr("category at byte 0x")) << cut;
  }
}

TEST(SiiParseErrors, ContentShorterThanItsLayout) {
  SiiInfo info;
  info.size = 1;
  const Bytes base = encode_sii(info).value();

  auto general = parse_sii(with_category(base, 30, Bytes(8, 0)));
  ASSERT_FALSE(general);
  EXPECT_THAT(general.error().message, HasSubstr("General category"));

  auto sm = parse_sii(with_category(base, 41, Bytes(6, 0)));
  ASSERT_FALSE(sm);
  EXPECT_THAT(sm.error().message, HasSubstr("SyncM category"));

  // A PDO that declares 2 entries but carries one.
  Bytes pdo{0x00, 0x1A, 2, 3, 0, 0, 0, 0};
  pdo.resize(16, 0);
  auto tx = parse_sii(with_category(base, 50, pdo));
  ASSERT_FALSE(tx);
  EXPECT_THAT(tx.error().message, HasSubstr("PDO 0x1A00 declares 2 entries"));

  auto dc = parse_sii(with_category(base, 60, Bytes(20, 0)));
  ASSERT_FALSE(dc);
  EXPECT_THAT(dc.error().message, HasSubstr("DC category"));

  // Three strings announced, one present.
  auto strings = parse_sii(with_category(base, 10, Bytes{3, 1, 'a', 5}));
  ASSERT_FALSE(strings);
  EXPECT_THAT(strings.error().message, HasSubstr("string 2 of 3"));
}

TEST(SiiImageLength, FindsTheEndCategoryOrAsksForMore) {
  const Bytes full = encode_sii(servo()).value();
  auto len = sii_image_length(full);
  ASSERT_TRUE(len);
  ASSERT_TRUE(len->has_value());
  EXPECT_EQ(**len, full.size() - 2);  // End type word; the trailing 0xFFFF is erased EEPROM
  for (std::size_t cut : {std::size_t{0}, std::size_t{64}, std::size_t{130}, full.size() - 3}) {
    auto partial = sii_image_length(ByteSpan(full).first(cut));
    ASSERT_TRUE(partial);
    EXPECT_FALSE(partial->has_value()) << cut;
  }
}

TEST(SiiImageLength, ChainOfEmptyCategoriesIsBounded) {
  // 64 Ki words of zeros: Nop categories of size 0 all the way, no End.
  const Bytes zeros(2 * 0x10000 + 8, 0);
  auto r = sii_image_length(zeros);
  ASSERT_FALSE(r);
  EXPECT_THAT(r.error().message, HasSubstr("without an End category"));
}

}  // namespace
}  // namespace sf::ethercat
