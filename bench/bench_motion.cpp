// Motion planner (libs/motion) on SCARA Robot 1's cell of the default line
// (sf/motion/testing/scara_cell.hpp): one pick-and-place from home — above
// the gummy dispenser, down to it (stop), up, back past home, above slot 3 of
// a small box at the station, down (stop), up — corners blended with 20 mm.
//   - time to plan it (goal ≤ 50 µs), next to a naive linear joint
//     interpolation of the same way-points in the same run (IK at each
//     way-point, straight joint-space lines at a fixed step per cycle, as the
//     scripted line's SmartArm::move_to does), and heap allocations per plan;
//   - path error: the tool's largest distance from the straight segments
//     through the way-points, at the set-points and between them (a drive
//     moves each axis straight from one target to the next), on the lines
//     and in the blends, for both;
//   - the set-point steps as a share of the axis limits (velocity,
//     acceleration), for both;
//   - the CSP sampler's cost per set-point next to a memcpy of the same
//     set-points.
//   bench_motion [ROUNDS]   (default 200 rounds of 50 plans)
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sf/bench/percentile.hpp"
#include "sf/motion/cartesian_path.hpp"
#include "sf/motion/csp_sampler.hpp"
#include "sf/motion/testing/scara_cell.hpp"

namespace {

std::atomic<std::size_t> g_allocations{0};

}  // namespace

// Counts heap allocations (the planner's goal: a few per plan, none per set-point).
void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) {
    return p;
  }
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t /*size*/) noexcept {
  std::free(p);
}

namespace {

using namespace sf::motion;
using namespace sf::motion::testing;
using Clock = std::chrono::steady_clock;

constexpr double kBlend = 0.02;
constexpr int kPlansPerRound = 50;
// 150 counts per cycle at 1e5 counts/rad, as SmartArm::move_to steps.
constexpr double kNaiveStep = 150.0 / 100'000.0;

// The naive peer: joint targets by IK, then straight joint-space lines with
// at most kNaiveStep per cycle on the longest axis, into a buffer. Empty when
// a way-point is out of reach.
std::vector<ScaraJoints> naive_plan(const ScaraGeometry& g, const ScaraJoints& start,
                                    const std::vector<Waypoint>& points) {
  std::vector<ScaraJoints> out{start};
  ScaraJoints now = start;
  for (const auto& w : points) {
    auto q = scara_inverse_nearest(g, w.pose, now);
    if (!q) {
      return {};
    }
    double longest = 0.0;
    for (std::size_t i = 0; i < 4; ++i) {
      longest = std::max(longest, std::abs((*q)[i] - now[i]));
    }
    const auto cycles = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(longest / kNaiveStep)));
    for (std::size_t k = 1; k <= cycles; ++k) {
      ScaraJoints p{};
      for (std::size_t i = 0; i < 4; ++i) {
        p[i] = now[i] + ((*q)[i] - now[i]) * static_cast<double>(k) / static_cast<double>(cycles);
      }
      out.push_back(p);
    }
    now = *q;
  }
  return out;
}

struct PathError {
  double at_setpoints = 0.0;
  double between = 0.0;  // 10 points per cycle on the drives' straight joint steps
};

PathError path_error(const ScaraGeometry& g, const std::vector<ScaraJoints>& q,
                     const std::vector<Vec3>& corners) {
  PathError e;
  for (std::size_t k = 0; k < q.size(); ++k) {
    e.at_setpoints = std::max(e.at_setpoints, distance_to_polyline(scara_forward(g, q[k]).position, corners));
    for (int s = 1; k > 0 && s < 10; ++s) {
      ScaraJoints mid{};
      for (std::size_t i = 0; i < 4; ++i) {
        mid[i] = q[k - 1][i] + (q[k][i] - q[k - 1][i]) * s / 10.0;
      }
      e.between = std::max(e.between, distance_to_polyline(scara_forward(g, mid).position, corners));
    }
  }
  e.between = std::max(e.between, e.at_setpoints);
  return e;
}

// The largest of the axes' shares of their limits.
double largest(const std::array<double, 4>& share) {
  return *std::max_element(share.begin(), share.end());
}

template <typename F>
double median_us_per_call(int rounds, int calls, F&& f) {
  std::vector<double> samples;
  for (int r = 0; r < rounds; ++r) {
    const auto t0 = Clock::now();
    for (int c = 0; c < calls; ++c) {
      f();
    }
    samples.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / calls);
  }
  return sf::bench::percentile(std::move(samples), 0.5);
}

}  // namespace

