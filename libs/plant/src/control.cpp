// The plant's control port (control.hpp).
#include "sf/plant/control.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sf/net/event_loop.hpp"
#include "sf/net/tcp.hpp"

namespace sf::plant {

namespace {

using nlohmann::json;

std::string failure(std::string_view message) {
  return json{{"ok", false}, {"error", message}}.dump();
}

Result<std::optional<std::chrono::nanoseconds>> seconds(const json& request, const char* key) {
  if (!request.contains(key)) {
    return std::optional<std::chrono::nanoseconds>{};
  }
  const auto& v = request[key];
  if (!v.is_number() || v.get<double>() < 0.0 || v.get<double>() > 1e7) {
    return make_error(Errc::invalid_argument, fmt::format("'{}' must be seconds (a number, 0..1e7)", key));
  }
  return std::optional{std::chrono::nanoseconds{static_cast<std::int64_t>(v.get<double>() * 1e9)}};
}

std::string fault_request(Plant& plant, const json& request, bool inject) {
  if (!request.contains("fault") || !request["fault"].is_string()) {
    return failure("'fault' must be a fault text such as \"jam:conveyor2\"");
  }
  auto fault = parse_fault(request["fault"].get<std::string>());
  if (!fault) {
    return failure(fault.error().message);
  }
  auto at = seconds(request, "at");
  auto duration = seconds(request, "for");
  if (!at || !duration) {
    return failure(!at ? at.error().message : duration.error().message);
  }
  auto lock = plant.lock();
  if (*at) {
    fault->at = plant.world().time() + **at;
  }
  fault->duration = *duration;
  auto status = inject ? plant.inject(*fault) : plant.clear(*fault);
  if (!status) {
    return failure(status.error().message);
  }
  return json{{"ok", true}}.dump();
}

std::string events_request(Plant& plant, const json& request) {
  std::uint64_t since = 0;
  if (request.contains("since")) {
    if (!request["since"].is_number_unsigned()) {
      return failure("'since' must be a non-negative integer");
    }
    since = request["since"].get<std::uint64_t>();
  }
  auto lock = plant.lock();
  json events = json::array();
  constexpr std::size_t kMaxEvents = 1000;  // one answer stays well under the line limit of a client
  const auto all = plant.world().events().since(since);
  const std::size_t n = std::min(all.size(), kMaxEvents);
  for (std::size_t i = 0; i < n; ++i) {
    events.push_back(to_json(all[i]));
  }
  const std::uint64_t first = plant.world().events().total() - plant.world().events().entries().size();
  return json{{"ok", true}, {"next", std::max(since, first) + n}, {"events", events}}.dump();
}

}  // namespace

std::string handle_control_request(Plant& plant, std::string_view line) {
  const json request = json::parse(line, nullptr, false);
  if (request.is_discarded() || !request.is_object()) {
    return failure("a request is one JSON object per line");
  }
  if (!request.contains("op") || !request["op"].is_string()) {
    return failure("'op' must be one of inject, clear, faults, snapshot, events");
  }
  const std::string op = request["op"].get<std::string>();
  if (op == "inject" || op == "clear") {
    return fault_request(plant, request, op == "inject");
  }
  if (op == "faults") {
    auto lock = plant.lock();
    json faults = json::array();
    for (const auto& f : plant.active_faults()) {
      faults.push_back(format(f));
    }
    return json{{"ok", true}, {"faults", faults}}.dump();
  }
  if (op == "snapshot") {
    auto lock = plant.lock();
    return json{{"ok", true}, {"snapshot", to_json(plant.snapshot())}}.dump();
  }
  if (op == "events") {
    return events_request(plant, request);
  }
  return failure(fmt::format("unknown op '{}' (known: inject, clear, faults, snapshot, events)", op));
}

struct ControlServer::Impl {
  Plant* plant = nullptr;
  net::LoopThread loop;
  std::unique_ptr<net::TcpListener> listener;
  std::set<std::shared_ptr<net::TcpConnection>> clients;

