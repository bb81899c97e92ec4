#include "cli/report_lines.h"

#include <cstdio>
#include <string>

namespace sinew::app {

void printJointLines(const physics::JointFigures& figures, const char* target) {
  for (const std::string& line :
       {physics::torqueLimitLine(figures), physics::furthestJointsLine(figures, target)})
    if (!line.empty()) std::printf("  %s\n", line.c_str());
}

}  // namespace sinew::app
