#include "sf/plant/events.hpp"

#include <fmt/format.h>

namespace sf::plant {

std::string_view to_string(EventKind kind) {
  switch (kind) {
    case EventKind::box_uploaded:
      return "box_uploaded";
    case EventKind::box_entered_station:
      return "box_entered_station";
    case EventKind::box_left_station:
      return "box_left_station";
    case EventKind::box_transferred:
      return "box_transferred";
    case EventKind::box_downloaded:
      return "box_downloaded";
    case EventKind::box_inspected:
      return "box_inspected";
    case EventKind::box_lost:
      return "box_lost";
    case EventKind::candy_picked:
      return "candy_picked";
    case EventKind::candy_placed:
      return "candy_placed";
    case EventKind::candy_dropped:
      return "candy_dropped";
    case EventKind::pick_missed:
      return "pick_missed";
    case EventKind::fault_raised:
      return "fault_raised";
    case EventKind::fault_cleared:
      return "fault_cleared";
    case EventKind::job_started:
      return "job_started";
    case EventKind::job_done:
      return "job_done";
    case EventKind::job_failed:
      return "job_failed";
  }
  return "?";
}

std::string format(const Event& e) {
  std::string out =
      fmt::format("{:.6f} {} {}", std::chrono::duration<double>(e.at).count(), to_string(e.kind), e.where);
  if (e.box != 0) {
    out += fmt::format(" box={}", e.box);
  }
  if (e.slot >= 0) {
    out += fmt::format(" slot={}", e.slot);
  }
  if (!e.candy.empty()) {
    out += fmt::format(" candy={}", e.candy);
  }
  if (!e.detail.empty()) {
    out += fmt::format(" ({})", e.detail);
  }
  return out;
}

void EventLog::add(Event event) {
  entries_.push_back(std::move(event));
  ++total_;
  if (entries_.size() > capacity_) {
    entries_.pop_front();
  }
}

std::vector<Event> EventLog::since(std::uint64_t from) const {
  const std::uint64_t first = total_ - entries_.size();
  std::vector<Event> out;
  for (std::uint64_t i = std::max(from, first); i < total_; ++i) {
    out.push_back(entries_[static_cast<std::size_t>(i - first)]);
  }
  return out;
}

}  // namespace sf::plant
