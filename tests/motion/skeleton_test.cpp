#include "sinew/motion/skeleton.h"

#include <cmath>

#include <gtest/gtest.h>

#include "sinew/motion/clip.h"

namespace sinew::motion {
namespace {

Skeleton twoBones() {
  Skeleton skeleton;
  const int root = skeleton.addJoint("root", kNoParent, {0.0, 1.0, 0.0});
  const int elbow = skeleton.addJoint("elbow", root, {0.0, 0.0, 0.5});
  skeleton.addJoint("hand", elbow, {0.0, 0.0, 0.25});
  return skeleton;
}

TEST(SkeletonTest, RefusesEveryInvalidSkeletonWithTheJointNamed) {
  EXPECT_FALSE(Skeleton{}.validate().ok());
  Skeleton duplicate = twoBones();
  duplicate.names[2] = "elbow";
  EXPECT_NE(duplicate.validate().message().find("duplicate"), std::string::npos);
  Skeleton order = twoBones();
  order.parents[1] = 2;
  EXPECT_NE(order.validate().message().find("'elbow'"), std::string::npos);
  Skeleton nan = twoBones();
  nan.offsets[2].x = std::nan("");
  EXPECT_NE(nan.validate().message().find("'hand'"), std::string::npos);
  Skeleton unnamed = twoBones();
  unnamed.names[0].clear();
  EXPECT_FALSE(unnamed.validate().ok());
  Skeleton ragged = twoBones();
  ragged.offsets.pop_back();
  EXPECT_FALSE(ragged.validate().ok());
  EXPECT_TRUE(twoBones().validate().ok());
}

TEST(SkeletonTest, ForwardKinematicsComposesParentsBeforeChildren) {
  const Skeleton skeleton = twoBones();
  Clip clip = restClip(skeleton, 2, 1.0 / 30.0);
  ASSERT_TRUE(clip.validate(skeleton).ok());
  // Frame 1: the root turns 90 degrees about Y, so +Z bones point along +X.
  clip.rotations[3 + 0] = glm::angleAxis(std::acos(-1.0) / 2.0, glm::dvec3(0.0, 1.0, 0.0));
  const std::vector<glm::dvec3> rest = worldPositions(skeleton, clip, 0);
  EXPECT_NEAR(rest[2].z, 0.75, 1e-12);
  EXPECT_NEAR(rest[2].y, 1.0, 1e-12);
  const std::vector<glm::dvec3> turned = worldPositions(skeleton, clip, 1);
  EXPECT_NEAR(turned[2].x, 0.75, 1e-12);
  EXPECT_NEAR(turned[2].z, 0.0, 1e-12);
  EXPECT_EQ(skeleton.depth(2), 2);
  EXPECT_EQ(skeleton.findJoint("hand"), 2);
  EXPECT_EQ(skeleton.findJoint("foot"), -1);
}

TEST(SkeletonTest, ClipValidationNamesTheProblem) {
  const Skeleton skeleton = twoBones();
  Clip clip = restClip(skeleton, 3, 0.0);
  EXPECT_NE(clip.validate(skeleton).message().find("frame time"), std::string::npos);
  clip.frame_time = 0.01;
  clip.translations[4].y = std::nan("");
  EXPECT_NE(clip.validate(skeleton).message().find("frame 1, joint 'elbow'"), std::string::npos);
}

}  // namespace
}  // namespace sinew::motion
