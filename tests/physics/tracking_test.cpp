// Tracking a TargetMotion: the recurrence, honest runs with pushes, determinism, terrain,
// recording on the skeleton, and what balance feedback buys against pushes.
#include "sinew/physics/tracking.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "physics_test_util.h"
#include "sinew/physics/joint_figures.h"
#include "sinew/physics/simulation.h"

namespace sinew::physics {
namespace {

// The target's horizontal direction of travel at its start.
glm::dvec3 travelOf(const MotionState& state) {
  return glm::normalize(glm::dvec3(state.base_linear.x, 0.0, state.base_linear.z));
}

// A controller for a test of one feedback term: the target from its first instant (no ramp), no
// swing lift, no torso hold; `gains` sets the term under test. Null (a test failure) if refused.
std::unique_ptr<TrackingController> oneTermController(
    World& world, const test_util::Character& c, const LinkPose& pose,
    const std::function<void(BalanceGains&)>& gains) {
  TrackingSettings settings;
  settings.ramp_s = 0.0;
  settings.balance.torso = 0.0;
  settings.balance.swing_lift = 0.0;
  gains(settings.balance);
  auto made = TrackingController::create(world, c.asset.skeleton, c.target, pose, settings);
  if (!made.ok()) {
    ADD_FAILURE() << made.message();
    return nullptr;
  }
  return std::move(made.value());
}

TEST(FourierTargets, RecurrenceMatchesTheTargetsPose) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  spectral::TargetMotion target = biped.target;
  target.secondary.push_back({3, 0, 1.7, 0.02, 0.4});  // breathing on the chest
  FourierTargets fourier(target);
  EXPECT_GE(fourier.maxHarmonic(), 5);
  const size_t joints = static_cast<size_t>(biped.asset.skeleton.jointCount());
  std::vector<glm::dquat> fast(joints), exact(joints);
  std::vector<glm::dvec3> fast_translations(joints), translations(joints);
  double worst = 0.0, worst_m = 0.0;
  for (int k = 0; k < 2400; ++k) {  // 10 s at 240 Hz
    const double t = k / 240.0;
    fourier.evaluate(t, fast, fast_translations);
    target.pose(t, exact, translations);
    for (size_t j = 0; j < joints; ++j) {
      worst = std::max(worst, glm::length(rotationVectorOf(glm::inverse(exact[j]) * fast[j])));
      worst_m = std::max(worst_m, glm::length(fast_translations[j] - translations[j]));
    }
  }
  std::printf("recurrence vs sin() per harmonic over 10 s: worst %.2e rad, %.2e m\n", worst,
              worst_m);
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(worst_m, 1e-10);  // the root's travel of 13 m included
}

SimulationSettings shortRun(double seconds) {
  SimulationSettings s;
  s.seconds = seconds;
  return s;
}

// Over a whole run with two pushes nothing but gravity, the ground and the pushes acts on the
// character: the accumulators are empty before every step, and the momentum's change is exactly
// gravity's impulse plus the ground's plus the pushes'.
// Link origins for a pose, by forward kinematics (world metres).
std::vector<glm::dvec3> linkOrigins(const BodyPlan& plan, const LinkPose& pose) {
  const std::vector<glm::dquat> rotations = linkWorldRotations(plan, pose);
  std::vector<glm::dvec3> origins(plan.links.size(), pose.base_position);
  for (size_t li = 1; li < plan.links.size(); ++li) {
    const size_t parent = static_cast<size_t>(plan.links[li].parent);
    origins[li] = origins[parent] + rotations[parent] * plan.links[li].pivot;
  }
  return origins;
}

// A world of c's first pose (raised by `lift` metres) moving 1 m/s faster than the target along
// its travel, and a oneTermController on it whose `gains` set the term under test.
struct AheadOfTarget {
  MotionState state;
  glm::dvec3 travel{0.0};  // the target's direction of travel (travelOf)
  std::unique_ptr<World> world;
  std::unique_ptr<TrackingController> controller;
  std::vector<double> zero;  // (dofs) no extra torques for World::step
};
// Either pointer is null (and a test failure added) if refused.
AheadOfTarget aheadOfTarget(const test_util::Character& c,
                            const std::function<void(BalanceGains&)>& gains, double lift = 0.0) {
  AheadOfTarget a;
  a.state = targetState(c.plan, c.asset.skeleton, c.target, 0.0);
  a.state.pose.base_position.y += lift;
  a.world = World::create(c.plan, a.state.pose).value();
  a.travel = travelOf(a.state);
  if (!a.world->setVelocities(a.state.base_linear + a.travel, a.state.base_angular,
                              a.state.joint_velocities).ok()) {
    ADD_FAILURE() << "setVelocities refused";
    a.world.reset();
    return a;
  }
  a.controller = oneTermController(*a.world, c, a.state.pose, gains);
  a.zero.assign(static_cast<size_t>(a.world->dofCount()), 0.0);
  return a;
}

// A world at the target's first pose (at rest) with a controller of `settings` on it; nulls (a
// test failure) if refused.
struct AtTarget {
  std::unique_ptr<World> world;
  std::unique_ptr<TrackingController> controller;
  std::vector<double> zero;  // (dofs) no torques of the test's own
};
AtTarget startAtTarget(const test_util::Character& c, const TrackingSettings& settings) {
  AtTarget a;
  const MotionState state = targetState(c.plan, c.asset.skeleton, c.target, 0.0);
  a.world = World::create(c.plan, state.pose).value();
  auto made = TrackingController::create(*a.world, c.asset.skeleton, c.target, state.pose, settings);
  if (!made.ok()) {
    ADD_FAILURE() << made.message();
    return a;
  }
  a.controller = std::move(made.value());
  a.zero.assign(static_cast<size_t>(a.world->dofCount()), 0.0);
  return a;
}

// The target's pose at time t, in link coordinates.
LinkPose targetPoseAt(const test_util::Character& c, double t) {
  const size_t joints = static_cast<size_t>(c.asset.skeleton.jointCount());
  std::vector<glm::dquat> rotations(joints);
  std::vector<glm::dvec3> translations(joints);
  c.target.pose(t, rotations, translations);
  return linkPoseFromSkeleton(c.plan, c.asset.skeleton, rotations, translations);
}

// A swing leg's placement: the leg (hip to foot) in the servos' target, on the base as it is, and
// in the motion's, on the motion's base, and the angle between them, rad.
struct LegTurn {
  glm::dvec3 placed, tracked;
  double turned = 0.0;
};
LegTurn legTurn(const BodyPlan& plan, const World& world, const TrackingController& controller,
                int hip, int foot) {
  std::vector<glm::dmat4> transforms(plan.links.size());
  world.linkTransforms(transforms);
  auto leg = [&](LinkPose pose, const glm::dquat& base) {
    pose.base_rotation = base;
    const std::vector<glm::dvec3> o = linkOrigins(plan, pose);
    return o[static_cast<size_t>(foot)] - o[static_cast<size_t>(hip)];
  };
  LegTurn t;
  t.placed = leg(controller.target(), glm::normalize(glm::quat_cast(glm::dmat3(transforms[0]))));
  t.tracked = leg(controller.motionTarget(), controller.motionTarget().base_rotation);
  t.turned = std::acos(
      std::clamp(glm::dot(glm::normalize(t.placed), glm::normalize(t.tracked)), -1.0, 1.0));
  return t;
}

std::vector<int> footLinks(const BodyPlan& plan) {
  std::vector<int> feet;
  for (size_t li = 0; li < plan.links.size(); ++li)
    if (plan.links[li].foot) feet.push_back(static_cast<int>(li));
  return feet;
}

// The bundled walk's feet swing alternately, half a stride apart, each clear of the ground (a
// third of its swing's height up) for about a quarter of the stride.
TEST(TargetFootCycles, TheWalksFeetSwingAlternately) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const std::vector<int> feet = footLinks(biped.plan);
  ASSERT_EQ(feet.size(), 2u);
  const std::vector<FootCycle> cycles =
      targetFootCycles(biped.plan, biped.asset.skeleton, biped.target, feet);
  const double period = biped.target.period();
  for (const FootCycle& c : cycles) {
    ASSERT_GE(c.liftoff_s, 0.0);
    ASSERT_GE(c.touchdown_s, 0.0);
    const double swing = std::fmod(c.touchdown_s - c.liftoff_s + period, period);
    std::printf("swing %.3f to %.3f s: %.0f%% of the %.3f s stride\n", c.liftoff_s, c.touchdown_s,
                100.0 * swing / period, period);
    EXPECT_GT(swing, 0.15 * period);
    EXPECT_LT(swing, 0.45 * period);
  }
  const double apart = std::fmod(cycles[1].touchdown_s - cycles[0].touchdown_s + period, period);
  EXPECT_NEAR(apart, 0.5 * period, 0.08 * period);
}

