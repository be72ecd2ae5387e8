// A Store that forwards to a real one, with hooks around every call: tests
// use them to take the database "down" (before returns an error), to lose an
// acknowledgement after a commit (after returns an error) or to kill the
// process at a chosen moment. The real store underneath does the work.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string_view>

#include "sf/historian/store.hpp"

namespace sf::historian::test {

class HookedStore final : public Store {
 public:
  // op: "register", "append", "events", "read".
  using Hook = std::function<std::optional<Error>(std::string_view op)>;

  HookedStore(std::unique_ptr<Store> inner, Hook before, Hook after = {})
      : inner_(std::move(inner)), before_(std::move(before)), after_(std::move(after)) {}

  Result<SeriesId> register_series(const SeriesInfo& info) override {
    return call("register", [&] { return inner_->register_series(info); });
  }
  Result<std::vector<Series>> list_series() override {
    return call("read", [&] { return inner_->list_series(); });
  }
  Status append(std::span<const Sample> samples) override {
    return call("append", [&] { return inner_->append(samples); });
  }
  Status append_events(std::span<const Event> events) override {
    return call("events", [&] { return inner_->append_events(events); });
  }
  Result<std::vector<Sample>> read_raw(SeriesId s, Timestamp from, Timestamp to, std::size_t limit) override {
    return call("read", [&] { return inner_->read_raw(s, from, to, limit); });
  }
  Result<std::optional<Sample>> latest(SeriesId s) override {
    return call("read", [&] { return inner_->latest(s); });
  }
  Result<std::vector<AggregateRow>> aggregate(SeriesId s, Timestamp from, Timestamp to, Micros interval,
                                              Aggregate which) override {
    return call("read", [&] { return inner_->aggregate(s, from, to, interval, which); });
  }
  Result<std::vector<Event>> read_events(const EventQuery& q) override {
    return call("read", [&] { return inner_->read_events(q); });
  }
  Result<RetentionResult> apply_retention(Timestamp before) override {
    return call("read", [&] { return inner_->apply_retention(before); });
  }
  Result<int> schema_version() override {
    return call("read", [&] { return inner_->schema_version(); });
  }
  [[nodiscard]] std::string_view backend() const override { return inner_->backend(); }

 private:
  template <typename F>
  auto call(std::string_view op, F&& f) -> decltype(f()) {
    if (before_) {
      if (auto e = before_(op)) {
        return *e;
      }
    }
    auto result = f();
    if (result && after_) {
      if (auto e = after_(op)) {
        return *e;
      }
    }
    return result;
  }

  std::unique_ptr<Store> inner_;
  Hook before_;
  Hook after_;
};

inline Error unreachable() {
  return make_error(Errc::io, "database unreachable (test)");
}

}  // namespace sf::historian::test
