// Historian ingest: samples per second into SQLite and into PostgreSQL through
// Store::append in batches, each next to the database's own bulk loader on
// the same rows in the same run (the figure to compare is the ratio):
//   SQLite      the sqlite3 shell: .import of a CSV, and one transaction of
//               INSERT statements, into a database with our schema
//   PostgreSQL  psql \copy of a CSV into our (partitioned) samples table,
//               on the same throwaway server (initdb'd by this program)
//   buffer      store-and-forward: the same rows into the buffer while the
//               database is away, then forwarded into SQLite, next to the
//               direct SQLite ingest above
// Usage: bench_historian_ingest [SAMPLES] [BATCH]   (defaults 200000, 1000)
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "pg_server.hpp"
#include "sf/core/clock.hpp"
#include "sf/historian/buffered_store.hpp"
#include "sf/historian/store.hpp"

namespace {

namespace hist = sf::historian;
namespace fs = std::filesystem;

constexpr std::size_t kSeries = 100;
const hist::Timestamp kT0 = hist::from_micros(1'763'683'200'000'000);  // midnight: one day partition

struct Rows {
  std::vector<hist::SeriesInfo> series;
  std::vector<hist::Sample> samples;
};

// Round-robin over the series, 1 ms apart per series: what a gateway sees.
Rows make_rows(std::size_t n) {
  Rows r;
  for (std::size_t i = 0; i < kSeries; ++i) {
    r.series.push_back(hist::SeriesInfo{.server = "opc.tcp://bench:4840",
                                        .node_id = fmt::format("ns=2;i={}", i),
                                        .browse_path = fmt::format("/Objects/Bench/V{}", i),
                                        .data_type = hist::DataType::float64,
                                        .unit = "mm"});
  }
  r.samples.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    const auto& s = r.series[k % kSeries];
    hist::Sample sample;
    sample.series = hist::series_id(s.server, s.node_id);
    sample.source_time = kT0 + std::chrono::milliseconds{static_cast<long>(k / kSeries)};
    sample.server_time = sample.source_time + std::chrono::microseconds{250};
    sample.value = static_cast<double>(k) * 0.25;
    r.samples.push_back(std::move(sample));
  }
  return r;
}

// The rows as CSV in the samples table's column order (vtype 4 = float64).
void write_csv(const Rows& rows, const fs::path& path, bool with_series_column) {
  std::ofstream out(path);
  for (const auto& s : rows.samples) {
    if (with_series_column) {
      out << s.series << ',';
    }
    out << hist::to_micros(s.source_time) << ",0," << hist::to_micros(s.server_time) << ",0,4,,"
        << fmt::format("{}", std::get<double>(s.value)) << ",,\n";
  }
}

double seconds_since(sf::Clock::time_point start) {
  return std::chrono::duration<double>(sf::SteadyClock::instance().now() - start).count();
}

// A store at `url` with the series registered.
std::unique_ptr<hist::Store> open_with_series(const std::string& url, const Rows& rows) {
  auto store = hist::open_store(url);
  if (!store) {
    std::cerr << "open " << url << ": " << store.error().describe() << "\n";
    std::exit(1);
  }
  for (const auto& s : rows.series) {
    (void)(*store)->register_series(s);
  }
  return std::move(*store);
}

// Times append() of every batch.
double ours(const std::string& url, const Rows& rows, std::size_t batch) {
  auto store = open_with_series(url, rows);
  const auto start = sf::SteadyClock::instance().now();
  for (std::size_t i = 0; i < rows.samples.size(); i += batch) {
    const auto n = std::min(batch, rows.samples.size() - i);
    if (auto st = store->append(std::span{rows.samples}.subspan(i, n)); !st) {
      std::cerr << "append: " << st.error().describe() << "\n";
      std::exit(1);
    }
  }
  return seconds_since(start);
}

// Times a shell command (the peer), which must succeed.
double timed(const std::string& command) {
  const auto start = sf::SteadyClock::instance().now();
  if (std::system(command.c_str()) != 0) {
    std::cerr << "peer failed: " << command << "\n";
    std::exit(1);
  }
  return seconds_since(start);
}

void report(std::string_view what, std::size_t n, double ours_s, std::string_view peer, double peer_s) {
  const double a = static_cast<double>(n) / ours_s;
  const double b = static_cast<double>(n) / peer_s;
  std::cout << fmt::format("{:<11} ours {:>9.0f} samples/s | {:<28} {:>9.0f} rows/s | ratio {:.2f}\n", what,
                           a, peer, b, a / b);
}

// A database with our schema and the series registered, for the peer to load into.
void prepare_peer(const std::string& url, const Rows& rows) {
  auto store = open_with_series(url, rows);
  // One sample far away in time creates the partition the peer's rows fall in
  // (PostgreSQL) without touching the rows' keys.
  hist::Sample probe;
  probe.series = hist::series_id(rows.series[0].server, rows.series[0].node_id);
  probe.source_time = kT0 + std::chrono::hours{23};
  (void)store->append(std::span{&probe, 1});
}

// Returns the time of the direct ingest, the peer of the buffer's figures.
double bench_sqlite(const Rows& rows, std::size_t batch, const fs::path& dir) {
  const auto db = dir / "ours.db";
  const double ours_s = ours("sqlite:" + db.string(), rows, batch);

  const auto csv = dir / "rows.csv";
  write_csv(rows, csv, true);
  const auto import_db = dir / "import.db";
  prepare_peer("sqlite:" + import_db.string(), rows);
  const double import_s =
      timed(fmt::format("sqlite3 {} \".import --csv {} samples\"", import_db.string(), csv.string()));

  const auto sql = dir / "rows.sql";
  {
    std::ofstream out(sql);
    out << "BEGIN;\n";
    for (const auto& s : rows.samples) {
      out << fmt::format("INSERT INTO samples VALUES({},{},0,{},0,4,NULL,{},NULL,NULL);\n", s.series,
                         hist::to_micros(s.source_time), hist::to_micros(s.server_time),
                         std::get<double>(s.value));
    }
    out << "COMMIT;\n";
  }
  const auto insert_db = dir / "insert.db";
  prepare_peer("sqlite:" + insert_db.string(), rows);
  const double insert_s = timed(fmt::format("sqlite3 {} < {}", insert_db.string(), sql.string()));

  report("SQLite", rows.samples.size(), ours_s, "sqlite3 .import (1 tx)", import_s);
  report("SQLite", rows.samples.size(), ours_s, "sqlite3 INSERTs in 1 tx", insert_s);
  return ours_s;
}

// BufferedStore while the database is away (every batch into the segment
// log, fdatasync each), then forwarding it all into SQLite when it is back.
void bench_buffer(const Rows& rows, std::size_t batch, const fs::path& dir, double direct_s) {
  bool up = false;
  const auto url = "sqlite:" + (dir / "forwarded.db").string();
  auto store = hist::BufferedStore::open(
      [&]() -> sf::Result<std::unique_ptr<hist::Store>> {
        if (!up) {
          return sf::make_error(sf::Errc::io, "away (benchmark)");
        }
        return hist::open_store(url);
      },
      hist::BufferOptions{.directory = dir / "buffer"}, sf::SteadyClock::instance());
  if (!store) {
    std::cerr << store.error().describe() << "\n";
    std::exit(1);
  }
  for (const auto& s : rows.series) {
    (void)(*store)->register_series(s);
  }
  auto start = sf::SteadyClock::instance().now();
  for (std::size_t i = 0; i < rows.samples.size(); i += batch) {
    const auto n = std::min(batch, rows.samples.size() - i);
    if (auto st = (*store)->append(std::span{rows.samples}.subspan(i, n)); !st) {
      std::cerr << "buffer: " << st.error().describe() << "\n";
      std::exit(1);
    }
  }
  const double buffer_s = seconds_since(start);
  up = true;
  start = sf::SteadyClock::instance().now();
  if (auto st = (*store)->flush(); !st) {
    std::cerr << "forward: " << st.error().describe() << "\n";
    std::exit(1);
  }
  const double forward_s = seconds_since(start);
  report("buffer", rows.samples.size(), buffer_s, "direct into SQLite (above)", direct_s);
  report("forward", rows.samples.size(), forward_s, "direct into SQLite (above)", direct_s);
}

void bench_postgres(const Rows& rows, std::size_t batch, const fs::path& dir) {
  auto server = sf::historian::testing::PgServer::start({.durable = true});
  if (!server) {
    std::cout << "PostgreSQL  skipped: " << server.error().describe() << "\n";
    return;
  }
  for (const char* name : {"ours", "peer"}) {
    if (auto st = (*server)->create_database(name); !st) {
      std::cerr << st.error().describe() << "\n";
      std::exit(1);
    }
  }
  const double ours_s = ours((*server)->url("ours"), rows, batch);
  const auto csv = dir / "rows.csv";
  write_csv(rows, csv, true);
  prepare_peer((*server)->url("peer"), rows);
  const double copy_s = timed(fmt::format(
      "{} -X -q -h 127.0.0.1 -p {} -U sf -d peer -c \"\\copy samples FROM '{}' WITH (FORMAT csv)\"",
      ((*server)->bin_dir() / "psql").string(), (*server)->port(), csv.string()));
  report("PostgreSQL", rows.samples.size(), ours_s, "psql \\copy (1 tx)", copy_s);
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 200'000;
  const std::size_t batch = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1000;
  char tmpl[] = "/tmp/sf-bench-hist-XXXXXX";
  if (::mkdtemp(tmpl) == nullptr) {
    return 1;
  }
  const fs::path dir{tmpl};
  const auto rows = make_rows(n);
  std::cout << fmt::format(
      "historian ingest: {} float64 samples over {} series, Store::append in batches of {}\n", n, kSeries,
      batch);
  const double direct_s = bench_sqlite(rows, batch, dir);
  bench_buffer(rows, batch, dir, direct_s);
  bench_postgres(rows, batch, dir);
  std::error_code ec;
  fs::remove_all(dir, ec);
  return 0;
}
