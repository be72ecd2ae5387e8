// The dashboard's REST API over real peers: an order service and a PackML machine on their own
// OPC UA servers (in this process), the cloud gateway with a SQLite historian and the knowledge
// loop between them and the API, and HTTP requests over loopback. Every route, its roles and
// its bad input; the routes against libs/dashboard/openapi.yaml.
#include <unistd.h>

#include <atomic>
#include <set>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "sf/cloud/gateway.hpp"
#include "sf/dashboard/dashboard.hpp"
#include "sf/dashboard/machine_board.hpp"
#include "sf/factory/controller_thread.hpp"
#include "sf/factory/machine_host.hpp"
#include "sf/factory/order_service.hpp"
#include "sf/factory/testing/packml_machine.hpp"
#include "sf/opcua/security/users.hpp"
#include "sf/opcua/server/server.hpp"
#include "sf/testing/temp_dir.hpp"
#include "sf/web/testing/client.hpp"
#include "sf/web/testing/tls_files.hpp"

namespace sf::dashboard {
namespace {

namespace ua = sf::opcua;
namespace http = boost::beast::http;
using namespace std::chrono_literals;
using nlohmann::json;

// Polls until pred holds (30 s at most: a failure, not a timing measurement).
template <typename Pred>
bool eventually(Pred pred) {
  const auto until = std::chrono::steady_clock::now() + 30s;
  while (!pred()) {
    if (std::chrono::steady_clock::now() > until) {
      return false;
    }
    std::this_thread::sleep_for(20ms);
  }
  return true;
}

struct Reply {
  int status = 0;
  json body;
  web::testing::HttpResponse raw;
};

// One user's session against the API: its cookie and CSRF token.
class User {
 public:
  explicit User(std::uint16_t port) : port_(port) {}
  Reply login(const std::string& name, const std::string& password = "secret") {
    auto r = request(http::verb::post, "/api/session", json{{"user", name}, {"password", password}}.dump());
    if (r.status == 200) {
      const std::string set_cookie(r.raw[http::field::set_cookie]);
      cookie_ = set_cookie.substr(0, set_cookie.find(';'));
      csrf_ = r.body.at("csrf");
    }
    return r;
  }
  Reply get(const std::string& target) { return request(http::verb::get, target); }
  Reply post(const std::string& target, const std::string& body = {}) {
    return request(http::verb::post, target, body);
  }
  Reply del(const std::string& target) { return request(http::verb::delete_, target); }
  Reply request(http::verb method, const std::string& target, const std::string& body = {},
                bool with_csrf = true) {
    web::testing::HeaderList headers;
    if (!cookie_.empty()) {
      headers.emplace_back("Cookie", cookie_);
      if (with_csrf) {
        headers.emplace_back("X-CSRF-Token", csrf_);
      }
    }
    Reply r;
    r.raw = web::testing::http_request(port_, method, target, body, "application/json", headers);
    r.status = static_cast<int>(r.raw.result_int());
    r.body = json::parse(r.raw.body(), nullptr, false);
    return r;
  }
  [[nodiscard]] const std::string& cookie() const { return cookie_; }

 private:
  std::uint16_t port_;
  std::string cookie_;
  std::string csrf_;
};

// The peers and the dashboard, once for the suite (starting them is the slow part).
struct Rig {
  testing::TempDir dir;
  std::unique_ptr<factory::OrderServiceProcess> orders;
  std::atomic<bool> stop{false};
  std::thread orders_loop;
  factory::testing::PackMLMachine machine{SteadyClock::instance(),
                                          factory::testing::PackMLMachine::default_identification(), 200ms};
  factory::ControllerThread thread{machine, SteadyClock::instance(), [] {
                                     factory::ControllerThreadOptions o;
                                     o.realtime = false;
                                     o.status_interval = 2ms;
                                     return o;
                                   }()};
  std::unique_ptr<ua::server::Server> machine_server;
  std::unique_ptr<factory::MachineHost> host;
  line::Layout layout = *line::default_layout();
  std::unique_ptr<cloud::Gateway> gateway;
  std::unique_ptr<Dashboard> dashboard;
  std::uint16_t port = 0;

