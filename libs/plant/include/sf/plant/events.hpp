// What happens on the line, in the order it happens: boxes entering and
// leaving stations, candies picked, placed and dropped, boxes uploaded,
// downloaded and inspected, faults. Stamped with simulated time, so two runs
// of one scenario and seed give the same log, line for line.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <string>
#include <string_view>
#include <vector>

namespace sf::plant {

using BoxId = std::uint32_t;

enum class EventKind {
  box_uploaded,
  box_entered_station,
  box_left_station,
  box_transferred,  // from one belt onto the next
  box_downloaded,
  box_inspected,
  box_lost,  // fell off the line
  candy_picked,
  candy_placed,
  candy_dropped,
  pick_missed,  // the gripper closed on nothing (or on an empty dispenser)
  fault_raised,
  fault_cleared,
  job_started,
  job_done,
  job_failed,
};
std::string_view to_string(EventKind kind);

struct Event {
  std::chrono::nanoseconds at{};  // simulated time since the plant started
  EventKind kind{};
  std::string where;  // machine, belt or "belt/station"
  BoxId box = 0;      // 0 = none
  int slot = -1;
  std::string candy;
  std::string detail;
  bool operator==(const Event&) const = default;
};
// "12.345678 candy_placed scara1 box=3 slot=5 candy=gummy"
std::string format(const Event& event);

// A bounded log: beyond `capacity` the oldest entries go (and are counted).
class EventLog {
 public:
  explicit EventLog(std::size_t capacity = 200'000) : capacity_(capacity) {}
  void add(Event event);
  [[nodiscard]] const std::deque<Event>& entries() const { return entries_; }
  [[nodiscard]] std::uint64_t total() const { return total_; }
  [[nodiscard]] std::uint64_t discarded() const { return total_ - entries_.size(); }
  // Entries with sequence number >= `from` (the first entry ever is 0).
  [[nodiscard]] std::vector<Event> since(std::uint64_t from) const;

 private:
  std::size_t capacity_;
  std::deque<Event> entries_;
  std::uint64_t total_ = 0;
};

}  // namespace sf::plant
