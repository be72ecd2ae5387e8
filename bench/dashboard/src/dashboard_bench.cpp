// The dashboard benchmark's run (dashboard.hpp): the line, its cloud here, the robot set to work,
// the browser's half (browser.mjs) as a child process, the page's samples paired with the
// gateway's.
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "line_cloud.hpp"
#include "sf/bench/dashboard.hpp"
#include "sf/bench/running_line.hpp"
#include "sf/bench/users.hpp"
#include "sf/core/clock.hpp"
#include "sf/core/process.hpp"
#include "sf/factory/order.hpp"

namespace sf::bench {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

constexpr auto kPollInterval = 100ms;
constexpr std::size_t kMoving = 5;  // values of an axis before the robot counts as moving
constexpr const char* kUser = "olga";
constexpr const char* kRole = "operator";

const line::RobotSpec* smart_robot(const line::Layout& layout) {
  for (const auto& r : layout.robots) {
    if (r.kind == line::RobotKind::smart_scara) {
      return &r;
    }
  }
  return nullptr;
}

// `count` orders of the largest box filled with `candy`, by default the candy types of the
// robot's dispensers alone, so that it is awarded loads: it keeps picking for minutes.
std::vector<factory::Order> robot_orders(const line::Layout& layout, const line::RobotSpec& robot,
                                         const std::vector<std::string>& only, std::size_t count) {
  std::set<std::string> candy(only.begin(), only.end());
  for (const auto& d : layout.dispensers) {
    if (only.empty() &&
        std::find(robot.dispensers.begin(), robot.dispensers.end(), d.name) != robot.dispensers.end()) {
      candy.insert(d.candy);
    }
  }
  const auto box = std::max_element(layout.catalog.box_types.begin(), layout.catalog.box_types.end(),
                                    [](const auto& a, const auto& b) { return a.capacity() < b.capacity(); });
  std::vector<factory::Order> orders;
  if (candy.empty() || box == layout.catalog.box_types.end()) {
    return orders;
  }
  const int each = box->capacity() / static_cast<int>(candy.size());
  for (std::size_t i = 1; i <= count; ++i) {
    factory::Order o{fmt::format("e2e-{}", i), box->name, {}};
    for (const auto& c : candy) {
      o.lines.push_back({c, each});
    }
    orders.push_back(std::move(o));
  }
  return orders;
}

class DashboardBench {
 public:
  DashboardBench(const DashboardBenchOptions& o, const std::function<void(std::string_view)>& progress)
      : options_(o), progress_(progress) {}

  Result<DashboardBenchResult> run() {
    SF_TRY(prepare());
    LineStartOptions start;
    start.smartfactory = options_.smartfactory;
    start.run_dir = options_.run_dir;
    start.orders_file = options_.run_dir / "orders.yaml";
    start.extra_args = {"--opcua-base-port", "0"};
    auto line = RunningLine::start(start, progress_);
    if (!line) {
      return line.error();
    }
    report("the line is up; starting its cloud here");
    auto cloud = LineCloud::start(options_.smartfactory, options_.run_dir / "cloud", line->processes(),
                                  options_.web_root, options_.run_dir / "users.yaml");
    if (!cloud) {
      line->stop();
      return cloud.error();
    }
    auto st = measure(*line, **cloud);
    report("stopping the cloud and the line");
    cloud->reset();
    line->stop();
    if (!st) {
      return st.error();
    }
    return std::move(result_);
  }

 private:
  void report(std::string_view what) const {
    if (progress_) {
      progress_(what);
    }
  }

  // The run directory, the orders that set the smart robot to work, the dashboard's user.
  Status prepare() {
    std::error_code ec;
    fs::create_directories(options_.run_dir, ec);
    if (ec) {
      return make_error(Errc::io, fmt::format("{}: {}", options_.run_dir.string(), ec.message()));
    }
    auto layout = line::default_layout();
    if (!layout) {
      return layout.error();
    }
    const auto* robot = smart_robot(*layout);
    if (robot == nullptr) {
      return make_error(Errc::not_found, "the layout has no smart robot");
    }
    result_.robot = robot->name;
    const auto orders = robot_orders(*layout, *robot, options_.candy, options_.orders);
    if (orders.empty()) {
      return make_error(Errc::not_found, fmt::format("no order {} could work on", robot->name));
    }
    std::ofstream(options_.run_dir / "orders.yaml") << factory::orders_yaml(orders);
    password_ = fmt::format("bench-{}", ::getpid());
    return write_users(options_.run_dir / "users.yaml", kUser, password_, kRole);
  }

