#include "sf/net/event_loop.hpp"

#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <future>
#include <mutex>
#include <queue>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "sf/core/log.hpp"

namespace sf::net {
namespace {

std::uint32_t to_epoll(unsigned events) {
  std::uint32_t e = 0;
  if ((events & EventLoop::kReadable) != 0U) {
    e |= EPOLLIN | EPOLLRDHUP;
  }
  if ((events & EventLoop::kWritable) != 0U) {
    e |= EPOLLOUT;
  }
  return e;
}

unsigned from_epoll(std::uint32_t e) {
  unsigned ready = 0;
  if ((e & (EPOLLIN | EPOLLRDHUP)) != 0U) {
    ready |= EventLoop::kReadable;
  }
  if ((e & EPOLLOUT) != 0U) {
    ready |= EventLoop::kWritable;
  }
  if ((e & (EPOLLERR | EPOLLHUP)) != 0U) {
    ready |= EventLoop::kError;
  }
  return ready;
}

}  // namespace

struct EventLoop::Impl {
  explicit Impl(const Clock& c) : clock(c) {}

  struct Timer {
    Clock::time_point due;
    TimerId id;
    // Heap order: earliest first, then by id so equal deadlines run in the order added.
    bool operator>(const Timer& other) const { return due != other.due ? due > other.due : id > other.id; }
  };
  struct TimerEntry {
    std::function<void()> fn;
    std::chrono::nanoseconds period{0};  // 0 = one-shot
  };
  struct Watcher {
    std::shared_ptr<std::function<void(unsigned)>> fn;
    unsigned events = 0;
  };

  const Clock& clock;
  int epoll_fd = -1;
  int wake_fd = -1;
  std::atomic<bool> stopping{false};
  std::atomic<std::thread::id> loop_thread{std::this_thread::get_id()};

  mutable std::mutex mutex;  // guards posted
  std::vector<std::function<void()>> posted;

  std::priority_queue<Timer, std::vector<Timer>, std::greater<>> heap;
  std::unordered_map<TimerId, TimerEntry> timers;
  TimerId next_timer = 1;

  std::unordered_map<int, Watcher> watchers;

  void wake() const {
    const std::uint64_t one = 1;
    // A full eventfd counter still wakes the loop, so EAGAIN is harmless.
    (void)!::write(wake_fd, &one, sizeof one);
  }

  void drain_wake() const {
    std::uint64_t value = 0;
    (void)!::read(wake_fd, &value, sizeof value);
  }

