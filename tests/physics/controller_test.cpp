#include "sinew/physics/controller.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "physics_test_util.h"

namespace sinew::physics {
namespace {

// Bullet clamps joint speeds at 100 rad/s; a run reaching it has diverged. Limbs slapping the
// ground in a fall reach 30-60 rad/s.
constexpr double kBlowUpRadPerS = 99.0;

BodyPlan bipedPlan(motion::MotionAsset& asset) {
  asset = test_util::loadAsset(sinew::test::sourceDir() / "assets" / "biped_walk.bvh");
  EXPECT_FALSE(asset.clips.empty());
  if (asset.clips.empty()) return {};
  return buildBodyPlan(asset.skeleton, &asset.clips[0]).value();
}

std::unique_ptr<World> bipedWorld(motion::MotionAsset& asset, BodyPlan& plan) {
  plan = bipedPlan(asset);
  return World::create(plan, test_util::firstPose(plan, asset.skeleton, asset.clips[0])).value();
}

TEST(PdController, RefusesInvalidInputs) {
  motion::MotionAsset asset;
  BodyPlan plan;
  std::unique_ptr<World> world = bipedWorld(asset, plan);
  ASSERT_TRUE(PdController::create(*world).ok());
  auto refused = [&](ControllerSettings s, const std::string& field) {
    Result<PdController> c = PdController::create(*world, s);
    EXPECT_FALSE(c.ok()) << field;
    EXPECT_NE(c.message().find(field), std::string::npos) << c.message();
  };
  ControllerSettings s;
  s.stiffness_per_load = 0.0;
  refused(s, "stiffness_per_load");
  s = {};
  s.damping_ratio = -1.0;
  refused(s, "damping_ratio");
  s = {};
  s.max_frequency_ratio = 0.5;
  refused(s, "max_frequency_ratio");
  s = {};
  s.support_torque_scale = std::nan("");
  refused(s, "support_torque_scale");
  s = {};
  s.limb_torque_scale = 0.0;
  refused(s, "limb_torque_scale");
  s = {};
  s.stability_budget = 1.0;
  refused(s, "stability_budget");
  s = {};
  s.tipping_margin = 0.0;
  refused(s, "tipping_margin");
  s = {};
  s.planted_contact_points = 0;
  refused(s, "planted_contact_points");
  // Gains are measured at rest at the initial pose: a world that has stepped is refused.
  world->step(std::vector<double>(static_cast<size_t>(world->dofCount()), 0.0));
  Result<PdController> late = PdController::create(*world);
  EXPECT_FALSE(late.ok());
  EXPECT_NE(late.message().find("stepped"), std::string::npos) << late.message();
}

TEST(PdController, GainsAreCappedByEffectiveInertia) {
  motion::MotionAsset asset;
  BodyPlan plan;
  std::unique_ptr<World> world = bipedWorld(asset, plan);
  const ControllerSettings settings;
  const double rate = 1.0 / world->dt();
  const std::vector<double> minv = world->jointInverseInertia();
  const PdController c = PdController::create(*world, settings).value();
  const double w = 2.0 * std::numbers::pi * settings.max_frequency_ratio * rate;
  const std::vector<int> offsets = plan.dofOffsets();
  const size_t dofs = static_cast<size_t>(plan.dofCount());
  std::printf("gain sets: %u (feet %zu); free / both feet planted:\n", c.stateCount(),
              c.feet().size());
  const unsigned planted = c.stateCount() - 1;
  for (size_t li = 1; li < plan.links.size(); ++li) {
    const int n = dofCount(plan.links[li].type);
    for (int d = 0; d < n; ++d) {
      const size_t i = static_cast<size_t>(offsets[li] + d);
      const DofGains& g = c.gains(0)[i];
      // The effective inertia is the inverse of the joint-space inverse inertia's diagonal.
      EXPECT_NEAR(g.inertia, 1.0 / minv[i * dofs + i], 1e-9 * g.inertia);
      EXPECT_LE(g.kp, g.inertia * w * w * (1.0 + 1e-12)) << plan.links[li].name;
      // A single degree of freedom's explicit step stays stable: (w h)^2 + 4 zeta (w h) < 4.
      const double wh = std::sqrt(g.kp / g.inertia) / rate;
      EXPECT_LT(wh * wh + 2.0 * g.kd / g.inertia / rate, 4.0) << plan.links[li].name;
      const DofGains& p = c.gains(planted)[i];
      std::printf(
          "  %-14s %-5s dof %d  I %.4f / %.4f kg m^2  kp %7.1f / %7.1f N m/rad  kd %6.2f / %6.2f"
          "  limit %.0f N m\n",
          plan.links[li].name.c_str(), jointTypeName(plan.links[li].type), d, g.inertia, p.inertia,
          g.kp, p.kp, g.kd, p.kd, c.torqueLimits()[li]);
    }
  }
  // The light feet's joints get a fraction of the legs' stiffness.
  double foot_kp = 0.0, hip_kp = 0.0;
  for (size_t li = 1; li < plan.links.size(); ++li) {
    const size_t i = static_cast<size_t>(offsets[li]);
    if (plan.links[li].foot) foot_kp = std::max(foot_kp, c.gains(0)[i].kp);
    if (plan.links[li].segment == motion::Segment::kThigh)
      hip_kp = std::max(hip_kp, c.gains(0)[i].kp);
  }
  EXPECT_LT(foot_kp, hip_kp);
}

// The biped under PD alone for 10 s from its first-frame pose: stays finite, no blow-up; prints
// how long it stays up.
TEST(PdController, BipedUnderPdStaysFiniteForTenSeconds) {
  motion::MotionAsset asset;
  const BodyPlan plan = bipedPlan(asset);
  ASSERT_FALSE(plan.links.empty());
  const LinkPose target = test_util::firstPose(plan, asset.skeleton, asset.clips[0]);
  const test_util::HoldResult r = test_util::holdPose(plan, target, 10.0);
  std::printf(
      "biped under PD 10 s: pelvis start %.3f m, min %.3f m (%.0f%%), below 70%% at %.2f s, "
      "max joint error (last 5 s) %.1f deg, max joint speed %.2f rad/s\n",
      r.start_height, r.min_height, 100.0 * r.min_height / r.start_height, r.fall_time,
      r.max_joint_error * 180.0 / std::numbers::pi, r.max_joint_speed);
  EXPECT_TRUE(r.finite);
  EXPECT_LT(r.max_joint_speed, kBlowUpRadPerS);
}

}  // namespace
}  // namespace sinew::physics