  void start() {
    write_users();
    auto setup = factory::parse_order_service_config(
        fmt::format("opcua: {{port: 0, modes: none, anonymous: operator}}\nwip: 1\n"
                    "dds: {{interface: lo, partition: dashboard-test-{}}}\n",
                    getpid()));
    ASSERT_TRUE(setup) << setup.error().describe();
    auto p = factory::OrderServiceProcess::create(std::move(*setup), SteadyClock::instance());
    ASSERT_TRUE(p) << p.error().describe();
    orders = std::move(*p);
    orders_loop =
        std::thread([this] { orders->run([this] { return stop.load(); }, nullptr, nullptr, 50ms); });

    ua::server::ServerConfig sc;
    sc.transport.host = "127.0.0.1";
    sc.transport.port = 0;
    sc.advertised_host = "127.0.0.1";
    sc.security.anonymous_role = "operator";
    machine_server = std::make_unique<ua::server::Server>(sc);
    factory::MachineHostOptions ho;
    ho.publish_interval = 5ms;
    auto attached = factory::MachineHost::attach(*machine_server, thread, machine.identification(), ho);
    ASSERT_TRUE(attached) << attached.error().describe();
    host = std::move(*attached);
    ASSERT_TRUE(machine_server->start().ok());
    thread.start();

    cloud::GatewayConfig gc;
    gc.historian.url = "sqlite:" + (dir.path() / "history.db").string();
    gc.historian.buffer = dir.path() / "buffer";
    gc.historian.flush_interval = 20ms;
    cloud::ServerConfig os;
    os.name = "orders";
    os.url = orders->opcua_endpoint();
    os.events = true;
    os.security.security = "none";
    os.publishing_interval_ms = 20;
    os.sampling_interval_ms = 20;
    os.subscribe = {{"/Objects/OrderService", "", "", 1}};
    gc.servers.push_back(os);
    cloud::ServerConfig ms = os;
    ms.name = "scara";
    ms.url = machine_server->endpoint_url();
    ms.events = false;
    ms.subscribe = {{"/Objects/Machines/ScaraRobot1", "", "", 3}};
    gc.servers.push_back(ms);
    gc.knowledge = cloud::KnowledgeConfig{};
    auto g = cloud::Gateway::create(gc);
    ASSERT_TRUE(g) << g.error().describe();
    gateway = std::move(*g);
    ASSERT_TRUE(gateway->start().ok());
    ASSERT_TRUE(eventually([&] {
      const auto s = gateway->status();
      return s.servers.size() == 2 && s.servers[0].phase == "subscribed" &&
             s.servers[1].phase == "subscribed";
    }));

    DashboardConfig dc;
    dc.users = dir.path() / "users.yaml";
    dc.orders_burst = 3;
    dc.order_period = 60s;
    auto d = Dashboard::create(*gateway, layout, dc);
    ASSERT_TRUE(d) << d.error().describe();
    dashboard = std::move(*d);
    auto listening = dashboard->start();
    ASSERT_TRUE(listening) << listening.error().describe();
    port = *listening;
  }

  void write_users() const {
    ua::security::UserDatabase users;
    const ua::security::PasswordHashParams cheap{10, 8, 1};  // fast enough for a test's logins
    auto hash = ua::security::hash_password("secret", cheap);
    ASSERT_TRUE(hash);
    for (const auto& [name, role] :
         std::vector<std::pair<std::string, std::string>>{{"alice", "consumer"},
                                                          {"bob", "consumer"},
                                                          {"carol", "consumer"},
                                                          {"dave", "consumer"},
                                                          {"victor", "viewer"},
                                                          {"olga", "operator"},
                                                          {"plc", "engineer-only"}}) {
      ua::security::User u{name, *hash, {}, {role == "engineer-only" ? "" : role}};
      if (role == "engineer-only") {
        u.roles = {};  // a user without any web role
      }
      ASSERT_TRUE(users.put(u)) << name;
    }
    ASSERT_TRUE(users.save(dir.path() / "users.yaml"));
  }