// At mid-swing the target the servos get has the swing foot raised by swing_lift x rig size,
// straight up, with the foot's attitude unchanged; the motion's own target is left as it was.
TEST(TrackingController, SwingLiftRaisesTheSwingFootStraightUp) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const std::vector<int> feet = footLinks(biped.plan);
  const FootCycle cycle =
      targetFootCycles(biped.plan, biped.asset.skeleton, biped.target, feet)[0];
  const double period = biped.target.period();
  const double middle =
      cycle.liftoff_s + 0.5 * std::fmod(cycle.touchdown_s - cycle.liftoff_s + period, period);
  const MotionState state = targetState(biped.plan, biped.asset.skeleton, biped.target, 0.0);
  std::unique_ptr<World> world = World::create(biped.plan, state.pose).value();
  TrackingSettings settings;
  settings.feedback = false;  // only the lift tells the two targets apart
  settings.balance.swing_lift = 0.03;
  auto made = TrackingController::create(*world, biped.asset.skeleton, biped.target, state.pose,
                                         settings);
  ASSERT_TRUE(made.ok()) << made.message();
  TrackingController& controller = *made.value();
  std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0);
  while (world->time() + 0.5 * world->dt() < middle) {
    controller.update(*world);
    world->step(zero);
  }
  controller.update(*world);
  const size_t foot = static_cast<size_t>(feet[0]);
  const glm::dvec3 lifted = linkOrigins(biped.plan, controller.target())[foot];
  const glm::dvec3 tracked = linkOrigins(biped.plan, controller.motionTarget())[foot];
  const glm::dvec3 moved = lifted - tracked;
  const double asked = 0.03 * biped.plan.size_m;
  std::printf("asked %.1f cm: up %.2f cm, sideways %.2f cm\n", 100.0 * asked, 100.0 * moved.y,
              100.0 * glm::length(glm::dvec2(moved.x, moved.z)));
  EXPECT_NEAR(moved.y, asked, 0.1 * asked);
  EXPECT_LT(glm::length(glm::dvec2(moved.x, moved.z)), 0.1 * asked);
  const glm::dquat a = linkWorldRotations(biped.plan, controller.target())[foot];
  const glm::dquat b = linkWorldRotations(biped.plan, controller.motionTarget())[foot];
  EXPECT_LT(glm::length(rotationVectorOf(glm::inverse(a) * b)), 1e-9);
  // The other foot stands: its target is the motion's.
  const size_t other = static_cast<size_t>(feet[1]);
  EXPECT_LT(glm::length(linkOrigins(biped.plan, controller.target())[other] -
                        linkOrigins(biped.plan, controller.motionTarget())[other]),
            1e-9);
}

// The stance gains move a planted foot's target by gain x the centre of mass's velocity error:
// a body started 1 m/s faster than the target has its stance foot's target moved forward by
// about stance_sagittal x 1 m (the ground holds the foot, so the servos hold the body back).
TEST(TrackingController, StanceGainsMoveThePlantedFootAgainstTheVelocityError) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  AheadOfTarget run = aheadOfTarget(biped, [](BalanceGains& g) { g.stance_sagittal = 0.05; });
  ASSERT_TRUE(run.world && run.controller);
  World* world = run.world.get();
  TrackingController& controller = *run.controller;
  const glm::dvec3 travel = run.travel;
  const std::vector<double>& zero = run.zero;
  const std::vector<int> feet = footLinks(biped.plan);
  glm::dvec3 previous_com(0.0);
  int checked = 0;
  for (int k = 0; k < 40 && checked == 0; ++k) {
    controller.update(*world);
    const glm::dvec3 com = poseKinematics(biped.plan, controller.motionTarget()).com;
    const glm::dvec3 error =
        world->linearMomentum() / world->totalMass() - (com - previous_com) / world->dt();
    previous_com = com;
    for (int foot : feet) {
      const size_t f = static_cast<size_t>(foot);
      if (k < 2 || world->linkContacts()[f] == 0) continue;
      const glm::dvec3 moved = linkOrigins(biped.plan, controller.target())[f] -
                               linkOrigins(biped.plan, controller.motionTarget())[f];
      const double asked = 0.05 * glm::dot(error, travel);
      std::printf("step %d, foot %zu: velocity error %.2f m/s forward; foot moved %.1f cm "
                  "forward (asked %.1f), %.1f cm up\n",
                  k, f, glm::dot(error, travel), 100.0 * glm::dot(moved, travel), 100.0 * asked,
                  100.0 * moved.y);
      EXPECT_GT(asked, 0.02);  // the body still runs ahead of the target
      EXPECT_NEAR(glm::dot(moved, travel), asked, 0.15 * asked);
      ++checked;
    }
    world->step(zero);
  }
  EXPECT_GT(checked, 0) << "no foot came down in 40 steps";
}

// stance_yaw turns the planted feet's targets about the vertical through the target's centre of
// mass against the heading error: a trotter started turned 0.2 rad to the left of its target
// (error -0.2 rad) has each planted foot's target moved by 0.2 x gain x (up x its arm), the front
// feet to the left, the hind feet to the right, so the ground turns the body back to the right.
TEST(TrackingController, StanceYawTurnsThePlantedFeetAgainstTheHeadingError) {
  const test_util::Character trot = test_util::loadCharacter("quadruped_trot.bvh");
  ASSERT_FALSE(trot.plan.links.empty());
  MotionState state = targetState(trot.plan, trot.asset.skeleton, trot.target, 0.0);
  const double turned = 0.2;
  state.pose.base_rotation =
      glm::angleAxis(turned, glm::dvec3(0.0, 1.0, 0.0)) * state.pose.base_rotation;
  std::unique_ptr<World> world = World::create(trot.plan, state.pose).value();
  std::unique_ptr<TrackingController> made = oneTermController(
      *world, trot, state.pose, [](BalanceGains& g) { g.stance_yaw = 0.3; });
  ASSERT_TRUE(made);
  TrackingController& controller = *made;
  const std::vector<int> feet = footLinks(trot.plan);
  std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0);
  bool front = false, hind = false;  // a foot ahead of the centre of mass checked, one behind
  for (int k = 0; k < 60 && !(front && hind); ++k) {
    controller.update(*world);
    const PoseKinematics reference = poseKinematics(trot.plan, controller.motionTarget());
    for (int foot : feet) {
      const size_t f = static_cast<size_t>(foot);
      if (world->linkContacts()[f] == 0) continue;
      const glm::dvec3 moved = linkOrigins(trot.plan, controller.target())[f] -
                               linkOrigins(trot.plan, controller.motionTarget())[f];
      const glm::dvec3 arm = reference.pivots[f] - reference.com;
      const glm::dvec3 asked = 0.3 * turned * glm::dvec3(arm.z, 0.0, -arm.x);
      std::printf("step %d, foot %zu: arm %.1f cm, moved %.2f cm (asked %.2f cm), %.0f%% along it\n",
                  k, f, 100.0 * glm::length(glm::dvec2(arm.x, arm.z)), 100.0 * glm::length(moved),
                  100.0 * glm::length(asked),
                  100.0 * glm::dot(moved, asked) / glm::dot(asked, asked));
      EXPECT_GT(glm::length(asked), 0.01);
      EXPECT_LT(glm::length(moved - asked), 0.15 * glm::length(asked));
      const double ahead = glm::dot(arm, state.base_linear);  // the trot travels forward
      front = front || ahead > 0.0;
      hind = hind || ahead < 0.0;
    }
    world->step(zero);
  }
  EXPECT_TRUE(front && hind) << "no front and hind foot down in 60 steps";
}

