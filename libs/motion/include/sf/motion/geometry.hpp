// Points and poses in the line's frame: x, y on the floor plane, z up, in
// metres; angles in radians, counter-clockwise seen from above.
#pragma once

#include <cmath>
#include <numbers>

namespace sf::motion {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;
  bool operator==(const Vec2&) const = default;
};
inline Vec2 operator+(Vec2 a, Vec2 b) {
  return {a.x + b.x, a.y + b.y};
}
inline Vec2 operator-(Vec2 a, Vec2 b) {
  return {a.x - b.x, a.y - b.y};
}
inline Vec2 operator*(double k, Vec2 a) {
  return {k * a.x, k * a.y};
}
inline double dot(Vec2 a, Vec2 b) {
  return a.x * b.x + a.y * b.y;
}
inline double norm(Vec2 a) {
  return std::hypot(a.x, a.y);
}
// `a` turned by `angle` about the origin.
inline Vec2 rotate(Vec2 a, double angle) {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  return {c * a.x - s * a.y, s * a.x + c * a.y};
}

struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
  bool operator==(const Vec3&) const = default;
  [[nodiscard]] Vec2 xy() const { return {x, y}; }
};
inline Vec3 operator+(Vec3 a, Vec3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 operator-(Vec3 a, Vec3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 operator*(double k, Vec3 a) {
  return {k * a.x, k * a.y, k * a.z};
}
inline double norm(Vec3 a) {
  return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
}

// A tool pose: its point and its rotation about the vertical axis (the
// tools here always point down).
struct ToolPose {
  Vec3 position;
  double yaw = 0.0;
};

// An angle brought into (−π, π].
inline double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * std::numbers::pi);
  return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a;
}

// The angle equal to `a` modulo 2π that is nearest to `reference`: a
// revolute joint that follows a path must not jump by a turn when the
// wrapped angle crosses ±π.
inline double unwrap_near(double a, double reference) {
  return reference + wrap_angle(a - reference);
}

}  // namespace sf::motion
