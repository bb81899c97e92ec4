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
  // Bit for bit: a replayed controller must be the one that was scored. Re-normalising the unit
  // base rotations moved their last bits, and the bundled stepper's evolved best, 10 s up in its
  // search, fell at 7.55 s when replayed from its best.json.
  EXPECT_EQ(harmonicDistance(loaded.value(), walk.target), 0.0);
  EXPECT_EQ(loaded.value().omega0, walk.target.omega0);
  ASSERT_EQ(loaded.value().base_rotations.size(), walk.target.base_rotations.size());
  for (size_t j = 0; j < walk.target.base_rotations.size(); ++j) {
    EXPECT_EQ(loaded.value().base_rotations[j], walk.target.base_rotations[j]) << j;
    EXPECT_EQ(loaded.value().base_translations[j], walk.target.base_translations[j]) << j;
  }
}

TEST(TargetIoTest, ABaseRotationThatIsNotUnitIsNormalised) {
  const Walk walk = bundledWalk();
  TargetMotion doubled = walk.target;
  doubled.base_rotations[1] *= 2.0;
  Result<TargetMotion> loaded =
      targetFromJson(targetToJson(doubled, walk.asset.skeleton), walk.asset.skeleton, "t.json");
  ASSERT_TRUE(loaded.ok()) << loaded.message();
  EXPECT_NEAR(glm::length(loaded.value().base_rotations[1]), 1.0, 1e-15);
  EXPECT_LT(poseDistanceDeg(loaded.value(), walk.target), 1e-9);
}

}  // namespace
}  // namespace sinew::spectral

namespace sinew::spectral {
namespace {

// The walk's coefficients with the first harmonic's "n" (of channel 0) written as `n`.
std::string withFirstN(const std::string& text, const std::string& n) {
  std::string out = text;
  const size_t at = out.find("\"n\": ");
  const size_t end = out.find_first_of(",\n}", at);
  return out.replace(at, end - at, "\"n\": " + n);
}

TEST(TargetIoTest, HarmonicIndicesAreWholeNumbersWithinTheLimit) {
  const Walk walk = bundledWalk();
  const std::string text = targetToJson(walk.target, walk.asset.skeleton);
  // 1e9 used to allocate 16 GB (a hang); 1.5 was read as 1.
  for (const char* bad : {"1e9", "100000000", "1.5", "0", "-3", "\"2\""}) {
    Result<TargetMotion> r = targetFromJson(withFirstN(text, bad), walk.asset.skeleton, "t.json");
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(r.message(),
              "t.json: channels[0].harmonics[0].n: expected a whole number from 1 to 1024")
        << bad;
  }
  EXPECT_TRUE(targetFromJson(withFirstN(text, "1024"), walk.asset.skeleton, "t.json").ok());
}

TEST(TargetIoTest, NumbersBeyondTheLimitsAreRefused) {
  const Walk walk = bundledWalk();
  const std::string text = targetToJson(walk.target, walk.asset.skeleton);
  std::string huge = text;
  const size_t at = huge.find("\"amplitude\": ");
  huge.replace(at, huge.find(',', at) - at, "\"amplitude\": 1e300");
  Result<TargetMotion> r = targetFromJson(huge, walk.asset.skeleton, "t.json");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("needs n in 1..1024, an amplitude in [0, 1e6]"), std::string::npos)
      << r.message();
  std::string omega = text;
  const size_t o = omega.find("\"omega0_rad_s\": ");
  omega.replace(o, omega.find(',', o) - o, "\"omega0_rad_s\": 1e300");
  EXPECT_NE(targetFromJson(omega, walk.asset.skeleton, "t.json").message().find("omega0"),
            std::string::npos);
}

TEST(TargetIoTest, JointsAreMatchedByNameAndHierarchy) {
  const Walk walk = bundledWalk();
  const std::string text = targetToJson(walk.target, walk.asset.skeleton);
  motion::Skeleton other = walk.asset.skeleton;
  other.parents[5] = 0;  // same names, another tree
  Result<TargetMotion> r = targetFromJson(text, other, "t.json");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.message(), "t.json: joints[5].parent: expected 'Hips', found '" +
                             walk.asset.skeleton.names[4] +
                             "' (the coefficients are for a rig with another hierarchy)");
}

TEST(TargetIoTest, UnknownKeysAreWarningsNamingTheField) {
  const Walk walk = bundledWalk();
  std::string text = targetToJson(walk.target, walk.asset.skeleton);
  text.replace(text.find("\"format\""), 8, "\"omega_0\": 3, \"format\"");
  std::vector<std::string> warnings;
  Result<TargetMotion> r = targetFromJson(text, walk.asset.skeleton, "t.json", &warnings);
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0], "t.json: unknown key 'omega_0' (ignored)");
}

TEST(TargetIoTest, ByteOrderMarkAndMissingFieldsGiveClearMessages) {
  const Walk walk = bundledWalk();
  const std::string text = targetToJson(walk.target, walk.asset.skeleton);
  EXPECT_TRUE(targetFromJson("\xEF\xBB\xBF" + text, walk.asset.skeleton, "t.json").ok());
  EXPECT_EQ(
      targetFromJson(R"({"format":"sinew.target","version":1})", walk.asset.skeleton, "t.json")
          .message(),
      "t.json: omega0_rad_s: expected a number");
}

}  // namespace
}  // namespace sinew::spectral
