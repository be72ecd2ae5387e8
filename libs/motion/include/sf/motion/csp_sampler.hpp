// Set-points for cyclic synchronous position (CSP, IEC 61800-7-201 / CiA 402
// §12): the controller sends each axis one position target per EtherCAT
// cycle. A sampler hands out the next cycle's joint targets of a planned
// move, one per call, with no allocation and constant work per call, so a
// 1 kHz loop can pull them. Joint units (rad, m): converting to the drives'
// counts is the caller's business (the robot's axis scaling).
#pragma once

#include <cstddef>

#include "sf/core/result.hpp"
#include "sf/motion/cartesian_path.hpp"
#include "sf/motion/joint_move.hpp"

namespace sf::motion {

class CspSampler {
 public:
  // The move must outlive the sampler.
  explicit CspSampler(const JointMove& move);
  explicit CspSampler(const CartesianPath& path);

  // The set-points of the next cycle (cycle 1 is one cycle after the move's
  // start, the last one is the target, at rest); false once the move has
  // ended or failed, `setpoint` untouched.
  bool next(ScaraJoints& setpoint);

  // Cycles handed out so far and in all.
  [[nodiscard]] std::size_t cycle() const { return cycle_; }
  [[nodiscard]] std::size_t cycles() const { return cycles_; }
  [[nodiscard]] bool done() const { return cycle_ >= cycles_; }

  // A Cartesian pose the arm cannot take at some cycle (the planner's checks
  // make it unexpected): the sampler stops there, its last set-point held,
  // and this says where. The caller stops the axes.
  [[nodiscard]] Status fault() const;

 private:
  const JointMove* move_ = nullptr;
  const CartesianPath* path_ = nullptr;
  CartesianPath::Cursor cursor_;
  ScaraJoints last_{};
  std::size_t cycle_ = 0;
  std::size_t cycles_ = 0;
  std::size_t failed_at_ = 0;  // cycle, 0 = none
};

}  // namespace sf::motion
