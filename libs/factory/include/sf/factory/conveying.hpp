// Conveying on the line's belts (paper §IV.B, the ConveyingDomain): the
// places a box is transported between, numbered for the Contract Net (an
// Operation's params are numbers), and the segments each conveyor serves with
// their transit times, all from the layout.
//
// A place is a station ("conveyor2/scara1") or a belt's entry ("conveyor2",
// the junction where boxes arrive from the belts that feed it). One conveyor
// moves only its own belt, so it carries a box from where it stands on its
// belt (a station, or anywhere between the entry and the next station) either
// to a later station of its belt or onto the next belt, where the box waits at
// that belt's entry. A route over several belts is several transports, one per
// conveyor in route order; consecutive segments of one conveyor may be merged
// into one transport (from the first segment's start to the last one's end).
#pragma once

#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sf/line/layout.hpp"

namespace sf::factory {

struct Place {
  std::string name;                    // "conveyor2/scara1", or "conveyor2" for the entry
  std::size_t belt = 0;                // index in the layout's belts
  std::optional<std::size_t> station;  // none: the belt's entry
  double at_m = 0.0;                   // along the belt
};

// Every place of the line, belt by belt in layout order: the entry, then the
// stations. A place's index here is its number in "transport" operations.
std::vector<Place> places(const line::Layout& layout);
std::optional<std::size_t> place_index(const line::Layout& layout, std::string_view name);

// A hop one conveyor serves, as the ConveyingDomain's INFORM carries it
// (negotiation::Segment with the conveyor's name).
struct TransportSegment {
  std::string from;
  std::string to;
  double length_m = 0.0;  // travel of the box along the belt
  std::chrono::nanoseconds transit_time{0};
  friend bool operator==(const TransportSegment&, const TransportSegment&) = default;
};

// How far `belt` carries a box from `from` to `to`: a later station of the
// belt, or the entry of a belt it feeds (the box crosses when its centre
// passes the belt's end). Nothing when this belt cannot take it there.
std::optional<double> belt_travel(const line::Layout& layout, std::size_t belt, const Place& from,
                                  const Place& to);

// The hops of `belt`: from its entry and each station to the next station,
// and from the last of them onto each belt it feeds; transit times at the
// belt's speed.
std::vector<TransportSegment> conveyor_segments(const line::Layout& layout, std::size_t belt);

// Travel time at a belt's layout speed.
std::chrono::nanoseconds travel_time(double metres, double speed_mps);

}  // namespace sf::factory
