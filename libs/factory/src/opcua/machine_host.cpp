// MachineHost (machine_host.hpp): the loop thread's timer that publishes the controller
// thread's snapshots, the method calls that cross to the controller thread, and serve_machine.
#include "sf/factory/machine_host.hpp"

#include <atomic>
#include <condition_variable>
#include <future>
#include <mutex>
#include <optional>

#include "sf/core/log.hpp"
#include "sf/opcua/server/nodeset.hpp"
#include "sf/opcua/status_codes.hpp"

namespace sf::factory {

namespace ua = sf::opcua;

// What the loop thread's timer and the method callbacks share with the host. `thread` is the
// controller's until the host is destroyed (nullptr after); the mutex keeps it from going away
// while a callback uses it. The model and publisher are the loop thread's.
struct MachineHost::Shared {
  std::mutex mutex;
  ControllerThread* thread = nullptr;
  std::optional<MachineModel> model;
  StatusPublisher publisher;
  net::EventLoop::TimerId timer = 0;

  explicit Shared(ControllerThread& t, std::chrono::milliseconds resolution)
      : thread(&t), publisher(resolution) {}

  // Loop thread: the snapshot's changes into the model. False once detached.
  bool publish(ua::server::AddressSpace& space, Clock::utc_time utc) {
    std::unique_lock lock(mutex);
    if (thread == nullptr) {
      return false;
    }
    const ControllerStatus status = thread->status();
    lock.unlock();
    model->apply(space, publisher.changes(status, utc));
    return true;
  }
};

namespace {

// A command for the controller thread and its answer. Whoever moves it out of `pending` first
// decides: the controller thread runs it, a caller that timed out drops it.
struct PendingCommand {
  enum : int { pending, running, dropped };
  std::atomic<int> state{pending};
  std::promise<ua::StatusCode> answer;

  bool claim(int next) {
    int expected = pending;
    return state.compare_exchange_strong(expected, next);
  }
};

// The model's CommandHandler: post to the controller thread, wait (machine_host.hpp's contract).
CommandHandler command_handler(const std::weak_ptr<MachineHost::Shared>& weak,
                               std::chrono::milliseconds timeout) {
  return [weak, timeout](PackMLCommand command) -> ua::StatusCode {
    auto pending = std::make_shared<PendingCommand>();
    auto answer = pending->answer.get_future();
    {
      auto shared = weak.lock();
      if (!shared) {
        return ua::status::BadShutdown;
      }
      const std::lock_guard lock(shared->mutex);
      if (shared->thread == nullptr) {
        return ua::status::BadShutdown;
      }
      shared->thread->post([pending, command](MachineController& controller) {
        if (pending->claim(PendingCommand::running)) {
          const Status st = controller.command(command);
          pending->answer.set_value(st ? ua::StatusCode{} : ua::status_of(st.error()));
        }
      });
    }
    if (answer.wait_for(timeout) != std::future_status::ready && pending->claim(PendingCommand::dropped)) {
      log::get("factory")->warn("{} not taken by the controller thread within {} ms", to_string(command),
                                timeout.count());
      return ua::status::BadTimeout;
    }
    return answer.get();
  };
}

}  // namespace

Result<std::unique_ptr<MachineHost>> MachineHost::attach(ua::server::Server& server, ControllerThread& thread,
                                                         const Identification& identification,
                                                         MachineHostOptions options) {
  auto shared = std::make_shared<Shared>(thread, options.time_resolution);
  const CommandHandler handler = command_handler(shared, options.command_timeout);
  Status built;
  server.with_address_space([&](ua::server::AddressSpace& space) {
    auto model = MachineModel::create(space, identification, handler, options.model);
    if (!model) {
      built = model.error();
      return;
    }
    shared->model.emplace(std::move(*model));
    net::EventLoop* loop = &server.loop();
    (void)shared->publish(space, loop->clock().utc_now());  // the first values, before clients look
    shared->timer = loop->add_periodic(options.publish_interval, [shared, srv = &server, loop] {
      srv->with_address_space([&](ua::server::AddressSpace& s) {
        if (!shared->publish(s, loop->clock().utc_now())) {
          loop->cancel_timer(shared->timer);  // the host is gone
        }
      });
    });
  });
  if (!built) {
    return built.error();
  }
  std::unique_ptr<MachineHost> host(new MachineHost(shared));
  host->machine_ = shared->model->machine();
  return host;
}

MachineHost::~MachineHost() {
  const std::lock_guard lock(shared_->mutex);
  shared_->thread = nullptr;
}

ua::NodeId MachineHost::node(std::string_view path) const {
  return shared_->model->node(path);  // the model's NodeIds never change: no loop thread needed
}

Status serve_machine(MachineController& controller, const MachineServerConfig& config, Clock& clock,
                     const std::stop_token& stop,
                     const std::function<void(const ua::server::Server&, ControllerThread&)>& started) {
  ua::server::Server server(config.server, clock);
  Status imported;
  server.with_address_space([&](ua::server::AddressSpace& space) {
    auto reports = ua::server::import_nodeset_files(space, config.nodesets);
    imported = reports ? Status{} : Status(reports.error());
  });
  if (!imported) {
    return imported.error();
  }
  ControllerThread thread(controller, clock, config.thread);
  auto host = MachineHost::attach(server, thread, controller.identification(), config.host);
  if (!host) {
    return host.error();
  }
  SF_TRY(server.start());
  thread.start();
  if (started) {
    started(server, thread);
  }
  std::mutex mutex;
  std::condition_variable_any stopped;
  std::unique_lock lock(mutex);
  stopped.wait(lock, stop, [] { return false; });
  thread.stop();
  host->reset();
  server.stop();
  return {};
}

}  // namespace sf::factory
