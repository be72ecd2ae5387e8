// The stations' tag readers at the hardware faces: the uploader's and
// downloader's PLC (input register station_box), a legacy robot's controller
// (station_box[k]) and the smart controller (DI 16–31) read the id of the box
// standing in place at their station, 0 otherwise; a box passing through on a
// running belt is not read.
#include <string>
#include <vector>

#include "sf/plant/testing/rig.hpp"

namespace sf::plant::testing {
namespace {

std::uint16_t smart_reader(Rig& rig) {
  return box_id_of(rig.plant().smart_robot("scara-robot-1")->controller().digital_inputs());
}

std::uint16_t toshiba_reader(Rig& rig) {
  return rig.ir("toshiba", robot_controller::kStationBox);
}

BoxId upload(Rig& rig) {
  rig.hr("uploader", transfer_plc::kBoxType, 1);
  EXPECT_EQ(rig.run_job("uploader"), FaultCode::none);
  return rig.ir("uploader", transfer_plc::kBoxId);
}

// Every motor of `belts` on, every stopper down, the diverters towards the next of `belts`.
void run_through(Rig& rig, const std::vector<std::string>& belts) {
  for (std::size_t i = 0; i < belts.size(); ++i) {
    const BeltSpec& spec = *rig.layout().belt(belts[i]);
    if (i + 1 < belts.size()) {
      rig.coil(belts[i], conveyor_plc::kDivert, spec.next.size() > 1 && spec.next[1] == belts[i + 1]);
    }
    for (std::size_t k = 0; k < spec.stations.size(); ++k) {
      rig.coil(belts[i], static_cast<std::uint16_t>(conveyor_plc::kStopper + k), false);
    }
    rig.coil(belts[i], conveyor_plc::kMotorRun, true);
  }
}

TEST(PlantTagReaders, TheUploaderReadsTheBoxItPutAtItsStationUntilItLeaves) {
  Rig rig;
  EXPECT_EQ(rig.ir("uploader", transfer_plc::kStationBox), 0);
  const BoxId id = upload(rig);
  ASSERT_NE(id, 0U);
  EXPECT_EQ(rig.ir("uploader", transfer_plc::kStationBox), id);
  EXPECT_EQ(rig.ir("conveyor1", conveyor_plc::kStationBox), id);  // the belt's reader at the same station
  rig.convey({"conveyor1", "conveyor2"}, 0);
  EXPECT_EQ(rig.ir("uploader", transfer_plc::kStationBox), 0);
}

TEST(PlantTagReaders, TheRobotsReadTheBoxAtTheirStationAndNoOther) {
  Rig rig;
  const BoxId first = upload(rig);
  rig.convey({"conveyor1", "conveyor2"}, 0);
  EXPECT_EQ(smart_reader(rig), first);
  EXPECT_EQ(toshiba_reader(rig), 0);
  // The bit field does not spill into the box-in-place bit below it.
  EXPECT_NE(rig.plant().smart_robot("scara-robot-1")->controller().digital_inputs() & (1U << kDiBoxInPlace),
            0U);
  const BoxId second = upload(rig);
  rig.convey({"conveyor1", "conveyor3"}, 0);
  EXPECT_EQ(toshiba_reader(rig), second);
  EXPECT_EQ(smart_reader(rig), first);
  rig.convey({"conveyor2", "conveyor4"}, 0);  // the first box on to the DENSO's station
  EXPECT_EQ(smart_reader(rig), 0);
  EXPECT_EQ(rig.ir("denso", robot_controller::kStationBox), first);
}

TEST(PlantTagReaders, TheDownloaderReadsTheBoxAtItsStationAndNothingOnceItIsOff) {
  Rig rig;
  const BoxId id = upload(rig);
  rig.convey({"conveyor1", "conveyor2", "conveyor4"}, 1);
  EXPECT_EQ(rig.ir("downloader", transfer_plc::kStationBox), id);
  ASSERT_EQ(rig.run_job("downloader"), FaultCode::none);
  EXPECT_EQ(rig.ir("downloader", transfer_plc::kStationBox), 0);
}

// A box carried through every station of the line with the stoppers down:
// the photo-eyes see it go by, no tag reader reads it at any step.
TEST(PlantTagReaders, ABoxPassingThroughOnARunningBeltIsNotRead) {
  Rig rig;
  const BoxId id = upload(rig);
  run_through(rig, {"conveyor1", "conveyor2", "conveyor4", "conveyor5"});
  bool seen_by_eye = false;
  int in_place_steps = 0;
  std::uint16_t read = 0;
  auto watch = [&] {
    seen_by_eye = seen_by_eye || rig.di("conveyor2", conveyor_plc::kStationEye) ||
                  rig.di("conveyor4", static_cast<std::uint16_t>(conveyor_plc::kStationEye + 1));
    in_place_steps += rig.world().box_in_place(*rig.layout().belt_index("conveyor4"), 1) != nullptr ? 1 : 0;
    for (std::uint16_t r :
         {smart_reader(rig), rig.ir("denso", robot_controller::kStationBox),
          rig.ir("downloader", transfer_plc::kStationBox), rig.ir("conveyor2", conveyor_plc::kStationBox)}) {
      read = read != 0 ? read : r;
    }
    return rig.world().box(id)->belt == *rig.layout().belt_index("conveyor5");
  };
  ASSERT_TRUE(rig.run_until(watch, 30s));
  EXPECT_TRUE(seen_by_eye);
  // The box's centre is within the station's tolerance for a few milliseconds only (±2 mm at 0.5 m/s).
  EXPECT_GT(in_place_steps, 0);
  EXPECT_LT(in_place_steps, 10);
  EXPECT_EQ(read, 0) << "a passing box was read";
}

}  // namespace
}  // namespace sf::plant::testing
