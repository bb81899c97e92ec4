// Lines of a simulation report that more than one command prints.
#pragma once

#include "sinew/physics/joint_figures.h"

namespace sinew::app {

// physics::torqueLimitLine and physics::furthestJointsLine (against `target`), each indented on
// a line of its own, and nothing for a line that is empty.
void printJointLines(const physics::JointFigures& figures, const char* target);

}  // namespace sinew::app
