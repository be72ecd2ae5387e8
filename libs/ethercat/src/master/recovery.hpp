// One slave on its way back to the segment's state (private to the master).
#pragma once

#include <cstddef>

#include "sf/core/clock.hpp"
#include "sf/ethercat/master/master.hpp"

namespace sf::ethercat::master {

struct Master::Recovery {
  using Step = RecoveryStep;
  std::size_t position = 0;
  Step step = Step::probe;
  Clock::time_point deadline{};    // of the current wait step
  Clock::time_point not_before{};  // back-off after a failure
};

}  // namespace sf::ethercat::master
