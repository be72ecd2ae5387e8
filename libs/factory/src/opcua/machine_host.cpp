// MachineHost (machine_host.hpp): the controller thread's step, the inbox that carries operator
// commands and posted tasks to it, and the publication of the model's changes to the server.
#include "sf/factory/machine_host.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <future>
#include <mutex>

#include <fmt/format.h>

#include "sf/core/log.hpp"
#include "sf/opcua/server/nodeset.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::factory {

namespace ua = sf::opcua;

// Tasks for the controller thread, shared with the method callbacks in the address space (which
// may outlive the host). A task gets nullptr when it will never run (the host is gone).
struct MachineHost::Inbox {
  using Task = std::function<void(MachineController*)>;

  std::mutex mutex;
  std::condition_variable changed;  // a task, or stop (for run())
  std::deque<Task> tasks;
  std::function<void()> wake;
  bool closed = false;
  bool stopping = false;

  bool push(Task task) {
    std::function<void()> wake_now;
    {
      const std::lock_guard lock(mutex);
      if (closed) {
        return false;
      }
      tasks.push_back(std::move(task));
      wake_now = wake;
    }
    changed.notify_all();
    if (wake_now) {
      wake_now();
    }
    return true;
  }

  std::deque<Task> take() {
    const std::lock_guard lock(mutex);
    return std::exchange(tasks, {});
  }

  void close() {
    std::deque<Task> dropped;
    {
      const std::lock_guard lock(mutex);
      closed = true;
      dropped = std::exchange(tasks, {});
    }
    for (Task& task : dropped) {
      task(nullptr);
    }
  }
};

namespace {

// A command for the controller thread and its answer. claim(): the one who moves it out of
// `pending` decides: the controller thread runs it, a caller that timed out drops it.
struct PendingCommand {
  enum : int { pending, running, dropped };
  std::atomic<int> state{pending};
  std::promise<ua::StatusCode> answer;

  bool claim(int next) {
    int expected = pending;
    return state.compare_exchange_strong(expected, next);
  }
};

// The CommandHandler of the model: queue, wake, wait (machine_host.hpp's contract).
CommandHandler command_handler(std::weak_ptr<MachineHost::Inbox> weak, std::chrono::milliseconds timeout) {
  return [weak = std::move(weak), timeout](PackMLCommand command) -> ua::StatusCode {
    auto inbox = weak.lock();
    if (!inbox) {
      return ua::status::BadShutdown;
    }
    auto pending = std::make_shared<PendingCommand>();
    auto answer = pending->answer.get_future();
    const bool queued = inbox->push([pending, command](MachineController* controller) {
      if (!pending->claim(PendingCommand::running)) {
        return;  // the caller gave up
      }
      if (controller == nullptr) {
        pending->answer.set_value(ua::status::BadShutdown);
        return;
      }
      const Status st = controller->command(command);
      pending->answer.set_value(st ? ua::StatusCode{} : ua::status_of(st.error()));
    });
    inbox.reset();
    if (!queued) {
      return ua::status::BadShutdown;
    }
    if (answer.wait_for(timeout) != std::future_status::ready && pending->claim(PendingCommand::dropped)) {
      log::get("factory")->warn("{} not taken by the controller within {} ms", to_string(command),
                                timeout.count());
      return ua::status::BadTimeout;
    }
    return answer.get();  // running or done: command() answers at once
  };
}

}  // namespace

MachineHost::MachineHost(ua::server::Server& server, MachineController& controller, const Clock& clock,
                         MachineHostOptions options)
    : server_(server),
      controller_(controller),
      clock_(clock),
      options_(std::move(options)),
      inbox_(std::make_shared<Inbox>()),
      publisher_(options_.time_resolution) {}

MachineHost::~MachineHost() {
  inbox_->close();
}

Result<std::unique_ptr<MachineHost>> MachineHost::attach(ua::server::Server& server,
                                                         MachineController& controller, const Clock& clock,
                                                         MachineHostOptions options) {
  std::unique_ptr<MachineHost> host(new MachineHost(server, controller, clock, std::move(options)));
  std::optional<Result<MachineModel>> built;
  const auto handler = command_handler(host->inbox_, host->options_.command_timeout);
  server.with_address_space([&](ua::server::AddressSpace& space) {
    built.emplace(MachineModel::create(space, controller.identification(), handler, host->options_.model));
  });
  if (!*built) {
    return built->error();
  }
  host->model_ = std::make_shared<MachineModel>(std::move(**built));
  host->publish();  // the first values, before any client can look
  return host;
}

Clock::time_point MachineHost::step(Clock::time_point now) {
  auto tasks = inbox_->take();
  for (auto& task : tasks) {
    task(&controller_);
  }
  const bool due = now >= next_poll_;
  if (due) {
    next_poll_ = controller_.poll(now);
  }
  if (due || !tasks.empty()) {
    publish();
  }
  return next_poll_;
}

void MachineHost::publish() {
  auto changes = publisher_.changes(controller_.status(), clock_.utc_now());
  if (changes.empty()) {
    return;
  }
  server_.post([model = model_, changes = std::move(changes)](ua::server::AddressSpace& space) {
    model->apply(space, changes);
  });
}

void MachineHost::run() {
  // The longest sleep between looks at the clock: a ManualClock or ScaledClock does not move with
  // the condition variable's steady time.
  constexpr auto kMaxSleep = std::chrono::milliseconds(50);
  for (;;) {
    const auto next = step(clock_.now());
    const auto wait =
        std::clamp<std::chrono::nanoseconds>(next - clock_.now(), std::chrono::nanoseconds(0), kMaxSleep);
    std::unique_lock lock(inbox_->mutex);
    inbox_->changed.wait_for(lock, wait, [&] { return inbox_->stopping || !inbox_->tasks.empty(); });
    if (inbox_->stopping) {
      inbox_->stopping = false;  // run() may be called again
      return;
    }
  }
}

void MachineHost::stop() {
  {
    const std::lock_guard lock(inbox_->mutex);
    inbox_->stopping = true;
  }
  inbox_->changed.notify_all();
}

void MachineHost::post(std::function<void(MachineController&)> fn) {
  (void)inbox_->push([fn = std::move(fn)](MachineController* controller) {
    if (controller != nullptr) {
      fn(*controller);
    }
  });
}

void MachineHost::set_wake(std::function<void()> wake) {
  const std::lock_guard lock(inbox_->mutex);
  inbox_->wake = std::move(wake);
}

const ua::NodeId& MachineHost::machine() const {
  return model_->machine();
}

ua::NodeId MachineHost::node(std::string_view path) const {
  return model_->node(path);
}

Status serve_machine(MachineController& controller, const MachineServerConfig& config, const Clock& clock,
                     const std::stop_token& stop,
                     const std::function<void(const ua::server::Server&)>& started) {
  ua::server::Server server(config.server, clock);
  Status imported;
  server.with_address_space([&](ua::server::AddressSpace& space) {
    auto reports = ua::server::import_nodeset_files(space, config.nodesets);
    imported = reports ? Status{} : Status(reports.error());
  });
  if (!imported) {
    return imported.error();
  }
  auto host = MachineHost::attach(server, controller, clock, config.host);
  if (!host) {
    return host.error();
  }
  SF_TRY(server.start());
  if (started) {
    started(server);
  }
  const std::stop_callback on_stop(stop, [&] { (*host)->stop(); });
  (*host)->run();
  host->reset();
  server.stop();
  return {};
}

}  // namespace sf::factory