// stance_yield slows the servos of every leg whose foot is down, and of no other joint: step by
// step through the biped's first half second, a planted foot and its leg's links (hip, knee) run at
// servo_rate x (1 - yield), the swinging leg and the upper body at servo_rate; without the gain
// the controller asks for no rates of its own.
TEST(TrackingController, StanceYieldSlowsThePlantedLegsServosOnly) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const BodyPlan& plan = biped.plan;
  const MotionState state = targetState(plan, biped.asset.skeleton, biped.target, 0.0);
  std::unique_ptr<World> world = World::create(plan, state.pose).value();
  std::unique_ptr<TrackingController> made = oneTermController(
      *world, biped, state.pose, [](BalanceGains& g) { g.stance_yield = 0.75; });
  ASSERT_TRUE(made);
  TrackingController& controller = *made;
  const std::vector<int> feet = footLinks(plan);
  const double rate = TrackingSettings().servo_rate;
  std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0);
  int planted_steps = 0, swing_steps = 0;
  for (int k = 0; k < 120; ++k) {
    controller.update(*world);
    const std::vector<double>& rates = controller.servoRates();
    ASSERT_EQ(rates.size(), plan.links.size());
    std::vector<char> planted_leg(plan.links.size(), 0);
    for (int foot : feet) {  // the foot, and its leg up to the link that carries another foot
      if (world->linkContacts()[static_cast<size_t>(foot)] == 0) continue;
      for (int li = foot; li > 0; li = plan.links[static_cast<size_t>(li)].parent) {
        bool shared = false;
        for (int other : feet) shared = shared || (other != foot && isAncestorLink(plan, li, other));
        if (shared) break;
        planted_leg[static_cast<size_t>(li)] = 1;
      }
    }
    for (size_t li = 1; li < plan.links.size(); ++li)
      EXPECT_DOUBLE_EQ(rates[li], planted_leg[li] ? rate * 0.25 : rate)
          << plan.links[li].name << " at step " << k;
    for (int foot : feet)
      (world->linkContacts()[static_cast<size_t>(foot)] ? planted_steps : swing_steps) += 1;
    world->step(zero);
  }
  std::printf("feet planted in %d foot-steps, in the air in %d\n", planted_steps, swing_steps);
  EXPECT_GT(planted_steps, 0);
  EXPECT_GT(swing_steps, 0);  // both cases were seen

  std::unique_ptr<World> other = World::create(plan, state.pose).value();
  std::unique_ptr<TrackingController> plain =
      oneTermController(*other, biped, state.pose, [](BalanceGains&) {});
  ASSERT_TRUE(plain);
  plain->update(*other);
  EXPECT_TRUE(plain->servoRates().empty());
}

// The motion the feedback compares the body with is the target's whole pose, its travel
// included: the reference centre of mass moves at the clip's speed (it stood still before, so
// the velocity gains saw the whole walking speed as an error).
TEST(TrackingController, TheMotionTargetTravelsWithTheTarget) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  TrackingSettings settings;
  settings.ramp_s = 0.0;
  AtTarget run = startAtTarget(biped, settings);
  ASSERT_TRUE(run.controller);
  World* world = run.world.get();
  TrackingController& controller = *run.controller;
  glm::dvec3 first(0.0);
  while (world->time() < 1.0) {
    controller.update(*world);
    const LinkPose expected = targetPoseAt(biped, world->time());
    ASSERT_LT(glm::length(controller.motionTarget().base_position - expected.base_position), 1e-9)
        << "at " << world->time() << " s";
    if (world->stepCount() == 0) first = expected.base_position;
    world->step(run.zero);
  }
  const glm::dvec3 moved = controller.motionTarget().base_position - first;
  const double speed = glm::length(glm::dvec2(moved.x, moved.z)) / world->time();
  std::printf("the motion target travelled %.2f m/s\n", speed);
  EXPECT_GT(speed, 0.5);  // the bundled walk's 1.3 m/s, give or take its sway within a second
}

// With a lead the servos are given the pose that far ahead; the motion target (the feedback's and
// the tracking error's reference) stays at the present.
TEST(TrackingController, ALeadGivesTheServosThePoseAheadAndKeepsTheMotionTargetNow) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  TrackingSettings settings;
  settings.ramp_s = 0.0;
  settings.feedback = false;
  settings.balance.swing_lift = 0.0;  // the targets as the motion has them
  settings.servo_lead_s = servoLag(240.0, settings.servo_rate);
  EXPECT_NEAR(settings.servo_lead_s, 1.0 / 48.0, 1e-12);
  AtTarget run = startAtTarget(biped, settings);
  ASSERT_TRUE(run.controller);
  World* world = run.world.get();
  TrackingController& controller = *run.controller;
  double moved = 0.0;  // how far the lead moves the servos' targets, rad, summed
  while (world->time() < 0.5) {
    controller.update(*world);
    const LinkPose now = targetPoseAt(biped, world->time());
    const LinkPose ahead = targetPoseAt(biped, world->time() + settings.servo_lead_s);
    for (size_t li = 1; li < biped.plan.links.size(); ++li) {
      ASSERT_LT(1.0 - std::abs(glm::dot(controller.motionTarget().rotations[li], now.rotations[li])),
                1e-12);
      ASSERT_LT(1.0 - std::abs(glm::dot(controller.target().rotations[li], ahead.rotations[li])),
                1e-12);
      moved += 2.0 * std::acos(std::min(1.0, std::abs(glm::dot(now.rotations[li],
                                                                ahead.rotations[li]))));
    }
    world->step(run.zero);
  }
  EXPECT_GT(moved, 1.0);  // the lead is not the present pose again

  settings.servo_lead_s = 1.5;
  EXPECT_NE(settings.validate().message().find("servo_lead_s"), std::string::npos);
}

// A planted leg's servos yield: they close (1 - stance_yield) of what the others do a step, so
// they trail by the lead / (1 - stance_yield) and are given the motion that far ahead; a leg in
// the air keeps the one lead. The feedback's gains are 0 so that only the swing hip (placed
// relative to the base as it is) differs from the motion. Without lead_yielding_legs (a
// best.json from before it) every leg has the one lead.
void expectPlantedLegsLedBy(double yielding_lead_factor, bool lead_yielding_legs) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  TrackingSettings settings;
  settings.ramp_s = 0.0;
  settings.balance = BalanceGains{};
  settings.balance.torso = 0.0;
  settings.balance.swing_lift = 0.0;
  settings.balance.stance_yield = 0.5;
  settings.servo_lead_s = servoLag(240.0, settings.servo_rate);
  settings.lead_yielding_legs = lead_yielding_legs;
  AtTarget run = startAtTarget(biped, settings);
  ASSERT_TRUE(run.controller);
  World* world = run.world.get();
  TrackingController& controller = *run.controller;
  const BodyPlan& plan = biped.plan;
  std::vector<int> feet;
  for (size_t li = 0; li < plan.links.size(); ++li)
    if (plan.links[li].foot) feet.push_back(static_cast<int>(li));
  ASSERT_EQ(feet.size(), 2u);
  auto legOf = [&](int li) {  // the foot whose leg holds link li, -1 for none
    for (size_t f = 0; f < feet.size(); ++f)
      if (isAncestorLink(plan, li, feet[f]) && !isAncestorLink(plan, li, feet[1 - f]))
        return static_cast<int>(f);
    return -1;
  };
  int planted = 0, swinging = 0;  // leg-steps seen of each kind
  while (world->time() < 0.6) {
    const std::vector<std::uint8_t> contacts = world->linkContacts();
    controller.update(*world);
    const double t = world->time();
    const LinkPose led = targetPoseAt(biped, t + settings.servo_lead_s);
    const LinkPose yielding = targetPoseAt(biped, t + settings.servo_lead_s * yielding_lead_factor);
    for (size_t li = 1; li < plan.links.size(); ++li) {
      const int f = legOf(static_cast<int>(li));
      if (f < 0) continue;
      const bool down = contacts[static_cast<size_t>(feet[static_cast<size_t>(f)])] != 0;
      const bool hip = legOf(plan.links[li].parent) < 0;
      if (!down && hip) continue;  // the swing hip is placed (placeSwingFoot)
      const glm::dquat& expected = down ? yielding.rotations[li] : led.rotations[li];
      ASSERT_LT(1.0 - std::abs(glm::dot(controller.target().rotations[li], expected)), 1e-9)
          << plan.links[li].name << " at " << t << (down ? " planted" : " in the air");
      ASSERT_NEAR(controller.target().angles[li], down ? yielding.angles[li] : led.angles[li], 1e-9);
      (down ? planted : swinging) += 1;
    }
    world->step(run.zero);
  }
  EXPECT_GT(planted, 100);
  EXPECT_GT(swinging, 100);
}

