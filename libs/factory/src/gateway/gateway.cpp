// The gateway core (gateway.hpp): poll loop, link health, PackML unit, job
// queue. What differs per kind of machine is its DeviceLogic.
#include "sf/factory/gateway.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "device_logic.hpp"
#include "plc_io.hpp"

namespace sf::factory {

namespace {

using S = PackMLState;
using gateway::JobResult;

// The controller behind the machine: its PLC, or a legacy robot's controller.
const line::PlcSpec& device_of(const GatewayConfig& c, const line::Layout& layout) {
  switch (c.kind) {
    case GatewayKind::conveyor:
      return layout.belt(c.controller.machine)->plc;
    case GatewayKind::uploader:
      return layout.uploader.plc;
    case GatewayKind::downloader:
      return layout.downloader.plc;
    case GatewayKind::legacy_robot:
      break;
  }
  return layout.robot(c.controller.machine)->controller;
}

Identification identify(const GatewayConfig& c, const line::Layout& layout) {
  Identification id{c.controller.machine, std::string(to_string(c.kind)), {}, {}, c.controller.serial_number};
  if (c.kind == GatewayKind::legacy_robot) {  // the machine is the arm, not its controller
    id.manufacturer = layout.robot(c.controller.machine)->vendor;
    id.model = layout.robot(c.controller.machine)->model;
  } else {
    id.manufacturer = device_of(c, layout).vendor;
    id.model = device_of(c, layout).model;
  }
  return id;
}

std::unique_ptr<gateway::DeviceLogic> make_logic(const GatewayConfig& c, const line::Layout& layout) {
  const gateway::LogicContext context{c, layout};
  switch (c.kind) {
    case GatewayKind::conveyor:
      return gateway::make_conveyor(context);
    case GatewayKind::uploader:
    case GatewayKind::downloader:
      return gateway::make_transfer(context);
    case GatewayKind::legacy_robot:
      return gateway::make_legacy_robot(context);
  }
  return nullptr;
}

// States in which the device's own faults (a jam) abort the unit: where it
// would produce or is about to.
bool watches_faults(S s) {
  return s != S::Stopped && s != S::Stopping && s != S::Aborting && s != S::Aborted && s != S::Clearing &&
         s != S::Resetting;
}

}  // namespace

Gateway::Gateway(GatewayConfig config, line::Layout layout, modbus::Client& client, const Clock& clock)
    : config_(std::move(config)),
      layout_(std::move(layout)),
      clock_(&clock),
      identification_(identify(config_, layout_)),
      logic_(make_logic(config_, layout_)),
      io_(std::make_unique<gateway::PlcIo>(client, logic_->tag_prefix(), logic_->tags())),
      unit_(clock),
      auto_start_pending_(config_.controller.auto_start) {}

Gateway::~Gateway() = default;

std::vector<std::string> Gateway::operations() const {
  return logic_->operations();
}

std::vector<TransportSegment> Gateway::segments() const {
  if (config_.kind != GatewayKind::conveyor) {
    return {};
  }
  return conveyor_segments(layout_, *layout_.belt_index(config_.controller.machine));
}

// --- the Contract Net's side ------------------------------------------------

std::string_view Gateway::link_state() const {
  switch (link_) {
    case Link::up:
      return "up";
    case Link::stale:
      return "stale";
    case Link::lost:
      return "lost";
    case Link::unknown:
      break;
  }
  return "unknown";
}

std::optional<std::string> Gateway::unavailable() const {
  if (link_ != Link::up) {
    return link_error_;
  }
  if (unit_.state() != S::Execute) {
    return fmt::format("{} is in {}", config_.controller.machine, to_string(unit_.state()));
  }
  return std::nullopt;
}

std::optional<std::string> Gateway::refusal(const Operation& op) const {
  if (auto why = unavailable()) {
    return why;
  }
  const auto ops = operations();
  if (std::find(ops.begin(), ops.end(), op.type) == ops.end()) {
    return fmt::format("{} does not do '{}'", config_.controller.machine, op.type);
  }
  return std::nullopt;
}

std::chrono::nanoseconds Gateway::backlog() const {
  return jobs_.backlog();
}

ConveyorOffer Gateway::conveyor_offer() const {
  ConveyorOffer offer{unavailable(), backlog(), {}};
  if (!offer.unavailable) {
    offer.segments = segments();
  }
  return offer;
}

std::optional<Estimate> Gateway::estimate(const Operation& op, std::string* why_not) const {
  auto why = refusal(op);
  auto duration =
      why ? Result<std::chrono::nanoseconds>(make_error(Errc::state, *why)) : logic_->duration(op);
  if (!duration) {
    if (why_not != nullptr) {
      *why_not = duration.error().message;
    }
    return std::nullopt;
  }
  return Estimate{backlog(), *duration, jobs_.length()};
}

Status Gateway::submit(const std::string& job, const Operation& op) {
  std::string why;
  const auto e = estimate(op, &why);
  return jobs_.admit(config_.controller.machine, job, op, e, why);
}

Status Gateway::cancel(const std::string& job) {
  // A job in work ends at the next poll, once no step runs on the device.
  if (auto st = jobs_.cancel(job); !st) {
    return st.error().with_context(config_.controller.machine);
  }
  return {};
}

// --- operators --------------------------------------------------------------

Status Gateway::command(PackMLCommand command) {
  SF_TRY(unit_.command(command, operator_stop_reason(command)));
  auto_start_pending_ = false;  // an operator has taken over
  held_by_link_ = false;
  return {};
}

ControllerStatus Gateway::status() const {
  ControllerStatus s = jobs_.status(unit_);
  s.fault = link_ == Link::up ? logic_->fault_text(*io_) : link_error_;
  switch (link_) {
    case Link::up:
      s.tags = io_->tags(Tag::Quality::good, {});
      break;
    case Link::stale:
      s.tags = io_->tags(Tag::Quality::uncertain, "stale: " + link_error_);
      break;
    case Link::unknown:
    case Link::lost:
      s.tags = io_->tags(Tag::Quality::bad, link_error_);
      break;
  }
  return s;
}

// --- the poll loop ----------------------------------------------------------

Clock::time_point Gateway::poll(Clock::time_point now) {
  if (now < next_poll_) {
    return next_poll_;
  }
  const auto dt = last_poll_ ? now - *last_poll_ : std::chrono::nanoseconds{0};
  last_poll_ = now;
  read_device();
  if (link_ == Link::up) {
    auto_start();
    run_unit(dt);
    if (auto error = io_->take_write_error()) {
      link_failed(*error);
    }
  } else {
    run_offline();
  }
  flush_outcomes();
  // A poll that overran (a timeout) is not made up for: the next one is a period after it.
  const auto period = config_.modbus.poll_period;
  next_poll_ = (next_poll_ == Clock::time_point::min() ? now : next_poll_) + period;
  if (next_poll_ <= clock_->now()) {
    next_poll_ = clock_->now() + period;
  }
  return next_poll_;
}

void Gateway::read_device() {
  auto read = io_->read();
  if (!read) {
    link_failed(read.error());
    return;
  }
  const Link before = link_;
  link_ = Link::up;
  link_error_.clear();
  last_good_ = clock_->now();
  link_changed(before);
}

void Gateway::link_failed(const modbus::ClientError& error) {
  const Link before = link_;
  link_exception_ = error.code == Errc::remote;
  link_error_ =
      fmt::format("{} {}: {}", config_.controller.machine,
                  link_exception_ ? "answers with a Modbus exception" : "does not answer", error.describe());
  const bool fresh = io_->has_values() && clock_->now() - last_good_ < config_.modbus.stale_after;
  link_ = fresh ? Link::stale : Link::lost;
  link_changed(before);
}

// A lost device holds production; its return resumes it (only a hold of its own making).
void Gateway::link_changed(Link before) {
  if (link_ == Link::lost && before != Link::lost && unit_.state() == S::Execute) {
    (void)unit_.command(
        PackMLCommand::Hold,
        StopReason{link_exception_ ? kStopPlcException : kStopPlcUnreachable, link_error_, {}});
    held_by_link_ = true;
  }
  if (link_ == Link::up && before != Link::up && held_by_link_ && unit_.state() == S::Held) {
    held_by_link_ = false;
    (void)unit_.command(PackMLCommand::Unhold);
  }
}

void Gateway::auto_start() {
  if (auto_start_pending_ && unit_.advance_to_execute()) {
    auto_start_pending_ = false;
  }
}

void Gateway::run_unit(std::chrono::nanoseconds dt) {
  if (watches_faults(unit_.state())) {
    if (auto fault = logic_->standing_fault(*io_)) {
      unit_.fault(*fault);
    }
  }
  dt_ = dt;
  unit_.run(*this);
}

void Gateway::execute() {
  work(true, dt_);
}

bool Gateway::reset() {
  return logic_->reset(*io_);
}

bool Gateway::clear() {
  return true;
}

bool Gateway::wind_down() {
  work(false, dt_);
  if (!logic_->settled()) {
    return false;
  }
  logic_->halt(*io_);
  return true;
}

void Gateway::stopped() {
  drop_all("stopped");
}

void Gateway::abort() {
  logic_->halt(*io_);
  drop_all(aborted());
}

// Wait states: follow what still runs on the device, start nothing.
void Gateway::wait() {
  if (jobs_.current() != nullptr) {
    work(false, dt_);
  }
}

// Without the device, only the states that lead away from production can finish.
void Gateway::run_offline() {
  switch (unit_.state()) {
    case S::Stopping:
    case S::Aborting:
      drop_all(unit_.state() == S::Stopping ? "stopped" : aborted());
      (void)unit_.state_complete();
      return;
    case S::Holding:
    case S::Suspending:
    case S::Clearing:
    case S::Completing:
      (void)unit_.state_complete();
      return;
    default:
      return;
  }
}

std::string Gateway::aborted() const {
  const auto reason = unit_.status().stop_reason;
  return reason ? fmt::format("aborted ({})", reason->message) : "aborted";
}

void Gateway::work(bool go, std::chrono::nanoseconds dt) {
  if (jobs_.current() == nullptr) {
    if (!go || !jobs_.begin_next([this](const Operation& op) { return logic_->ready(op, *io_); })) {
      return;
    }
    logic_->begin(jobs_.current()->op);
    dt = std::chrono::nanoseconds{0};
  }
  QueuedJob& current = *jobs_.current();
  const bool proceed = go && !current.cancel;
  if (proceed) {
    current.active += dt;
    if (current.active > current.estimate + config_.controller.job_timeout) {
      logic_->halt(*io_);
      const auto late = std::chrono::duration<double>(current.active - current.estimate).count();
      return end_current(logic_->interrupted(fmt::format("timed out ({:.1f} s over its estimate)", late)));
    }
  }
  if (auto result = logic_->step(*io_, proceed)) {
    return end_current(std::move(*result));
  }
  if (current.cancel && logic_->settled()) {
    logic_->halt(*io_);
    end_current(logic_->interrupted("cancelled"));
  }
}

void Gateway::end_current(JobResult result) {
  unit_.count(result.ok);
  jobs_.finish(result.ok, std::move(result.detail), std::move(result.results));
  if (result.machine_fault) {
    unit_.fault(*result.machine_fault);
  }
}

void Gateway::drop_all(const std::string& why) {
  if (jobs_.current() != nullptr) {
    end_current(logic_->interrupted(why));
  }
  jobs_.drop_queued(why);
}

void Gateway::flush_outcomes() {
  // Callbacks may submit or cancel: they see a gateway whose state is complete.
  for (const auto& o : jobs_.take_outcomes()) {
    job_ended(o);
  }
}

Result<modbus::TcpClientOptions> tcp_options(const GatewaySetup& setup) {
  const GatewayConfig& c = setup.config;
  const std::uint16_t port = c.modbus.port != 0 ? c.modbus.port : device_of(c, setup.layout).port;
  if (port == 0) {
    return make_error(Errc::invalid_argument,
                      fmt::format("{}: no Modbus port: neither modbus.port nor the layout gives one",
                                  c.controller.machine));
  }
  modbus::TcpClientOptions o;
  o.host = c.modbus.host;
  o.port = port;
  o.unit_id = c.modbus.unit_id;
  o.response_timeout = c.modbus.timeout;
  return o;
}

}  // namespace sf::factory
