// Lines of a simulation report that more than one command prints.
#pragma once

#include "sinew/physics/simulation.h"

namespace sinew::app {

// "  at the torque limit: UpperLeg_R 31%, UpperLeg_L 26% of the steps": the joints at their
// torque limit in 5% of the steps or more, most first (four at most, "(and more)" after). Prints
// nothing when no joint is. Why a run fell, for an artist: the joints that could give no more.
void printTorqueLimited(const physics::SimulationReport& report);

}  // namespace sinew::app