TEST(TrackingController, APlantedLegThatYieldsIsLedByItsOwnLag) {
  expectPlantedLegsLedBy(1.0 / (1.0 - 0.5), true);
  expectPlantedLegsLedBy(1.0, false);
}

// A servo closing a fifth of its error a step trails a moving target by dt / 0.2 (servoLag):
// in free flight (no gravity, no ground, no feedback) leading the targets by that lag takes most
// of the tracking error out. The stepper's joints: 3.0 deg RMS without the lead, 1.0 with it.
TEST(Simulation, LeadingTheServosByTheirLagTakesItOutOfTheTracking) {
  const test_util::Character stepper = test_util::loadCharacter("stepper_step.bvh");
  ASSERT_FALSE(stepper.plan.links.empty());
  SimulationSettings settings;
  settings.seconds = 3.0;
  settings.world.gravity_m_s2 = 0.0;
  settings.world.ground_height_m = -50.0;
  settings.world.place_on_ground = false;
  settings.tracking.feedback = false;
  settings.stop_at_fall = false;
  double error_deg[2] = {0.0, 0.0};
  for (int led = 0; led < 2; ++led) {
    settings.tracking.servo_lead_s =
        led ? servoLag(settings.world.step_hz, settings.tracking.servo_rate) : 0.0;
    Result<SimulationReport> run =
        simulate(stepper.plan, stepper.asset.skeleton, stepper.target, settings);
    ASSERT_TRUE(run.ok()) << run.message();
    error_deg[led] = run.value().track_err_rad_rms * 180.0 / std::numbers::pi;
  }
  std::printf("free flight tracking: %.2f deg without the lead, %.2f deg with it\n", error_deg[0],
              error_deg[1]);
  EXPECT_GT(error_deg[0], 2.0);
  EXPECT_LT(error_deg[1], 0.4 * error_deg[0]);
}

TEST(Simulation, OnlyGravityGroundAndScheduledPushesAct) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const LinkPose standing = standingPose(biped.plan, biped.asset.skeleton);
  std::unique_ptr<World> world = World::create(biped.plan, standing).value();
  auto controller = TrackingController::create(*world, biped.asset.skeleton, biped.target, standing);
  ASSERT_TRUE(controller.ok()) << controller.message();
  std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0);
  const glm::dvec3 p0 = world->linearMomentum();
  glm::dvec3 ground(0.0);
  for (int s = 0; s < 720; ++s) {
    if (s == 120) {
      ASSERT_TRUE(world->push(0, glm::dvec3(40.0, 0.0, 0.0)).ok());
    }
    if (s == 400) {
      ASSERT_TRUE(world->push(3, glm::dvec3(0.0, 0.0, -15.0)).ok());
    }
    controller.value()->update(*world);
    world->step(zero);
    ground += world->lastContactImpulse();
  }
  const ExternalLoads& loads = world->externalLoads();
  EXPECT_EQ(loads.max_base_force_n, 0.0);
  EXPECT_EQ(loads.max_base_torque_nm, 0.0);
  EXPECT_EQ(loads.max_link_force_n, 0.0);
  EXPECT_EQ(loads.max_link_torque_nm, 0.0);
  EXPECT_EQ(world->pushedImpulse(), glm::dvec3(40.0, 0.0, -15.0));
  // The ground's impulse is read from the contact points after each step; over a run with
  // slips and landings it does not close the balance exactly (printed), so the pushes are
  // accounted for exactly in the air below.
  const glm::dvec3 gravity(0.0, -9.81 * world->totalMass() * world->time(), 0.0);
  const glm::dvec3 residual = world->linearMomentum() - p0 - (gravity + ground + world->pushedImpulse());
  std::printf("momentum balance over 3 s of tracking with pushes: residual %.2f N s of %.0f N s "
              "gravity\n", glm::length(residual), glm::length(gravity));
}

// A push delivers exactly its impulse: the same run with and without it, in the air with the
// servos working, differ in momentum by the impulse right after the push's step.
TEST(Simulation, PushesDeliverExactlyTheirImpulse) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const LinkPose standing = standingPose(biped.plan, biped.asset.skeleton);
  WorldSettings high;
  high.ground_height_m = -1000.0;
  high.place_on_ground = false;
  const glm::dvec3 impulse(25.0, 10.0, -15.0);
  int chest = 0;  // a heavy link: a 30 N s kick on a hand would exceed Bullet's joint speed clamp
  for (size_t li = 0; li < biped.plan.links.size(); ++li)
    if (biped.plan.links[li].name == "Chest") chest = static_cast<int>(li);
  ASSERT_GT(chest, 0);
  glm::dvec3 momentum[2];
  glm::dvec3 delivered[2];
  for (int pushed = 0; pushed < 2; ++pushed) {
    std::unique_ptr<World> world = World::create(biped.plan, standing, high).value();
    auto controller = TrackingController::create(*world, biped.asset.skeleton, biped.target, standing);
    ASSERT_TRUE(controller.ok()) << controller.message();
    std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0);
    for (int s = 0; s <= 100; ++s) {
      if (s == 100 && pushed == 1) {
        ASSERT_TRUE(world->push(chest, impulse).ok());
      }
      controller.value()->update(*world);
      world->step(zero);
    }
    momentum[pushed] = world->linearMomentum();
    delivered[pushed] = world->pushedImpulse();
    EXPECT_EQ(world->externalLoads().max_link_force_n, 0.0);
  }
  const double error = glm::length(momentum[1] - momentum[0] - impulse);
  std::printf("push of %.1f N s: momentum changed by it to %.2e N s\n", glm::length(impulse), error);
  EXPECT_LT(error, 3e-3 * glm::length(impulse));  // measured 1e-3 of it
  EXPECT_EQ(delivered[1], impulse);
  EXPECT_EQ(delivered[0], glm::dvec3(0.0));
  ASSERT_FALSE(World::create(biped.plan, standing).value()->push(99, impulse).ok());
}

TEST(Simulation, SameInputsGiveBitIdenticalRecordings) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  SimulationSettings settings = shortRun(2.0);
  settings.pushes.push_back({0.5, glm::dvec3(20.0, 0.0, 0.0), ""});
  const SimulationReport a = simulate(biped.plan, biped.asset.skeleton, biped.target, settings).value();
  const SimulationReport b = simulate(biped.plan, biped.asset.skeleton, biped.target, settings).value();
  ASSERT_EQ(a.motion.rotations.size(), b.motion.rotations.size());
  EXPECT_EQ(0, std::memcmp(a.motion.rotations.data(), b.motion.rotations.data(),
                           a.motion.rotations.size() * sizeof(glm::dquat)));
  EXPECT_EQ(0, std::memcmp(a.motion.translations.data(), b.motion.translations.data(),
                           a.motion.translations.size() * sizeof(glm::dvec3)));
  EXPECT_EQ(a.energy_j, b.energy_j);
  EXPECT_EQ(a.distance_m, b.distance_m);
}

