#include "sinew/core/rotation.h"

#include <cmath>

namespace sinew {

double angleBetween(const glm::dquat& a, const glm::dquat& b) {
  const glm::dquat d = glm::conjugate(a) * b;
  return 2.0 * std::atan2(glm::length(glm::dvec3(d.x, d.y, d.z)), std::abs(d.w));
}

glm::dvec3 rotationVector(const glm::dquat& q) {
  const glm::dvec3 xyz(q.x, q.y, q.z);
  const double s = glm::length(xyz);
  if (s < 1e-12) return 2.0 * xyz;  // small-angle limit: angle ~ 2 s, axis xyz / s
  // atan(s / w) where w > 0 (the usual case) agrees with atan2 to an ulp at under half the cost:
  // the analysis maps every joint of every frame.
  const double angle = q.w > 0.0 ? 2.0 * std::atan(s / q.w) : 2.0 * std::atan2(s, q.w);
  return xyz * (angle / s);
}

glm::dvec3 shortRotationVector(const glm::dquat& q) {
  return rotationVector(positiveW(q));
}

glm::dquat fromRotationVector(const glm::dvec3& v) {
  const double angle = glm::length(v);
  if (angle < 1e-12) return glm::normalize(glm::dquat(1.0, v.x / 2.0, v.y / 2.0, v.z / 2.0));
  const glm::dvec3 axis = v / angle;
  const double s = std::sin(angle / 2.0);
  return glm::dquat(std::cos(angle / 2.0), axis.x * s, axis.y * s, axis.z * s);
}

glm::dquat positiveW(const glm::dquat& q) {
  return q.w < 0.0 ? -q : q;
}

glm::dquat shortSlerp(const glm::dquat& a, glm::dquat b, double t) {
  if (glm::dot(a, b) < 0.0) b = -b;
  return glm::normalize(glm::slerp(a, b, t));
}

}  // namespace sinew
