// Machines and conveyors: their current state from the machine board, PackML commands through
// their OPC UA methods (OPC 30050 §6.3.6-8; the machine's model answers BadInvalidState for a
// command its state does not take).
#include <fmt/format.h>

#include "context.hpp"
#include "sf/core/log.hpp"
#include "sf/factory/machine_model.hpp"

namespace sf::dashboard {

namespace {

using web::Request;
using web::Response;

void refresh_connections(Context& c) {
  for (const auto& s : c.gateway.status().servers) {
    c.machines.set_connected(s.name, s.connected);
  }
}

Response command(Context& c, const Request& r, const Session& s) {
  const std::string& name = r.path_params.at("name");
  const std::string& text = r.path_params.at("command");
  if (!c.machines.contains(name)) {
    return web::error_response(404, fmt::format("no machine '{}'", name));
  }
  const auto cmd = factory::packml_command(text);
  if (!cmd) {
    return web::error_response(400,
                               fmt::format("'{}' is no PackML command (Start, Stop, Hold, Unhold, Suspend, "
                                           "Unsuspend, Reset, Abort, Clear)",
                                           text));
  }
  const auto address = c.machines.address(name);
  if (!address) {
    return web::error_response(503, fmt::format("machine '{}' has not been heard from", name));
  }
  auto done =
      c.gateway.call(address->first, address->second + "/" + factory::method_object_path(*cmd), text, {});
  if (!done) {
    return call_error(done.error(), fmt::format("machine '{}'", name));
  }
  log::get("dashboard")->info("{} ({}) sent {} to {}", s.user, to_string(s.role), text, name);
  return web::json_response({{"machine", name}, {"command", text}, {"result", "Good"}});
}

}  // namespace

Status add_machine_routes(web::Router& router, Context& c) {
  SF_TRY(router.add("GET", "/api/machines", guarded(c, Role::viewer, [&c](const Request&, const Session&) {
                      refresh_connections(c);
                      return web::json_response(c.machines.all());
                    })));
  SF_TRY(router.add(
      "GET", "/api/machines/{name}", guarded(c, Role::viewer, [&c](const Request& r, const Session&) {
        refresh_connections(c);
        auto m = c.machines.machine(r.path_params.at("name"), true);
        return m ? web::json_response(*m)
                 : web::error_response(404, fmt::format("no machine '{}'", r.path_params.at("name")));
      })));
  SF_TRY(router.add(
      "POST", "/api/machines/{name}/commands/{command}",
      guarded(c, Role::operator_, [&c](const Request& r, const Session& s) { return command(c, r, s); })));
  return {};
}

}  // namespace sf::dashboard
