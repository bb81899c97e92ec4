#include "sinew/motion/euler.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>

#include <glm/gtc/matrix_access.hpp>
#include <glm/mat3x3.hpp>

namespace sinew::motion {
namespace {

glm::dvec3 unitAxis(int axis) {
  glm::dvec3 v(0.0);
  v[axis] = 1.0;
  return v;
}

// Shifts `angle` by a multiple of 2 pi to lie within pi of `reference`.
double nearestWrap(double angle, double reference) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  return angle + kTwoPi * std::round((reference - angle) / kTwoPi);
}

// Even permutations of (X, Y, Z) (XYZ, YZX, ZXY) have parity +1, odd ones -1.
double parity(const EulerOrder& order) {
  const int i = order.axes[0];
  const int j = order.axes[1];
  return ((j - i + 3) % 3 == 1) ? 1.0 : -1.0;
}

}  // namespace

std::optional<EulerOrder> EulerOrder::fromName(std::string_view name) {
  if (name.size() != 3) return std::nullopt;
  EulerOrder order;
  bool seen[3] = {false, false, false};
  for (int n = 0; n < 3; ++n) {
    const int axis = std::toupper(static_cast<unsigned char>(name[n])) - 'X';
    if (axis < 0 || axis > 2 || seen[axis]) return std::nullopt;
    seen[axis] = true;
    order.axes[n] = axis;
  }
  return order;
}

std::array<char, 4> EulerOrder::name() const {
  return {static_cast<char>('X' + axes[0]), static_cast<char>('X' + axes[1]),
          static_cast<char>('X' + axes[2]), '\0'};
}

glm::dquat eulerToQuat(const EulerOrder& order, const glm::dvec3& angles) {
  glm::dquat q(1.0, 0.0, 0.0, 0.0);
  for (int n = 0; n < 3; ++n) q = q * glm::angleAxis(angles[n], unitAxis(order.axes[n]));
  return q;
}

glm::dvec3 quatToEuler(const EulerOrder& order, const glm::dquat& q, const glm::dvec3& reference,
                       EulerRange range) {
  // R = R_i(a) R_j(b) R_k(c) with (i, j, k) a permutation of the axes and s its parity:
  // sin b = s M_ik, a = atan2(-s M_jk, M_kk), c = atan2(-s M_ij, M_ii).
  const glm::dmat3 m = glm::mat3_cast(glm::normalize(q));
  const auto at = [&m](int row, int col) { return m[col][row]; };  // glm is column-major
  const int i = order.axes[0];
  const int j = order.axes[1];
  const int k = order.axes[2];
  const double s = parity(order);
  const double sin_b = std::clamp(s * at(i, k), -1.0, 1.0);
  glm::dvec3 first;
  first[1] = std::asin(sin_b);
  if (std::abs(sin_b) < 1.0 - 1e-12) {
    first[0] = std::atan2(-s * at(j, k), at(k, k));
    first[2] = std::atan2(-s * at(i, j), at(i, i));
  } else {
    // Gimbal lock: only a +- c is defined. Keep c at its reference; R_i(a) is what remains.
    first[2] = reference[2];
    const glm::dquat rest = glm::normalize(q) * glm::angleAxis(-first[2], unitAxis(k)) *
                            glm::angleAxis(-first[1], unitAxis(j));
    const double xyz[3] = {rest.x, rest.y, rest.z};
    first[0] = 2.0 * std::atan2(xyz[i], rest.w);
  }
  // The other branch: (a + pi, pi - b, c + pi) is the same rotation.
  const double pi = std::numbers::pi;
  glm::dvec3 second(first[0] + pi, pi - first[1], first[2] + pi);
  if (range == EulerRange::kPrincipal) {
    // First branch as is (middle angle from asin); outer angles into [-pi, pi], where exactly
    // +-pi goes to the side of the reference.
    for (int n : {0, 2}) {
      first[n] = nearestWrap(first[n], 0.0);
      if (std::abs(std::abs(first[n]) - pi) < 1e-12) first[n] = reference[n] < 0.0 ? -pi : pi;
    }
    return first;
  }
  for (int n = 0; n < 3; ++n) {
    first[n] = nearestWrap(first[n], reference[n]);
    second[n] = nearestWrap(second[n], reference[n]);
  }
  const auto distance = [&reference](const glm::dvec3& v) {
    const glm::dvec3 d = v - reference;
    return glm::dot(d, d);
  };
  return distance(first) <= distance(second) ? first : second;
}

}  // namespace sinew::motion
