// Joint servos (implicit PD solved with the contacts): convergence on every axis, torque limits,
// and the standing criterion of the physics issue.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <span>

#include <gtest/gtest.h>

#include "physics_test_util.h"
#include "sinew/physics/tracking.h"

namespace sinew::physics {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;
// Bullet clamps joint speeds at 100 rad/s; a run reaching it has diverged.
constexpr double kBlowUpRadPerS = 99.0;

// A ball joint's coordinate turned by up to 0.5 rad about one axis of its frame, the way that
// keeps it inside the joint's range (0.05 rad from its sides; smaller turns when neither way
// does): a target the servo can reach.
glm::dquat stepInsideRange(const Link& link, const glm::dquat& from, int axis, double& turned) {
  glm::dvec3 unit(0.0);
  unit[axis] = 1.0;
  for (double size = 0.5; size > 0.0; size -= 0.05)
    for (double sign : {1.0, -1.0}) {
      const glm::dquat q = from * glm::angleAxis(sign * size, unit);
      const glm::dvec3 v = ballRangeCoordinates(link, q);
      bool inside = true;
      for (int k = 0; k < 3; ++k)
        inside = inside && v[k] > link.ball_lower[k] + 0.05 && v[k] < link.ball_upper[k] - 0.05;
      if (inside) {
        turned = size;
        return q;
      }
    }
  turned = 0.0;
  return from;
}

// Every ball axis and hinge of the biped, floating without gravity, reaches a target 0.5 rad away
// (or as far as its range allows) within a second.
TEST(Servo, EveryJointReachesItsTargetOnEveryAxis) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const BodyPlan& plan = biped.plan;
  const LinkPose standing = standingPose(plan, biped.asset.skeleton);
  WorldSettings floating;
  floating.gravity_m_s2 = 0.0;
  floating.place_on_ground = false;
  floating.ground_height_m = -100.0;
  int checked = 0;
  double smallest_turn = 0.5;
  for (size_t li = 1; li < plan.links.size(); ++li) {
    const int axes = plan.links[li].type == JointType::kBall ? 3 : (plan.links[li].type == JointType::kHinge ? 1 : 0);
    for (int axis = 0; axis < axes; ++axis) {
      std::unique_ptr<World> world = World::create(plan, standing, floating).value();
      std::vector<double> limits(plan.links.size(), 500.0);
      limits[0] = 0.0;
      ASSERT_TRUE(world->enableServos(limits, 0.2).ok());
      LinkPose target = standing;
      if (axes == 3) {
        double turned = 0.0;
        target.rotations[li] =
            stepInsideRange(plan.links[li], standing.rotations[li], axis, turned);
        smallest_turn = std::min(smallest_turn, turned);
      } else {
        target.angles[li] = std::clamp(standing.angles[li] + 0.5, plan.links[li].hinge_lower,
                                       plan.links[li].hinge_upper);
      }
      world->setServoTargets(target);
      std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0);
      for (int s = 0; s < 240; ++s) world->step(zero);
      const LinkPose now = world->jointPositions();
      const double error =
          axes == 3 ? glm::length(rotationVectorOf(glm::inverse(now.rotations[li]) * target.rotations[li]))
                    : std::abs(now.angles[li] - target.angles[li]);
      EXPECT_LT(error, 1e-3) << plan.links[li].name << " axis " << axis;
      EXPECT_LT(world->externalLoads().max_base_force_n, 1e-12);
      ++checked;
    }
  }
  EXPECT_EQ(checked, plan.dofCount());
  std::printf("every ball axis turned by 0.5 rad inside its range (the smallest turn %.2f rad)\n",
              smallest_turn);
  EXPECT_GE(smallest_turn, 0.2);
}

