#include "sinew/physics/joint_figures.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <numbers>

namespace sinew::physics {
namespace {

// The links (from 1, the base has no joint) whose value is at least `least`, the largest first.
std::vector<size_t> largestFirst(const std::vector<double>& per_link, size_t links, double least) {
  std::vector<size_t> order;
  for (size_t li = 1; li < std::min(per_link.size(), links); ++li)
    if (per_link[li] >= least) order.push_back(li);
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return per_link[a] > per_link[b]; });
  return order;
}

std::string number(const char* format, double value) {
  char text[32];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace

JointFigures jointFigures(const SimulationReport& report) {
  return {report.links, report.torque_limited_share, report.track_err_by_link_rad};
}

std::string torqueLimitLine(const JointFigures& f) {
  const std::vector<size_t> order = largestFirst(f.torque_limited_share, f.links.size(), 0.05);
  if (order.empty()) return {};
  std::string line = "at the torque limit:";
  for (size_t k = 0; k < order.size() && k < 4; ++k)
    line += (k > 0 ? ", " : " ") + f.links[order[k]] + " " +
            number("%.0f%%", 100.0 * f.torque_limited_share[order[k]]);
  return line + " of the steps" + (order.size() > 4 ? " (and more)" : "");
}

std::string furthestJointsLine(const JointFigures& f, std::string_view target) {
  const std::vector<size_t> order =
      largestFirst(f.track_err_by_link_rad, f.links.size(), std::numeric_limits<double>::min());
  if (order.empty()) return {};
  std::string line = "furthest from " + std::string(target) + ":";
  for (size_t k = 0; k < order.size() && k < 3; ++k)
    line += (k > 0 ? ", " : " ") + f.links[order[k]] + " " +
            number("%.1f", f.track_err_by_link_rad[order[k]] * 180.0 / std::numbers::pi);
  return line + " deg RMS";
}

}  // namespace sinew::physics
