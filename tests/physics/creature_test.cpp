// The project's own creatures: every rig in assets/ builds a valid body plan with the feet it
// should have.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "physics_test_util.h"

namespace sinew::physics {
namespace {

struct AssetRig {
  const char* file;
  int feet;
  bool human;
};

constexpr AssetRig kAssetRigs[] = {
    {"biped_walk.bvh", 2, true},
    {"quadruped_trot.bvh", 4, false},
    {"hopper_hop.bvh", 1, false},
    {"stepper_step.bvh", 2, false},
};

void printPlan(const std::string& label, const BodyPlan& plan) {
  int ball = 0, hinge = 0, fixed = 0;
  for (const Link& l : plan.links) {
    ball += l.type == JointType::kBall;
    hinge += l.type == JointType::kHinge;
    fixed += l.type == JointType::kFixed;
  }
  std::printf("%-20s %2zu links (%d ball, %d hinge, %d fixed), %2d DOF, %7.2f kg, size %.2f m%s\n",
              label.c_str(), plan.links.size(), ball, hinge, fixed, plan.dofCount(),
              plan.total_mass_kg, plan.size_m, plan.human ? ", human (de Leva)" : ", by volume");
}

TEST(CreatureAssets, EveryAssetBuildsAValidBodyPlanWithItsFeet) {
  for (const AssetRig& rig : kAssetRigs) {
    SCOPED_TRACE(rig.file);
    const motion::MotionAsset asset =
        test_util::loadAsset(sinew::test::sourceDir() / "assets" / rig.file);
    ASSERT_EQ(asset.clips.size(), 1u);
    EXPECT_EQ(asset.detection.frame.unit, motion::LengthUnit::kCentimetres);
    EXPECT_EQ(asset.detection.frame.up, motion::UpAxis::kY);
    Result<BodyPlan> built = buildBodyPlan(asset.skeleton, &asset.clips[0]);
    ASSERT_TRUE(built.ok()) << built.message();
    const BodyPlan& plan = built.value();
    printPlan(rig.file, plan);
    for (const Link& l : plan.links) {
      std::printf("  %-16s parent %2d %-6s %-7s mass %6.2f kg%s\n", l.name.c_str(), l.parent,
                  jointTypeName(l.type), l.shape.type == ShapeType::kBox ? "box"
                                         : l.shape.type == ShapeType::kCapsule ? "capsule"
                                                                               : "sphere",
                  l.mass_kg, l.foot ? "  foot" : "");
    }
    EXPECT_TRUE(plan.validate().ok()) << plan.validate().message();
    EXPECT_EQ(plan.human, rig.human);
    int feet = 0;
    for (const Link& l : plan.links) {
      if (!l.foot) continue;
      ++feet;
      EXPECT_EQ(l.shape.type, ShapeType::kBox) << l.name;
      EXPECT_TRUE(l.supports) << l.name;
    }
    EXPECT_EQ(feet, rig.feet);
    EXPECT_GT(plan.dofCount(), 0);
    EXPECT_EQ(plan.links[0].type, JointType::kBase);
  }
}

// The shank of every leg (the foot's parent link) moves as a hinge: the generators solve the legs
// with the knee (stifle, elbow) turning about one axis.
TEST(CreatureAssets, KneesOfTheNewCreaturesAreHinges) {
  for (const char* file : {"quadruped_trot.bvh", "hopper_hop.bvh", "stepper_step.bvh"}) {
    SCOPED_TRACE(file);
    const motion::MotionAsset asset =
        test_util::loadAsset(sinew::test::sourceDir() / "assets" / file);
    ASSERT_FALSE(asset.clips.empty());
    const BodyPlan plan = buildBodyPlan(asset.skeleton, &asset.clips[0]).value();
    int knees = 0;
    for (const Link& l : plan.links) {
      if (!l.foot) continue;
      const Link& shank = plan.links[static_cast<size_t>(l.parent)];
      EXPECT_EQ(shank.type, JointType::kHinge) << shank.name;
      EXPECT_LT(shank.hinge_lower, shank.hinge_upper) << shank.name;
      knees += shank.type == JointType::kHinge;
    }
    EXPECT_GT(knees, 0);
  }
}

}  // namespace
}  // namespace sinew::physics
