// What the machine and gateway processes share (controller_process.hpp).
#include "sf/factory/controller_process.hpp"

#include <fmt/format.h>

#include "sf/opcua/server/history.hpp"
#include "sf/opcua/server/nodeset.hpp"
#include "sf/opcua/server/security_setup.hpp"

namespace sf::factory {

Result<std::unique_ptr<opcua::server::Server>> settings_server(const ControllerSettings& settings,
                                                               Clock& clock, std::string& security) {
  opcua::server::ServerConfig config;
  config.transport.port = settings.opcua_port;
  if (!settings.opcua_host.empty()) {  // one interface of several (a host per protocol, paper §VII.A)
    config.transport.host = settings.opcua_host;
    config.advertised_host = settings.opcua_host;
  }
  config.identity.application_name = fmt::format("smartfactory {}", settings.machine);
  auto configured = opcua::server::configure_server_security(settings.opcua_security, false, config);
  if (!configured) {
    return Error(configured.error()).with_context("OPC UA security");
  }
  security = *configured;
  auto server = std::make_unique<opcua::server::Server>(std::move(config), clock);
  // The values of Historizing variables (historize()), kept so that a cloud that was away reads
  // back what it missed (HistoryRead). The server owns both the history and its address space.
  auto history = std::make_shared<opcua::server::MemoryHistory>(kHistoryDepth);
  server->with_address_space([&](opcua::server::AddressSpace& space) { history->attach(space); });
  server->set_history_database(history);
  return server;
}

Result<std::unique_ptr<ModelServer>> ModelServer::start(const ControllerSettings& settings,
                                                        ControllerThread& thread,
                                                        const Identification& identification, Clock& clock) {
  std::unique_ptr<ModelServer> m(new ModelServer());
  auto server = settings_server(settings, clock, m->security_);
  if (!server) {
    return server.error();
  }
  m->server_ = std::move(*server);
  m->host_name_ = settings.opcua_host;
  Status imported;
  m->server_->with_address_space([&](opcua::server::AddressSpace& space) {
    auto reports = opcua::server::import_nodeset_files(space, settings.opcua_nodesets);
    imported = reports ? Status{} : Status(reports.error());
  });
  if (!imported) {
    return imported.error();
  }
  auto host = MachineHost::attach(*m->server_, thread, identification);
  if (!host) {
    return host.error();
  }
  m->host_ = std::move(*host);
  SF_TRY(m->server_->start());
  return m;
}

ModelServer::~ModelServer() {
  host_.reset();
  if (server_) {
    server_->stop();
  }
}

std::string settings_endpoint(const std::string& opcua_host, std::uint16_t port) {
  return fmt::format("opc.tcp://{}:{}", opcua_host.empty() ? "localhost" : opcua_host, port);
}

std::string ModelServer::endpoint() const {
  return settings_endpoint(host_name_, server_->port());
}

Result<std::unique_ptr<HostedController>> HostedController::create(
    MachineController& controller, const ControllerSettings& settings, ControllerThreadOptions options,
    Clock& clock, std::function<void(std::function<void()>)> deliver) {
  std::unique_ptr<HostedController> h(new HostedController());
  h->clock_ = &clock;
  h->thread_ = std::make_unique<ControllerThread>(controller, clock, options);
  auto model = ModelServer::start(settings, *h->thread_, controller.identification(), clock);
  if (!model) {
    return Error(model.error()).with_context(fmt::format("the OPC UA server of {}", settings.machine));
  }
  h->model_ = std::move(*model);
  h->remote_ =
      std::make_unique<RemoteController>(*h->thread_, controller.identification(), std::move(deliver));
  return h;
}

HostedController::~HostedController() {
  if (thread_) {
    thread_->stop();
  }
  model_.reset();
}

void HostedController::run(dds::Executor& executor, negotiation::Agent& agent,
                           const std::function<bool()>& stop, Reports reports) {
  thread_->start();
  StatusReporter reporter(*clock_, std::move(reports.headline), std::move(reports.report), reports.interval);
  negotiation::run_agents(executor, *clock_, {&agent, &reporter}, stop);
  thread_->stop();
}

void StatusReporter::tick() {
  const auto now = clock_->now();
  std::string shown = headline_();
  if (now < next_ && shown == last_) {
    return;
  }
  last_ = std::move(shown);
  next_ = interval_.count() > 0 ? now + interval_ : Clock::time_point::max();
  if (report_) {
    report_();
  }
}

// Checked often enough to see a change of state soon after it happens.
std::optional<Clock::time_point> StatusReporter::next_deadline() const {
  return std::min(next_, clock_->now() + std::chrono::milliseconds{50});
}

}  // namespace sf::factory