  ~Rig() {
    if (dashboard) {
      dashboard->stop();
    }
    if (gateway) {
      gateway->stop();
    }
    host.reset();
    thread.stop();
    if (machine_server) {
      machine_server->stop();
    }
    stop = true;
    if (orders_loop.joinable()) {
      orders_loop.join();
    }
  }
};

class DashboardApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    rig = new Rig();  // NOLINT: the suite's, deleted in TearDownTestSuite
    rig->start();
  }
  static void TearDownTestSuite() {
    delete rig;
    rig = nullptr;
  }
  void SetUp() override {
    ASSERT_NE(rig, nullptr);
    ASSERT_NE(rig->port, 0) << "the rig did not start";
  }
  static User as(const std::string& name) {
    User u(rig->port);
    EXPECT_EQ(u.login(name).status, 200) << name;
    return u;
  }
  static User anonymous() { return User(rig->port); }

  static Rig* rig;
};
Rig* DashboardApi::rig = nullptr;

TEST_F(DashboardApi, SessionsLogInCarryACsrfTokenAndLogOut) {
  User u(rig->port);
  EXPECT_EQ(u.login("alice", "wrong").status, 401);
  EXPECT_EQ(u.login("nobody").status, 401);
  EXPECT_EQ(u.login("plc").status, 403);  // a user of the OPC UA servers without a web role
  EXPECT_EQ(u.request(http::verb::post, "/api/session", "{not json").status, 400);
  EXPECT_EQ(u.request(http::verb::post, "/api/session", R"({"user": "alice"})").status, 400);
  EXPECT_EQ(u.get("/api/session").status, 401);

  auto in = u.login("alice");
  ASSERT_EQ(in.status, 200);
  const std::string set_cookie(in.raw[http::field::set_cookie]);
  EXPECT_NE(set_cookie.find("HttpOnly"), std::string::npos) << set_cookie;
  EXPECT_NE(set_cookie.find("SameSite=Strict"), std::string::npos) << set_cookie;
  EXPECT_EQ(set_cookie.find("Secure"), std::string::npos) << "Secure without TLS: " << set_cookie;
  EXPECT_EQ(in.body.at("role"), "consumer");
  EXPECT_EQ(in.body.at("csrf").get<std::string>().size(), 64U);
  auto who = u.get("/api/session");
  ASSERT_EQ(who.status, 200);
  EXPECT_EQ(who.body.at("user"), "alice");

  EXPECT_EQ(u.request(http::verb::delete_, "/api/session", {}, false).status, 403);  // no CSRF token
  EXPECT_EQ(u.del("/api/session").status, 204);
  EXPECT_EQ(u.get("/api/session").status, 401);
}

// A second dashboard on the same gateway, over TLS: the cookie never travels in clear text and
// browsers are told to keep to HTTPS.
TEST_F(DashboardApi, OverTlsTheSessionCookieIsSecureAndHstsIsSent) {
  const auto& files = web::testing::TlsFiles::get();
  DashboardConfig dc;
  dc.users = rig->dir.path() / "users.yaml";
  dc.http.tls = web::TlsConfig{files.chain, files.key};
  auto d = Dashboard::create(*rig->gateway, rig->layout, dc);
  ASSERT_TRUE(d) << d.error().describe();
  auto port = (*d)->start();
  ASSERT_TRUE(port) << port.error().describe();
  const auto in = web::testing::https_request(files.ca, *port, http::verb::post, "/api/session",
                                              json{{"user", "alice"}, {"password", "secret"}}.dump());
  ASSERT_EQ(in.result_int(), 200U) << in.body();
  const std::string set_cookie(in[http::field::set_cookie]);
  EXPECT_NE(set_cookie.find("; Secure"), std::string::npos) << set_cookie;
  EXPECT_NE(set_cookie.find("HttpOnly"), std::string::npos) << set_cookie;
  EXPECT_EQ(in[http::field::strict_transport_security], "max-age=31536000");
  (*d)->stop();
}