// A rate per link: two of the floating biped's hinges asked to turn 0.3 rad; given rates 0.2 and
// 0.05 by setServoTargets, each closes in a step what it closes when the world's one rate is its
// own (enableServos' 0.2, or 0.05) to within 15% (the two arms move each other through the
// floating torso), and the slow one less than half as much.
TEST(Servo, EachLinkClosesItsOwnRateOfTheError) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const BodyPlan& plan = biped.plan;
  const LinkPose standing = standingPose(plan, biped.asset.skeleton);
  std::vector<size_t> hinges;
  for (size_t li = 1; li < plan.links.size(); ++li)
    if (plan.links[li].type == JointType::kHinge) hinges.push_back(li);
  ASSERT_GE(hinges.size(), 2u);
  hinges.resize(2);
  LinkPose target = standing;
  for (size_t hinge : hinges) {  // towards the middle of the range, where there is room
    const Link& link = plan.links[hinge];
    const double way = standing.angles[hinge] < 0.5 * (link.hinge_lower + link.hinge_upper) ? 1.0 : -1.0;
    target.angles[hinge] = standing.angles[hinge] + way * 0.3;
  }
  // The share of each hinge's error closed in one step: servos at `world_rate`, and `rates`.
  auto closedInAStep = [&](double world_rate, std::span<const double> rates) {
    WorldSettings floating;
    floating.gravity_m_s2 = 0.0;
    floating.place_on_ground = false;
    floating.ground_height_m = -100.0;
    std::unique_ptr<World> world = World::create(plan, standing, floating).value();
    std::vector<double> limits(plan.links.size(), 1e5);  // the rate binds, not the torque
    limits[0] = 0.0;
    EXPECT_TRUE(world->enableServos(limits, world_rate).ok());
    world->setServoTargets(target, rates);
    std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0);
    world->step(zero);
    const LinkPose now = world->jointPositions();
    std::array<double, 2> closed{};
    for (size_t k = 0; k < 2; ++k)
      closed[k] = (now.angles[hinges[k]] - standing.angles[hinges[k]]) /
                  (target.angles[hinges[k]] - standing.angles[hinges[k]]);
    return closed;
  };
  std::vector<double> rates(plan.links.size(), 0.2);
  rates[hinges[1]] = 0.05;
  const std::array<double, 2> mixed = closedInAStep(0.2, rates);
  const std::array<double, 2> fast = closedInAStep(0.2, {});
  const std::array<double, 2> slow = closedInAStep(0.05, {});
  std::printf("closed in a step: %s at rate 0.2 %.4f (the world's 0.2: %.4f), %s at 0.05 %.4f "
              "(the world's 0.05: %.4f)\n",
              plan.links[hinges[0]].name.c_str(), mixed[0], fast[0],
              plan.links[hinges[1]].name.c_str(), mixed[1], slow[1]);
  EXPECT_NEAR(mixed[0], fast[0], 0.15 * fast[0]);  // the arms move each other through the torso
  EXPECT_NEAR(mixed[1], slow[1], 0.15 * slow[1]);
  EXPECT_LT(mixed[1], 0.5 * mixed[0]);
  EXPECT_GT(mixed[1], 0.0);
}

// The servos never apply more than their limits.
TEST(Servo, TorquesStayWithinTheirLimits) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const BodyPlan& plan = biped.plan;
  const MotionState state = targetState(plan, biped.asset.skeleton, biped.target, 0.0);
  std::unique_ptr<World> world = World::create(plan, state.pose).value();
  const std::vector<double> limits = jointTorqueLimits(plan, 0.1, 0.5, 9.81);
  ASSERT_TRUE(world->enableServos(limits, 0.2).ok());
  std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0), torques(zero.size());
  const std::vector<int> offsets = plan.dofOffsets();
  double largest_share = 0.0;
  for (int s = 0; s < 480; ++s) {
    LinkPose target = state.pose;  // an unreachable crouch: every joint pushes at its limit
    for (size_t li = 1; li < plan.links.size(); ++li) {
      target.angles[li] = plan.links[li].hinge_upper;
      target.rotations[li] = glm::angleAxis(1.2, glm::dvec3(1.0, 0.0, 0.0));
    }
    world->setServoTargets(target);
    world->step(zero);
    world->servoTorques(torques);
    for (size_t li = 1; li < plan.links.size(); ++li)
      for (int d = 0; d < dofCount(plan.links[li].type); ++d)
        largest_share = std::max(largest_share, std::abs(torques[static_cast<size_t>(offsets[li] + d)]) / limits[li]);
  }
  std::printf("largest servo torque: %.6f of its limit\n", largest_share);
  EXPECT_LE(largest_share, 1.0 + 1e-9);
  EXPECT_GT(largest_share, 0.99);  // the limits were reached: the check saw real loads
}