  int timeout_ms() const {
    {
      // Posted work pending: do not sleep.
      const std::lock_guard lock(mutex);
      if (!posted.empty()) {
        return 0;
      }
    }
    if (heap.empty()) {
      return -1;
    }
    const auto now = clock.now();
    if (heap.top().due <= now) {
      return 0;
    }
    // Round up so the loop never wakes just before the deadline and spins.
    const auto wait = std::chrono::ceil<std::chrono::milliseconds>(heap.top().due - now).count();
    return static_cast<int>(std::min<std::int64_t>(wait, 60'000));
  }

  void run_posted() {
    std::vector<std::function<void()>> batch;
    {
      const std::lock_guard lock(mutex);
      batch.swap(posted);
    }
    for (auto& fn : batch) {
      fn();
    }
  }

  void run_timers() {
    const auto now = clock.now();
    // Only timers due now; a timer added by a callback with delay 0 runs on the next pass.
    std::vector<Timer> due;
    while (!heap.empty() && heap.top().due <= now) {
      due.push_back(heap.top());
      heap.pop();
    }
    for (const auto& t : due) {
      auto it = timers.find(t.id);
      if (it == timers.end()) {
        continue;  // cancelled
      }
      if (it->second.period.count() > 0) {
        heap.push(Timer{t.due + it->second.period, t.id});
        auto fn = it->second.fn;  // copy: the callback may cancel itself
        fn();
      } else {
        auto fn = std::move(it->second.fn);
        timers.erase(it);
        fn();
      }
    }
  }

  void dispatch(int fd, std::uint32_t epoll_events) {
    auto it = watchers.find(fd);
    if (it == watchers.end()) {
      return;  // unwatched by an earlier callback of this round
    }
    auto fn = it->second.fn;  // keeps the callback alive if it unwatches itself
    (*fn)(from_epoll(epoll_events));
  }
};

EventLoop::EventLoop(const Clock& clock) : impl_(std::make_unique<Impl>(clock)) {
  impl_->epoll_fd = ::epoll_create1(EPOLL_CLOEXEC);
  impl_->wake_fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (impl_->epoll_fd < 0 || impl_->wake_fd < 0) {
    // Without epoll nothing can work; this only happens when the process is out of fds.
    sf::log::get("net")->critical("event loop: epoll/eventfd failed: {}", std::strerror(errno));
    std::abort();
  }
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.fd = impl_->wake_fd;
  ::epoll_ctl(impl_->epoll_fd, EPOLL_CTL_ADD, impl_->wake_fd, &ev);
}

EventLoop::~EventLoop() {
  // Pending callbacks may own objects (connections) whose destructors cancel timers or unwatch
  // fds on this loop: destroy them while the loop is still whole.
  for (int round = 0; round < 8 && !(impl_->timers.empty() && impl_->posted.empty()); ++round) {
    auto timers = std::move(impl_->timers);
    impl_->timers.clear();
    std::vector<std::function<void()>> posted;
    {
      const std::lock_guard lock(impl_->mutex);
      posted.swap(impl_->posted);
    }
    timers.clear();
    posted.clear();
  }
  impl_->heap = {};
  auto watchers = std::move(impl_->watchers);
  impl_->watchers.clear();
  watchers.clear();
  ::close(impl_->wake_fd);
  ::close(impl_->epoll_fd);
}

void EventLoop::run() {
  impl_->loop_thread.store(std::this_thread::get_id());
  std::vector<epoll_event> events(64);
  while (!impl_->stopping.load()) {
    impl_->run_posted();
    if (impl_->stopping.load()) {
      break;
    }
    impl_->run_timers();
    if (impl_->stopping.load()) {
      break;
    }
    const int n =
        ::epoll_wait(impl_->epoll_fd, events.data(), static_cast<int>(events.size()), impl_->timeout_ms());
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      sf::log::get("net")->error("event loop: epoll_wait failed: {}", std::strerror(errno));
      break;
    }
    for (int i = 0; i < n && !impl_->stopping.load(); ++i) {
      const auto& ev = events[static_cast<std::size_t>(i)];
      if (ev.data.fd == impl_->wake_fd) {
        impl_->drain_wake();
      } else {
        impl_->dispatch(ev.data.fd, ev.events);
      }
    }
  }
  impl_->stopping.store(false);
}

void EventLoop::stop() {
  impl_->stopping.store(true);
  impl_->wake();
}

void EventLoop::post(std::function<void()> fn) {
  {
    const std::lock_guard lock(impl_->mutex);
    impl_->posted.push_back(std::move(fn));
  }
  impl_->wake();
}

bool EventLoop::in_loop_thread() const {
  return impl_->loop_thread.load() == std::this_thread::get_id();
}

const Clock& EventLoop::clock() const {
  return impl_->clock;
}

EventLoop::TimerId EventLoop::add_timer(std::chrono::nanoseconds delay, std::function<void()> fn) {
  const TimerId id = impl_->next_timer++;
  impl_->timers.emplace(id, Impl::TimerEntry{std::move(fn), std::chrono::nanoseconds{0}});
  impl_->heap.push(Impl::Timer{impl_->clock.now() + std::max(delay, std::chrono::nanoseconds{0}), id});
  return id;
}

EventLoop::TimerId EventLoop::add_periodic(std::chrono::nanoseconds period, std::function<void()> fn) {
  // A zero period would spin the loop; one millisecond is the epoll resolution anyway.
  period = std::max(period, std::chrono::nanoseconds{std::chrono::milliseconds{1}});
  const TimerId id = impl_->next_timer++;
  impl_->timers.emplace(id, Impl::TimerEntry{std::move(fn), period});
  impl_->heap.push(Impl::Timer{impl_->clock.now() + period, id});
  return id;
}

void EventLoop::cancel_timer(TimerId id) {
  // The heap entry stays until due and is skipped then; erasing the entry is what cancels.
  impl_->timers.erase(id);
  // Drop cancelled entries at the top so a far-future heap does not grow without bound.
  while (!impl_->heap.empty() && impl_->timers.count(impl_->heap.top().id) == 0) {
    impl_->heap.pop();
  }
}

void EventLoop::watch(int fd, unsigned events, std::function<void(unsigned)> fn) {
  epoll_event ev{};
  ev.events = to_epoll(events);
  ev.data.fd = fd;
  const bool known = impl_->watchers.count(fd) != 0;
  if (::epoll_ctl(impl_->epoll_fd, known ? EPOLL_CTL_MOD : EPOLL_CTL_ADD, fd, &ev) != 0) {
    sf::log::get("net")->error("event loop: watching fd {} failed: {}", fd, std::strerror(errno));
    return;
  }
  impl_->watchers[fd] = Impl::Watcher{std::make_shared<std::function<void(unsigned)>>(std::move(fn)), events};
}

void EventLoop::modify(int fd, unsigned events) {
  auto it = impl_->watchers.find(fd);
  if (it == impl_->watchers.end() || it->second.events == events) {
    return;
  }
  epoll_event ev{};
  ev.events = to_epoll(events);
  ev.data.fd = fd;
  if (::epoll_ctl(impl_->epoll_fd, EPOLL_CTL_MOD, fd, &ev) != 0) {
    sf::log::get("net")->error("event loop: modifying fd {} failed: {}", fd, std::strerror(errno));
    return;
  }
  it->second.events = events;
}

void EventLoop::unwatch(int fd) {
  if (impl_->watchers.erase(fd) != 0) {
    ::epoll_ctl(impl_->epoll_fd, EPOLL_CTL_DEL, fd, nullptr);
  }
}

LoopThread::LoopThread(const Clock& clock) : loop_(clock) {
  thread_ = std::thread([this] { loop_.run(); });
}

LoopThread::~LoopThread() {
  loop_.stop();
  if (thread_.joinable()) {
    thread_.join();
  }
}

void LoopThread::run_sync(const std::function<void()>& fn) {
  if (loop_.in_loop_thread() && thread_.get_id() == std::this_thread::get_id()) {
    fn();
    return;
  }
  std::promise<void> done;
  loop_.post([&] {
    fn();
    done.set_value();
  });
  done.get_future().wait();
}

}  // namespace sf::net
