// `smartfactory opcua server|browse|read|write|call|subscribe`: our OPC UA server on a port, and
// a small command-line UA client (readable output or --json) for any OPC UA server. Security
// options: opcua_security.cpp; `opcua pki` and `opcua users`: opcua_pki.cpp, opcua_users.cpp.
// Everything here parses options and prints; the opcua module does the work.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "opcua_nodeset.hpp"
#include "opcua_security.hpp"
#include "opcua_values.hpp"
#include "sf/core/log.hpp"
#include "sf/examples/opcua_demo.hpp"
#include "sf/opcua/client/client.hpp"
#include "sf/opcua/server/ns0.hpp"
#include "sf/opcua/server/server.hpp"
#include "sf/opcua/value_text.hpp"

namespace sf::app {
namespace {

namespace ua = sf::opcua;
using nlohmann::json;
using namespace std::chrono_literals;

// --- server -------------------------------------------------------------------------

struct ServerOptions {
  std::string host = "0.0.0.0";
  std::uint16_t port = 4840;
  std::string advertised_host;
  bool demo_model = false;
  std::size_t bench_variables = 0;
  std::vector<std::string> nodesets;
  std::size_t max_sessions = 100;
  std::size_t max_channels_per_address = ua::ServerTransportConfig{}.max_channels_per_address;
  std::size_t max_subscriptions = 1000;
  std::size_t max_monitored_items = 100'000;
  double duration_s = 0;
  double status_interval_s = 10;
  ServerSecurityOptions security;
};

int run_server(const ServerOptions& o) {
  ua::server::ServerConfig config;
  config.transport.host = o.host;
  config.transport.port = o.port;
  config.advertised_host = o.advertised_host;
  config.sessions.max_sessions = o.max_sessions;
  // Each session needs its own secure channel.
  config.transport.max_channels = std::max(config.transport.max_channels, o.max_sessions);
  config.transport.max_channels_per_address = o.max_channels_per_address;
  config.subscriptions.max_subscriptions = o.max_subscriptions;
  config.subscriptions.max_monitored_items = o.max_monitored_items;
  auto security = apply_server_security(o.security, o.demo_model, config);
  if (!security) {
    std::cerr << "opcua server: " << security.error().message << "\n";
    return kExitFailure;
  }
  std::cerr << "opcua server: " << *security << "\n";
  ua::server::Server server(config);
  if (o.demo_model) {
    examples::DemoModelOptions demo;
    demo.bench_variables = o.bench_variables;
    if (auto st = examples::add_demo_model(server, demo); !st) {
      std::cerr << "opcua server: demo model: " << st.error().describe() << "\n";
      return kExitFailure;
    }
  }
  if (auto st = load_nodesets(server, o.nodesets); !st) {
    std::cerr << "opcua server: " << st.error().message << "\n";
    return kExitFailure;
  }
  if (auto st = server.start(); !st) {
    std::cerr << "opcua server: " << st.error().describe() << "\n";
    return kExitFailure;
  }
  install_stop_signals();
  // The first stdout line names the real port (useful with --port 0); scripts wait for it.
  std::printf("listening on %s\n", server.endpoint_url().c_str());
  std::fflush(stdout);
  const auto start = std::chrono::steady_clock::now();
  auto last_status = start;
  while (!stop_requested()) {
    std::this_thread::sleep_for(50ms);
    const auto now = std::chrono::steady_clock::now();
    if (o.duration_s > 0 && now - start >= std::chrono::duration<double>(o.duration_s)) {
      break;
    }
    if (o.status_interval_s > 0 && now - last_status >= std::chrono::duration<double>(o.status_interval_s)) {
      std::fprintf(stderr, "opcua server: %zu sessions, %zu subscriptions, %zu monitored items\n",
                   server.session_count(), server.subscription_count(), server.monitored_item_count());
      last_status = now;
    }
  }
  server.stop();
  std::fprintf(stderr, "opcua server: stopped\n");
  return kExitOk;
}

// --- client commands ----------------------------------------------------------------

struct ClientOptions {
  std::string url;
  bool json = false;
  double timeout_s = 10;
  ClientSecurityOptions security;
};

void add_client_options(CLI::App& cmd, ClientOptions& o) {
  cmd.add_option("url", o.url, "Server endpoint, e.g. opc.tcp://localhost:4840")->required();
  cmd.add_flag("--json", o.json, "Print JSON instead of text");
  cmd.add_option("--timeout", o.timeout_s, "Seconds to wait for each request")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  add_client_security_options(cmd, o.security);
}

// A connected client for one command; prints the error and returns nullptr on failure.
std::unique_ptr<ua::SyncClient> connect(const ClientOptions& o, const char* command) {
  ua::ClientConfig config;
  config.endpoint_url = o.url;
  config.session_name = fmt::format("smartfactory opcua {}", command);
  config.request_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(o.timeout_s * 1000));
  config.auto_reconnect = false;
  if (auto st = apply_client_security(o.security, config); !st) {
    std::cerr << "opcua " << command << ": " << st.error().message << "\n";
    return nullptr;
  }
  auto client = std::make_unique<ua::SyncClient>(config);
  if (auto st = client->connect(); !st) {
    std::cerr << "opcua " << command << ": cannot connect to " << o.url << ": " << st.error().message << "\n";
    if (const std::string hint = security_hint(o.security, st.error()); !hint.empty()) {
      std::cerr << "opcua " << command << ": " << hint << "\n";
    }
    return nullptr;
  }
  return client;
}

// Resolves "nsu=URI;..." against the server's NamespaceArray.
Result<ua::NodeId> resolve_node(ua::SyncClient& client, std::string_view text) {
  auto ref = ua::parse_node_ref(text);
  if (!ref) {
    return ref.error();
  }
  if (!ref->namespace_uri.empty()) {
    auto ns = client.namespace_index(ref->namespace_uri);
    if (!ns) {
      return make_error(Errc::not_found, fmt::format("the server has no namespace '{}'", ref->namespace_uri));
    }
    ref->node_id.namespace_index = *ns;
  }
  return ref->node_id;
}

int fail(const char* command, const Error& error) {
  std::cerr << "opcua " << command << ": " << error.message << "\n";
  return kExitFailure;
}

// --- browse

struct BrowseOptions : ClientOptions {
  std::string node = "i=85";
  unsigned depth = 1;
};

json reference_to_json(const ua::ReferenceDescription& r) {
  return json{{"nodeId", ua::to_string(r.node_id)},
              {"browseName", ua::to_string(r.browse_name)},
              {"displayName", r.display_name.text.str()},
              {"nodeClass", static_cast<int>(r.node_class)},
              {"typeDefinition", ua::to_string(r.type_definition)}};
}

void browse_tree(ua::SyncClient& client, const ua::NodeId& node, unsigned depth, unsigned indent, json* out,
                 bool text) {
  auto refs = client.browse_children(node);
  if (!refs) {
    if (text) {
      std::printf("%*s(%s)\n", static_cast<int>(indent * 2), "", refs.error().message.c_str());
    }
    return;
  }
  for (const auto& r : *refs) {
    json entry = reference_to_json(r);
    if (text) {
      std::printf("%*s%s  %s  [%s]\n", static_cast<int>(indent * 2), "", ua::to_string(r.browse_name).c_str(),
                  ua::to_string(r.node_id).c_str(), ua::to_string(r.node_class).c_str());
    }
    if (depth > 1 && r.node_id.server_index == 0) {
      json children = json::array();
      browse_tree(client, r.node_id.node_id, depth - 1, indent + 1, &children, text);
      entry["children"] = std::move(children);
    }
    if (out != nullptr) {
      out->push_back(std::move(entry));
    }
  }
}

int run_browse(const BrowseOptions& o) {
  auto client = connect(o, "browse");
  if (!client) {
    return kExitFailure;
  }
  auto node = resolve_node(*client, o.node);
  if (!node) {
    return fail("browse", node.error());
  }
  json out = json::array();
  browse_tree(*client, *node, o.depth, 0, o.json ? &out : nullptr, !o.json);
  if (o.json) {
    std::cout << out.dump() << "\n";
  }
  client->disconnect();
  return kExitOk;
}

// --- read

struct ReadOptions : ClientOptions {
  std::vector<std::string> nodes;
};

int run_read(const ReadOptions& o) {
  auto client = connect(o, "read");
  if (!client) {
    return kExitFailure;
  }
  std::vector<ua::ReadValueId> items;
  for (const auto& text : o.nodes) {
    auto node = resolve_node(*client, text);
    if (!node) {
      return fail("read", node.error());
    }
    items.push_back(ua::value_of(*node));
  }
  auto values = client->read(items);
  if (!values) {
    return fail("read", values.error());
  }
  json out = json::array();
  bool all_good = true;
  for (std::size_t i = 0; i < values->size(); ++i) {
    const auto& dv = (*values)[i];
    all_good = all_good && !dv.status.is_bad();
    if (o.json) {
      json entry = data_value_to_json(dv);
      entry["nodeId"] = ua::to_string(items[i].node_id);
      out.push_back(std::move(entry));
    } else {
      std::printf("%s = %s  (%s, %s)\n", ua::to_string(items[i].node_id).c_str(),
                  ua::to_string(dv.value).c_str(), std::string(ua::to_string(dv.value.type())).c_str(),
                  ua::to_string(dv.status).c_str());
    }
  }
  if (o.json) {
    std::cout << out.dump() << "\n";
  }
  client->disconnect();
  return all_good ? kExitOk : kExitFailure;
}

// --- write

struct WriteOptions : ClientOptions {
  std::string node;
  std::string value;
};

int run_write(const WriteOptions& o) {
  auto client = connect(o, "write");
  if (!client) {
    return kExitFailure;
  }
  auto node = resolve_node(*client, o.node);
  if (!node) {
    return fail("write", node.error());
  }
  // Without TYPE:VALUE the value takes the node's DataType (read first).
  ua::ReadValueId data_type_item = ua::value_of(*node);
  data_type_item.attribute_id = ua::attribute_id::DataType;
  auto data_type = client->read({data_type_item});
  ua::BuiltinType type = ua::BuiltinType::Null;
  if (data_type && !data_type->empty()) {
    if (const auto* id = (*data_type)[0].value.get_if<ua::NodeId>()) {
      type = ua::server::builtin_type_of(*id);
    }
  }
  auto value = ua::parse_typed_variant(o.value, type);
  if (!value) {
    return fail("write", value.error());
  }
  ua::WriteValue item;
  item.node_id = *node;
  item.attribute_id = ua::attribute_id::Value;
  item.value = ua::DataValue(*value);
  auto results = client->write({item});
  if (!results) {
    return fail("write", results.error());
  }
  const ua::StatusCode status =
      results->empty() ? ua::StatusCode(ua::status::BadUnexpectedError) : (*results)[0];
  if (o.json) {
    std::cout << json{{"nodeId", ua::to_string(*node)}, {"status", ua::to_string(status)}}.dump() << "\n";
  } else {
    std::printf("%s ← %s: %s\n", ua::to_string(*node).c_str(), ua::to_string(*value).c_str(),
                ua::to_string(status).c_str());
  }
  client->disconnect();
  return status.is_bad() ? kExitFailure : kExitOk;
}

// --- call

struct CallOptions : ClientOptions {
  std::string object;
  std::string method;
  std::vector<std::string> args;
};

// The built-in types of a method's InputArguments (OPC 10000-3 §5.7), to type bare arguments.
std::vector<ua::BuiltinType> input_argument_types(ua::SyncClient& client, const ua::NodeId& method) {
  std::vector<ua::BuiltinType> types;
  auto refs = client.browse_children(method);
  if (!refs) {
    return types;
  }
  for (const auto& r : *refs) {
    if (r.browse_name.name != "InputArguments") {
      continue;
    }
    auto value = client.read_value(r.node_id.node_id);
    const auto* args = value ? value->value.array_if<ua::ExtensionObject>() : nullptr;
    if (args == nullptr) {
      return types;
    }
    for (const auto& arg : *args) {
      const auto* a = arg.get_if<ua::Argument>();
      types.push_back(a != nullptr ? ua::server::builtin_type_of(a->data_type) : ua::BuiltinType::Null);
    }
  }
  return types;
}

int run_call(const CallOptions& o) {
  auto client = connect(o, "call");
  if (!client) {
    return kExitFailure;
  }
  auto object = resolve_node(*client, o.object);
  auto method = object ? resolve_node(*client, o.method) : object;
  if (!object || !method) {
    return fail("call", object ? method.error() : object.error());
  }
  const auto types = input_argument_types(*client, *method);
  std::vector<ua::Variant> inputs;
  for (std::size_t i = 0; i < o.args.size(); ++i) {
    auto value = ua::parse_typed_variant(o.args[i], i < types.size() ? types[i] : ua::BuiltinType::Null);
    if (!value) {
      return fail("call", value.error());
    }
    inputs.push_back(std::move(*value));
  }
  auto outputs = client->call_method(*object, *method, inputs);
  if (!outputs) {
    return fail("call", outputs.error());
  }
  if (o.json) {
    json out = json::array();
    for (const auto& v : *outputs) {
      out.push_back(variant_to_json(v));
    }
    std::cout << json{{"status", "Good"}, {"outputs", out}}.dump() << "\n";
  } else {
    for (const auto& v : *outputs) {
      std::printf("%s\n", ua::to_string(v).c_str());
    }
  }
  client->disconnect();
  return kExitOk;
}

// --- subscribe

struct SubscribeOptions : ClientOptions {
  std::vector<std::string> nodes;
  double interval_ms = 100;
  std::size_t count = 0;
  double duration_s = 0;
};

int run_subscribe(const SubscribeOptions& o) {
  auto client = connect(o, "subscribe");
  if (!client) {
    return kExitFailure;
  }
  ua::Client::SubscriptionParams params;
  params.publishing_interval_ms = o.interval_ms;
  auto subscription = client->create_subscription(params);
  if (!subscription) {
    return fail("subscribe", subscription.error());
  }
  std::mutex mutex;
  std::size_t received = 0;
  for (const auto& text : o.nodes) {
    auto node = resolve_node(*client, text);
    if (!node) {
      return fail("subscribe", node.error());
    }
    ua::MonitoringParameters parameters;
    parameters.sampling_interval = o.interval_ms;
    parameters.queue_size = 10;
    parameters.discard_oldest = true;
    const std::string name = ua::to_string(*node);
    auto handle = client->monitor_value(*subscription, ua::value_of(*node), parameters,
                                        [&, name, json_out = o.json](const ua::DataValue& dv) {
                                          std::lock_guard lock(mutex);
                                          ++received;
                                          if (json_out) {
                                            json entry = data_value_to_json(dv);
                                            entry["nodeId"] = name;
                                            std::cout << entry.dump() << std::endl;
                                          } else {
                                            std::cout << ua::to_string(dv.source_timestamp) << "  " << name
                                                      << " = " << ua::to_string(dv.value) << "  "
                                                      << ua::to_string(dv.status) << std::endl;
                                          }
                                        });
    if (!handle) {
      return fail("subscribe", handle.error());
    }
  }
  install_stop_signals();
  const auto start = std::chrono::steady_clock::now();
  while (!stop_requested()) {
    std::this_thread::sleep_for(20ms);
    {
      std::lock_guard lock(mutex);
      if (o.count > 0 && received >= o.count) {
        break;
      }
    }
    if (o.duration_s > 0 &&
        std::chrono::steady_clock::now() - start >= std::chrono::duration<double>(o.duration_s)) {
      break;
    }
  }
  client->disconnect();
  return kExitOk;
}

}  // namespace