// A rig from assets/ standing 10 s under the servos, its figures printed.
test_util::HoldResult standTenSeconds(const char* file) {
  const test_util::Character c = test_util::loadCharacter(file);
  EXPECT_FALSE(c.plan.links.empty()) << file;
  if (c.plan.links.empty()) return {};
  const test_util::HoldResult r =
      test_util::holdWithServos(c.plan, standingPose(c.plan, c.asset.skeleton), 10.0);
  std::printf("%s standing 10 s under servos: pelvis %.3f m, lowest %.3f m, largest joint error "
              "(last 5 s) %.2f deg (%s), fastest joint %.3f rad/s\n",
              file, r.start_height, r.min_height, r.max_joint_error * kDeg,
              c.plan.links[static_cast<size_t>(r.worst_link)].name.c_str(), r.max_joint_speed);
  EXPECT_TRUE(r.finite) << file;
  EXPECT_LT(r.fall_time, 0.0) << file;
  EXPECT_EQ(r.loads.max_base_force_n, 0.0) << file;
  EXPECT_EQ(r.loads.max_link_force_n, 0.0) << file;
  return r;
}

// The criterion: the biped holds its standing pose for 10 s on flat ground.
TEST(Servo, BipedHoldsItsStandingPoseForTenSeconds) {
  const test_util::HoldResult r = standTenSeconds("biped_walk.bvh");
  EXPECT_GT(r.min_height, 0.97 * r.start_height);
  // The ankles give most (3.1 deg at 10 solver iterations, 0.25 at 40): the servo and the
  // contacts share the solver's iterations. The body sways; it does not sink.
  EXPECT_LT(r.max_joint_error * kDeg, 5.0);
}

// The criterion for the quadruped: it stands 10 s too.
TEST(Servo, QuadrupedHoldsItsStandingPoseForTenSeconds) {
  const test_util::HoldResult r = standTenSeconds("quadruped_trot.bvh");
  EXPECT_GT(r.min_height, 0.95 * r.start_height);
}

// Every rig in assets/ and the shared data builds a plan and holds its standing pose under the
// servos for 5 s without NaN or a joint speed blow-up; the bundled biped, quadruped and stepper
// also stay up (base above 70% of its start). Not asserted, printed: the one-legged hopper has
// no static balance, and the real captures of the shared data fall today (at 1-1.3 s; the body
// plan's real-capture work is to fix that).
TEST(Servo, EveryRigHoldsFiveSecondsWithoutBlowingUpAndTheBundledStandersStand) {
  const std::vector<std::string> standers = {"biped_walk.bvh", "quadruped_trot.bvh",
                                             "stepper_step.bvh"};
  std::vector<std::filesystem::path> rigs;
  for (const char* file :
       {"biped_walk.bvh", "quadruped_trot.bvh", "hopper_hop.bvh", "stepper_step.bvh"})
    rigs.push_back(sinew::test::sourceDir() / "assets" / file);
  if (sinew::test::haveSharedData()) {
    for (const auto& p : sinew::test::sharedFiles("bvh", ".bvh")) rigs.push_back(p);
    for (const auto& p : sinew::test::sharedFiles("gltf", ".glb")) rigs.push_back(p);
  } else {
    std::printf("shared data not found at %s: only assets/ rigs\n",
                sinew::test::sharedData().string().c_str());
  }
  for (const auto& path : rigs) {
    const motion::MotionAsset asset = test_util::loadAsset(path);
    if (asset.clips.empty()) {
      ADD_FAILURE() << path << ": no clip";
      continue;
    }
    Result<BodyPlan> built = buildBodyPlan(asset.skeleton, &asset.clips[0]);
    ASSERT_TRUE(built.ok()) << path << ": " << built.message();
    const BodyPlan& plan = built.value();
    const test_util::HoldResult r =
        test_util::holdWithServos(plan, standingPose(plan, asset.skeleton), 5.0);
    const bool up = r.min_height > 0.7 * r.start_height;
    std::printf(
        "%-38s %3d joints %3zu links %3d DOF %9.2f kg  size %6.2f m  base %.2f -> min %.2f m "
        "%s",
        path.filename().string().c_str(), asset.skeleton.jointCount(), plan.links.size(),
        plan.dofCount(), plan.total_mass_kg, plan.size_m, r.start_height, r.min_height,
        up ? "stayed up" : "fell");
    if (!up) std::printf(" at %.2f s", r.fall_time);
    std::printf("  max joint speed %.1f rad/s\n", r.max_joint_speed);
    EXPECT_TRUE(r.finite) << path;
    EXPECT_LT(r.max_joint_speed, kBlowUpRadPerS) << path;
    const bool stander = path.parent_path().filename() == "assets" &&
                         std::find(standers.begin(), standers.end(), path.filename().string()) !=
                             standers.end();
    if (stander) {
      EXPECT_TRUE(up) << path << ": the base fell from " << r.start_height << " m to "
                      << r.min_height << " m at " << r.fall_time << " s";
    }
  }
}

}  // namespace
}  // namespace sinew::physics
