// The legacy controllers of the line as Modbus devices (registers.hpp): each
// is the closed program of a real PLC or robot controller. A client reaches
// it through a modbus::Server (TCP) or a modbus::MemoryClient (same process);
// the plant runs its program once per world step with scan().
//
// Locking: scan() runs with the plant's world lock held and takes the
// device's mutex() itself (order: world, then device); the Modbus hooks
// never touch the world, so requests and scans never wait on each other in
// a cycle.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sf/line/registers.hpp"
#include "sf/modbus/device.hpp"
#include "sf/modbus/register_bank.hpp"
#include "sf/plant/world.hpp"

namespace sf::plant {

class PlcDevice : public modbus::Device {
 public:
  PlcDevice(std::string name, modbus::BankLayout layout);
  modbus::RegisterBank& bank() override { return bank_; }
  [[nodiscard]] const std::string& name() const { return name_; }
  // One program cycle of `dt` seconds: read the outputs the clients wrote,
  // act on the world, publish the inputs.
  void scan(World& world, double dt);
  [[nodiscard]] FaultCode fault_code() const { return fault_code_; }

 protected:
  virtual void run(World& world, double dt) = 0;
  modbus::RegisterBank bank_;
  FaultCode fault_code_ = FaultCode::none;

 private:
  std::string name_;
};

// The job handshake of registers.hpp: start → busy → done | fault.
class JobHandshake {
 public:
  enum class Phase { ready, busy, done, fault };
  // Reads start and fault_reset; true when a new job begins now.
  bool scan(const modbus::RegisterBank& bank);
  void finish() { phase_ = Phase::done; }
  void fail(FaultCode code) {
    phase_ = Phase::fault;
    code_ = code;
  }
  [[nodiscard]] Phase phase() const { return phase_; }
  [[nodiscard]] FaultCode code() const { return code_; }
  // ready, busy, done, fault at discrete inputs 0..3 (both job-driven maps).
  void publish(modbus::RegisterBank& bank) const;

 private:
  Phase phase_ = Phase::ready;
  FaultCode code_ = FaultCode::none;
  bool last_start_ = false;
  bool last_reset_ = false;
};

class ConveyorPlc final : public PlcDevice {
 public:
  ConveyorPlc(const World& world, std::size_t belt);

 private:
  void run(World& world, double dt) override;
  void publish(const World& world);
  std::size_t belt_;
  bool last_reset_ = false;
};

// The box uploader (puts an empty box of the requested type at its station)
// or the box downloader (takes the box there off the line and inspects it).
class TransferPlc final : public PlcDevice {
 public:
  enum class Role { upload, download };
  TransferPlc(const World& world, Role role);

 private:
  void run(World& world, double dt) override;
  void begin(World& world);
  void finish_job(World& world);
  void publish_inspection(const Inspection& inspection);
  [[nodiscard]] const TransferSpec& spec(const World& world) const;

  Role role_;
  StationRef station_;
  JobHandshake job_;
  double remaining_s_ = 0.0;
  double waited_s_ = 0.0;
  std::size_t box_type_ = 0;
  std::uint16_t jobs_done_ = 0;
};

// The closed controller of a legacy robot: a job (candy type, slot, station)
// runs as its own moves — over the dispenser, down, grip, up, over the slot,
// down, release, up, home — at the arm's tool speed.
class RobotControllerPlc final : public PlcDevice {
 public:
  RobotControllerPlc(World& world, std::size_t robot);

 private:
  struct Waypoint {
    motion::Vec3 at;
    enum class Action { none, grip, release, check_part } action = Action::none;
  };
  void run(World& world, double dt) override;
  void begin(World& world);
  void move(World& world, double dt);
  void arrive(World& world, const Waypoint& waypoint);
  void fail(World& world, FaultCode code, const std::string& why);
  void set_tool(World& world, const motion::Vec3& at);
  void publish(const World& world);
  [[nodiscard]] int dispenser_for(const World& world, std::size_t candy) const;

  std::size_t robot_;
  motion::Vec3 home_;
  JobHandshake job_;
  std::vector<Waypoint> plan_;
  std::size_t next_ = 0;
  double dwell_s_ = 0.0;
  std::vector<double> joints_;
  std::uint16_t jobs_done_ = 0;
};

}  // namespace sf::plant
