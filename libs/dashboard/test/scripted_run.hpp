// A scripted run of one machine (the uploader) whose state times and counts the OEE tests work
// out by hand; the same run goes through the historian in oee_history_test.cpp.
#pragma once

#include <chrono>
#include <cstdint>
#include <vector>

#include "sf/dashboard/oee.hpp"

namespace sf::dashboard::test {

// Seconds from the run's origin (2026-11-28T10:00:00Z) as a historian timestamp.
inline Timestamp at(double s) {
  constexpr std::int64_t kOrigin = 1'795'860'000'000'000;
  return historian::from_micros(kOrigin + static_cast<std::int64_t>(s * 1e6));
}

inline constexpr double kRunEnd = 1000.0;

using S = factory::PackMLState;

// States from −50 s (before the range [0, 1000) the tests ask for), counts from −50 s.
inline MachineHistory scripted_run() {
  MachineHistory h;
  h.machine = "Uploader";
  h.states = {{at(-50), S::Stopped}, {at(100), S::Resetting}, {at(110), S::Idle},    {at(120), S::Starting},
              {at(130), S::Execute}, {at(530), S::Holding},   {at(540), S::Held},    {at(640), S::Unholding},
              {at(650), S::Execute}, {at(850), S::Aborting},  {at(855), S::Aborted}, {at(960), S::Clearing},
              {at(970), S::Stopped}};
  h.processed = {{at(-50), 40},  {at(200), 60},  {at(400), 120},
                 {at(520), 160}, {at(700), 200}, {at(840), 250}};
  h.defective = {{at(-50), 2}, {at(400), 5}, {at(840), 12}};
  return h;
}

}  // namespace sf::dashboard::test
