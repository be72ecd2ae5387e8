// Durations on the controller's cycle grid.
#pragma once

#include <cmath>
#include <cstddef>

namespace sf::motion::detail {

// Whole cycles covering `duration`; a duration a rounding error above a
// whole number of cycles does not cost one more.
inline std::size_t whole_cycles(double duration, double cycle) {
  return static_cast<std::size_t>(std::ceil(duration / cycle - 1e-9));
}

}  // namespace sf::motion::detail