void register_opcua(CLI::App& app, CommandResult& result) {
  auto* group = app.add_subcommand("opcua", "OPC UA machine-to-cloud: our server, and a command-line client");
  group->require_subcommand(1);
  group->footer(
      "Try it on one machine:\n"
      "  smartfactory opcua server --port 4840 --demo-model &\n"
      "  smartfactory opcua browse opc.tcp://localhost:4840 --node 'nsu=urn:smartfactory:demo;s=Demo'\n"
      "  smartfactory opcua call opc.tcp://localhost:4840 'nsu=urn:smartfactory:demo;s=Demo' "
      "'nsu=urn:smartfactory:demo;s=Demo.Multiply' 6 7\n"
      "Node ids: i=85, ns=2;s=Demo.Counter, or nsu=URI;s=... (namespace by URI).\n"
      "Security: server and clients of one machine share the PKI folder (--pki) and trust each other;\n"
      "other peers are refused until trusted (`opcua pki`). Users: `opcua users add`, `server --users`.");

  auto server = std::make_shared<ServerOptions>();
  auto* server_cmd = group->add_subcommand(
      "server", "Run an OPC UA server (UA-TCP, signed and encrypted by default) until signalled");
  server_cmd->add_option("--host", server->host, "Address to listen on")->capture_default_str();
  server_cmd
      ->add_option("--port", server->port, "TCP port (0 = any free port; the first line printed names it)")
      ->capture_default_str();
  server_cmd->add_option(
      "--advertised-host", server->advertised_host,
      "Host name in the endpoint URLs the server advertises (default: this machine's name)");
  server_cmd->add_flag("--demo-model", server->demo_model,
                       "Add the demo model: Objects/Demo with Temperature, Counter and Multiply(a, b)");
  server_cmd
      ->add_option("--bench-variables", server->bench_variables,
                   "With --demo-model, for benchmarks: N more Double variables ns=<demo>;s=Demo.Bench.0 .. "
                   "Demo.Bench.<N-1>, all changing every 100 ms")
      ->needs("--demo-model")
      ->capture_default_str();
  server_cmd->add_option("--nodeset", server->nodesets,
                         "Load a NodeSet2 XML file (repeatable, in order; check one with `opcua nodeset`)");
  server_cmd
      ->add_option("--max-sessions", server->max_sessions,
                   "Sessions the server holds at most (and secure channels, at least 100)")
      ->capture_default_str();
  server_cmd
      ->add_option("--max-channels-per-address", server->max_channels_per_address,
                   "Secure channels one client address may hold (0 = no limit of its own); idle ones give "
                   "way to new connections")
      ->capture_default_str();
  server_cmd->add_option("--max-subscriptions", server->max_subscriptions, "Subscriptions over all sessions")
      ->capture_default_str();
  server_cmd
      ->add_option("--max-monitored-items", server->max_monitored_items, "Monitored items over all sessions")
      ->capture_default_str();
  server_cmd
      ->add_option("--duration", server->duration_s, "Stop after this many seconds (0 = until signalled)")
      ->capture_default_str();
  server_cmd
      ->add_option("--status-interval", server->status_interval_s,
                   "Seconds between status lines on stderr (0 = none)")
      ->capture_default_str();
  add_server_security_options(*server_cmd, server->security);
  server_cmd->callback([server, &result] { result.exit_code = run_server(*server); });

  auto browse = std::make_shared<BrowseOptions>();
  auto* browse_cmd = group->add_subcommand("browse", "List the children of a node (hierarchical references)");
  add_client_options(*browse_cmd, *browse);
  browse_cmd->add_option("--node", browse->node, "Node to start from")->capture_default_str();
  browse_cmd->add_option("--depth", browse->depth, "Levels to descend")
      ->check(CLI::Range(1U, 16U))
      ->capture_default_str();
  browse_cmd->callback([browse, &result] { result.exit_code = run_browse(*browse); });

  auto read = std::make_shared<ReadOptions>();
  auto* read_cmd = group->add_subcommand("read", "Read the Value attribute of nodes");
  add_client_options(*read_cmd, *read);
  read_cmd->add_option("nodes", read->nodes, "Node ids")->required();
  read_cmd->callback([read, &result] { result.exit_code = run_read(*read); });

  auto write = std::make_shared<WriteOptions>();
  auto* write_cmd = group->add_subcommand("write", "Write the Value attribute of a node");
  add_client_options(*write_cmd, *write);
  write_cmd->add_option("node", write->node, "Node id")->required();
  write_cmd
      ->add_option("value", write->value,
                   "Value in the node's DataType (read first), or TYPE:VALUE, e.g. Int32:5, "
                   "Double:[1.5,2]")
      ->required();
  write_cmd->callback([write, &result] { result.exit_code = run_write(*write); });

  auto call = std::make_shared<CallOptions>();
  auto* call_cmd = group->add_subcommand("call", "Call a method; arguments typed by its InputArguments");
  add_client_options(*call_cmd, *call);
  call_cmd->add_option("object", call->object, "Object (or ObjectType) the method belongs to")->required();
  call_cmd->add_option("method", call->method, "Method node id")->required();
  call_cmd->add_option("args", call->args, "Input arguments (VALUE or TYPE:VALUE)");
  call_cmd->callback([call, &result] { result.exit_code = run_call(*call); });

  auto subscribe = std::make_shared<SubscribeOptions>();
  auto* subscribe_cmd = group->add_subcommand("subscribe", "Print data changes of nodes as they arrive");
  add_client_options(*subscribe_cmd, *subscribe);
  subscribe_cmd->add_option("nodes", subscribe->nodes, "Node ids")->required();
  subscribe_cmd->add_option("--interval", subscribe->interval_ms, "Publishing and sampling interval in ms")
      ->capture_default_str();
  subscribe_cmd->add_option("--count", subscribe->count, "Stop after this many changes (0 = no limit)")
      ->capture_default_str();
  subscribe_cmd
      ->add_option("--duration", subscribe->duration_s, "Stop after this many seconds (0 = no limit)")
      ->capture_default_str();
  subscribe_cmd->callback([subscribe, &result] { result.exit_code = run_subscribe(*subscribe); });

  register_opcua_nodeset(*group, result);
  register_opcua_pki(*group, result);
  register_opcua_users(*group, result);
}

}  // namespace sf::app
