// Times and durations as people type them on the command line, and as the
// CLI prints them: ISO 8601 (UTC unless an offset is given) or relative to
// now ("-10m"), durations like "500ms", "1s", "7d", "1h30m".
#pragma once

#include <string>
#include <string_view>

#include "sf/core/result.hpp"
#include "sf/historian/types.hpp"

namespace sf::historian {

// Units us, ms, s, m, h, d, w; several may follow each other ("1h30m").
Result<Micros> parse_duration(std::string_view text);

// "now", "-10m" / "+1h" / "now-10m" (relative to `now`),
// "2026-11-21", "2026-11-21T10:15", "2026-11-21T10:15:30.25Z", "...+01:00".
Result<Timestamp> parse_time(std::string_view text, Timestamp now);

// "2026-11-21T10:15:30Z", with ".ffffff" when there are sub-seconds.
std::string format_time(Timestamp t);

}  // namespace sf::historian
