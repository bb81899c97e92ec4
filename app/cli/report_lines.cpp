#include "cli/report_lines.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

namespace sinew::app {

namespace {

// The links (from 1) whose value is at least `least`, the largest first.
std::vector<size_t> largestFirst(const std::vector<double>& per_link, double least) {
  std::vector<size_t> order;
  for (size_t li = 1; li < per_link.size(); ++li)
    if (per_link[li] >= least) order.push_back(li);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return per_link[a] > per_link[b]; });
  return order;
}

}  // namespace

void printTorqueLimited(const physics::SimulationReport& r) {
  const std::vector<size_t> order = largestFirst(r.torque_limited_share, 0.05);
  if (order.empty()) return;
  std::printf("  at the torque limit:");
  for (size_t k = 0; k < order.size() && k < 4; ++k)
    std::printf("%s %s %.0f%%", k > 0 ? "," : "", r.links[order[k]].c_str(),
                100.0 * r.torque_limited_share[order[k]]);
  std::printf(" of the steps%s\n", order.size() > 4 ? " (and more)" : "");
}

void printTrackingByJoint(const physics::SimulationReport& r, const char* target) {
  const std::vector<size_t> order = largestFirst(r.track_err_by_link_rad, std::numeric_limits<double>::min());
  if (order.empty()) return;
  std::printf("  furthest from %s:", target);
  for (size_t k = 0; k < order.size() && k < 3; ++k)
    std::printf("%s %s %.1f", k > 0 ? "," : "", r.links[order[k]].c_str(),
                r.track_err_by_link_rad[order[k]] * 180.0 / std::numbers::pi);
  std::printf(" deg RMS\n");
}

}  // namespace sinew::app
