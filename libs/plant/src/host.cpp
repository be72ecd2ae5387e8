// PlantHost (host.hpp): the plant's faces served to other processes.
#include "sf/plant/host.hpp"

#include <fmt/format.h>

#include "sf/core/log.hpp"
#include "sf/plant/control.hpp"

namespace sf::plant {

PlantHost::PlantHost(Plant& plant, Clock& clock, HostOptions options)
    : plant_(plant), clock_(clock), options_(std::move(options)) {}

PlantHost::~PlantHost() {
  stop();
}

Result<std::unique_ptr<PlantHost>> PlantHost::start(Plant& plant, Clock& clock, HostOptions options) {
  if (!options.real_time && dynamic_cast<ManualClock*>(&clock) == nullptr) {
    return make_error(Errc::invalid_argument, "a plant that runs as fast as it can needs a ManualClock");
  }
  std::unique_ptr<PlantHost> host(new PlantHost(plant, clock, std::move(options)));
  SF_TRY(host->serve_modbus());
  SF_TRY(host->serve_ethercat());
  auto control = ControlServer::start(plant, host->options_.control_host, host->options_.control_port);
  if (!control) {
    return control.error();
  }
  host->control_ = std::move(*control);
  host->endpoints_.push_back(
      {"plant", "control", fmt::format("{}:{}", host->options_.control_host, host->control_->port())});
  host->wall_start_ = std::chrono::steady_clock::now();
  host->sim_start_ = clock.now();
  host->thread_ = std::thread([h = host.get()] { h->loop(); });
  return host;
}

Status PlantHost::serve_modbus() {
  std::uint16_t index = 0;
  for (const auto& plc : plant_.plcs()) {
    const Layout& l = plant_.layout();
    std::uint16_t port = 0;
    if (const BeltSpec* belt = l.belt(plc->name())) {
      port = belt->plc.port;
    } else if (plc->name() == l.uploader.name) {
      port = l.uploader.plc.port;
    } else if (plc->name() == l.downloader.name) {
      port = l.downloader.plc.port;
    } else if (const RobotSpec* robot = l.robot(plc->name())) {
      port = robot->controller.port;
    }
    if (port == 0 && options_.modbus_port != 0) {
      port = static_cast<std::uint16_t>(options_.modbus_port + index);
    }
    ++index;
    modbus::ServerOptions server_options;
    server_options.host = options_.modbus_host;
    server_options.port = port;
    auto server = modbus::Server::listen(*plc, server_options);
    if (!server) {
      return server.error().with_context(fmt::format("Modbus server of {}", plc->name()));
    }
    SF_TRY((*server)->start());
    endpoints_.push_back({plc->name(), "modbus-tcp", (*server)->endpoint()});
    modbus_.push_back(std::move(*server));
  }
  return {};
}

namespace {

// The plant answers only frames that waited less than this in its socket (a wire never queues a
// frame; libs/ethercat/src/link/arrival.hpp): ten times a master's frame timeout (2 ms here and in
// SOEM), so no answer a master still waits for is dropped, and far below the time a master's 8-bit
// datagram index takes to wrap (256 frames: over 85 ms at its cycle and acyclic frames).
constexpr std::chrono::milliseconds kMaxFrameAge{20};

}  // namespace

Status PlantHost::serve_ethercat() {
  std::uint16_t index = 0;
  for (const auto& robot : plant_.smart_robots()) {
    std::unique_ptr<ethercat::Link> link;
    std::string protocol = "ethercat-udp";
    std::string address;
    if (auto it = options_.ecat_interfaces.find(robot->name()); it != options_.ecat_interfaces.end()) {
      auto raw = ethercat::RawSocketLink::open(it->second, {.max_queue_age = kMaxFrameAge});
      if (!raw) {
        return raw.error().with_context(fmt::format("EtherCAT segment of {}", robot->name()));
      }
      protocol = "ethercat-raw";
      address = it->second;
      link = std::move(*raw);
    } else {
      const auto port =
          options_.ecat_port == 0 ? std::uint16_t{0} : static_cast<std::uint16_t>(options_.ecat_port + index);
      auto udp = ethercat::UdpLink::listen(options_.ecat_host, port, kMaxFrameAge);
      if (!udp) {
        return udp.error().with_context(fmt::format("EtherCAT segment of {}", robot->name()));
      }
      address = fmt::format("{}:{}", options_.ecat_host, (*udp)->local_port());
      link = std::move(*udp);
    }
    ++index;
    auto runner = std::make_unique<ethercat::slave::SegmentRunner>(robot->segment(), *link);
    SF_TRY(runner->start());
    endpoints_.push_back({robot->name(), protocol, address});
    links_.push_back(std::move(link));
    runners_.push_back(std::move(runner));
  }
  return {};
}

void PlantHost::loop() {
  auto* manual = dynamic_cast<ManualClock*>(&clock_);
  auto next = clock_.now();
  while (!stop_.load()) {
    if (options_.real_time) {
      next += kWorldStep;
      clock_.sleep_until(next);
    } else {
      manual->advance(kWorldStep);
    }
    auto lock = plant_.lock();
    plant_.advance_to(clock_.now());
  }
}

double PlantHost::pace() const {
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start_).count();
  const double sim = std::chrono::duration<double>(clock_.now() - sim_start_).count();
  return wall > 0.0 ? sim / wall : 0.0;
}

void PlantHost::stop() {
  stop_.store(true);
  if (thread_.joinable()) {
    thread_.join();
  }
  for (auto& runner : runners_) {
    runner->stop();
  }
  for (auto& server : modbus_) {
    server->stop();
  }
  control_.reset();
}

}  // namespace sf::plant
