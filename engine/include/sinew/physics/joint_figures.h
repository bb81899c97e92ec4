// Where a run's trouble lies, joint by joint, in words an artist reads: the joints that sat at
// their torque limit and the joints furthest from what they tracked. One owner for these lines,
// which `sinew simulate`, `sinew evolve` and the editor's Evolve panel print.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sinew/physics/simulation.h"

namespace sinew::physics {

// The per-joint figures of a SimulationReport (each vector per link, 0 the base), kept apart from
// the rest of the report so that a search can keep its best run's without the run's motion.
struct JointFigures {
  std::vector<std::string> links;
  std::vector<double> torque_limited_share;   // SimulationReport::torque_limited_share
  std::vector<double> track_err_by_link_rad;  // SimulationReport::track_err_by_link_rad
};
JointFigures jointFigures(const SimulationReport& report);

// "at the torque limit: UpperLeg_R 31%, UpperLeg_L 26% of the steps": the joints at their torque
// limit in 5% of the steps or more, most first (four at most, "(and more)" after); empty when no
// joint is. Why a run fell: the joints that could give no more.
std::string torqueLimitLine(const JointFigures& figures);

// "furthest from the clip: Foot_R 8.4, UpperLeg_R 8.1, LowerLeg_R 7.9 deg RMS": the three joints
// with the largest tracking error, so an artist sees where the motion's style went. `target`
// names what it was measured against ("the clip", "the target"). Empty for a run that tracked
// nothing.
std::string furthestJointsLine(const JointFigures& figures, std::string_view target);

}  // namespace sinew::physics
