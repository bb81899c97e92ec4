#include "sinew/motion/units.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <sstream>

namespace sinew::motion {

double metresPerUnit(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::kMetres: return 1.0;
    case LengthUnit::kCentimetres: return 0.01;
    case LengthUnit::kMillimetres: return 0.001;
    case LengthUnit::kInches: return 0.0254;
  }
  return 1.0;
}

std::string_view unitName(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::kMetres: return "m";
    case LengthUnit::kCentimetres: return "cm";
    case LengthUnit::kMillimetres: return "mm";
    case LengthUnit::kInches: return "in";
  }
  return "m";
}

std::optional<LengthUnit> unitFromName(std::string_view name) {
  for (LengthUnit unit : {LengthUnit::kMetres, LengthUnit::kCentimetres, LengthUnit::kMillimetres,
                          LengthUnit::kInches}) {
    if (name == unitName(unit)) return unit;
  }
  return std::nullopt;
}

std::string_view upAxisName(UpAxis up) { return up == UpAxis::kY ? "Y" : "Z"; }

std::optional<UpAxis> upAxisFromName(std::string_view name) {
  if (name == "Y" || name == "y") return UpAxis::kY;
  if (name == "Z" || name == "z") return UpAxis::kZ;
  return std::nullopt;
}

glm::dquat SourceFrame::axisRotation() const {
  if (up == UpAxis::kY) return glm::dquat(1.0, 0.0, 0.0, 0.0);
  return glm::angleAxis(-std::numbers::pi / 2.0, glm::dvec3(1.0, 0.0, 0.0));
}

glm::dvec3 SourceFrame::pointToEngine(const glm::dvec3& p) const {
  const glm::dvec3 scaled = p * metresPerUnit(unit);
  return up == UpAxis::kY ? scaled : glm::dvec3(scaled.x, scaled.z, -scaled.y);
}

glm::dvec3 SourceFrame::pointFromEngine(const glm::dvec3& p) const {
  const glm::dvec3 axes = up == UpAxis::kY ? p : glm::dvec3(p.x, -p.z, p.y);
  return axes / metresPerUnit(unit);
}

glm::dquat SourceFrame::rotationToEngine(const glm::dquat& q) const {
  if (up == UpAxis::kY) return q;
  const glm::dquat c = axisRotation();
  return c * q * glm::conjugate(c);
}

glm::dquat SourceFrame::rotationFromEngine(const glm::dquat& q) const {
  if (up == UpAxis::kY) return q;
  const glm::dquat c = axisRotation();
  return glm::conjugate(c) * q * c;
}

FrameDetection detectFrame(std::span<const glm::dvec3> points, const std::vector<bool>& is_leaf,
                           int centre) {
  FrameDetection result;
  if (points.empty() || is_leaf.size() != points.size() || centre < 0 ||
      centre >= static_cast<int>(points.size())) {
    result.reason = "no joints to measure; assuming metres, Y-up";
    return result;
  }
  glm::dvec3 lo(points[0]);
  glm::dvec3 hi(points[0]);
  for (const glm::dvec3& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double size = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});

  // Score each candidate up axis: how many chain ends share the lowest level (feet on the
  // ground), provided the pelvis stands clearly above that level.
  int best_axis = 1;
  int best_score = -1;
  std::ostringstream why;
  for (int axis : {1, 2}) {
    double leaf_low = hi[axis];
    for (size_t n = 0; n < points.size(); ++n) {
      if (is_leaf[n]) leaf_low = std::min(leaf_low, points[n][axis]);
    }
    const double centre_height = points[centre][axis] - leaf_low;
    int on_ground = 0;
    for (size_t n = 0; n < points.size(); ++n) {
      if (is_leaf[n] && points[n][axis] - leaf_low < 0.1 * size) ++on_ground;
    }
    const bool upright = size > 0.0 && centre_height > 0.2 * size;
    const int score = upright ? on_ground : 0;
    why << (axis == 1 ? "Y" : "Z") << ": " << on_ground << " chain ends at the lowest level, pelvis "
        << (upright ? "above" : "not above") << " them; ";
    if (score > best_score) {
      best_score = score;
      best_axis = axis;
    }
  }
  result.frame.up = best_axis == 1 ? UpAxis::kY : UpAxis::kZ;
  const double height = hi[best_axis] - lo[best_axis];
  result.height_in_file_units = height;
  if (height >= 1000.0) {
    result.frame.unit = LengthUnit::kMillimetres;
  } else if (height >= 10.0) {
    result.frame.unit = LengthUnit::kCentimetres;
  } else {
    result.frame.unit = LengthUnit::kMetres;
  }
  std::ostringstream reason;
  reason << "height " << height << " file units along " << upAxisName(result.frame.up)
         << " reads as " << unitName(result.frame.unit) << " (" << why.str()
         << "override with --units and --up)";
  result.reason = reason.str();
  return result;
}

}  // namespace sinew::motion
