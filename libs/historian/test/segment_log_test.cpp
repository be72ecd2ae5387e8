#include <fstream>

#include <gtest/gtest.h>

#include "sf/historian/segment_log.hpp"
#include "temp_dir.hpp"

namespace sf::historian {
namespace {

namespace fs = std::filesystem;

Bytes payload(int i) {
  return Bytes(static_cast<std::size_t>(10 + i), static_cast<std::uint8_t>(i));
}

class SegmentLogTest : public ::testing::Test {
 protected:
  std::unique_ptr<SegmentLog> open(OnCorruption mode = OnCorruption::salvage,
                                   std::size_t segment_bytes = 8U << 20U) {
    auto log = SegmentLog::open(SegmentLogOptions{dir_.path(), segment_bytes, false, mode});
    EXPECT_TRUE(log.ok()) << log.error().describe();
    return log ? std::move(*log) : nullptr;
  }

  static void append(SegmentLog& log, int from, int to) {
    for (int i = from; i < to; ++i) {
      ASSERT_TRUE(log.append(RecordType::samples, payload(i)).ok());
    }
  }

  static std::vector<Bytes> pending(SegmentLog& log) {
    auto records = log.peek(1U << 30U);
    EXPECT_TRUE(records.ok());
    std::vector<Bytes> out;
    for (const auto& r : records.value_or({})) {
      out.push_back(r.payload);
    }
    return out;
  }

  std::vector<fs::path> files(const std::string& prefix) const {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir_.path())) {
      if (e.path().filename().string().starts_with(prefix)) {
        out.push_back(e.path());
      }
    }
    std::sort(out.begin(), out.end());
    return out;
  }

  test::TempDir dir_;
};

TEST_F(SegmentLogTest, RecordsComeBackInOrderAcrossReopens) {
  {
    auto log = open();
    EXPECT_TRUE(log->empty());
    append(*log, 0, 5);
    EXPECT_EQ(log->pending_records(), 5U);
    auto first = log->peek(0);  // at least one record, whatever the budget
    ASSERT_TRUE(first.ok());
    ASSERT_EQ(first->size(), 1U);
    auto two = log->peek(25);
    ASSERT_EQ(two->size(), 2U);
    ASSERT_TRUE(log->consume(*two).ok());
  }
  auto log = open();
  EXPECT_EQ(pending(*log), (std::vector<Bytes>{payload(2), payload(3), payload(4)}));
  ASSERT_TRUE(log->consume(*log->peek(1U << 30U)).ok());
  EXPECT_TRUE(log->empty());
  log.reset();
  EXPECT_TRUE(open()->empty());
}

TEST_F(SegmentLogTest, SegmentsRotateAndConsumedOnesAreDeleted) {
  auto log = open(OnCorruption::salvage, 100);
  append(*log, 0, 20);
  EXPECT_GT(files("seg-").size(), 5U);
  std::vector<Bytes> expected;
  for (int i = 0; i < 20; ++i) {
    expected.push_back(payload(i));
  }
  EXPECT_EQ(pending(*log), expected);
  while (!log->empty()) {
    ASSERT_TRUE(log->consume(*log->peek(30)).ok());
  }
  EXPECT_EQ(files("seg-").size(), 1U);
  append(*log, 20, 21);
  EXPECT_EQ(pending(*log), std::vector<Bytes>{payload(20)});
}

TEST_F(SegmentLogTest, AnIncompleteLastRecordIsCutOff) {
  ASSERT_TRUE(open()->append(RecordType::samples, payload(1)).ok());
  const auto seg = files("seg-").back();
  const auto half = frame_record(RecordType::samples, payload(2));
  std::ofstream(seg, std::ios::app | std::ios::binary).write(reinterpret_cast<const char*>(half.data()), 10);
  auto log = open();
  EXPECT_EQ(log->report().torn_bytes, 10U);
  EXPECT_EQ(log->report().bad_regions, 0U);
  append(*log, 3, 4);
  EXPECT_EQ(pending(*log), (std::vector<Bytes>{payload(1), payload(3)}));
}

void flip_byte(const fs::path& file, std::size_t at) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(static_cast<std::streamoff>(at));
  char c = 0;
  f.read(&c, 1);
  c = static_cast<char>(c ^ 0x40);
  f.seekp(static_cast<std::streamoff>(at));
  f.write(&c, 1);
}

std::size_t second_record_payload() {
  return kSegmentHeaderBytes + kRecordHeaderBytes + payload(0).size() + kRecordHeaderBytes + 3;
}

