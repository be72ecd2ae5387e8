#include "sf/negotiation/memory_transport.hpp"

#include <algorithm>
#include <utility>

namespace sf::negotiation {

MemoryNetwork::MemoryNetwork(const Clock& clock, MemoryNetworkOptions options)
    : clock_(&clock), options_(options), rng_(options.seed) {}

MemoryManagerEndpoint& MemoryNetwork::add_manager() {
  managers_.push_back(
      std::unique_ptr<MemoryManagerEndpoint>(new MemoryManagerEndpoint(*this, managers_.size())));
  return *managers_.back();
}

MemoryContractorEndpoint& MemoryNetwork::add_contractor(std::string name,
                                                        std::vector<std::string> operations) {
  contractors_.push_back(std::unique_ptr<MemoryContractorEndpoint>(
      new MemoryContractorEndpoint(*this, std::move(name), std::move(operations))));
  return *contractors_.back();
}

MemoryConveyorEndpoint& MemoryNetwork::add_conveyor(std::string name) {
  conveyors_.push_back(
      std::unique_ptr<MemoryConveyorEndpoint>(new MemoryConveyorEndpoint(*this, std::move(name))));
  return *conveyors_.back();
}

Clock::time_point MemoryNetwork::due_time(const std::string& channel) {
  auto due = clock_->now() + options_.latency;
  if (options_.jitter.count() > 0) {
    std::uniform_int_distribution<std::int64_t> extra{0, options_.jitter.count()};
    due += std::chrono::nanoseconds{extra(rng_)};
  }
  if (options_.keep_order) {
    auto& last = channel_due_[channel];
    due = std::max(due, last);
    last = due;
  }
  return due;
}

void MemoryNetwork::post(const std::string& channel, std::function<void()> deliver) {
  ++stats_.sent;
  const auto due = due_time(channel);
  if (options_.duplicate_probability > 0.0 &&
      std::uniform_real_distribution<double>{0.0, 1.0}(rng_) < options_.duplicate_probability) {
    ++stats_.duplicated;
    queue_.emplace(std::make_pair(due_time(channel), ++seq_), deliver);
  }
  queue_.emplace(std::make_pair(due, ++seq_), std::move(deliver));
}

std::size_t MemoryNetwork::deliver() {
  std::size_t n = 0;
  while (!queue_.empty() && queue_.begin()->first.first <= clock_->now()) {
    auto node = queue_.extract(queue_.begin());
    node.mapped()();
    ++n;
  }
  stats_.delivered += n;
  return n;
}

std::optional<Clock::time_point> MemoryNetwork::next_delivery() const {
  if (queue_.empty()) {
    return std::nullopt;
  }
  return queue_.begin()->first.first;
}

std::size_t MemoryNetwork::live_contractors(const std::string& operation) const {
  // A dead contractor still counts until its lease expires, as a DDS match does.
  return static_cast<std::size_t>(std::count_if(contractors_.begin(), contractors_.end(), [&](const auto& c) {
    return !c->reported_lost_ && c->serves(operation);
  }));
}

void MemoryNetwork::tell_managers(const MemoryContractorEndpoint& contractor,
                                  void (ManagerInbox::*what)(const std::string&, const std::string&)) {
  for (auto& m : managers_) {
    for (const auto& op : contractor.operations_) {
      if (m->inbox_ != nullptr) {
        (m->inbox_->*what)(op, contractor.name_);
      }
    }
  }
}

void MemoryNetwork::kill(const std::string& contractor) {
  for (auto& c : contractors_) {
    if (c->name_ != contractor || !c->alive_) {
      continue;
    }
    c->alive_ = false;
    // Liveliness expiry is not a message: it is not reordered or duplicated.
    queue_.emplace(std::make_pair(clock_->now() + options_.lease, ++seq_), [this, dead = c.get()] {
      dead->reported_lost_ = true;
      tell_managers(*dead, &ManagerInbox::on_contractor_lost);
    });
  }
}

void MemoryNetwork::cut_off(const std::string& contractor) {
  for (auto& c : contractors_) {
    if (c->name_ != contractor || !c->alive_ || c->cut_off_) {
      continue;
    }
    c->cut_off_ = true;
    queue_.emplace(std::make_pair(clock_->now() + options_.lease, ++seq_),
                   [this, cut = c.get(), n = ++c->cuts_] {
                     if (cut->cut_off_ && cut->cuts_ == n && cut->alive_ && !cut->reported_lost_) {
                       cut->reported_lost_ = true;
                       tell_managers(*cut, &ManagerInbox::on_contractor_lost);
                     }
                   });
  }
}

void MemoryNetwork::reconnect(const std::string& contractor) {
  for (auto& c : contractors_) {
    if (c->name_ != contractor || !c->cut_off_) {
      continue;
    }
    c->cut_off_ = false;
    if (c->reported_lost_ && c->alive_) {
      c->reported_lost_ = false;
      tell_managers(*c, &ManagerInbox::on_contractor_alive);
    }
    for (auto& again : std::exchange(c->held_, {})) {
      again();
    }
  }
}

void MemoryNetwork::post_to(MemoryContractorEndpoint* to, const std::string& channel,
                            std::function<void(ContractorInbox&)> deliver) {
  post(channel, [this, to, channel, deliver = std::move(deliver)]() mutable {
    if (!to->alive_) {
      ++stats_.dropped;
    } else if (to->cut_off_) {
      to->held_.emplace_back([this, to, channel, deliver = std::move(deliver)]() mutable {
        post_to(to, channel, std::move(deliver));
      });
    } else if (to->inbox_ != nullptr) {
      deliver(*to->inbox_);
    }
  });
}

// --- manager endpoint ---------------------------------------------------------

Status MemoryManagerEndpoint::announce(const Announce& a) {
  for (auto& c : net_->contractors_) {
    if (c->alive_ && c->serves(a.operation)) {
      net_->post_to(c.get(), "m" + std::to_string(id_) + "/ANNOUNCE",
                    [a](ContractorInbox& inbox) { inbox.on_announce(a); });
    }
  }
  return {};
}

Status MemoryManagerEndpoint::send(const ManagerMessage& m) {
  for (auto& c : net_->contractors_) {
    if (c->alive_ && c->serves(m.operation)) {
      net_->post_to(c.get(), "m" + std::to_string(id_) + "/AWARD",
                    [m](ContractorInbox& inbox) { inbox.on_manager_message(m); });
    }
  }
  return {};
}

void MemoryManagerEndpoint::close(const std::string& operation, const std::string& conversation) {
  for (auto& c : net_->contractors_) {
    if (c->alive_ && c->serves(operation)) {
      // Disposal follows the AWARD writer's data, so it shares that channel.
      net_->post_to(c.get(), "m" + std::to_string(id_) + "/AWARD",
                    [operation, conversation](ContractorInbox& inbox) {
                      inbox.on_conversation_closed(operation, conversation);
                    });
    }
  }
}

std::size_t MemoryManagerEndpoint::contractors(const std::string& operation) const {
  return net_->live_contractors(operation);
}

Status MemoryManagerEndpoint::request(const TransportRequest& r) {
  for (auto& c : net_->conveyors_) {
    MemoryConveyorEndpoint* to = c.get();
    net_->post("m" + std::to_string(id_) + "/REQUEST", [to, r] {
      if (to->inbox_ != nullptr) {
        to->inbox_->on_request(r);
      }
    });
  }
  return {};
}

void MemoryManagerEndpoint::close(const std::string& conversation) {
  for (auto& c : net_->conveyors_) {
    MemoryConveyorEndpoint* to = c.get();
    net_->post("m" + std::to_string(id_) + "/REQUEST", [to, conversation] {
      if (to->inbox_ != nullptr) {
        to->inbox_->on_request_closed(conversation);
      }
    });
  }
}

std::size_t MemoryManagerEndpoint::conveyors() const {
  return net_->conveyors_.size();
}

// --- contractor and conveyor endpoints ------------------------------------------

bool MemoryContractorEndpoint::serves(const std::string& operation) const {
  return std::find(operations_.begin(), operations_.end(), operation) != operations_.end();
}

Status MemoryContractorEndpoint::send(const ContractorMessage& m) {
  if (!alive_) {
    return Error{Errc::state, "contractor is dead"};
  }
  for (auto& mgr : net_->managers_) {
    MemoryManagerEndpoint* to = mgr.get();
    auto deliver = [to, m] {
      if (to->inbox_ != nullptr) {
        to->inbox_->on_contractor_message(m);
      }
    };
    if (cut_off_) {
      held_.emplace_back([net = net_, channel = name_ + "/BID", deliver] { net->post(channel, deliver); });
    } else {
      net_->post(name_ + "/BID", std::move(deliver));
    }
  }
  return {};
}

void MemoryContractorEndpoint::close(const std::string& /*operation*/, const std::string& /*conversation*/) {
  ++closed_;
}

Status MemoryConveyorEndpoint::inform(const TransportInform& i) {
  for (auto& mgr : net_->managers_) {
    MemoryManagerEndpoint* to = mgr.get();
    net_->post(name_ + "/INFORM", [to, i] {
      if (to->route_inbox_ != nullptr) {
        to->route_inbox_->on_inform(i);
      }
    });
  }
  return {};
}

void MemoryConveyorEndpoint::close(const std::string& /*conversation*/) {}

}  // namespace sf::negotiation
