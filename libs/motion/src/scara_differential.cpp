#include "sf/motion/scara_differential.hpp"

#include <cmath>

#include <fmt/format.h>

namespace sf::motion {

namespace {

// Solves M·(a, b) = r for M = [l1·n(θ1) | l2·n(σ)] by Cramer's rule:
// a = (r·e(σ)) / (l1·sin θ2), b = −(r·e(θ1)) / (l2·sin θ2).
struct Frame {
  Vec2 e1, n1, es, ns;
  double l1 = 0.0;
  double l2 = 0.0;
  double s2 = 0.0;
  [[nodiscard]] std::array<double, 2> solve(Vec2 r) const {
    return {dot(r, es) / (l1 * s2), -dot(r, e1) / (l2 * s2)};
  }
};

}  // namespace

JointDerivatives scara_joint_derivatives(const ScaraGeometry& g, const ScaraJoints& q,
                                         const PoseDerivatives& p) {
  const double sigma = q[0] + q[1];
  const Frame f{{std::cos(q[0]), std::sin(q[0])},
                {-std::sin(q[0]), std::cos(q[0])},
                {std::cos(sigma), std::sin(sigma)},
                {-std::sin(sigma), std::cos(sigma)},
                g.l1,
                g.l2,
                std::sin(q[1])};
  const auto [t1, s1] = f.solve({p.first[0], p.first[1]});
  const Vec2 r2 = Vec2{p.second[0], p.second[1]} + (g.l1 * t1 * t1) * f.e1 + (g.l2 * s1 * s1) * f.es;
  const auto [t2, s2] = f.solve(r2);
  const Vec2 r3 = Vec2{p.third[0], p.third[1]} + (3.0 * g.l1 * t1 * t2) * f.e1 +
                  (g.l1 * t1 * t1 * t1) * f.n1 + (3.0 * g.l2 * s1 * s2) * f.es + (g.l2 * s1 * s1 * s1) * f.ns;
  const auto [t3, s3] = f.solve(r3);
  return {{t1, s1 - t1, p.first[2], p.first[3] - s1},
          {t2, s2 - t2, p.second[2], p.second[3] - s2},
          {t3, s3 - t3, p.third[2], p.third[3] - s3}};
}

double scara_conditioning(const ScaraJoints& q) {
  return std::abs(std::sin(q[1]));
}

Status check_singularity(const ScaraGeometry& g, const ScaraJoints& q, double margin) {
  const double c = scara_conditioning(q);
  if (c >= margin) {
    return {};
  }
  const double r = std::sqrt(g.l1 * g.l1 + g.l2 * g.l2 + 2.0 * g.l1 * g.l2 * std::cos(q[1]));
  const bool stretched = std::cos(q[1]) > 0.0;
  return make_error(
      Errc::out_of_range,
      fmt::format("{:.4f} m from the shoulder axis the arm is {} (|sin θ2| = {:.4f} < margin {:.4f})", r,
                  stretched ? "near full stretch, the singular outer edge of its reach"
                            : "nearly folded, the singular inner radius",
                  c, margin));
}

}  // namespace sf::motion
