// Rotation maths: identities, log/exp round trips, the short way, and the edges where formulas
// break down (half a turn, near identity).
#include "sinew/core/rotation.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

namespace sinew {
namespace {

constexpr double kPi = std::numbers::pi;

glm::dquat about(double angle, const glm::dvec3& axis) {
  return glm::angleAxis(angle, glm::normalize(axis));
}

// Same rotation: q or -q.
double rotationGap(const glm::dquat& a, const glm::dquat& b) {
  return std::min(glm::length(glm::dvec4(a.w - b.w, a.x - b.x, a.y - b.y, a.z - b.z)),
                  glm::length(glm::dvec4(a.w + b.w, a.x + b.x, a.y + b.y, a.z + b.z)));
}

TEST(RotationTest, IdentityMapsToTheZeroVectorAndBack) {
  const glm::dquat identity(1.0, 0.0, 0.0, 0.0);
  EXPECT_EQ(rotationVector(identity), glm::dvec3(0.0));
  EXPECT_EQ(shortRotationVector(-identity), glm::dvec3(0.0));
  EXPECT_EQ(fromRotationVector(glm::dvec3(0.0)), identity);
  EXPECT_EQ(angleBetween(identity, identity), 0.0);
  EXPECT_EQ(angleBetween(identity, -identity), 0.0);  // -1 is the same rotation
}

TEST(RotationTest, KnownRotationsHaveTheirAxisTimesAngle) {
  const glm::dvec3 v = rotationVector(about(kPi / 2.0, glm::dvec3(0.0, 0.0, 1.0)));
  EXPECT_NEAR(v.x, 0.0, 1e-15);
  EXPECT_NEAR(v.y, 0.0, 1e-15);
  EXPECT_NEAR(v.z, kPi / 2.0, 1e-15);
  const glm::dquat q = fromRotationVector(glm::dvec3(0.3, 0.0, 0.0));
  EXPECT_NEAR(q.w, std::cos(0.15), 1e-15);
  EXPECT_NEAR(q.x, std::sin(0.15), 1e-15);
  EXPECT_NEAR(angleBetween(glm::dquat(1.0, 0.0, 0.0, 0.0), q), 0.3, 1e-15);
  // Composition: the angle between a and a*r is r's angle, whatever a is.
  const glm::dquat a = about(1.1, glm::dvec3(1.0, 2.0, -0.5));
  EXPECT_NEAR(angleBetween(a, a * about(0.7, glm::dvec3(-1.0, 0.2, 0.4))), 0.7, 1e-14);
  EXPECT_NEAR(angleBetween(a, a * about(0.7, glm::dvec3(-1.0, 0.2, 0.4))),
              angleBetween(a * about(0.7, glm::dvec3(-1.0, 0.2, 0.4)), a), 1e-15);
}

TEST(RotationTest, LogAndExpRoundTrip) {
  const glm::dvec3 axes[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {-0.3, 0.8, 0.1}};
  for (const glm::dvec3& axis : axes) {
    for (double angle : {1e-9, 1e-6, 0.01, 0.5, 1.0, 2.0, 3.0, kPi - 1e-6}) {
      const glm::dvec3 v = glm::normalize(axis) * angle;
      const glm::dvec3 back = rotationVector(fromRotationVector(v));
      EXPECT_NEAR(glm::length(back - v), 0.0, 1e-14 * std::max(1.0, angle)) << angle;
      const glm::dquat q = about(angle, axis);
      EXPECT_LT(rotationGap(fromRotationVector(rotationVector(q)), q), 1e-15) << angle;
      EXPECT_NEAR(angleBetween(glm::dquat(1.0, 0.0, 0.0, 0.0), q), angle, 1e-14) << angle;
    }
  }
}

TEST(RotationTest, NearIdentityStaysExact) {
  // acos(w) loses everything below 1e-8 rad; the vector and the angle must not.
  for (double angle : {1e-13, 1e-10, 1e-8}) {
    const glm::dquat q = about(angle, glm::dvec3(0.0, 1.0, 0.0));
    EXPECT_NEAR(rotationVector(q).y, angle, angle * 1e-12);
    EXPECT_NEAR(angleBetween(glm::dquat(1.0, 0.0, 0.0, 0.0), q), angle, angle * 1e-12);
    EXPECT_NEAR(fromRotationVector(glm::dvec3(0.0, angle, 0.0)).y, std::sin(angle / 2.0),
                angle * 1e-12);
  }
}

TEST(RotationTest, HalfATurnAndTheShortWay) {
  const glm::dquat half = about(kPi, glm::dvec3(1.0, 0.0, 0.0));  // w = cos(pi/2) ~ 6e-17
  EXPECT_NEAR(glm::length(rotationVector(half)), kPi, 1e-15);
  EXPECT_NEAR(glm::length(shortRotationVector(half)), kPi, 1e-15);
  EXPECT_NEAR(angleBetween(glm::dquat(1.0, 0.0, 0.0, 0.0), half), kPi, 1e-15);
  // Exactly w = 0: half a turn either way.
  const glm::dquat exact(0.0, 0.0, 1.0, 0.0);
  EXPECT_NEAR(rotationVector(exact).y, kPi, 1e-15);
  EXPECT_LT(rotationGap(fromRotationVector(glm::dvec3(0.0, kPi, 0.0)), exact), 1e-15);
  // -q: the same rotation; the vector as it is goes the long way, the short one does not.
  const glm::dquat q = about(0.4, glm::dvec3(0.0, 0.0, 1.0));
  EXPECT_NEAR(rotationVector(-q).z, 0.4 - 2.0 * kPi, 1e-14);
  EXPECT_NEAR(shortRotationVector(-q).z, 0.4, 1e-15);
  EXPECT_EQ(positiveW(-q), q);
  EXPECT_EQ(positiveW(q), q);
  EXPECT_NEAR(angleBetween(q, -q), 0.0, 1e-15);
}

TEST(RotationTest, ShortSlerpTakesTheShortWay) {
  const glm::dquat a = about(0.2, glm::dvec3(0.0, 1.0, 0.0));
  const glm::dquat b = about(0.8, glm::dvec3(0.0, 1.0, 0.0));
  EXPECT_LT(rotationGap(shortSlerp(a, b, 0.5), about(0.5, glm::dvec3(0.0, 1.0, 0.0))), 1e-15);
  EXPECT_LT(rotationGap(shortSlerp(a, -b, 0.5), about(0.5, glm::dvec3(0.0, 1.0, 0.0))), 1e-15);
  EXPECT_LT(rotationGap(shortSlerp(a, b, 0.0), a), 1e-15);
  EXPECT_LT(rotationGap(shortSlerp(a, -b, 1.0), b), 1e-15);
}

}  // namespace
}  // namespace sinew
