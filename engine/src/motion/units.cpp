#include "sinew/motion/units.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <sstream>

namespace sinew::motion {

double metresPerUnit(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::kMetres:
      return 1.0;
    case LengthUnit::kCentimetres:
      return 0.01;
    case LengthUnit::kMillimetres:
      return 0.001;
    case LengthUnit::kInches:
      return 0.0254;
    case LengthUnit::kFeet:
      return 0.3048;
    case LengthUnit::kCmu:
      return 0.0254 / 0.45;
  }
  return 1.0;
}

std::string_view unitName(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::kMetres:
      return "m";
    case LengthUnit::kCentimetres:
      return "cm";
    case LengthUnit::kMillimetres:
      return "mm";
    case LengthUnit::kInches:
      return "in";
    case LengthUnit::kFeet:
      return "ft";
    case LengthUnit::kCmu:
      return "cmu";
  }
  return "m";
}

std::optional<LengthUnit> unitFromName(std::string_view name) {
  for (LengthUnit unit : kAllLengthUnits) {
    if (name == unitName(unit)) return unit;
  }
  return std::nullopt;
}

std::string_view upAxisName(UpAxis up) {
  return up == UpAxis::kY ? "Y" : "Z";
}

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

}  // namespace sinew::motion