TEST_F(DashboardApi, EveryRouteNeedsASessionOfItsRole) {
  const std::vector<std::string> viewer_reads{
      "/api/machines", "/api/machines/scara-robot-1", "/api/series", "/api/alarms", "/api/oee", "/api/layout",
      "/api/status"};
  auto nobody = anonymous();
  auto alice = as("alice");
  auto victor = as("victor");
  for (const auto& target : viewer_reads) {
    EXPECT_EQ(nobody.get(target).status, 401) << target;
    EXPECT_EQ(alice.get(target).status, 403) << target;
    EXPECT_EQ(victor.get(target).status, 200) << target;
  }
  EXPECT_EQ(nobody.get("/api/orders").status, 401);
  EXPECT_EQ(alice.get("/api/orders").status, 200);
  // Open to everybody: what an order may contain, and the API's description.
  auto catalog = nobody.get("/api/catalog");
  ASSERT_EQ(catalog.status, 200);
  EXPECT_FALSE(catalog.body.at("box_types").empty());
  EXPECT_EQ(nobody.get("/api/openapi.yaml").status, 200);
  auto body = nobody.get("/api/nothing-here");
  EXPECT_EQ(body.status, 404);
  EXPECT_TRUE(body.body.contains("error"));
}

TEST_F(DashboardApi, AConsumersOrderIsMadeKnownToTheOrderServiceAndFollowed) {
  auto alice = as("alice");
  auto placed = alice.post("/api/orders", R"({"box": "small-box", "candy": {"gummy": 2, "toffee": 1}})");
  ASSERT_EQ(placed.status, 201) << placed.raw.body();
  const std::string id = placed.body.at("id");
  EXPECT_TRUE(id.starts_with("alice-")) << id;
  EXPECT_EQ(placed.body.at("owner"), "alice");
  EXPECT_EQ(std::string(placed.raw[http::field::location]), "/api/orders/" + id);

  // The order service accepts it and starts its box: the steps come back through the gateway.
  Reply order;
  ASSERT_TRUE(eventually([&] {
    order = alice.get("/api/orders/" + id);
    return order.status == 200 && order.body.at("state") == "in work";
  })) << order.raw.body();
  EXPECT_EQ(order.body.at("box"), "small-box");
  EXPECT_EQ(order.body.at("candy"), (json{{"gummy", 2}, {"toffee", 1}}));
  EXPECT_EQ(order.body.at("steps").at(0).at("what"), "accepted");
  auto negotiation = alice.get("/api/orders/" + id + "/negotiation");
  ASSERT_EQ(negotiation.status, 200);
  EXPECT_EQ(negotiation.body.at(0).at("what"), "accepted");

  // Consumers see their own orders only; a viewer sees all.
  auto bob = as("bob");
  EXPECT_EQ(bob.get("/api/orders/" + id).status, 404);
  EXPECT_EQ(bob.get("/api/orders/" + id + "/negotiation").status, 404);
  for (const auto& o : bob.get("/api/orders").body) {
    EXPECT_NE(o.at("id"), id);
  }
  auto mine = alice.get("/api/orders");
  ASSERT_EQ(mine.status, 200);
  EXPECT_TRUE(
      std::any_of(mine.body.begin(), mine.body.end(), [&](const json& o) { return o.at("id") == id; }));
  auto all = as("victor").get("/api/orders?limit=1000");
  EXPECT_TRUE(std::any_of(all.body.begin(), all.body.end(), [&](const json& o) { return o.at("id") == id; }));
  EXPECT_EQ(alice.get("/api/orders?limit=0").status, 400);
  EXPECT_EQ(alice.get("/api/orders?limit=x").status, 400);
  EXPECT_EQ(alice.get("/api/orders/no-such-order").status, 404);
}

