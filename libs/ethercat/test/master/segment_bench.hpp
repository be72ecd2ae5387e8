// Test bench: an emulated segment behind a SegmentLink, a ManualClock, and a
// master on top. Helpers run cycles the way an application does.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "sf/core/clock.hpp"
#include "sf/ethercat/master/master.hpp"
#include "sf/ethercat/slave/segment.hpp"

namespace sf::ethercat::master::test {

inline MasterOptions quick_options() {
  MasterOptions o;
  // Fewer static drift frames keep the tests short; DC tests use the default.
  o.dc_static_drift_frames = 2000;
  return o;
}

struct Bench {
  explicit Bench(const std::string& spec, MasterOptions options = quick_options(),
                 slave::SegmentOptions segment_options = {}) {
    auto s = slave::Segment::create(spec, clock, segment_options);
    if (!s) {
      ADD_FAILURE() << s.error().describe();
      return;
    }
    segment = std::move(*s);
    link = std::make_unique<slave::SegmentLink>(*segment);
    master = std::make_unique<Master>(*link, clock, options);
  }

  // A segment the test fills itself (custom devices).
  explicit Bench(const std::function<void(slave::Segment&)>& build, MasterOptions options = quick_options()) {
    segment = std::make_unique<slave::Segment>(clock);
    build(*segment);
    link = std::make_unique<slave::SegmentLink>(*segment);
    master = std::make_unique<Master>(*link, clock, options);
  }

  // One cycle of `period`: exchange, then maintain.
  ExchangeResult cycle(std::chrono::nanoseconds period = std::chrono::milliseconds{1}) {
    clock.advance(period);
    auto r = master->exchange();
    master->maintain();
    return r;
  }

  ManualClock clock;  // declared first: the segment keeps a reference
  std::unique_ptr<slave::Segment> segment;
  std::unique_ptr<slave::SegmentLink> link;
  std::unique_ptr<Master> master;
};

}  // namespace sf::ethercat::master::test
