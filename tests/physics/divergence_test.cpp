// Divergence is detected where it happens (issue 14): a non-finite state, a joint at Bullet's
// velocity clamp, kinetic energy from nowhere. A diverged or flung run reports finite figures and
// never "stayed up".
#include "sinew/physics/divergence.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "physics_test_util.h"
#include "sinew/physics/simulation.h"

namespace sinew::physics {
namespace {

TEST(Divergence, ARestingCharacterHasNotDiverged) {
  const test_util::Character c = test_util::loadCharacter("biped_walk.bvh");
  std::unique_ptr<World> world =
      World::create(c.plan, test_util::firstPose(c.plan, c.asset.skeleton, c.asset.clips[0]))
          .value();
  EXPECT_EQ(divergence(*world, 0.0), "");
  std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0);
  for (int s = 0; s < 240; ++s) world->step(zero);
  EXPECT_EQ(divergence(*world, 0.0), "");  // a second of falling down is not divergence
}

TEST(Divergence, JointsAtTheClampAndEnergyFromNowhereAreDivergence) {
  const test_util::Character c = test_util::loadCharacter("biped_walk.bvh");
  std::unique_ptr<World> world =
      World::create(c.plan, test_util::firstPose(c.plan, c.asset.skeleton, c.asset.clips[0]))
          .value();
  std::vector<double> joints(static_cast<size_t>(world->dofCount()), 0.0);
  joints[3] = kBulletMaxCoordinateVelocity_rad_s;
  ASSERT_TRUE(world->setVelocities(glm::dvec3(0.0), glm::dvec3(0.0), joints).ok());
  EXPECT_EQ(divergence(*world, 0.0), "a joint at 100 rad/s, Bullet's velocity clamp");
  joints[3] = 0.0;
  ASSERT_TRUE(world->setVelocities(glm::dvec3(500.0, 0.0, 0.0), glm::dvec3(0.0), joints).ok());
  EXPECT_EQ(divergence(*world, 0.0).rfind("energy blow-up: the centre of mass at 500 m/s", 0), 0u)
      << divergence(*world, 0.0);
  // The same speed is what a push of that size gives: not divergence.
  EXPECT_EQ(divergence(*world, 500.0 * world->totalMass()), "");
}

TEST(Divergence, PushesBeyondTheLimitAreRefused) {
  SimulationSettings settings;
  settings.pushes.push_back({1.0, glm::dvec3(1e6, 0.0, 0.0), ""});
  EXPECT_EQ(settings.validate().message(),
            "pushes[0]: time must be >= 0 s, impulse at most 10000 N s");
  settings.pushes[0].impulse_ns = glm::dvec3(1e308, 1e308, 0.0);  // length overflows to inf
  EXPECT_FALSE(settings.validate().ok());
}

TEST(Divergence, AViolentPushReportsAFallWithFiniteFigures) {
  const test_util::Character c = test_util::loadCharacter("biped_walk.bvh");
  SimulationSettings settings;
  settings.seconds = 4.0;
  settings.pushes.push_back({0.5, glm::dvec3(10000.0, 0.0, 0.0), ""});  // the limit, N s
  Result<SimulationReport> run = simulate(c.plan, c.asset.skeleton, c.target, settings);
  ASSERT_TRUE(run.ok()) << run.message();
  const SimulationReport& r = run.value();
  std::printf("10,000 N s push: fell %d at %.2f s (%s), diverged %d, distance %.1f m\n", r.fell,
              r.fall_time_s, r.fall_reason.c_str(), r.diverged, r.distance_m);
  EXPECT_TRUE(r.fell);  // never "stayed up"
  for (double v : {r.distance_m, r.speed_m_s, r.track_err_rad_rms, r.energy_j, r.torque_sq_per_kg,
                   r.min_uprightness, r.seconds})
    EXPECT_TRUE(std::isfinite(v));
  EXPECT_TRUE(r.motion.validate(c.asset.skeleton).ok())
      << r.motion.validate(c.asset.skeleton).message();
}

}  // namespace
}  // namespace sinew::physics
