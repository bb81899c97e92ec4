// Helpers shared by the physics tests: load a rig, build its plan, hold its first pose under PD.
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "sinew/physics/body_plan.h"
#include "sinew/physics/controller.h"
#include "sinew/physics/tracking.h"
#include "sinew/physics/world.h"
#include "sinew/spectral/analysis.h"
#include "support/test_support.h"

namespace sinew::physics::test_util {

inline motion::MotionAsset loadAsset(const std::filesystem::path& path) {
  Result<motion::MotionAsset> asset = motion::importMotion(path);
  EXPECT_TRUE(asset.ok()) << path << ": " << asset.message();
  if (!asset.ok()) return {};
  return std::move(asset).value();
}

// First-frame pose of a clip in link coordinates.
inline LinkPose firstPose(const BodyPlan& plan, const motion::Skeleton& skeleton,
                          const motion::Clip& clip) {
  const size_t n = static_cast<size_t>(skeleton.jointCount());
  return linkPoseFromSkeleton(plan, skeleton, std::span(clip.rotations.data(), n),
                              std::span(clip.translations.data(), n));
}

// A rig from assets/ with its plan and the harmonic model (K = 5) of its clip.
struct Character {
  motion::MotionAsset asset;
  BodyPlan plan;
  spectral::TargetMotion target;
};

// The same from any motion file.
inline Character loadCharacterFrom(const std::filesystem::path& path) {
  Character c;
  c.asset = loadAsset(path);
  if (c.asset.clips.empty()) return c;
  Result<BodyPlan> plan = buildBodyPlan(c.asset.skeleton, &c.asset.clips[0]);
  EXPECT_TRUE(plan.ok()) << plan.message();
  Result<spectral::MotionSpectrum> spectrum = spectral::analyze(c.asset.skeleton, c.asset.clips[0]);
  EXPECT_TRUE(spectrum.ok()) << spectrum.message();
  if (!plan.ok() || !spectrum.ok()) return c;
  c.plan = std::move(plan).value();
  c.target = spectral::targetFromSpectrum(spectrum.value(), {}, path.filename().string());
  return c;
}

inline Character loadCharacter(const std::string& asset_name) {
  return loadCharacterFrom(sinew::test::sourceDir() / "assets" / asset_name);
}

struct HoldResult {
  double start_height = 0.0;     // base height after placement, m
  double min_height = 0.0;       // lowest base height over the run, m
  double max_joint_error = 0.0;  // largest joint angle error over the last half of the run, rad
  double max_joint_speed = 0.0;  // rad/s
  bool finite = true;
  double fall_time = -1.0;  // when the base first dropped below 70% of its start, s; -1 never
  int worst_link = 0;       // the link with the largest joint error
  ExternalLoads loads;
  std::vector<glm::dmat4> final_transforms;  // (links)
};

// Starts a world at `target`, lets `setup` prepare it (false: give up), then calls `step` once
// per fixed step for `seconds`, measuring the hold.
template <class Setup, class Step>
HoldResult hold(const BodyPlan& plan, const LinkPose& target, double seconds,
                const WorldSettings& world_settings, Setup setup, Step step) {
  HoldResult out;
  Result<std::unique_ptr<World>> created = World::create(plan, target, world_settings);
  EXPECT_TRUE(created.ok()) << created.message();
  if (!created.ok()) return out;
  World& world = *created.value();
  if (!setup(world)) return out;
  out.start_height = world.jointPositions().base_position.y;
  out.min_height = out.start_height;
  const long long steps = std::llround(seconds * world_settings.step_hz);
  for (long long s = 0; s < steps; ++s) {
    step(world);
    if (!world.finite()) {
      out.finite = false;
      break;
    }
    const LinkPose now = world.jointPositions();
    out.min_height = std::min(out.min_height, now.base_position.y);
    if (out.fall_time < 0.0 && now.base_position.y < 0.7 * out.start_height)
      out.fall_time = world.time();
    out.max_joint_speed = std::max(out.max_joint_speed, world.maxJointSpeed());
    if (s >= steps / 2) {
      for (size_t li = 1; li < plan.links.size(); ++li) {
        double e = 0.0;
        if (plan.links[li].type == JointType::kBall)
          e = glm::length(rotationVectorOf(glm::inverse(now.rotations[li]) * target.rotations[li]));
        else if (plan.links[li].type == JointType::kHinge)
          e = std::abs(now.angles[li] - target.angles[li]);
        if (e > out.max_joint_error) out.worst_link = static_cast<int>(li);
        out.max_joint_error = std::max(out.max_joint_error, e);
      }
    }
  }
  out.loads = world.externalLoads();
  out.final_transforms.resize(plan.links.size());
  world.linkTransforms(out.final_transforms);
  return out;
}

// Holds `target` under explicit PD for `seconds` from the same pose.
inline HoldResult holdPose(const BodyPlan& plan, const LinkPose& target, double seconds,
                           const WorldSettings& world_settings = {},
                           const ControllerSettings& controller_settings = {}) {
  std::unique_ptr<PdController> controller;
  std::vector<double> torques(static_cast<size_t>(plan.dofCount()), 0.0);
  return hold(
      plan, target, seconds, world_settings,
      [&](World& world) {
        Result<PdController> made = PdController::create(world, controller_settings);
        EXPECT_TRUE(made.ok()) << made.message();
        if (!made.ok()) return false;
        controller = std::make_unique<PdController>(std::move(made).value());
        return true;
      },
      [&](World& world) {
        controller->computeTorques(world, target, torques);
        world.step(torques);
      });
}

// Holds `target` with the joint servos (default tracking limits and rate) for `seconds`.
inline HoldResult holdWithServos(const BodyPlan& plan, const LinkPose& target, double seconds,
                                 const WorldSettings& world_settings = {}) {
  std::vector<double> zero(static_cast<size_t>(plan.dofCount()), 0.0);
  return hold(
      plan, target, seconds, world_settings,
      [&](World& world) {
        const TrackingSettings defaults;
        Status enabled = world.enableServos(
            jointTorqueLimits(plan, defaults.support_torque_scale, defaults.limb_torque_scale, 9.81),
            defaults.servo_rate);
        EXPECT_TRUE(enabled.ok()) << enabled.message();
        world.setServoTargets(target);
        return enabled.ok();
      },
      [&](World& world) { world.step(zero); });
}

}  // namespace sinew::physics::test_util