// The recording's first frame is the start pose on the skeleton: every joint with a body of its
// own at its simulated rotation, which at t = 0 is the target's.
TEST(Simulation, RecordingStartsAtTheTargetsPoseOnTheSkeleton) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const motion::Skeleton& skeleton = biped.asset.skeleton;
  SimulationSettings settings = shortRun(1.0);
  settings.record_fps = 60.0;
  const SimulationReport r = simulate(biped.plan, skeleton, biped.target, settings).value();
  EXPECT_EQ(r.motion.frame_count, 61);
  EXPECT_TRUE(r.motion.validate(skeleton).ok());
  const size_t joints = static_cast<size_t>(skeleton.jointCount());
  std::vector<glm::dquat> rotations(joints);
  std::vector<glm::dvec3> translations(joints);
  biped.target.pose(0.0, rotations, translations);
  // World positions of the joints at frame 0 against the target's (the base placed on the
  // ground may sit a few millimetres off in height).
  const std::vector<glm::dvec3> recorded = motion::worldPositions(skeleton, r.motion, 0);
  motion::Clip reference = motion::restClip(skeleton, 1, 1.0 / 30.0);
  reference.rotations = rotations;
  reference.translations = translations;
  const std::vector<glm::dvec3> wanted = motion::worldPositions(skeleton, reference, 0);
  const glm::dvec3 shift = recorded[0] - wanted[0];
  double worst = 0.0;
  for (size_t j = 0; j < joints; ++j) worst = std::max(worst, glm::length(recorded[j] - wanted[j] - shift));
  std::printf("recorded frame 0 vs target: worst joint %.2e m (root shifted %.4f m)\n", worst,
              glm::length(shift));
  EXPECT_LT(worst, 1e-6);
}

TEST(Simulation, EveryTerrainBuildsAndSimulates) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  using Kind = TerrainSettings::Kind;
  for (Kind kind : {Kind::kFlat, Kind::kSlope, Kind::kSteps, Kind::kRough}) {
    WorldSettings ws;
    ws.terrain.kind = kind;
    ws.terrain.slope_deg = 3.0;
    ws.terrain.step_start_m = 1.0;
    ws.terrain.amplitude_m = 0.01;
    const test_util::HoldResult r =
        test_util::holdWithServos(biped.plan, standingPose(biped.plan, biped.asset.skeleton), 3.0, ws);
    std::printf("%-6s pelvis %.3f -> lowest %.3f m, fell at %.2f s (-1: stood), fastest joint %.2f rad/s\n",
                terrainKindName(kind), r.start_height, r.min_height, r.fall_time, r.max_joint_speed);
    EXPECT_TRUE(r.finite) << terrainKindName(kind);
    EXPECT_LT(r.max_joint_speed, 99.0) << terrainKindName(kind);
    // Level soles on a slope or on bumps stand on their edges: a statue topples there (printed);
    // on flat ground and before the first step it stands.
    if (kind == Kind::kFlat || kind == Kind::kSteps) {
      EXPECT_LT(r.fall_time, 0.0) << terrainKindName(kind);
    }
  }
  // The ground's height where it should be.
  WorldSettings steps;
  steps.terrain.kind = Kind::kSteps;
  steps.terrain.step_height_m = 0.1;
  steps.terrain.step_depth_m = 0.5;
  steps.terrain.step_start_m = 2.0;
  const LinkPose standing = standingPose(biped.plan, biped.asset.skeleton);
  std::unique_ptr<World> world = World::create(biped.plan, standing, steps).value();
  EXPECT_DOUBLE_EQ(world->groundHeight(0.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(world->groundHeight(0.0, 2.2), 0.1);
  EXPECT_DOUBLE_EQ(world->groundHeight(3.0, 3.1), 0.3);
  WorldSettings bad;
  bad.terrain.kind = Kind::kSlope;
  bad.terrain.slope_deg = 60.0;
  Result<std::unique_ptr<World>> refused = World::create(biped.plan, standing, bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("terrain.slope_deg"), std::string::npos) << refused.message();
}

}  // namespace
}  // namespace sinew::physics

namespace sinew::physics {
namespace {

// The printed comparison the physics issue asks for: the largest push (forward, backward and
// sideways, on the pelvis, 0.5 s into a walk, in steps of 5 N s) the biped takes without falling
// in the next 1.5 s, with and without balance feedback.
//
// Printed, not asserted either way: with the default feedback gains the un-evolved walk is
// chaotic in the order in which Bullet's solver visits its constraints. Adding constraints that
// never act (Bullet sorts its list by island with an unstable sort, so the order depends on the
// list's length) turned this comparison from "backward: 80 N s with feedback, 5 without" into
// "with feedback it falls within 2 s unpushed" and back (15 orders, docs/physics.md); the ball
// ranges' constraints are such a change. What held in every order: without feedback the walk
// lasts the 2 s.
TEST(Simulation, BalanceFeedbackAgainstPushes) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  auto survives = [&](bool feedback, double impulse, const glm::dvec3& direction) {
    SimulationSettings settings;
    settings.seconds = 2.0;
    settings.tracking.feedback = feedback;
    settings.pushes.push_back({0.5, impulse * direction, ""});
    const SimulationReport r = simulate(biped.plan, biped.asset.skeleton, biped.target, settings).value();
    return !r.fell;
  };
  for (const glm::dvec3& direction : {glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1), glm::dvec3(1, 0, 0)}) {
    double largest[2] = {-1.0, -1.0};
    for (int feedback = 0; feedback < 2; ++feedback)
      for (double impulse = 0.0; impulse <= 150.0; impulse += 5.0) {
        if (!survives(feedback != 0, impulse, direction)) break;
        largest[feedback] = impulse;
      }
    std::printf(
        "push along (%+.0f, %+.0f, %+.0f) at 0.5 s: survives %.0f N s without feedback, %.0f N s "
        "with (-1: falls unpushed)\n",
        direction.x, direction.y, direction.z, largest[0], largest[1]);
    EXPECT_GE(largest[0], 0.0) << "direction " << direction.x << " " << direction.z;
  }
}

// A fall says which way the body went, in the frame of the heading the target faces (the
// bundled walk faces +Z, its left is +X): a hard push on the pelvis without feedback fells it
// the way it was pushed.
TEST(Simulation, AFallSaysWhichWayTheBodyWent) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const struct {
    glm::dvec3 push;
    const char* way;
  } cases[] = {{{0, 0, 150}, "forwards: "},
               {{0, 0, -150}, "backwards: "},
               {{150, 0, 0}, "to the left: "},
               {{-150, 0, 0}, "to the right: "}};
  for (const auto& c : cases) {
    SimulationSettings settings;
    settings.seconds = 3.0;
    settings.tracking.feedback = false;
    settings.pushes.push_back({0.5, c.push, ""});
    const SimulationReport r =
        simulate(biped.plan, biped.asset.skeleton, biped.target, settings).value();
    ASSERT_TRUE(r.fell) << c.way;
    EXPECT_EQ(r.fall_reason.rfind(c.way, 0), 0u) << r.fall_reason;
  }
}

