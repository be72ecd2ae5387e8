// Test and benchmark support, not part of the library: SCARA Robot 1's cell
// on the default line (layouts/prototype-line.yaml; line_test keeps these
// equal to it) — the arm, its dispensers, the small box's slots at its
// station, a pick-and-place through them — and helpers that read a move back
// cycle by cycle as the drives receive it.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "sf/motion/cartesian_path.hpp"
#include "sf/motion/csp_sampler.hpp"
#include "sf/motion/scara.hpp"

namespace sf::motion::testing {

inline ScaraGeometry robot1() {
  ScaraGeometry g;
  g.base = {3.5, 0.35, 0.8};
  g.l1 = 0.30;
  g.l2 = 0.25;
  g.limits[2] = {0.0, 0.30};
  return g;
}

// Dispensers scara1-chocolate and scara1-gummy; slots 3 and 8 of a small box
// (3 × 4 slots, pitch 35 mm, 50 mm high) at the station conveyor2/scara1.
inline constexpr Vec3 kChocolate{3.3, 0.7, 0.9};
inline constexpr Vec3 kGummy{3.7, 0.7, 0.9};
inline constexpr Vec3 kSlot3{3.5525, -0.035, 0.85};
inline constexpr Vec3 kSlot8{3.4475, 0.035, 0.85};

// Beside the shoulder, between the dispensers and the station: the arm
// swings through it from one to the other, because a straight line from a
// dispenser to a slot passes within 0.13 m of the shoulder axis, closer than
// θ2's limits let the arm fold (0.18 m).
inline constexpr Vec3 kHome{3.9, 0.35, 0.95};

inline Vec3 above(Vec3 p, double dz) {
  return {p.x, p.y, p.z + dz};
}

// The arm at home, left elbow.
inline ScaraJoints home(const ScaraGeometry& g) {
  return scara_inverse(g, {kHome, 0.0}, Elbow::left).value();
}

// A pick-and-place from home: above the gummy dispenser, down to it (stop,
// 50 ms for the vacuum), up, back past home, above slot 3, down to 10 mm
// above it (stop, 50 ms), up 80 mm. Corners blended with `radius`.
inline std::vector<Waypoint> pick_and_place(double radius) {
  return {{{above(kGummy, 0.05), 0.0}, radius, 0.0}, {{kGummy, 0.0}, 0.0, 0.05},
          {{above(kGummy, 0.05), 0.0}, radius, 0.0}, {{kHome, 0.0}, radius, 0.0},
          {{above(kSlot3, 0.05), 0.5}, radius, 0.0}, {{above(kSlot3, 0.01), 0.5}, 0.0, 0.05},
          {{above(kSlot3, 0.08), 0.5}, 0.0, 0.0}};
}

// Every set-point of a move, the start first.
inline std::vector<ScaraJoints> setpoints(CspSampler sampler, const ScaraJoints& start) {
  std::vector<ScaraJoints> q{start};
  ScaraJoints next{};
  while (sampler.next(next)) {
    q.push_back(next);
  }
  return q;
}

// Largest |Δq|/dt, |Δ²q|/dt², |Δ³q|/dt³ of each axis over the set-points,
// as a share of the axis' limit (≤ 1 is within), the arm at rest before
// and after.
struct StepPeaks {
  std::array<double, 4> velocity{};
  std::array<double, 4> acceleration{};
  std::array<double, 4> jerk{};
  [[nodiscard]] double worst() const {
    double w = 0.0;
    for (std::size_t i = 0; i < 4; ++i) {
      w = std::max({w, velocity[i], acceleration[i], jerk[i]});
    }
    return w;
  }
};

inline StepPeaks step_peaks(std::vector<ScaraJoints> q, double dt, const AxisLimits& limits) {
  q.insert(q.begin(), 2, q.front());
  q.insert(q.end(), 2, q.back());
  StepPeaks p;
  for (std::size_t k = 3; k < q.size(); ++k) {
    for (std::size_t i = 0; i < 4; ++i) {
      const double d1 = q[k][i] - q[k - 1][i];
      const double d2 = d1 - (q[k - 1][i] - q[k - 2][i]);
      const double d3 = d2 - (q[k - 1][i] - 2.0 * q[k - 2][i] + q[k - 3][i]);
      p.velocity[i] = std::max(p.velocity[i], std::abs(d1) / dt / limits[i].velocity);
      p.acceleration[i] = std::max(p.acceleration[i], std::abs(d2) / (dt * dt) / limits[i].acceleration);
      p.jerk[i] = std::max(p.jerk[i], std::abs(d3) / (dt * dt * dt) / limits[i].jerk);
    }
  }
  return p;
}

// Distance from p to the segment a–b.
inline double distance_to_segment(Vec3 p, Vec3 a, Vec3 b) {
  const Vec3 d = b - a;
  const double dd = d.x * d.x + d.y * d.y + d.z * d.z;
  const Vec3 ap = p - a;
  const double u = dd == 0.0 ? 0.0 : std::clamp((ap.x * d.x + ap.y * d.y + ap.z * d.z) / dd, 0.0, 1.0);
  return norm(p - (a + u * d));
}

// Distance from p to the polyline through `points`.
inline double distance_to_polyline(Vec3 p, const std::vector<Vec3>& points) {
  double best = norm(p - points.front());
  for (std::size_t i = 1; i < points.size(); ++i) {
    best = std::min(best, distance_to_segment(p, points[i - 1], points[i]));
  }
  return best;
}

}  // namespace sf::motion::testing
