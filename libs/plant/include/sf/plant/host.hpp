// PlantHost: serves a Plant's hardware faces to other processes and runs its
// physics in real (or scaled, or unbounded) time:
//   - one Modbus TCP server per legacy controller;
//   - one EtherCAT segment per smart robot, on EtherCAT-in-UDP (loopback,
//     no root) or on a raw-socket interface (a veth in a namespace, a NIC);
//   - the physics loop: every kWorldStep of the clock, advance the plant;
//   - a control port (control.hpp) for faults and snapshots.
// Everything runs on threads of its own; stop() (or the destructor) ends them.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "sf/core/clock.hpp"
#include "sf/core/result.hpp"
#include "sf/ethercat/link.hpp"
#include "sf/ethercat/slave/segment.hpp"
#include "sf/modbus/server.hpp"
#include "sf/plant/plant.hpp"

namespace sf::plant {

class ControlServer;

struct HostOptions {
  // Modbus: every PLC listens on modbus_host; the layout's `plc.port` when
  // set, else modbus_port + its index when modbus_port != 0, else a free port.
  std::string modbus_host = "127.0.0.1";
  std::uint16_t modbus_port = 0;
  // EtherCAT per smart robot: an interface name in ecat_interfaces (raw
  // socket), else UDP on ecat_host, port ecat_port + its index (0 = free ports).
  std::map<std::string, std::string> ecat_interfaces;
  std::string ecat_host = "127.0.0.1";
  std::uint16_t ecat_port = ethercat::UdpLink::kPort;
  // Control port for `plant faults` and snapshots (0 = a free port).
  std::string control_host = "127.0.0.1";
  std::uint16_t control_port = 0;
  // false: the loop advances a ManualClock as fast as it can (--speed max).
  bool real_time = true;
};

struct Endpoint {
  std::string machine;   // "conveyor1", "scara1", "plant"
  std::string protocol;  // "modbus-tcp", "ethercat-udp", "ethercat-raw", "control"
  std::string address;   // "127.0.0.1:1502", "veth1"
};

class PlantHost {
 public:
  // `clock` is the plant's; with real_time = false it must be a ManualClock.
  static Result<std::unique_ptr<PlantHost>> start(Plant& plant, Clock& clock, HostOptions options);
  ~PlantHost();
  PlantHost(const PlantHost&) = delete;
  PlantHost& operator=(const PlantHost&) = delete;

  [[nodiscard]] const std::vector<Endpoint>& endpoints() const { return endpoints_; }
  void stop();
  // Simulated seconds per wall second since start (the loop's pace).
  [[nodiscard]] double pace() const;

 private:
  PlantHost(Plant& plant, Clock& clock, HostOptions options);
  Status serve_modbus();
  Status serve_ethercat();
  void loop();

  Plant& plant_;
  Clock& clock_;
  HostOptions options_;
  std::vector<Endpoint> endpoints_;
  std::vector<std::unique_ptr<modbus::Server>> modbus_;
  std::vector<std::unique_ptr<ethercat::Link>> links_;
  std::vector<std::unique_ptr<ethercat::slave::SegmentRunner>> runners_;
  std::unique_ptr<ControlServer> control_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::chrono::steady_clock::time_point wall_start_;
  Clock::time_point sim_start_;
};

}  // namespace sf::plant