  // The recorder goes before the cloud whose live bus it listens to.
  Status measure(const RunningLine& line, LineCloud& cloud) {
    const AxisRecorder recorder(cloud.gateway().live(), result_.robot);
    SF_TRY(wait_moving(line, recorder));
    if (const auto* server = cloud.server(result_.robot)) {
      result_.sampling_ms = server->sampling_interval_ms;
      result_.publishing_ms = server->publishing_interval_ms;
    }
    auto topics = axis_topics(cloud);
    result_.axes = topics.size();
    SF_TRY(run_browser(cloud, topics));
    const auto& b = result_.browser;
    result_.latency = latency_figures(recorder.samples(), b.samples, b.client_samples, b.window);
    return {};
  }

  // Until the robot's axes change: its first box is uploaded and brought to it.
  Status wait_moving(const RunningLine& line, const AxisRecorder& recorder) const {
    report(fmt::format("waiting for {} to move", result_.robot));
    auto& clock = SteadyClock::instance();
    const auto limit = clock.now() + options_.move_limit;
    while (recorder.moving_series(kMoving).empty()) {
      if (!line.running()) {
        return make_error(Errc::io, "the line ended");
      }
      if (clock.now() > limit) {
        return make_error(Errc::timeout,
                          fmt::format("{} did not move within {} s (the line's logs: {})", result_.robot,
                                      options_.move_limit.count(), options_.run_dir.string()));
      }
      clock.sleep_until(clock.now() + kPollInterval);
    }
    return {};
  }

  // series/<id> of every axis position of the robot the gateway has registered.
  std::vector<std::string> axis_topics(LineCloud& cloud) const {
    std::vector<std::string> topics;
    auto series = cloud.gateway().store().list_series();
    for (const auto& s : series ? *series : std::vector<historian::Series>{}) {
      if (is_axis_position(s.info, result_.robot)) {
        topics.push_back(fmt::format("series/{}", s.id));
      }
    }
    return topics;
  }

  Status run_browser(LineCloud& cloud, const std::vector<std::string>& topics) {
    ProcessOptions p;
    p.argv = {"node",          (options_.source_dir / "bench" / "dashboard" / "browser.mjs").string(),
              "--url",         fmt::format("http://127.0.0.1:{}/", cloud.port()),
              "--user",        kUser,
              "--password",    password_,
              "--chromium",    options_.chromium,
              "--screenshots", (options_.run_dir / "screenshots").string(),
              "--machine",     result_.robot,
              "--topics",      fmt::format("{}", fmt::join(topics, ",")),
              "--samples",     std::to_string(options_.samples),
              "--seconds",     std::to_string(options_.seconds),
              "--loads",       std::to_string(options_.loads)};
    p.cwd = options_.source_dir;
    p.out = Stdio::pipe();
    report(fmt::format("Chromium on the dashboard at 127.0.0.1:{}, {} axes of {}", cloud.port(),
                       topics.size(), result_.robot));
    auto node = Process::spawn(std::move(p));
    if (!node) {
      return node.error();
    }
    std::optional<BrowserResult> browser;
    // Chromium's start and each load may take minutes on a loaded host (browser.mjs's WAIT_MS).
    const auto limit = SteadyClock::instance().now() + std::chrono::seconds(options_.seconds) +
                       std::chrono::minutes(2 * (options_.loads + 3));
    while (SteadyClock::instance().now() < limit) {
      auto l = node->read_line(1s);
      result_.live = cloud.live_counts();  // the page's client while it is connected
      if (l) {
        if (auto r = parse_browser_result(*l)) {
          browser = std::move(*r);
        } else {
          report(*l);
        }
      } else if (l.error().code != Errc::timeout) {
        break;  // the stream ended
      }
    }
    auto waited = node->wait(30s);  // it closes Chromium after its result
    const auto ended = waited ? *waited : node->terminate(10s);
    if (!browser) {
      return make_error(Errc::io, fmt::format("the browser's half gave no result ({})", ended.describe()));
    }
    result_.browser = std::move(*browser);
    return {};
  }

  const DashboardBenchOptions& options_;
  const std::function<void(std::string_view)>& progress_;
  std::string password_;
  DashboardBenchResult result_;
};

}  // namespace

Status check_prerequisites(const DashboardBenchOptions& options) {
  const std::pair<fs::path, const char*> needed[] = {
      {options.chromium, "Chromium (Debian's chromium; scripts/setup installs it)"},
      {options.source_dir / "node_modules" / "puppeteer-core", "puppeteer-core (scripts/setup runs npm ci)"},
      {options.web_root / "operator.html", "the web root's pages (the build's dashboard_web target)"},
      {options.smartfactory, "the smartfactory program"}};
  for (const auto& [path, what] : needed) {
    if (!fs::exists(path)) {
      return make_error(Errc::not_found, fmt::format("no {} at {}", what, path.string()));
    }
  }
  if (!find_program("node")) {
    return make_error(Errc::not_found, "node is not on PATH (scripts/setup installs it)");
  }
  return {};
}

Result<DashboardBenchResult> run_dashboard_bench(const DashboardBenchOptions& options,
                                                 const std::function<void(std::string_view)>& progress) {
  DashboardBench bench(options, progress);
  return bench.run();
}

}  // namespace sf::bench
