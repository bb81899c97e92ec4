#include "sinew/physics/world.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "physics_test_util.h"

namespace sinew::physics {
namespace {

// One free box (the base only): 1 kg, 0.2 x 0.1 x 0.3 m.
BodyPlan boxPlan() {
  BodyPlan plan;
  Link box;
  box.name = "box";
  box.type = JointType::kBase;
  box.shape.type = ShapeType::kBox;
  box.shape.half_extents = {0.1, 0.05, 0.15};
  box.mass_kg = 1.0;
  box.inertia = {1.0 / 3.0 * (0.05 * 0.05 + 0.15 * 0.15), 1.0 / 3.0 * (0.1 * 0.1 + 0.15 * 0.15),
                 1.0 / 3.0 * (0.1 * 0.1 + 0.05 * 0.05)};
  plan.links.push_back(box);
  plan.total_mass_kg = 1.0;
  plan.size_m = 0.3;
  return plan;
}

LinkPose poseFor(const BodyPlan& plan, double height) {
  LinkPose pose;
  pose.base_position = {0.0, height, 0.0};
  pose.rotations.assign(plan.links.size(), glm::dquat(1.0, 0.0, 0.0, 0.0));
  pose.angles.assign(plan.links.size(), 0.0);
  return pose;
}

TEST(World, RefusesInvalidInputs) {
  const BodyPlan plan = boxPlan();
  const LinkPose pose = poseFor(plan, 1.0);
  ASSERT_TRUE(World::create(plan, pose).ok());
  auto refused = [&](WorldSettings s, const std::string& field) {
    Result<std::unique_ptr<World>> w = World::create(plan, pose, s);
    EXPECT_FALSE(w.ok()) << field;
    EXPECT_NE(w.message().find(field), std::string::npos) << w.message();
  };
  WorldSettings s;
  s.step_hz = 0.0;
  refused(s, "step_hz");
  s = {};
  s.gravity_m_s2 = -1.0;
  refused(s, "gravity_m_s2");
  s = {};
  s.ground_friction = std::nan("");
  refused(s, "ground_friction");
  s = {};
  s.solver_iterations = 0;
  refused(s, "solver_iterations");
  s = {};
  s.ground_clearance_m = -0.1;
  refused(s, "ground_clearance_m");

  LinkPose short_pose = pose;
  short_pose.rotations.clear();
  Result<std::unique_ptr<World>> w = World::create(plan, short_pose);
  EXPECT_FALSE(w.ok());
  EXPECT_NE(w.message().find("initial pose"), std::string::npos) << w.message();
  LinkPose bad_rotation = pose;
  bad_rotation.base_rotation = glm::dquat(2.0, 0.0, 0.0, 0.0);
  EXPECT_FALSE(World::create(plan, bad_rotation).ok());
  BodyPlan bad_plan = plan;
  bad_plan.links[0].mass_kg = -1.0;
  w = World::create(bad_plan, pose);
  EXPECT_FALSE(w.ok());
  EXPECT_NE(w.message().find("mass_kg"), std::string::npos) << w.message();
}

// Falls from rest: v(t) = g t before contact; measured from the base's momentum and position.
TEST(World, DroppedBoxFallsWithG) {
  const BodyPlan plan = boxPlan();
  WorldSettings settings;
  settings.place_on_ground = false;
  std::unique_ptr<World> world = World::create(plan, poseFor(plan, 2.0), settings).value();
  const double y0 = world->jointPositions().base_position.y;
  const int steps = 120;  // 0.5 s: falls 1.23 m, still 0.7 m above the ground
  for (int s = 0; s < steps; ++s) world->step({});
  const double t = world->time();
  const double v = world->linearMomentum().y / world->totalMass();
  const double drop = y0 - world->jointPositions().base_position.y;
  const double g_velocity = -v / t;
  const double g_position = 2.0 * drop / (t * (t + world->dt()));
  std::printf(
      "dropped box: after %.3f s v = %.4f m/s -> g = %.4f m/s^2; drop %.4f m -> g = %.4f "
      "m/s^2 (semi-implicit Euler: drop = g t (t + dt) / 2)\n",
      t, v, g_velocity, drop, g_position);
  EXPECT_NEAR(g_velocity, 9.81, 0.05);
  EXPECT_NEAR(g_position, 9.81, 0.05);
  EXPECT_EQ(world->linkContacts()[0], 0);
}

TEST(World, DroppedBipedFallsWithGAndLands) {
  const motion::MotionAsset asset =
      test_util::loadAsset(sinew::test::sourceDir() / "assets" / "biped_walk.bvh");
  ASSERT_FALSE(asset.clips.empty());
  const BodyPlan plan = buildBodyPlan(asset.skeleton, &asset.clips[0]).value();
  LinkPose pose = test_util::firstPose(plan, asset.skeleton, asset.clips[0]);
  WorldSettings settings;
  settings.place_on_ground = false;
  pose.base_position.y += 1.0;  // one metre up: 0.45 s of free fall
  std::unique_ptr<World> world = World::create(plan, pose, settings).value();
  const glm::dvec3 p0 = world->linearMomentum();
  const std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0);
  const int steps = 72;  // 0.3 s
  for (int s = 0; s < steps; ++s) world->step(zero);
  const double a = -(world->linearMomentum().y - p0.y) / world->totalMass() / world->time();
  std::printf("dropped biped (limp, %zu links, %.1f kg): centre of mass acceleration %.4f m/s^2\n",
              plan.links.size(), world->totalMass(), a);
  EXPECT_NEAR(a, 9.81, 0.05);
  for (int s = 0; s < 480; ++s) world->step(zero);
  EXPECT_TRUE(world->finite());
  EXPECT_GT(world->centreOfMass().y, 0.0) << "fell through the ground";
}

// Honesty: over a whole run, the character's momentum changes only by gravity and the ground's
// contact impulses, and nothing but joint torques is ever put on the multibody.
TEST(World, OnlyGravityAndContactsActOnTheCharacter) {
  const motion::MotionAsset asset =
      test_util::loadAsset(sinew::test::sourceDir() / "assets" / "biped_walk.bvh");
  ASSERT_FALSE(asset.clips.empty());
  const BodyPlan plan = buildBodyPlan(asset.skeleton, &asset.clips[0]).value();
  const LinkPose target = test_util::firstPose(plan, asset.skeleton, asset.clips[0]);
  WorldSettings settings;
  std::unique_ptr<World> world = World::create(plan, target, settings).value();
  PdController controller = PdController::create(*world).value();
  const size_t dofs = static_cast<size_t>(world->dofCount());
  std::vector<double> torques(dofs);
  const glm::dvec3 gravity(0.0, -settings.gravity_m_s2, 0.0);
  glm::dvec3 expected = world->linearMomentum();
  glm::dvec3 contact_total(0.0);
  double worst_step = 0.0;
  const int steps = 3 * 240;
  for (int s = 0; s < steps; ++s) {
    controller.computeTorques(*world, target, torques);
    const glm::dvec3 before = world->linearMomentum();
    world->step(torques);
    const glm::dvec3 impulse =
        gravity * world->totalMass() * world->dt() + world->lastContactImpulse();
    contact_total += world->lastContactImpulse();
    worst_step = std::max(worst_step, glm::length(world->linearMomentum() - before - impulse));
    expected += impulse;
  }
  const glm::dvec3 residual = world->linearMomentum() - expected;
  const double gravity_impulse = world->totalMass() * settings.gravity_m_s2 * world->time();
  const ExternalLoads& loads = world->externalLoads();
  std::printf(
      "honesty over %.1f s: gravity impulse %.2f N s, contact impulse (%.3f, %.3f, %.3f) N s, "
      "momentum residual %.2e N s (worst step %.2e); external loads before steps: base "
      "%.1e N %.1e N m, links %.1e N %.1e N m\n",
      world->time(), gravity_impulse, contact_total.x, contact_total.y, contact_total.z,
      glm::length(residual), worst_step, loads.max_base_force_n, loads.max_base_torque_nm,
      loads.max_link_force_n, loads.max_link_torque_nm);
  EXPECT_EQ(loads.max_base_force_n, 0.0);
  EXPECT_EQ(loads.max_base_torque_nm, 0.0);
  EXPECT_EQ(loads.max_link_force_n, 0.0);
  EXPECT_EQ(loads.max_link_torque_nm, 0.0);
  // Bullet reports each contact's normal and friction impulses on its manifold points; what the
  // solver applied and what the points report agree over the run to about 1e-4 of the gravity
  // impulse (single steps differ more where points are dropped and re-added).
  EXPECT_LT(glm::length(residual), 1e-3 * gravity_impulse);
}

TEST(World, SameInputsGiveBitIdenticalResults) {
  const motion::MotionAsset asset =
      test_util::loadAsset(sinew::test::sourceDir() / "assets" / "biped_walk.bvh");
  ASSERT_FALSE(asset.clips.empty());
  const BodyPlan plan = buildBodyPlan(asset.skeleton, &asset.clips[0]).value();
  const LinkPose target = test_util::firstPose(plan, asset.skeleton, asset.clips[0]);
  const test_util::HoldResult a = test_util::holdPose(plan, target, 2.0);
  const test_util::HoldResult b = test_util::holdPose(plan, target, 2.0);
  ASSERT_EQ(a.final_transforms.size(), b.final_transforms.size());
  ASSERT_FALSE(a.final_transforms.empty());
  EXPECT_EQ(std::memcmp(a.final_transforms.data(), b.final_transforms.data(),
                        a.final_transforms.size() * sizeof(glm::dmat4)),
            0);
  std::printf("determinism: two 2 s runs, %zu link transforms bit-identical: %s\n",
              a.final_transforms.size(),
              std::memcmp(a.final_transforms.data(), b.final_transforms.data(),
                          a.final_transforms.size() * sizeof(glm::dmat4)) == 0
                  ? "yes"
                  : "no");
}

}  // namespace
}  // namespace sinew::physics
