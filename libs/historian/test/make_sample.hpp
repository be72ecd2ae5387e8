// Samples for tests, built member by member: GCC 12 misreports the value
// variant as maybe-uninitialised when a Sample is aggregate-initialised in a
// loop (-Werror=maybe-uninitialized).
#pragma once

#include "sf/historian/types.hpp"

namespace sf::historian::test {

inline Sample make_sample(SeriesId id, Timestamp source, Timestamp server, Value value, std::uint32_t seq = 0,
                          StatusCode status = kGood) {
  Sample s;
  s.series = id;
  s.source_time = source;
  s.server_time = server;
  s.seq = seq;
  s.status = status;
  s.value = std::move(value);
  return s;
}

}  // namespace sf::historian::test