// The report counts the steps a joint's servo spends at its torque limit: none with limits far
// above what the walk asks, most of them for the legs that carry the body when those are weak.
TEST(Simulation, TheReportCountsStepsAtTheTorqueLimit) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  auto limited = [&](double support_scale, double limb_scale) {
    SimulationSettings settings;
    settings.seconds = 0.5;
    settings.stop_at_fall = false;
    settings.tracking.support_torque_scale = support_scale;
    settings.tracking.limb_torque_scale = limb_scale;
    return simulate(biped.plan, biped.asset.skeleton, biped.target, settings).value();
  };
  const SimulationReport strong = limited(100.0, 100.0);
  ASSERT_EQ(strong.torque_limited_share.size(), biped.plan.links.size());
  ASSERT_EQ(strong.links.size(), biped.plan.links.size());
  for (double share : strong.torque_limited_share) EXPECT_EQ(share, 0.0);
  const SimulationReport weak = limited(0.01, 100.0);
  for (size_t li = 1; li < biped.plan.links.size(); ++li) {
    const double share = weak.torque_limited_share[li];
    EXPECT_GE(share, 0.0);
    EXPECT_LE(share, 1.0);
    if (biped.plan.links[li].supports) EXPECT_GT(share, 0.5) << weak.links[li];
    else EXPECT_EQ(share, 0.0) << weak.links[li];
  }
}

// The lines an artist reads: the joints at their torque limit 5% of the steps or more, busiest
// first, four at most; the three joints furthest from the target, in degrees; nothing from the
// base (link 0) and nothing when no joint qualifies.
TEST(Simulation, JointLinesNameTheBusiestAndTheFurthestJoints) {
  JointFigures f;
  f.links = {"Hips", "Knee_L", "Knee_R", "Hip_L", "Hip_R", "Ankle_L", "Ankle_R"};
  f.torque_limited_share = {0.9, 0.31, 0.049, 0.26, 0.5, 0.05, 0.07};
  f.track_err_by_link_rad = {1.0, 0.0, 0.1, 0.2, 0.05, 0.3, 0.0};
  EXPECT_EQ(torqueLimitLine(f),
            "at the torque limit: Hip_R 50%, Knee_L 31%, Hip_L 26%, Ankle_R 7% of the steps "
            "(and more)");
  EXPECT_EQ(furthestJointsLine(f, "the clip"),
            "furthest from the clip: Ankle_L 17.2, Hip_L 11.5, Knee_R 5.7 deg RMS");
  f.torque_limited_share = {0.9, 0.01, 0.0, 0.049, 0.0, 0.0, 0.0};
  f.track_err_by_link_rad.assign(f.links.size(), 0.0);
  EXPECT_EQ(torqueLimitLine(f), "");
  EXPECT_EQ(furthestJointsLine(f, "the clip"), "");
  EXPECT_EQ(torqueLimitLine(JointFigures{}), "");  // a report without links (another process's)
}

// Settings for a traced run of `seconds`.
SimulationSettings tracedSettings(double seconds) {
  SimulationSettings settings;
  settings.seconds = seconds;
  settings.trace = true;
  return settings;
}

// A traced run keeps one row per step that agrees with the report's own counts (contacts, steps
// at the torque limit), the target's centre of mass starts where the body's does and moves as
// the motion does, and every number is finite; a traced run longer than the cap is refused.
TEST(Simulation, ATraceRecordsEveryStepAsTheReportCountsIt) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  SimulationSettings settings = tracedSettings(0.5);
  const SimulationReport r = simulate(biped.plan, biped.asset.skeleton, biped.target, settings).value();
  ASSERT_FALSE(r.fell) << r.fall_reason;
  const double dt = 1.0 / settings.world.step_hz;
  ASSERT_EQ(r.trace.size(), 120u);
  std::vector<double> down(r.feet.size(), 0.0), limited(biped.plan.links.size(), 0.0);
  std::vector<double> squared(biped.plan.links.size(), 0.0);
  for (size_t k = 0; k < r.trace.size(); ++k) {
    const TraceStep& step = r.trace[k];
    EXPECT_NEAR(step.time_s, dt * static_cast<double>(k + 1), 1e-9);
    ASSERT_EQ(step.foot_contacts.size(), r.feet.size());
    ASSERT_EQ(step.at_limit.size(), biped.plan.links.size());
    for (size_t f = 0; f < r.feet.size(); ++f) {
      down[f] += step.foot_contacts[f] > 0 ? 1.0 : 0.0;
      EXPECT_GE(step.foot_forces_n[f], 0.0);
      if (step.foot_contacts[f] == 0) {
        EXPECT_EQ(step.foot_forces_n[f], 0.0);
      }
    }
    if (step.stance_foot >= 0) {  // chosen from the contacts before the step
      ASSERT_GT(k, 0u);
      EXPECT_GT(r.trace[k - 1].foot_contacts[static_cast<size_t>(step.stance_foot)], 0);
    }
    for (size_t li = 0; li < step.at_limit.size(); ++li) limited[li] += step.at_limit[li];
    ASSERT_EQ(step.errors_rad.size(), biped.plan.links.size());
    for (size_t li = 0; li < step.errors_rad.size(); ++li) {
      EXPECT_TRUE(std::isfinite(step.errors_rad[li]) && step.errors_rad[li] >= 0.0);
      squared[li] += step.errors_rad[li] * step.errors_rad[li];
    }
    for (const glm::dvec3& v : {step.com, step.com_velocity, step.target_com, step.target_velocity})
      EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
    for (double t : step.torques_nm) EXPECT_TRUE(std::isfinite(t) && t >= 0.0);
  }
  for (size_t f = 0; f < r.feet.size(); ++f)
    EXPECT_NEAR(down[f] / 120.0, r.contact_share[f], 1e-12) << r.feet[f];
  for (size_t li = 0; li < limited.size(); ++li)
    EXPECT_NEAR(limited[li] / 120.0, r.torque_limited_share[li], 1e-12) << r.links[li];
  // The per-step angles are the ones the report's tracking error sums, and the joints turn off
  // their targets (a walk pulled by gravity and the ground; the base has none).
  double all = 0.0;
  for (size_t li = 0; li < squared.size(); ++li) {
    EXPECT_NEAR(std::sqrt(squared[li] / 120.0), r.track_err_by_link_rad[li], 1e-12) << r.links[li];
    all += squared[li];
  }
  EXPECT_EQ(squared[0], 0.0);
  EXPECT_GT(all, 0.0);
  // The body starts in the target's pose, so the two centres of mass start together; the walk
  // goes forward (+Z) at about 1.3 m/s, the target's velocity with it.
  EXPECT_LT(glm::length(r.trace[0].com - r.trace[0].target_com), 0.02);
  ASSERT_EQ(r.trace[0].target_foot_positions.size(), r.feet.size());
  for (size_t f = 0; f < r.feet.size(); ++f)  // and so do the feet, the target's and the body's
    EXPECT_LT(glm::length(r.trace[0].foot_positions[f] - r.trace[0].target_foot_positions[f]), 0.02)
        << r.feet[f];
  EXPECT_NEAR(r.trace[0].target_velocity.z, r.trace[0].com_velocity.z, 0.1);
  double mean_vz = 0.0;
  for (const TraceStep& step : r.trace) mean_vz += step.target_velocity.z / 120.0;
  EXPECT_GT(mean_vz, 0.8);
  EXPECT_LT(mean_vz, 2.0);

  settings.seconds = kMaxTracedSeconds + 1.0;
  const Result<SimulationReport> long_run = simulate(biped.plan, biped.asset.skeleton, biped.target, settings);
  ASSERT_FALSE(long_run.ok());
  EXPECT_NE(long_run.message().find("trace"), std::string::npos) << long_run.message();
  settings.trace = false;
  settings.seconds = 0.5;
  EXPECT_TRUE(simulate(biped.plan, biped.asset.skeleton, biped.target, settings).value().trace.empty());
}

