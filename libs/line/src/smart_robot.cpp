#include "sf/line/smart_robot.hpp"

#include <cmath>

namespace sf::line {

motion::ScaraJoints joints_from_counts(const std::array<double, kArmAxes>& counts) {
  return {counts[0] / kCountsPerRadian, counts[1] / kCountsPerRadian, counts[2] / kCountsPerMetre,
          counts[3] / kCountsPerRadian};
}

std::array<std::int32_t, kArmAxes> counts_from_joints(const motion::ScaraJoints& q) {
  return {static_cast<std::int32_t>(std::lround(q[0] * kCountsPerRadian)),
          static_cast<std::int32_t>(std::lround(q[1] * kCountsPerRadian)),
          static_cast<std::int32_t>(std::lround(q[2] * kCountsPerMetre)),
          static_cast<std::int32_t>(std::lround(q[3] * kCountsPerRadian))};
}

}  // namespace sf::line