TEST_F(DashboardApi, InvalidOrdersAreRefusedAndNothingIsStored) {
  auto carol = as("carol");
  auto victor = as("victor");
  const auto before = victor.get("/api/orders?limit=1000").body.size();
  const std::vector<std::pair<std::string, std::string>> bad{
      {R"({"box": "gift-12", "candy": {"gummy": 1}})", "box"},
      {R"({"box": "small-box", "candy": {"mint": 1}})", "mint"},
      {R"({"box": "small-box", "candy": {"gummy": 0}})", "gummy"},
      {R"({"box": "small-box", "candy": {"gummy": -3}})", "gummy"},
      {R"({"box": "small-box", "candy": {"gummy": 500}})", ""},
      {R"({"box": "small-box", "candy": {}})", ""},
      {R"({"box": "small-box", "candy": {"gummy": "two"}})", "whole number"},
      {R"({"box": "small-box", "candy": {"gummy": 1.5}})", "whole number"},
      {R"({"box": "small-box", "candy": [1]})", "expected"},
      {R"({"candy": {"gummy": 1}})", "expected"},
      {R"([])", "expected"},
      {R"({"box": "small-box", "candy": {"gummy": 1})", ""},  // cut short
      {"", ""},
  };
  for (const auto& [body, says] : bad) {
    auto r = carol.post("/api/orders", body);
    EXPECT_EQ(r.status, 400) << body;
    ASSERT_TRUE(r.body.is_object()) << body;
    EXPECT_EQ(r.body.at("status"), 400);
    EXPECT_NE(r.body.at("error").get<std::string>().find(says), std::string::npos) << r.body.at("error");
  }
  // Over the body limit; without the CSRF token; without a session.
  EXPECT_EQ(carol.post("/api/orders", std::string(std::size_t{200} * 1024, ' ')).status, 413);
  EXPECT_EQ(
      carol.request(http::verb::post, "/api/orders", R"({"box": "small-box", "candy": {"gummy": 1}})", false)
          .status,
      403);
  EXPECT_EQ(anonymous().post("/api/orders", R"({"box": "small-box", "candy": {"gummy": 1}})").status, 401);
  EXPECT_EQ(victor.get("/api/orders?limit=1000").body.size(), before);
  EXPECT_TRUE(carol.get("/api/orders").body.empty());
}

TEST_F(DashboardApi, OrdersArePlacedAtALimitedRatePerUser) {
  auto dave = as("dave");
  int accepted = 0;
  Reply refused;
  for (int i = 0; i < 5 && refused.status == 0; ++i) {
    auto r = dave.post("/api/orders", R"({"box": "small-box", "candy": {"chocolate": 1}})");
    if (r.status == 201) {
      ++accepted;
    } else {
      refused = r;
    }
  }
  EXPECT_EQ(accepted, 3);  // the configured burst
  EXPECT_EQ(refused.status, 429);
  EXPECT_FALSE(std::string(refused.raw[http::field::retry_after]).empty());
  EXPECT_EQ(dave.get("/api/orders").body.size(), 3U);
}

TEST_F(DashboardApi, AQueuedOrderIsCancelledAndOneInWorkIsNot) {
  auto olga = as("olga");
  // One box at a time (wip 1) and no machine on DDS: the first order stays in work, the next queued.
  auto first = olga.post("/api/orders", R"({"box": "small-box", "candy": {"gummy": 1}})");
  auto second = olga.post("/api/orders", R"({"box": "small-box", "candy": {"gummy": 1}})");
  ASSERT_EQ(first.status, 201);
  ASSERT_EQ(second.status, 201);
  const std::string queued = second.body.at("id");
  ASSERT_TRUE(
      eventually([&] { return olga.get("/api/orders/" + queued).body.value("state", "") == "queued"; }));
  auto bob = as("bob");
  EXPECT_EQ(bob.del("/api/orders/" + queued).status, 404);  // not his
  EXPECT_EQ(olga.request(http::verb::delete_, "/api/orders/" + queued, {}, false).status, 403);
  EXPECT_EQ(olga.del("/api/orders/" + queued).status, 202);
  ASSERT_TRUE(
      eventually([&] { return olga.get("/api/orders/" + queued).body.value("state", "") == "cancelled"; }));
  EXPECT_EQ(olga.del("/api/orders/" + queued).status, 409);
  EXPECT_EQ(olga.del("/api/orders/nothing").status, 404);
}

