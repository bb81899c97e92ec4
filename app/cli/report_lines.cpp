#include "cli/report_lines.h"

#include <algorithm>
#include <cstdio>
#include <numbers>
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

void printTrackingByJoint(const physics::SimulationReport& r, const char* target) {
  std::vector<size_t> order;
  for (size_t li = 1; li < r.track_err_by_link_rad.size(); ++li)
    if (r.track_err_by_link_rad[li] > 0.0) order.push_back(li);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return r.track_err_by_link_rad[a] > r.track_err_by_link_rad[b];
  });
  if (order.empty()) return;
  std::printf("  furthest from %s:", target);
  for (size_t k = 0; k < order.size() && k < 3; ++k)
    std::printf("%s %s %.1f", k > 0 ? "," : "", r.links[order[k]].c_str(),
                r.track_err_by_link_rad[order[k]] * 180.0 / std::numbers::pi);
  std::printf(" deg RMS\n");
}

}  // namespace sinew::app
