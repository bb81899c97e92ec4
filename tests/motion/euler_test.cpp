#include "sinew/motion/euler.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace sinew::motion {
namespace {

constexpr const char* kOrders[] = {"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"};

double rotationDistance(const glm::dquat& a, const glm::dquat& b) {
  return 1.0 - std::abs(glm::dot(glm::normalize(a), glm::normalize(b)));
}

TEST(EulerTest, RefusesBadOrderNames) {
  EXPECT_FALSE(EulerOrder::fromName("XXY"));
  EXPECT_FALSE(EulerOrder::fromName("XY"));
  EXPECT_FALSE(EulerOrder::fromName("ABC"));
  EXPECT_FALSE(EulerOrder::fromName("XYZW"));
  ASSERT_TRUE(EulerOrder::fromName("zxy"));
  EXPECT_EQ(std::string(EulerOrder::fromName("zxy")->name().data()), "ZXY");
}

TEST(EulerTest, ComposesIntrinsicallyInChannelOrder) {
  // ZXY: R = Rz(90) Rx(90): the X axis goes first to Z's image of X... check on a vector.
  const EulerOrder zxy = *EulerOrder::fromName("ZXY");
  const double quarter = std::numbers::pi / 2.0;
  const glm::dquat q = eulerToQuat(zxy, {quarter, quarter, 0.0});
  // Rx(90) takes +Y to +Z; Rz(90) leaves +Z alone.
  const glm::dvec3 v = q * glm::dvec3(0.0, 1.0, 0.0);
  EXPECT_NEAR(v.x, 0.0, 1e-12);
  EXPECT_NEAR(v.y, 0.0, 1e-12);
  EXPECT_NEAR(v.z, 1.0, 1e-12);
}

TEST(EulerTest, RoundTripsRandomAnglesInEveryOrder) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-3.1, 3.1);
  std::uniform_real_distribution<double> middle(-1.5, 1.5);
  for (const char* name : kOrders) {
    const EulerOrder order = *EulerOrder::fromName(name);
    for (int n = 0; n < 2000; ++n) {
      const glm::dvec3 angles(angle(rng), middle(rng), angle(rng));
      const glm::dvec3 back = quatToEuler(order, eulerToQuat(order, angles), angles);
      EXPECT_NEAR(back.x, angles.x, 1e-9) << name;
      EXPECT_NEAR(back.y, angles.y, 1e-9) << name;
      EXPECT_NEAR(back.z, angles.z, 1e-9) << name;
    }
  }
}

TEST(EulerTest, PicksTheBranchAndWrapNearestTheReference) {
  const EulerOrder zyx = *EulerOrder::fromName("ZYX");
  const double deg = std::numbers::pi / 180.0;
  // 190 degrees comes back as 190 when the reference says so, as -170 near zero.
  const glm::dvec3 angles(190 * deg, 20 * deg, -30 * deg);
  const glm::dquat q = eulerToQuat(zyx, angles);
  const glm::dvec3 near_ref = quatToEuler(zyx, q, {185 * deg, 0.0, 0.0});
  EXPECT_NEAR(near_ref.x / deg, 190.0, 1e-9);
  const glm::dvec3 near_zero = quatToEuler(zyx, q, glm::dvec3(0.0));
  EXPECT_NEAR(near_zero.x / deg, -170.0, 1e-9);
  // The other branch (middle angle beyond 90 degrees) when the reference lives there.
  const glm::dvec3 wide(10 * deg, 120 * deg, 5 * deg);
  const glm::dvec3 wide_back = quatToEuler(zyx, eulerToQuat(zyx, wide), wide);
  EXPECT_NEAR(wide_back.y / deg, 120.0, 1e-9);
  EXPECT_NEAR(wide_back.x / deg, 10.0, 1e-9);
}

TEST(EulerTest, PrincipalRangeIsWhatPlainExportersWrite) {
  const EulerOrder zxy = *EulerOrder::fromName("ZXY");
  const double deg = std::numbers::pi / 180.0;
  // A middle angle past 90 degrees comes back as the principal equivalent, whatever the reference.
  const glm::dquat q = eulerToQuat(zxy, {10 * deg, 120 * deg, 5 * deg});
  const glm::dvec3 principal = quatToEuler(zxy, q, {10 * deg, 120 * deg, 5 * deg},
                                           EulerRange::kPrincipal);
  EXPECT_NEAR(principal.y / deg, 60.0, 1e-9);
  EXPECT_NEAR(principal.x / deg, -170.0, 1e-9);
  EXPECT_NEAR(principal.z / deg, -175.0, 1e-9);
  // Exactly 180 degrees keeps the sign of the reference.
  const glm::dquat flip = eulerToQuat(zxy, {180 * deg, 0.0, 0.0});
  EXPECT_NEAR(quatToEuler(zxy, flip, {-179 * deg, 0, 0}, EulerRange::kPrincipal).x / deg, -180.0,
              1e-9);
  EXPECT_NEAR(quatToEuler(zxy, flip, {179 * deg, 0, 0}, EulerRange::kPrincipal).x / deg, 180.0,
              1e-9);
}

TEST(EulerTest, GimbalLockStillReproducesTheRotation) {
  for (const char* name : kOrders) {
    const EulerOrder order = *EulerOrder::fromName(name);
    const glm::dvec3 angles(0.4, std::numbers::pi / 2.0, -0.3);
    const glm::dquat q = eulerToQuat(order, angles);
    const glm::dvec3 back = quatToEuler(order, q, glm::dvec3(0.0));
    EXPECT_LT(rotationDistance(eulerToQuat(order, back), q), 1e-12) << name;
  }
}

}  // namespace
}  // namespace sinew::motion
