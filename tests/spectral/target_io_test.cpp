#include "sinew/spectral/target_io.h"

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "support/test_support.h"

namespace sinew::spectral {
namespace {

struct Walk {
  motion::MotionAsset asset;
  TargetMotion target;
};

Walk bundledWalk() {
  Walk walk{motion::importMotion(test::sourceDir() / "assets" / "biped_walk.bvh").value(), {}};
  walk.target = targetFromSpectrum(analyze(walk.asset.skeleton, walk.asset.clips[0]).value());
  return walk;
}

TEST(TargetIoTest, RefusesBrokenFilesNamingTheField) {
  const Walk walk = bundledWalk();
  const motion::Skeleton& skeleton = walk.asset.skeleton;
  EXPECT_EQ(targetFromJson("{", skeleton, "t.json").message(), "t.json: not valid JSON");
  EXPECT_NE(targetFromJson(R"({"format":"other"})", skeleton, "t.json").message().find("format"),
            std::string::npos);
  std::string text = targetToJson(walk.target, skeleton);
  std::string bad_axis = text;
  bad_axis.replace(bad_axis.find("\"axis\": \"x\""), 11, "\"axis\": \"w\"");
  EXPECT_NE(targetFromJson(bad_axis, skeleton, "t.json").message().find("channels[0].axis"),
            std::string::npos);
  std::string bad_joint = text;
  bad_joint.replace(bad_joint.find("\"joint\": \"Hips\""), 15, "\"joint\": \"Tail\"");
  EXPECT_NE(targetFromJson(bad_joint, skeleton, "t.json").message().find(".joint: no such joint"),
            std::string::npos);
  motion::Skeleton other = skeleton;
  other.names[3] = "Torso";
  EXPECT_NE(targetFromJson(text, other, "t.json").message().find("joints[3].name: expected 'Torso'"),
            std::string::npos);
}

TEST(TargetIoTest, SavedCoefficientsLoadBackToTheSameMotion) {
  const Walk walk = bundledWalk();
  test::TempDir dir;
  ASSERT_TRUE(saveTarget(dir / "walk.json", walk.target, walk.asset.skeleton).ok());
  Result<TargetMotion> loaded = loadTarget(dir / "walk.json", walk.asset.skeleton);
  ASSERT_TRUE(loaded.ok()) << loaded.message();
  EXPECT_LT(harmonicDistance(loaded.value(), walk.target), 1e-12);  // quaternions re-normalised
  EXPECT_LT(poseDistanceDeg(loaded.value(), walk.target), 1e-9);
  EXPECT_DOUBLE_EQ(loaded.value().omega0, walk.target.omega0);
}

}  // namespace
}  // namespace sinew::spectral