// A footfall is a touchdown after a swing, not a planted sole chattering: the footfalls are
// exactly the touchdowns (read from the trace) that follow a quarter of the foot's swing in the
// target off the ground, and the bundled walk's chattering soles touch down more often than that.
TEST(Simulation, AFootfallIsATouchdownAfterASwingNotAChatter) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  const SimulationSettings settings = tracedSettings(2.0);
  const SimulationReport r = simulate(biped.plan, biped.asset.skeleton, biped.target, settings).value();
  std::vector<int> feet;
  for (size_t li = 0; li < biped.plan.links.size(); ++li)
    if (biped.plan.links[li].foot) feet.push_back(static_cast<int>(li));
  const std::vector<FootCycle> cycles =
      targetFootCycles(biped.plan, biped.asset.skeleton, biped.target, feet);
  ASSERT_EQ(cycles.size(), r.feet.size());
  const double period = biped.target.period(), dt = 1.0 / settings.world.step_hz;
  std::vector<Footfall> expected;
  int touchdowns = 0;
  for (size_t f = 0; f < r.feet.size(); ++f) {
    ASSERT_GE(cycles[f].liftoff_s, 0.0);
    const double swing = std::fmod(cycles[f].touchdown_s - cycles[f].liftoff_s + period, period);
    const int gap = static_cast<int>(std::lround(0.25 * swing / dt));
    EXPECT_GT(gap, 5);  // longer than a chatter (20 ms)
    int off = r.trace[0].foot_contacts[f] > 0 ? 0 : gap;
    for (size_t k = 1; k < r.trace.size(); ++k) {
      if (r.trace[k].foot_contacts[f] == 0) {
        ++off;
        continue;
      }
      if (off > 0) ++touchdowns;
      if (off >= gap) expected.push_back({static_cast<int>(f), r.trace[k].time_s, r.trace[k].foot_positions[f]});
      off = 0;
    }
  }
  ASSERT_EQ(r.footfalls.size(), expected.size());
  EXPECT_GT(touchdowns, static_cast<int>(expected.size()));
  std::printf("bundled walk, 2 s: %d touchdowns, %zu footfalls\n", touchdowns, r.footfalls.size());
  for (const Footfall& fall : r.footfalls) {
    bool found = false;
    for (const Footfall& e : expected)
      found = found || (e.foot == fall.foot && std::abs(e.time_s - fall.time_s) < 1e-9 &&
                        glm::length(e.position - fall.position) < 1e-12);
    EXPECT_TRUE(found) << r.feet[static_cast<size_t>(fall.foot)] << " at " << fall.time_s;
  }
}

// Legs balance in pairs: the biped's two under its pelvis; the quadruped's forelegs under the
// chest and its hind legs under the pelvis, each pair with its own hips.
TEST(TrackingController, FindsTheLegPairsOfABipedAndAQuadruped) {
  for (const char* name : {"biped_walk.bvh", "quadruped_trot.bvh"}) {
    const test_util::Character c = test_util::loadCharacter(name);
    ASSERT_FALSE(c.plan.links.empty());
    const MotionState state = targetState(c.plan, c.asset.skeleton, c.target, 0.0);
    std::unique_ptr<World> world = World::create(c.plan, state.pose).value();
    auto made = TrackingController::create(*world, c.asset.skeleton, c.target, state.pose);
    ASSERT_TRUE(made.ok()) << made.message();
    const TrackingController& controller = *made.value();
    const std::vector<LegPair>& pairs = controller.legPairs();
    ASSERT_EQ(pairs.size(), controller.feet().size() / 2) << name;
    EXPECT_TRUE(controller.balancing());
    for (const LegPair& pair : pairs) {
      const int foot[2] = {controller.feet()[static_cast<size_t>(pair.feet[0])],
                           controller.feet()[static_cast<size_t>(pair.feet[1])]};
      std::printf("%s: %s and %s meet at %s (hips %s, %s)\n", name,
                  c.plan.links[static_cast<size_t>(foot[0])].name.c_str(),
                  c.plan.links[static_cast<size_t>(foot[1])].name.c_str(),
                  c.plan.links[static_cast<size_t>(pair.base)].name.c_str(),
                  c.plan.links[static_cast<size_t>(pair.hips[0])].name.c_str(),
                  c.plan.links[static_cast<size_t>(pair.hips[1])].name.c_str());
      EXPECT_NE(pair.hips[0], pair.hips[1]);
      for (int side = 0; side < 2; ++side)
        EXPECT_EQ(c.plan.links[static_cast<size_t>(pair.hips[side])].parent, pair.base);
      // A pair is a left and a right leg: its hips lie either side of the base, across the
      // direction of travel, not one behind the other.
      const std::vector<glm::dvec3> origins = linkOrigins(c.plan, state.pose);
      const glm::dvec3 across = origins[static_cast<size_t>(pair.hips[0])] -
                                origins[static_cast<size_t>(pair.hips[1])];
      const glm::dvec3 forward = glm::normalize(
          linkWorldRotations(c.plan, state.pose)[static_cast<size_t>(pair.base)] *
          pair.forward_local);
      EXPECT_LT(std::abs(glm::dot(across, forward)), 0.3 * glm::length(across)) << name;
    }
  }
}

// A foot no other foot pairs with balances alone: the hopper's one leg, about the pelvis it hangs
// from, its hip the thigh (the first ball joint of the leg).
TEST(TrackingController, AHoppersOneLegBalancesAlone) {
  const test_util::Character hopper = test_util::loadCharacter("hopper_hop.bvh");
  ASSERT_FALSE(hopper.plan.links.empty());
  const std::vector<LegPair> pairs = findLegPairs(hopper.plan);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_TRUE(pairs[0].alone());
  EXPECT_EQ(hopper.plan.links[static_cast<size_t>(pairs[0].hips[0])].name, "UpLeg");
  EXPECT_EQ(pairs[0].base, 0);
  for (const char* name : {"biped_walk.bvh", "quadruped_trot.bvh", "stepper_step.bvh"})
    for (const LegPair& pair : findLegPairs(test_util::loadCharacter(name).plan))
      EXPECT_FALSE(pair.alone()) << name;
}

// In the air, a leg alone is placed to catch the body (Raibert's hopper): a hopper dropped from
// 0.4 m above its target while moving 1 m/s faster has its hip's target turned forward by
// cv_sagittal x the velocity error, so the foot lands ahead and brakes the body.
TEST(TrackingController, ALegAloneIsPlacedAgainstTheVelocityErrorInTheAir) {
  const test_util::Character hopper = test_util::loadCharacter("hopper_hop.bvh");
  ASSERT_FALSE(hopper.plan.links.empty());
  AheadOfTarget run = aheadOfTarget(hopper, [](BalanceGains& g) { g.cv_sagittal = 0.2; }, 0.4);
  ASSERT_TRUE(run.world && run.controller);
  World* world = run.world.get();
  TrackingController& controller = *run.controller;
  const glm::dvec3 travel = run.travel;
  const std::vector<double>& zero = run.zero;
  const int hip = controller.legPairs()[0].hips[0];
  const int foot = controller.feet()[0];
  glm::dvec3 previous_com(0.0);
  int checked = 0;
  for (int k = 0; k < 6; ++k) {
    controller.update(*world);
    const glm::dvec3 com = poseKinematics(hopper.plan, controller.motionTarget()).com;
    const double error = glm::dot(world->linearMomentum() / world->totalMass() -
                                      (com - previous_com) / world->dt(), travel);
    previous_com = com;
    if (k >= 2) {
      ASSERT_EQ(world->linkContacts()[static_cast<size_t>(foot)], 0) << "landed at step " << k;
      // The hip's target is relative to the body as it is (its base turns in the air), the
      // motion's relative to the motion's base.
      const auto [placed, tracked, turned] = legTurn(hopper.plan, *world, controller, hip, foot);
      std::printf("step %d: velocity error %.2f m/s forward; leg turned %.3f rad (asked %.3f), "
                  "foot %.1f cm forward\n",
                  k, error, turned, 0.2 * error, 100.0 * glm::dot(placed - tracked, travel));
      EXPECT_GT(error, 0.9);
      EXPECT_NEAR(turned, 0.2 * error, 0.05 * 0.2 * error);
      EXPECT_GT(glm::dot(placed - tracked, travel), 0.0);
      ++checked;
    }
    world->step(zero);
  }
  EXPECT_EQ(checked, 4);
}