TEST_F(SegmentLogTest, DamageKeepsEveryReadableRecordAndTheDamagedBytes) {
  append(*open(), 0, 5);
  flip_byte(files("seg-").front(), second_record_payload());
  auto log = open();
  EXPECT_EQ(log->report().bad_regions, 1U);
  ASSERT_FALSE(log->report().messages.empty());
  EXPECT_NE(log->report().messages[0].find("checksum"), std::string::npos) << log->report().messages[0];
  EXPECT_EQ(pending(*log), (std::vector<Bytes>{payload(0), payload(2), payload(3), payload(4)}));
  ASSERT_EQ(files("corrupt").size(), 1U);
  const auto kept = fs::directory_iterator(dir_.path() / "corrupt")->path();
  EXPECT_EQ(fs::file_size(kept), kRecordHeaderBytes + payload(1).size());
}

TEST_F(SegmentLogTest, DamageInFailModeIsAClearErrorAndChangesNothing) {
  append(*open(), 0, 5);
  const auto seg = files("seg-").front();
  flip_byte(seg, second_record_payload());
  const auto size = fs::file_size(seg);
  auto log = SegmentLog::open(SegmentLogOptions{dir_.path(), 8U << 20U, false, OnCorruption::fail});
  ASSERT_FALSE(log.ok());
  EXPECT_EQ(log.error().code, Errc::malformed);
  const auto& m = log.error().message;
  EXPECT_NE(m.find(seg.filename().string()), std::string::npos) << m;
  EXPECT_NE(m.find("damaged at byte 39"), std::string::npos) << m;
  EXPECT_NE(m.find("salvage"), std::string::npos) << m;
  EXPECT_EQ(fs::file_size(seg), size);
  EXPECT_FALSE(fs::exists(dir_.path() / "corrupt"));
}

TEST_F(SegmentLogTest, ASegmentWithoutHeaderIsMovedAside) {
  append(*open(), 0, 2);
  flip_byte(files("seg-").front(), 0);
  auto log = open();
  EXPECT_EQ(log->report().bad_regions, 1U);
  EXPECT_TRUE(log->empty());
  EXPECT_EQ(files("corrupt").size(), 1U);
  append(*log, 7, 8);
  EXPECT_EQ(pending(*log), std::vector<Bytes>{payload(7)});
}

TEST_F(SegmentLogTest, AnUnreadableCursorReplaysEverything) {
  {
    auto log = open();
    append(*log, 0, 4);
    ASSERT_TRUE(log->consume(*log->peek(15)).ok());
    EXPECT_EQ(log->pending_records(), 3U);
  }
  std::ofstream(dir_.path() / "cursor", std::ios::trunc) << "garbage";
  auto log = open();
  EXPECT_TRUE(log->report().cursor_lost);
  EXPECT_EQ(log->pending_records(), 4U);
}

TEST_F(SegmentLogTest, OneProcessAtATime) {
  auto log = open();
  auto second = SegmentLog::open(SegmentLogOptions{dir_.path()});
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.error().code, Errc::state);
  EXPECT_NE(second.error().message.find("in use"), std::string::npos);
}

TEST_F(SegmentLogTest, RejectedRecordsAreKeptReadable) {
  auto log = open();
  append(*log, 0, 2);
  auto records = log->peek(1U << 20U);
  ASSERT_TRUE(log->reject(*records).ok());
  ASSERT_TRUE(log->consume(*records).ok());
  std::ifstream in(dir_.path() / "rejected.log", std::ios::binary);
  const Bytes bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto scan = scan_segment(bytes);
  ASSERT_EQ(scan.records.size(), 2U);
  EXPECT_EQ(Bytes(scan.records[1].payload(bytes).begin(), scan.records[1].payload(bytes).end()), payload(1));
}

TEST(ScanSegment, ResynchronisesAfterGarbage) {
  Bytes file = segment_header(3);
  const auto a = frame_record(RecordType::series, Bytes{1});
  const auto b = frame_record(RecordType::events, Bytes{2, 2});
  file.insert(file.end(), a.begin(), a.end());
  file.insert(file.end(), {0x53, 0x46, 0x52, 0x31, 0xff, 0xff});  // a magic number and rubbish
  file.insert(file.end(), b.begin(), b.end());
  const auto scan = scan_segment(file);
  EXPECT_EQ(scan.number, 3U);
  ASSERT_EQ(scan.records.size(), 2U);
  EXPECT_EQ(scan.records[1].type, RecordType::events);
  ASSERT_EQ(scan.bad.size(), 1U);
  EXPECT_EQ(scan.bad[0].length, 6U);
  EXPECT_EQ(scan.tail_bytes, 0U);
  EXPECT_FALSE(scan_segment(Bytes{1, 2, 3}).header_error.empty());
}

TEST(Crc32c, KnownAnswer) {
  const std::string text = "123456789";
  EXPECT_EQ(crc32c(ByteSpan{reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}), 0xE3069283U);
}

}  // namespace
}  // namespace sf::historian