TEST_F(DashboardApi, MachinesShowTheirStateAndTakeCommandsFromOperatorsOnly) {
  auto victor = as("victor");
  auto olga = as("olga");
  Reply m;
  ASSERT_TRUE(eventually([&] {
    m = victor.get("/api/machines/scara-robot-1");
    return m.status == 200 && m.body.at("state").is_string();
  })) << m.raw.body();
  EXPECT_EQ(m.body.at("server"), "scara");
  EXPECT_TRUE(m.body.at("connected").get<bool>());
  EXPECT_TRUE(m.body.at("values").contains("PackML/Admin/StateCurrentTime")) << m.body.at("values");
  auto all = victor.get("/api/machines");
  ASSERT_EQ(all.status, 200);
  EXPECT_EQ(all.body.size(), machines_of(rig->layout).size());
  EXPECT_EQ(victor.get("/api/machines/no-such-machine").status, 404);

  // Reset and Start take the machine to Execute (OPC 30050 §6.3.8); a viewer may not.
  EXPECT_EQ(victor.post("/api/machines/scara-robot-1/commands/Reset").status, 403);
  EXPECT_EQ(olga.post("/api/machines/scara-robot-1/commands/Explode").status, 400);
  EXPECT_EQ(olga.post("/api/machines/no-such-machine/commands/Start").status, 404);
  EXPECT_EQ(olga.request(http::verb::post, "/api/machines/scara-robot-1/commands/Reset", {}, false).status,
            403);
  auto state = [&] { return victor.get("/api/machines/scara-robot-1").body.value("state", json()); };
  if (state() != "Idle") {
    (void)olga.post("/api/machines/scara-robot-1/commands/Clear");
    (void)olga.post("/api/machines/scara-robot-1/commands/Reset");
  }
  ASSERT_TRUE(eventually([&] { return state() == "Idle"; })) << state();
  auto started = olga.post("/api/machines/scara-robot-1/commands/Start");
  EXPECT_EQ(started.status, 200) << started.raw.body();
  ASSERT_TRUE(eventually([&] { return state() == "Execute"; })) << state();
  auto held = olga.post("/api/machines/scara-robot-1/commands/Hold");
  EXPECT_EQ(held.status, 200) << held.raw.body();
  ASSERT_TRUE(eventually([&] { return state() == "Held"; })) << state();
  auto refused = olga.post("/api/machines/scara-robot-1/commands/Start");  // not from Held
  EXPECT_EQ(refused.status, 409) << refused.raw.body();
  EXPECT_EQ(olga.post("/api/machines/scara-robot-1/commands/Unhold").status, 200);
  ASSERT_TRUE(eventually([&] { return state() == "Execute"; })) << state();
}

TEST_F(DashboardApi, SeriesHistoryIsReadRawAndAggregated) {
  auto victor = as("victor");
  Reply list;
  ASSERT_TRUE(eventually([&] {
    list = victor.get("/api/series?path=/Objects/Machines/ScaraRobot1/PackML/Status/StateCurrent");
    return list.status == 200 && list.body.size() == 1;
  })) << list.raw.body();
  const auto id = list.body.at(0).at("id").get<std::string>();  // text: 63 bits do not fit a JS number
  EXPECT_EQ(list.body.at(0).at("server"), "scara");
  Reply raw;
  ASSERT_TRUE(eventually([&] {
    raw = victor.get(fmt::format("/api/series/{}/raw?from=-1h", id));
    return raw.status == 200 && !raw.body.empty();
  })) << raw.raw.body();
  EXPECT_TRUE(raw.body.at(0).at("v").is_number_integer());
  EXPECT_TRUE(raw.body.at(0).at("t").get<std::string>().ends_with("Z"));
  auto agg = victor.get(fmt::format("/api/series/{}/aggregate?from=-1h&points=10", id));
  ASSERT_EQ(agg.status, 200) << agg.raw.body();
  ASSERT_FALSE(agg.body.empty());
  EXPECT_GE(agg.body.at(0).at("count").get<int>(), 1);
  EXPECT_LE(agg.body.size(), 10U);
  // Bad ranges, ids and parameters: 4xx with a JSON error.
  for (const auto& target :
       {fmt::format("/api/series/{}/raw?from=yesterday-ish", id),
        fmt::format("/api/series/{}/raw?from=-1h&to=-2h", id), fmt::format("/api/series/{}/raw?limit=0", id),
        fmt::format("/api/series/{}/aggregate?points=0", id),
        fmt::format("/api/series/{}/aggregate?points=99999999", id),
        fmt::format("/api/series/{}/raw?from=0&to=99999999999999", id), std::string("/api/series/x/raw")}) {
    auto r = victor.get(target);
    EXPECT_EQ(r.status, 400) << target << " " << r.raw.body();
    EXPECT_TRUE(r.body.contains("error")) << target;
  }
  EXPECT_EQ(victor.get("/api/series/12345/raw").status, 404);
}

