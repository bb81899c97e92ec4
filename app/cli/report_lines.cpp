#include "cli/report_lines.h"

#include <algorithm>
#include <cstdio>
#include <vector>

namespace sinew::app {

void printTorqueLimited(const physics::SimulationReport& r) {
  std::vector<size_t> order;
  for (size_t li = 1; li < r.torque_limited_share.size(); ++li)
    if (r.torque_limited_share[li] >= 0.05) order.push_back(li);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return r.torque_limited_share[a] > r.torque_limited_share[b];
  });
  if (order.empty()) return;
  std::printf("  at the torque limit:");
  for (size_t k = 0; k < order.size() && k < 4; ++k)
    std::printf("%s %s %.0f%%", k > 0 ? "," : "", r.links[order[k]].c_str(),
                100.0 * r.torque_limited_share[order[k]]);
  std::printf(" of the steps%s\n", order.size() > 4 ? " (and more)" : "");
}

}  // namespace sinew::app