// A pair with both feet in the air (a run's flight, a pushed walk's) goes on placing the swing
// foot of the foot last down: a biped walking 1 m/s faster than its target, thrown up off the
// ground, has the swing hip's target turned forward by cv_sagittal x the velocity error until a
// foot lands. Until 2026-12-07 the placement was dropped in the air: a pushed Bandai walk's swing
// foot, placed 13 cm to catch it, swung back to the target's within its 75 ms off the ground.
TEST(TrackingController, APairInTheAirGoesOnPlacingTheSwingFoot) {
  const test_util::Character biped = test_util::loadCharacter("biped_walk.bvh");
  ASSERT_FALSE(biped.plan.links.empty());
  AheadOfTarget run = aheadOfTarget(biped, [](BalanceGains& g) { g.cv_sagittal = 0.2; });
  ASSERT_TRUE(run.world && run.controller);
  World* world = run.world.get();
  TrackingController& controller = *run.controller;
  const glm::dvec3 travel = run.travel;
  const std::vector<double>& zero = run.zero;
  const LegPair pair = controller.legPairs()[0];
  int last_down = -1;  // the pair's side (0, 1) last down
  for (int k = 0; k < 40 && last_down < 0; ++k) {
    controller.update(*world);
    for (int side = 0; side < 2; ++side)
      if (controller.stanceFoot() == pair.feet[side]) last_down = side;
    world->step(zero);
  }
  ASSERT_GE(last_down, 0) << "no foot came down in 40 steps";
  ASSERT_TRUE(world->push(0, glm::dvec3(0.0, 1.5 * world->totalMass(), 0.0)).ok());  // 1.5 m/s up
  const int hip = pair.hips[1 - last_down];
  const int foot = controller.feet()[static_cast<size_t>(pair.feet[1 - last_down])];
  glm::dvec3 previous_com = poseKinematics(biped.plan, controller.motionTarget()).com;
  int checked = 0;
  for (int k = 0; k < 60 && checked < 5; ++k) {
    world->step(zero);
    controller.update(*world);
    const glm::dvec3 com = poseKinematics(biped.plan, controller.motionTarget()).com;
    const double error = glm::dot(world->linearMomentum() / world->totalMass() -
                                      (com - previous_com) / world->dt(), travel);
    previous_com = com;
    bool flight = true;
    for (int f : controller.feet())
      flight = flight && world->linkContacts()[static_cast<size_t>(f)] == 0;
    if (!flight) continue;
    const auto [placed, tracked, turned] = legTurn(biped.plan, *world, controller, hip, foot);
    std::printf("step %d in the air: velocity error %.2f m/s forward; swing leg turned %.3f rad "
                "(asked %.3f), foot %.1f cm forward\n",
                k, error, turned, 0.2 * error, 100.0 * glm::dot(placed - tracked, travel));
    EXPECT_GT(error, 0.5);
    EXPECT_NEAR(turned, 0.2 * error, 0.1 * 0.2 * error);
    EXPECT_GT(glm::dot(placed - tracked, travel), 0.0);
    ++checked;
  }
  EXPECT_EQ(checked, 5) << "the biped did not leave the ground";
}

// Each pair's forward (what its heading, its sagittal and coronal frames are measured about) over
// the target's whole cycle: its largest tilt out of the horizontal and its largest angle from the
// way the motion travels, in degrees. Expects the tilt within 30 degrees, and the turn too where
// `straight` (a clip that turns, as CMU 131's dance does, turns its pelvis away from its travel).
void expectForwardAlongTheTravel(const test_util::Character& c, const std::string& name,
                                 bool straight) {
  ASSERT_FALSE(c.plan.links.empty()) << name;
  const MotionState state = targetState(c.plan, c.asset.skeleton, c.target, 0.0);
  std::unique_ptr<World> world = World::create(c.plan, state.pose).value();
  auto made = TrackingController::create(*world, c.asset.skeleton, c.target, state.pose);
  ASSERT_TRUE(made.ok()) << made.message();
  const double period = c.target.period();
  const glm::dvec3 travel = poseKinematics(c.plan, targetState(c.plan, c.asset.skeleton, c.target,
                                                               period).pose).com -
                            poseKinematics(c.plan, state.pose).com;
  const glm::dvec3 along = glm::normalize(glm::dvec3(travel.x, 0.0, travel.z));
  double tilt = 0.0, off = 0.0;
  for (int k = 0; k < 16; ++k) {
    const LinkPose pose = targetState(c.plan, c.asset.skeleton, c.target, period * k / 16.0).pose;
    const std::vector<glm::dquat> world_rotations = linkWorldRotations(c.plan, pose);
    for (const LegPair& pair : made.value()->legPairs()) {
      const glm::dvec3 f = world_rotations[static_cast<size_t>(pair.base)] * pair.forward_local;
      tilt = std::max(tilt, std::asin(std::clamp(std::abs(f.y), 0.0, 1.0)));
      off = std::max(off, std::acos(std::clamp(
                              glm::dot(glm::normalize(glm::dvec3(f.x, 0.0, f.z)), along), -1.0, 1.0)));
    }
  }
  std::printf("%-40s %zu pairs, travel %.2f m a period: forward tilts up to %.1f deg, turns up to "
              "%.1f deg from the travel\n",
              name.c_str(), made.value()->legPairs().size(), glm::length(travel),
              glm::degrees(tilt), glm::degrees(off));
  EXPECT_LT(glm::degrees(tilt), 30.0) << name;
  if (straight) {
    EXPECT_LT(glm::degrees(off), 30.0) << name;
  }
}

// The forward is taken from the motion (its travel, in its first pose), not from the rest pose:
// the MANN dog's rest pose lies on its side, and a forward taken there pointed straight down once
// the motion's attitude was on (tilted 78-86 degrees), so its headings swung by up to 1.7 rad
// within 0.1 s of a straight walk.
TEST(TrackingController, EveryPairsForwardStaysAlongTheBundledCreaturesTravel) {
  for (const char* name : {"biped_walk.bvh", "quadruped_trot.bvh", "stepper_step.bvh"})
    expectForwardAlongTheTravel(test_util::loadCharacter(name), name, true);
}

TEST(TrackingController, EveryPairsForwardStaysAlongTheRealCapturesTravel) {
  SINEW_REQUIRE_SHARED_DATA();
  for (const std::filesystem::path& path : sinew::test::sharedFiles("bvh", ".bvh")) {
    const std::string name = path.filename().string();
    expectForwardAlongTheTravel(test_util::loadCharacterFrom(path), name, false);
  }
}

// The bundled trot with its leg pairs balanced sideways (coronal gains only) stays up the 10 s it
// falls within without feedback: the pairs' feedback, not the tracking alone, holds it.
TEST(Simulation, LegPairFeedbackKeepsTheQuadrupedTrotUp) {
  const test_util::Character trot = test_util::loadCharacter("quadruped_trot.bvh");
  ASSERT_FALSE(trot.plan.links.empty());
  auto run = [&](bool feedback) {
    SimulationSettings settings;
    settings.seconds = 10.0;
    settings.tracking.feedback = feedback;
    settings.tracking.balance.cd_coronal = 0.5;
    settings.tracking.balance.cv_coronal = 0.2;
    return simulate(trot.plan, trot.asset.skeleton, trot.target, settings).value();
  };
  const SimulationReport without = run(false), with = run(true);
  std::printf("the trot: %.2f s up without feedback, %.2f s with (%.2f m, %.2f m/s)\n",
              without.fell ? without.fall_time_s : 10.0, with.fell ? with.fall_time_s : 10.0,
              with.distance_m, with.speed_m_s);
  EXPECT_TRUE(without.fell);
  EXPECT_FALSE(with.fell) << with.fall_reason;
  EXPECT_GT(with.distance_m, 3.0);
}

}  // namespace
}  // namespace sinew::physics