TEST_F(DashboardApi, AlarmsComeFromTheKnowledgeLoopWithTheirExplanation) {
  auto victor = as("victor");
  // The machine's Fault text, as its controller would publish it, on the gateway's live bus.
  historian::SeriesInfo fault{"scara", "nsu=urn:smartfactory:machines;s=ScaraRobot1.Fault",
                              "/Objects/Machines/ScaraRobot1/Fault", historian::DataType::string};
  cloud::LiveUpdate u;
  u.series = &fault;
  u.sample.source_time = std::chrono::time_point_cast<historian::Micros>(std::chrono::system_clock::now());
  u.sample.value = std::string("gripper lost vacuum");
  rig->gateway->live().publish(u);
  Reply alarms;
  ASSERT_TRUE(eventually([&] {
    alarms = victor.get("/api/alarms");
    return alarms.status == 200 && std::any_of(alarms.body.begin(), alarms.body.end(),
                                               [](const json& a) { return a.at("rule") == "fault"; });
  })) << alarms.raw.body();
  const auto a = *std::find_if(alarms.body.begin(), alarms.body.end(),
                               [](const json& x) { return x.at("rule") == "fault"; });
  EXPECT_NE(a.at("message").get<std::string>().find("gripper lost vacuum"), std::string::npos) << a;
  EXPECT_FALSE(a.at("facts").empty());
  EXPECT_TRUE(a.at("active").get<bool>());
  EXPECT_FALSE(a.at("acked").get<bool>());

  // Acknowledged by an operator once, with a comment; a viewer may not.
  const std::string ack = "/api/alarms/" + a.at("id").get<std::string>() + "/ack";
  EXPECT_EQ(victor.post(ack, R"({"comment": "seen"})").status, 403);
  auto olga = as("olga");
  EXPECT_EQ(olga.post(ack, R"({"comment": 7})").status, 400);
  EXPECT_EQ(olga.post(ack, "{oops").status, 400);
  EXPECT_EQ(olga.post("/api/alarms/no-such-alarm/ack").status, 404);
  auto acked = olga.post(ack, R"({"comment": "vacuum hose replaced"})");
  ASSERT_EQ(acked.status, 200) << acked.raw.body();
  EXPECT_TRUE(acked.body.at("acked").get<bool>());
  EXPECT_EQ(acked.body.at("acked_by"), "olga");
  EXPECT_EQ(acked.body.at("ack_comment"), "vacuum hose replaced");
  EXPECT_EQ(olga.post(ack).status, 409);  // once

  u.sample.source_time += 1s;
  u.sample.value = std::string();
  rig->gateway->live().publish(u);
  ASSERT_TRUE(eventually([&] {
    auto now = victor.get("/api/alarms");
    return std::none_of(now.body.begin(), now.body.end(),
                        [](const json& x) { return x.at("rule") == "fault"; });
  }));
  Reply history;
  ASSERT_TRUE(eventually([&] {
    history = victor.get("/api/alarms?active=false&from=-1h");
    return std::count_if(history.body.begin(), history.body.end(), [](const json& x) {
             return x.at("rule") == "fault";
           }) >= 3;  // raised, acknowledged, cleared
  })) << history.raw.body();
  EXPECT_EQ(victor.get("/api/alarms?active=maybe").status, 400);
}