int main(int argc, char** argv) {
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 200;
  const ScaraGeometry g = robot1();
  const MotionLimits lim;
  const ScaraJoints start = home(g);
  const auto points = pick_and_place(kBlend);
  std::vector<Vec3> corners{kHome};
  for (const auto& w : points) {
    corners.push_back(w.pose.position);
  }

  auto blended = plan_path(g, lim, start, points);
  auto stopping = plan_path(g, lim, start, pick_and_place(0.0));
  if (!blended || !stopping) {
    std::fprintf(stderr, "plan: %s\n", (blended ? stopping : blended).error().describe().c_str());
    return 1;
  }

  std::size_t sink = 0;
  const double ours_us = median_us_per_call(rounds, kPlansPerRound, [&] {
    auto p = plan_path(g, lim, start, points);
    sink += p->cycles();
  });
  const double naive_us =
      median_us_per_call(rounds, kPlansPerRound, [&] { sink += naive_plan(g, start, points).size(); });
  const std::size_t before = g_allocations.load();
  {
    auto p = plan_path(g, lim, start, points);
    sink += p->cycles();
  }
  const std::size_t allocations = g_allocations.load() - before;

  const auto ours = setpoints(CspSampler(*blended), start);
  const auto ours_stopping = setpoints(CspSampler(*stopping), start);
  const auto naive = naive_plan(g, start, points);
  if (naive.empty()) {
    std::fprintf(stderr, "naive: a way-point is out of reach\n");
    return 1;
  }
  // Sampling: pull every set-point through the sampler, next to copying
  // the same number of set-points from a buffer.
  std::vector<ScaraJoints> copy(ours.size());
  const double sample_us = median_us_per_call(rounds / 10 + 1, 10, [&] {
    CspSampler sampler(*blended);
    ScaraJoints q{};
    while (sampler.next(q)) {
      sink += static_cast<std::size_t>(q[0] > 0.0);
    }
  });
  const double memcpy_us = median_us_per_call(rounds / 10 + 1, 10, [&] {
    std::memcpy(copy.data(), ours.data(), ours.size() * sizeof(ScaraJoints));
    sink += static_cast<std::size_t>(copy.back()[0] > 0.0);
  });
  std::size_t sampling_allocations = 0;
  {
    CspSampler sampler(*blended);
    ScaraJoints q{};
    const std::size_t before_sampling = g_allocations.load();
    while (sampler.next(q)) {
      sink += static_cast<std::size_t>(q[0] > 0.0);
    }
    sampling_allocations = g_allocations.load() - before_sampling;
  }

  const auto e_ours = path_error(g, ours, corners);
  const auto e_stop = path_error(g, ours_stopping, corners);
  const auto e_naive = path_error(g, naive, corners);
  const StepPeaks s_ours = step_peaks(ours, lim.cycle, lim.axes);
  const StepPeaks s_naive = step_peaks(naive, lim.cycle, lim.axes);

  fmt::print(
      "Motion planner: SCARA Robot 1 pick-and-place, 7 way-points, blend {:.0f} mm ({} rounds of {} plans)\n",
      kBlend * 1000, rounds, kPlansPerRound);
  fmt::print("{:<34} {:>10} {:>10} {:>7}\n", "", "ours", "naive", "ratio");
  fmt::print("{:<34} {:>10.2f} {:>10.2f} {:>6.2f}x   (goal <= 50 us)\n", "plan time us (median)", ours_us,
             naive_us, ours_us / naive_us);
  fmt::print("{:<34} {:>10} {:>10}\n", "heap allocations per plan", allocations, "-");
  fmt::print("{:<34} {:>10.3f} {:>10.3f}\n", "motion time s", blended->duration(),
             static_cast<double>(naive.size() - 1) * lim.cycle);
  fmt::print("{:<34} {:>10.3f} {:>10.3f}\n", "path error mm at set-points", e_ours.at_setpoints * 1e3,
             e_naive.at_setpoints * 1e3);
  fmt::print("{:<34} {:>10.3f} {:>10.3f}\n", "path error mm between set-points", e_ours.between * 1e3,
             e_naive.between * 1e3);
  fmt::print("{:<34} {:>10.2f} {:>10.2f}\n", "largest step / velocity limit", largest(s_ours.velocity),
             largest(s_naive.velocity));
  fmt::print("{:<34} {:>10.2f} {:>10.2f}\n", "largest step / acceleration limit",
             largest(s_ours.acceleration), largest(s_naive.acceleration));
  fmt::print("{:<34} {:>10.2f} {:>10.0f}\n", "largest step / jerk limit", largest(s_ours.jerk),
             largest(s_naive.jerk));
  fmt::print(
      "without blending (stops at every way-point): motion {:.3f} s, path error {:.2e} mm at set-points, "
      "{:.4f} mm between\n",
      stopping->duration(), e_stop.at_setpoints * 1e3, e_stop.between * 1e3);
  const double per_setpoint_ns = sample_us * 1e3 / static_cast<double>(ours.size() - 1);
  fmt::print(
      "CSP sampler: {:.1f} ns per set-point ({:.3f} % of a {:.0f} ms cycle), memcpy of the set-points "
      "{:.1f} ns each ({:.0f}x), {} heap allocations while sampling\n",
      per_setpoint_ns, per_setpoint_ns / (lim.cycle * 1e9) * 100.0, lim.cycle * 1e3,
      memcpy_us * 1e3 / static_cast<double>(ours.size() - 1), sample_us / memcpy_us, sampling_allocations);
  return sink == 0 ? 1 : 0;
}
