// Lines of a simulation report that more than one command prints.
#pragma once

#include "sinew/physics/simulation.h"

namespace sinew::app {

// "  at the torque limit: UpperLeg_R 31%, UpperLeg_L 26% of the steps": the joints at their
// torque limit in 5% of the steps or more, most first (four at most, "(and more)" after). Prints
// nothing when no joint is. Why a run fell, for an artist: the joints that could give no more.
void printTorqueLimited(const physics::SimulationReport& report);

// "  furthest from the clip: Foot_R 8.4, UpperLeg_R 8.1, LowerLeg_R 7.9 deg RMS": the three
// joints with the largest tracking error (SimulationReport::track_err_by_link_rad), so an artist
// sees where the motion's style went. `target` names what it was measured against ("the clip",
// "the target"). Prints nothing for a run that tracked nothing.
void printTrackingByJoint(const physics::SimulationReport& report, const char* target);

}  // namespace sinew::app