TEST_F(DashboardApi, OeeIsGivenPerMachineAndForTheLine) {
  auto victor = as("victor");
  auto oee = victor.get("/api/oee?machine=scara-robot-1&from=-10m&buckets=5");
  ASSERT_EQ(oee.status, 200) << oee.raw.body();
  ASSERT_EQ(oee.body.at("machines").size(), 1U);
  EXPECT_EQ(oee.body.at("machines").at(0).at("machine"), "ScaraRobot1");
  EXPECT_EQ(oee.body.at("trend").size(), 5U);
  EXPECT_TRUE(oee.body.contains("line"));
  EXPECT_EQ(victor.get("/api/oee?from=-1m&to=-2m").status, 400);
  EXPECT_EQ(victor.get("/api/oee?buckets=-1").status, 400);
  EXPECT_EQ(victor.get("/api/oee?machine=no-such-machine").status, 404);
}

// Every route of the server is described in openapi.yaml with its method, and every path the
// description names is a route.
TEST_F(DashboardApi, TheOpenApiDescriptionNamesEveryRoute) {
  const YAML::Node doc = YAML::Load(std::string(openapi_yaml()));
  ASSERT_EQ(doc["openapi"].as<std::string>().substr(0, 2), "3.");
  std::set<std::pair<std::string, std::string>> described;
  for (const auto& path : doc["paths"]) {
    for (const auto& op : path.second) {
      const auto method = op.first.as<std::string>();
      if (method == "parameters") {
        continue;
      }
      std::string upper;
      for (char ch : method) {
        upper += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
      }
      described.emplace(upper, path.first.as<std::string>());
      EXPECT_TRUE(op.second["responses"])
          << upper << " " << path.first.as<std::string>() << " has no responses";
    }
  }
  std::set<std::pair<std::string, std::string>> served;
  for (const auto& r : rig->dashboard->routes()) {
    served.insert(r);
  }
  served.emplace("GET", "/api/live");  // the WebSocket endpoint, described in the info text
  for (const auto& r : served) {
    if (r.second != "/api/live") {
      EXPECT_TRUE(described.contains(r)) << r.first << " " << r.second << " is not in openapi.yaml";
    }
  }
  for (const auto& d : described) {
    EXPECT_TRUE(served.contains(d)) << d.first << " " << d.second << " is described but not served";
  }
}

TEST_F(DashboardApi, LiveTopicsNeedASessionAndConsumersSeeTheirOwnOrdersOnly) {
  auto refused = web::testing::raw_exchange(
      rig->port,
      "GET /api/live HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n");
  EXPECT_EQ(web::testing::raw_status(refused), 401) << refused;

  auto alice = as("alice");
  auto placed = alice.post("/api/orders", R"({"box": "small-box", "candy": {"gummy": 1}})");
  if (placed.status == 429) {
    GTEST_SKIP() << "alice's order budget went to other tests";  // not expected with the order above
  }
  ASSERT_EQ(placed.status, 201);
  const std::string id = placed.body.at("id");
  web::testing::LiveClient live(rig->port, 0, alice.cookie());
  live.send(json{{"subscribe", {"order/" + id, "machines", "order/someone-else"}}}.dump());
  EXPECT_EQ(live.receive(), (json{{"error", "not allowed"}, {"topics", {"machines", "order/someone-else"}}}));
  EXPECT_EQ(live.receive(), (json{{"subscribed", {"order/" + id}}}));
  json update = live.receive();  // the next step of the order (its acceptance or later)
  EXPECT_EQ(update.at("topic"), "order/" + id);
  EXPECT_EQ(update.at("value").at("id"), id);

  auto victor = as("victor");
  web::testing::LiveClient watcher(rig->port, 0, victor.cookie());
  watcher.send(R"({"subscribe": ["machines"]})");
  EXPECT_EQ(watcher.receive(), (json{{"subscribed", {"machines"}}}));
  auto olga = as("olga");
  (void)olga.post("/api/machines/scara-robot-1/commands/Hold");  // a change to see
  (void)olga.post("/api/machines/scara-robot-1/commands/Unhold");
  json machines = watcher.receive();
  EXPECT_EQ(machines.at("topic"), "machines");
  EXPECT_TRUE(machines.at("value").is_array());
}

}  // namespace
}  // namespace sf::dashboard
