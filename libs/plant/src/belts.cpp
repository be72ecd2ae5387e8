// Conveyor belt physics (world.hpp): boxes ride the belt at its speed, stop
// at a raised stopper, queue behind the box ahead, cross onto the next belt
// when its entry is free, and wait at the end when it is not: no box
// overlaps another and none is lost at a transfer.
#include <algorithm>
#include <cmath>

#include "sf/plant/world.hpp"

namespace sf::plant {

namespace {
constexpr double kEpsilon = 1e-9;
constexpr double kIndexSlack = 0.01;  // m: more than a box moves in one step (10 m/s)
}  // namespace

double World::box_length(const Box& box) const {
  return layout_.catalog.box_types[box.type].size_m.x;
}

std::optional<std::size_t> World::exit_of(std::size_t b) const {
  const auto& next = next_[b];
  if (next.empty()) {
    return std::nullopt;
  }
  return next[std::min(belts_[b].exit, next.size() - 1)];
}

bool World::crossing(const Box& box) const {
  return box.s > length_[box.belt] - box_length(box) / 2.0 + kEpsilon;
}

// Calls `hit` for the boxes that may be on belt b within [lo, hi] or crossing
// onto it: those indexed on b in that window (the index is sorted by s at the
// start of the step; boxes move less than kIndexSlack within a step and never
// overtake) and the front box of each belt feeding b (a box that crossed
// since the index was built is found there). The checks read where each box
// is now. False as soon as `hit` is true.
template <typename F>
bool World::none_near(std::size_t b, double lo, double hi, F hit) const {
  const auto& list = on_belt_[b];
  auto it = std::lower_bound(list.begin(), list.end(), lo - kIndexSlack,
                             [&](std::size_t i, double v) { return boxes_[i].s < v; });
  for (; it != list.end() && boxes_[*it].s <= hi + kIndexSlack; ++it) {
    if (hit(boxes_[*it])) {
      return false;
    }
  }
  for (std::size_t f : feeders_[b]) {
    if (!on_belt_[f].empty() && hit(boxes_[on_belt_[f].back()])) {
      return false;
    }
  }
  return true;
}

void World::reindex() {
  for (auto& list : on_belt_) {
    list.clear();
  }
  for (std::size_t i = 0; i < boxes_.size(); ++i) {
    on_belt_[boxes_[i].belt].push_back(i);
  }
  for (auto& list : on_belt_) {
    std::sort(list.begin(), list.end(),
              [&](std::size_t x, std::size_t y) { return boxes_[x].s < boxes_[y].s; });
  }
}

bool World::entry_free(std::size_t b, double front, BoxId except) const {
  return none_near(b, -max_half_, front + max_half_, [&](const Box& o) {
    if (o.id == except) {
      return false;
    }
    return (o.belt == b && o.s - box_length(o) / 2.0 < front - kEpsilon) ||
           (o.belt != b && crossing(o) && exit_of(o.belt) == b);
  });
}

bool World::span_free(std::size_t b, double s, double half, BoxId except) const {
  return none_near(b, s - half - max_half_, s + half + max_half_, [&](const Box& o) {
    if (o.id == except) {
      return false;
    }
    return (o.belt == b && std::abs(o.s - s) < half + box_length(o) / 2.0 - kEpsilon) ||
           (o.belt != b && crossing(o) && exit_of(o.belt) == b &&
            s - half < o.s + box_length(o) / 2.0 - length_[o.belt]);
  });
}

bool World::covered(std::size_t b, double s) const {
  return !none_near(b, s - max_half_, s + max_half_, [&](const Box& o) {
    const double half = box_length(o) / 2.0;
    return (o.belt == b && std::abs(o.s - s) <= half) ||
           (o.belt != b && crossing(o) && exit_of(o.belt) == b && s <= o.s + half - length_[o.belt]);
  });
}

void World::move_forward(std::size_t b, Box& box, double ds, const Box* ahead) {
  const BeltSpec& spec = layout_.belts[b];
  const double length = length_[b];
  const double half = box_length(box) / 2.0;
  double limit = box.s + ds;
  for (std::size_t k = 0; k < spec.stations.size(); ++k) {
    const double at = spec.stations[k].at_m;
    if (belts_[b].stoppers[k] && box.s <= at + kEpsilon && limit > at) {
      limit = at;
    }
  }
  if (ahead != nullptr) {
    limit = std::min(limit, ahead->s - box_length(*ahead) / 2.0 - half);
  }
  const double hold = length - half;
  if (limit > hold) {
    const auto next = exit_of(b);
    if (!next || !entry_free(*next, limit - length + half, box.id)) {
      limit = std::min(limit, std::max(box.s, hold));
    }
  }
  limit = std::max(limit, box.s);
  if (limit > length) {
    const auto next = exit_of(b);
    record(EventKind::box_transferred, layout_.belts[*next].name, box.id, -1, {}, "from " + spec.name);
    box.belt = *next;
    box.s = limit - length;
    box.moved_step = steps_;
    return;
  }
  box.s = limit;
}

void World::move_backward(std::size_t b, Box& box, double ds, const Box* behind) {
  const BeltSpec& spec = layout_.belts[b];
  const double half = box_length(box) / 2.0;
  double limit = box.s - ds;
  for (std::size_t k = 0; k < spec.stations.size(); ++k) {
    const double at = spec.stations[k].at_m;
    if (belts_[b].stoppers[k] && box.s >= at - kEpsilon && limit < at) {
      limit = at;
    }
  }
  if (behind != nullptr) {
    limit = std::max(limit, behind->s + box_length(*behind) / 2.0 + half);
  }
  box.s = std::min(box.s, std::max(limit, half));
}

void World::move_belt(std::size_t b, double dt) {
  BeltState& belt = belts_[b];
  std::vector<Box*>& on = moving_;
  on.clear();
  for (std::size_t i : on_belt_[b]) {
    if (boxes_[i].belt == b && boxes_[i].moved_step != steps_) {
      on.push_back(&boxes_[i]);
    }
  }
  const bool running = belt.motor && belt.speed_mps > 0.0;
  if (running) {
    belt.odometer_m += belt.speed_mps * dt;
  }
  if (!running || belt.jammed) {  // a jammed belt slips under its boxes
    for (Box* box : on) {
      note_station(*box, false);
    }
    return;
  }
  const double ds = belt.speed_mps * dt;
  if (!belt.reverse) {
    std::sort(on.begin(), on.end(), [](const Box* x, const Box* y) { return x->s > y->s; });
    const Box* ahead = nullptr;
    for (Box* box : on) {
      const double before = box->s;
      move_forward(b, *box, ds, ahead);
      note_station(*box, box->belt != b || box->s != before);
      ahead = box->belt == b ? box : nullptr;
    }
    return;
  }
  std::sort(on.begin(), on.end(), [](const Box* x, const Box* y) { return x->s < y->s; });
  const Box* behind = nullptr;
  for (Box* box : on) {
    const double before = box->s;
    move_backward(b, *box, ds, behind);
    note_station(*box, box->s != before);
    behind = box;
  }
}

// A box "enters" a station when it comes to rest in place there, and
// "leaves" it when it moves away.
void World::note_station(Box& box, bool moved) {
  const auto& stations = layout_.belts[box.belt].stations;
  if (box.station >= 0) {
    const auto k = static_cast<std::size_t>(box.station);
    if (k >= stations.size() || std::abs(box.s - stations[k].at_m) > kInPlaceTolerance) {
      record(EventKind::box_left_station, station_name(box.belt, k), box.id);
      box.station = -1;
    }
  }
  if (moved || box.station >= 0) {
    return;
  }
  for (std::size_t k = 0; k < stations.size(); ++k) {
    if (std::abs(box.s - stations[k].at_m) <= kInPlaceTolerance) {
      box.station = static_cast<int>(k);
      record(EventKind::box_entered_station, station_name(box.belt, k), box.id);
      return;
    }
  }
}

bool World::entry_eye(std::size_t b) const {
  return covered(b, kEyeInset);
}

bool World::exit_eye(std::size_t b) const {
  return belts_[b].jammed || covered(b, length_[b] - kEyeInset);
}

bool World::station_eye(std::size_t b, std::size_t station) const {
  return covered(b, layout_.belts[b].stations.at(station).at_m);
}

const Box* World::box_in_place(std::size_t b, std::size_t station) const {
  const double at = layout_.belts[b].stations.at(station).at_m;
  const Box* found = nullptr;
  (void)none_near(b, at - kInPlaceTolerance, at + kInPlaceTolerance, [&](const Box& o) {
    if (o.belt == b && std::abs(o.s - at) <= kInPlaceTolerance) {
      found = &o;
    }
    return found != nullptr;
  });
  return found;
}

std::uint16_t World::tag_reading(std::size_t b, std::size_t station) const {
  const Box* box = box_in_place(b, station);
  if (box == nullptr || box->station != static_cast<int>(station)) {
    return 0;
  }
  return static_cast<std::uint16_t>(box->id);
}

}  // namespace sf::plant
