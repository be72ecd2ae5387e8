#include "sf/motion/csp_sampler.hpp"

#include <fmt/format.h>

namespace sf::motion {

CspSampler::CspSampler(const JointMove& move) : move_(&move), last_(move.from()), cycles_(move.cycles()) {}

CspSampler::CspSampler(const CartesianPath& path)
    : path_(&path), last_(path.start_joints()), cycles_(path.cycles()) {}

bool CspSampler::next(ScaraJoints& setpoint) {
  if (cycle_ >= cycles_) {
    return false;
  }
  const std::size_t k = cycle_ + 1;
  if (move_ != nullptr) {
    last_ = move_->setpoint(k);
  } else {
    auto q = path_->setpoint(k, last_, cursor_);
    if (!q) {
      failed_at_ = k;
      cycles_ = cycle_;
      return false;
    }
    last_ = *q;
  }
  cycle_ = k;
  setpoint = last_;
  return true;
}

Status CspSampler::fault() const {
  if (failed_at_ == 0) {
    return {};
  }
  const double t = static_cast<double>(failed_at_) * path_->cycle();
  CartesianPath::Cursor cursor;
  auto q = path_->joints_at(t, last_, cursor);
  return make_error(Errc::out_of_range,
                    fmt::format("cycle {} ({:.3f} s into the path): {}", failed_at_, t,
                                q ? std::string("no joints for the pose") : q.error().message));
}

}  // namespace sf::motion
