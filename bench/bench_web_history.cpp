// REST history query: GET /api/series/{id}/aggregate of one series of SAMPLES samples aggregated
// to POINTS points, through the whole dashboard (HTTP, session, route, Gateway's store, JSON),
// on SQLite and on PostgreSQL, each next to peers in the same run on the same database:
//   store   Store::aggregate of the same range and interval (what the route calls)
//   sqlite3 the sqlite3 shell running the equivalent GROUP BY (a process per query)
//   psql    psql running it against the same server (a process per query)
// The figure to compare is the ratio API / peer (median of REPEATS rounds, each runs all in turn).
// Usage: bench_web_history [SAMPLES] [POINTS] [REPEATS]   (defaults 1000000, 1000, 5)
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "pg_server.hpp"
#include "sf/bench/users.hpp"
#include "sf/cloud/gateway.hpp"
#include "sf/core/clock.hpp"
#include "sf/dashboard/dashboard.hpp"
#include "sf/historian/store.hpp"
#include "sf/web/testing/client.hpp"

namespace {

namespace hist = sf::historian;
namespace fs = std::filesystem;
namespace http = boost::beast::http;

// Midnight: the whole series falls in one day (one PostgreSQL partition).
constexpr hist::Timestamp kT0{hist::Micros{1'763'683'200'000'000}};
constexpr std::chrono::milliseconds kPeriod{10};  // 1 M samples: 2 h 47 min

struct Options {
  std::size_t samples = 1'000'000;
  std::size_t points = 1000;
  int repeats = 5;
};

[[noreturn]] void fail(const std::string& what) {
  std::cerr << what << "\n";
  std::exit(1);  // NOLINT(concurrency-mt-unsafe): the benchmark ends here, its threads with it
}

double ms_since(sf::Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(sf::SteadyClock::instance().now() - start).count();
}

double median(std::vector<double> times) {
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

// Runs each contender once per round, in turn (the VM's load drifts alike for all), and returns
// the median time of each.
std::vector<double> median_ms(int rounds, const std::vector<std::function<void()>>& contenders) {
  std::vector<std::vector<double>> times(contenders.size());
  for (int i = 0; i < rounds; ++i) {
    for (std::size_t c = 0; c < contenders.size(); ++c) {
      const auto start = sf::SteadyClock::instance().now();
      contenders[c]();
      times[c].push_back(ms_since(start));
    }
  }
  std::vector<double> medians;
  medians.reserve(times.size());
  for (auto& t : times) {
    medians.push_back(median(std::move(t)));
  }
  return medians;
}

// The series at `url`: SAMPLES float64 samples kPeriod apart, appended in batches of 10 000.
hist::SeriesId fill(const std::string& url, std::size_t samples) {
  auto store = hist::open_store(url);
  if (!store) {
    fail("open " + url + ": " + store.error().describe());
  }
  const hist::SeriesInfo info{.server = "opc.tcp://bench:4840",
                              .node_id = "ns=2;s=Axis1.Position",
                              .browse_path = "/Objects/Bench/Axis1/Position",
                              .data_type = hist::DataType::float64,
                              .unit = "mm"};
  auto id = (*store)->register_series(info);
  if (!id) {
    fail("register: " + id.error().describe());
  }
  std::vector<hist::Sample> batch;
  for (std::size_t k = 0; k < samples;) {
    batch.clear();
    for (; k < samples && batch.size() < 10'000; ++k) {
      hist::Sample s;
      s.series = *id;
      s.source_time = kT0 + kPeriod * static_cast<long>(k);
      s.server_time = s.source_time;
      s.value = std::sin(static_cast<double>(k) * 1e-3) * 100.0;
      batch.push_back(std::move(s));
    }
    if (auto st = (*store)->append(batch); !st) {
      fail("append: " + st.error().describe());
    }
  }
  return *id;
}

// The equivalent of the store's aggregate query on float64 rows (sqlite_store.cpp, pg_store.cpp).
std::string group_by_sql(hist::SeriesId id, const Options& o) {
  const auto from = hist::to_micros(kT0);
  const auto to = from + static_cast<std::int64_t>(o.samples) * kPeriod.count() * 1000;
  const auto interval = (to - from) / static_cast<std::int64_t>(o.points);
  return fmt::format(
      "SELECT (source_time - {1}) / {3} AS bucket, count(*), min(v_real), max(v_real), avg(v_real) "
      "FROM samples WHERE series_id = {0} AND source_time >= {1} AND source_time < {2} "
      "AND (status >> 30) <> 2 GROUP BY bucket ORDER BY bucket",
      id, from, to, interval);
}

struct Row {
  std::string backend;
  double api_ms = 0;
  double store_ms = 0;
  std::string peer;
  double peer_ms = 0;
};

// The last answer of the API covers every sample in POINTS points.
void check(const sf::web::testing::HttpResponse& r, const Options& o) {
  if (r.result_int() != 200) {
    fail(fmt::format("GET aggregate: {} {}", r.result_int(), r.body()));
  }
  const auto body = nlohmann::json::parse(r.body());
  std::uint64_t counted = 0;
  for (const auto& p : body) {
    counted += p.at("count").get<std::uint64_t>();
  }
  if (body.size() != o.points || counted != o.samples) {
    fail(fmt::format("the API aggregated {} samples into {} points", counted, body.size()));
  }
}

// Times the API, the store and the CLI peer on the series at `url`.
Row measure(const std::string& backend, const std::string& url, hist::SeriesId id, const Options& o,
            const fs::path& dir, const std::string& peer, const std::string& peer_command) {
  sf::cloud::GatewayConfig gc;
  gc.historian.url = url;
  gc.historian.buffer = dir / (backend + ".buffer");
  auto gateway = sf::cloud::Gateway::create(gc);
  if (!gateway || !(*gateway)->start()) {
    fail("gateway on " + url);
  }
  const auto layout = sf::line::default_layout();
  sf::dashboard::DashboardConfig dc;
  dc.users = dir / "users.yaml";
  auto dashboard = sf::dashboard::Dashboard::create(**gateway, *layout, dc);
  if (!dashboard) {
    fail("dashboard: " + dashboard.error().describe());
  }
  auto port = (*dashboard)->start();
  if (!port) {
    fail("dashboard start: " + port.error().describe());
  }
  auto login = sf::web::testing::http_request(*port, http::verb::post, "/api/session",
                                              R"({"user": "viewer", "password": "secret"})");
  if (login.result_int() != 200) {
    fail("login: " + login.body());
  }
  const std::string cookie(login[http::field::set_cookie]);
  const sf::web::testing::HeaderList headers{{"Cookie", cookie.substr(0, cookie.find(';'))}};
  const auto from_ms = hist::to_micros(kT0) / 1000;
  const auto to_ms = from_ms + static_cast<std::int64_t>(o.samples) * kPeriod.count();
  const auto target =
      fmt::format("/api/series/{}/aggregate?from={}&to={}&points={}", id, from_ms, to_ms, o.points);

  Row row{backend, 0, 0, peer, 0};
  sf::web::testing::HttpResponse last;
  const auto api = [&] {
    last = sf::web::testing::http_request(*port, http::verb::get, target, {}, "application/json", headers);
  };
  const hist::Micros interval{(to_ms - from_ms) * 1000 / static_cast<std::int64_t>(o.points)};
  const auto store = [&] {
    auto rows = (*gateway)->store().aggregate(id, kT0, kT0 + interval * static_cast<long>(o.points), interval,
                                              hist::Aggregate::all);
    if (!rows || rows->size() != o.points) {
      fail("Store::aggregate");
    }
  };
  const auto cli = [&] {
    if (std::system(peer_command.c_str()) != 0) {  // NOLINT(concurrency-mt-unsafe): one thread runs it
      fail("peer failed: " + peer_command);
    }
  };
  const auto ms = median_ms(o.repeats, {api, store, cli});
  row.api_ms = ms[0];
  row.store_ms = ms[1];
  row.peer_ms = ms[2];
  check(last, o);
  (*dashboard)->stop();
  (*gateway)->stop();
  return row;
}

void print(const Row& r) {
  std::cout << fmt::format("{:<10} {:>9.1f} {:>9.1f} {:>6.2f}  {:<8} {:>9.1f} {:>6.2f}\n", r.backend,
                           r.api_ms, r.store_ms, r.api_ms / r.store_ms, r.peer, r.peer_ms,
                           r.api_ms / r.peer_ms);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (argc > 1) {
    o.samples = std::stoul(argv[1]);
  }
  if (argc > 2) {
    o.points = std::stoul(argv[2]);
  }
  if (argc > 3) {
    o.repeats = std::stoi(argv[3]);
  }
  if (o.samples % o.points != 0) {
    fail("SAMPLES must be a multiple of POINTS");
  }
  const fs::path dir = fs::temp_directory_path() / fmt::format("bench_web_history.{}", ::getpid());
  fs::create_directories(dir);
  if (!sf::bench::write_users(dir / "users.yaml", "viewer", "secret", "viewer")) {
    fail("cannot write the users file");
  }
  std::cout << fmt::format("{} samples of one series → {} points, median of {} rounds (ms)\n", o.samples,
                           o.points, o.repeats);
  std::cout << fmt::format("{:<10} {:>9} {:>9} {:>6}  {:<8} {:>9} {:>6}\n", "backend", "API", "store",
                           "API/st", "peer", "peer", "API/pr");

  const auto db = dir / "history.db";
  const auto sqlite_id = fill("sqlite:" + db.string(), o.samples);
  print(measure("SQLite", "sqlite:" + db.string(), sqlite_id, o, dir, "sqlite3",
                fmt::format("sqlite3 {} \"{}\" > /dev/null", db.string(), group_by_sql(sqlite_id, o))));

  if (!sf::historian::testing::PgServer::find_bin_dir()) {
    std::cout << "PostgreSQL   not installed\n";
  } else {
    auto pg = sf::historian::testing::PgServer::start();
    if (!pg || !(*pg)->create_database("history")) {
      fail("cannot start PostgreSQL");
    }
    const auto url = (*pg)->url("history");
    const auto pg_id = fill(url, o.samples);
    (void)(*pg)->psql("history", "VACUUM ANALYZE");
    print(measure("PostgreSQL", url, pg_id, o, dir, "psql",
                  fmt::format("{}/psql -X -q -h 127.0.0.1 -p {} -U sf -d history -c \"{}\" > /dev/null",
                              (*pg)->bin_dir().string(), (*pg)->port(), group_by_sql(pg_id, o))));
  }
  fs::remove_all(dir);
  return 0;
}