  void accept(std::shared_ptr<net::TcpConnection> c) {
    if (clients.size() >= kMaxClients) {
      const std::string busy = failure("too many control clients") + "\n";
      c->send(Bytes(busy.begin(), busy.end()));
      c->close();
      return;
    }
    clients.insert(c);
    auto buffer = std::make_shared<std::string>();
    std::weak_ptr<net::TcpConnection> weak = c;
    c->set_on_data([this, buffer, weak](ByteSpan bytes) {
      auto conn = weak.lock();
      if (!conn) {
        return;
      }
      buffer->append(reinterpret_cast<const char*>(bytes.data()), bytes.size());  // NOLINT
      std::size_t newline = 0;
      while ((newline = buffer->find('\n')) != std::string::npos) {
        std::string answer =
            handle_control_request(*plant, std::string_view(*buffer).substr(0, newline)) + "\n";
        buffer->erase(0, newline + 1);
        conn->send(Bytes(answer.begin(), answer.end()));
      }
      if (buffer->size() > kMaxLine) {
        const std::string answer = failure("request line too long") + "\n";
        conn->send(Bytes(answer.begin(), answer.end()));
        conn->close();
      }
    });
    c->set_on_close([this, weak](const Status&) {
      if (auto conn = weak.lock()) {
        clients.erase(conn);
      }
    });
  }
};

ControlServer::ControlServer(std::unique_ptr<Impl> impl, std::uint16_t port)
    : impl_(std::move(impl)), port_(port) {}

ControlServer::~ControlServer() {
  impl_->loop.run_sync([this] {
    impl_->listener.reset();
    for (const auto& c : impl_->clients) {
      c->abort();
    }
    impl_->clients.clear();
  });
}

Result<std::unique_ptr<ControlServer>> ControlServer::start(Plant& plant, const std::string& host,
                                                            std::uint16_t port) {
  auto impl = std::make_unique<Impl>();
  impl->plant = &plant;
  Impl* raw = impl.get();
  Result<std::unique_ptr<net::TcpListener>> listener = make_error(Errc::state, "not started");
  raw->loop.run_sync([&] {
    listener =
        net::TcpListener::listen(raw->loop.loop(), host, port,
                                 [raw](std::shared_ptr<net::TcpConnection> c) { raw->accept(std::move(c)); });
  });
  if (!listener) {
    return listener.error();
  }
  const std::uint16_t bound = (*listener)->port();
  raw->listener = std::move(*listener);
  return std::unique_ptr<ControlServer>(new ControlServer(std::move(impl), bound));
}

// --- client --------------------------------------------------------------------

Result<std::string> control_request(const std::string& host, std::uint16_t port, std::string_view request) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  if (::inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1) {
    return make_error(Errc::invalid_argument,
                      fmt::format("control: '{}' is not a numeric IPv4 address", host));
  }
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    return make_error(Errc::io, fmt::format("control: socket: {}", std::strerror(errno)));
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {  // NOLINT
    return make_error(Errc::io,
                      fmt::format("control: connect to {}:{}: {}", host, port, std::strerror(errno)));
  }
  std::string line = std::string(request) + "\n";
  if (::send(fd, line.data(), line.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(line.size())) {
    return make_error(Errc::io, fmt::format("control: send: {}", std::strerror(errno)));
  }
  std::string answer;
  char buf[4096];
  while (answer.find('\n') == std::string::npos) {
    pollfd pfd{fd, POLLIN, 0};
    if (::poll(&pfd, 1, 5000) <= 0) {
      return make_error(Errc::timeout, fmt::format("control: no answer from {}:{} within 5 s", host, port));
    }
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) {
      return make_error(Errc::io, fmt::format("control: {}:{} closed the connection", host, port));
    }
    answer.append(buf, static_cast<std::size_t>(n));
    if (answer.size() > 64 * 1024 * 1024) {
      return make_error(Errc::limit_exceeded, "control: answer too long");
    }
  }
  answer.resize(answer.find('\n'));
  return answer;
}

}  // namespace sf::plant
