// How fast a Cartesian path may go: the bounds of a line's path parameter
// from the tool's and the axes' limits, and the check of a blend's overlap
// (cartesian_path.hpp explains both).
#pragma once

#include "sf/core/result.hpp"
#include "sf/motion/cartesian_path.hpp"

namespace sf::motion::detail {

// The fastest profile of u along `line` within every limit, after checking
// that the line stays in reach, within the joint limits and out of the
// singularity margin. `joints`: the joints at the line's start on entry,
// at its end on return.
Result<JerkProfile> line_profile(const ScaraGeometry& g, const MotionLimits& limits, Elbow elbow,
                                 const PathSegment& line, ScaraJoints& joints);

// True when the tool moving on `a` and on `b` started at `b_start` (while
// `a` still decelerates) stays within every limit. `joints`: near the
// corner, for θ1 and θ4's turn.
bool overlap_within_limits(const ScaraGeometry& g, const MotionLimits& limits, Elbow elbow,
                           const PathSegment& a, const PathSegment& b, double b_start,
                           const ScaraJoints& joints);

}  // namespace sf::motion::detail
