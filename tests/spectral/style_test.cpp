#include "sinew/spectral/style.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "sinew/spectral/bands.h"
#include "spectral/spectral_test_util.h"
#include "support/test_support.h"

namespace sinew::spectral {
namespace {

using test_util::Analysed;
using test_util::analyseFile;
using test_util::bandai;

TEST(TargetMotionTest, RefusesInvalidTargets) {
  const Analysed walk = analyseFile(test::sourceDir() / "assets" / "biped_walk.bvh");
  const motion::Skeleton& skeleton = walk.asset.skeleton;
  ASSERT_TRUE(walk.target.validate(skeleton).ok()) << walk.target.validate(skeleton).message();
  TargetMotion bad = walk.target;
  bad.omega0 = 0.0;
  EXPECT_NE(bad.validate(skeleton).message().find("omega0"), std::string::npos);
  bad = walk.target;
  bad.channels.push_back(bad.channels.front());
  EXPECT_NE(bad.validate(skeleton).message().find("twice"), std::string::npos);
  bad = walk.target;
  bad.channels.front().terms.push_back({0, 1.0, 0.0});
  EXPECT_NE(bad.validate(skeleton).message().find("n in 1..1024"), std::string::npos);
  bad = walk.target;
  bad.channels.front().terms.push_back({1025, 1.0, 0.0});  // sizes buffers: 1e9 was a hang
  EXPECT_NE(bad.validate(skeleton).message().find("n in 1..1024"), std::string::npos);
  bad = walk.target;
  bad.base_rotations.pop_back();
  EXPECT_FALSE(bad.validate(skeleton).ok());
}

TEST(TargetMotionTest, SampledLoopsCloseAndMatchTheModel) {
  const Analysed walk = analyseFile(test::sourceDir() / "assets" / "biped_walk.bvh");
  const motion::Clip clip = walk.target.sample(30.0, 3);
  ASSERT_TRUE(clip.validate(walk.asset.skeleton).ok());
  EXPECT_EQ(clip.frame_count, 97);  // 3 strides of 32 frames, plus the closing frame
  EXPECT_DOUBLE_EQ(clip.frame_time, 1.0 / 30.0);  // exactly the rate asked for
  EXPECT_NEAR(clip.duration(), 3 * walk.target.period(), 0.5 * 3 / 30.0);
  const int last = clip.frame_count - 1;
  for (int j = 0; j < clip.joint_count; ++j) {
    EXPECT_NEAR(std::abs(glm::dot(clip.rotation(0, j), clip.rotation(last, j))), 1.0, 1e-12);
  }
  // Travel: three strides at 1.30 m/s.
  EXPECT_NEAR(clip.translation(last, 0).z - clip.translation(0, 0).z, 3 * 1.0667 * 1.30, 0.02);
}

TEST(BandGainsTest, RefusesBadBandsAndNamesGroups) {
  BandGains gains;
  EXPECT_TRUE(gains.validate().ok());
  EXPECT_NE(gains.set("tempo", "", 1.0).message().find("unknown band 'tempo' (gait, style, detail)"),
            std::string::npos);
  EXPECT_NE(gains.set("style", "tail", 1.0).message().find("unknown joint group 'tail'"),
            std::string::npos);
  EXPECT_FALSE(gains.set("style", "legs", -1.0).ok());
  BandGains overlapping;
  overlapping.bands[1].first = 2;
  EXPECT_NE(overlapping.validate().message().find("overlaps"), std::string::npos);
  motion::Skeleton skeleton;
  const int hips = skeleton.addJoint("Hips", motion::kNoParent, {});
  const int hip = skeleton.addJoint("LHipJoint", hips, {});
  skeleton.addJoint("LeftKnee", hip, {});
  const int chest = skeleton.addJoint("Chest", hips, {});
  const int arm = skeleton.addJoint("UpperArm_L", chest, {});
  skeleton.addJoint("Index1", arm, {});
  skeleton.addJoint("Head", chest, {});
  const std::vector<JointGroup> groups = jointGroups(skeleton);
  const std::vector<JointGroup> expected = {JointGroup::kSpine, JointGroup::kLegs, JointGroup::kLegs,
                                            JointGroup::kSpine, JointGroup::kArms, JointGroup::kArms,
                                            JointGroup::kHead};
  EXPECT_EQ(groups, expected);
}

TEST(BandGainsTest, GainsScaleTheirBandOnlyForTheirGroup) {
  const Analysed walk = analyseFile(test::sourceDir() / "assets" / "biped_walk.bvh");
  BandGains gains;
  ASSERT_TRUE(gains.set("style", "legs", 0.0).ok());
  ASSERT_TRUE(gains.set("gait", "arms", 2.0).ok());
  const TargetMotion edited = applyBandGains(walk.target, walk.asset.skeleton, gains);
  const std::vector<JointGroup> groups = jointGroups(walk.asset.skeleton);
  for (size_t c = 0; c < edited.channels.size(); ++c) {
    const JointGroup group = groups[edited.channels[c].joint];
    for (size_t h = 0; h < edited.channels[c].terms.size(); ++h) {
      const Harmonic& before = walk.target.channels[c].terms[h];
      const Harmonic& after = edited.channels[c].terms[h];
      double expected = before.amplitude;
      if (group == JointGroup::kLegs && before.n >= 3 && before.n <= 5) expected = 0.0;
      if (group == JointGroup::kArms && before.n <= 2) expected *= 2.0;
      EXPECT_DOUBLE_EQ(after.amplitude, expected);
      EXPECT_DOUBLE_EQ(after.phase, before.phase);
    }
  }
}

TEST(StyleTest, WeightZeroIsTheIdentityAndOneReproducesTheStyledClip) {
  SINEW_REQUIRE_SHARED_DATA();
  const Analysed normal = analyseFile(bandai("walk_normal"));
  const Analysed tired = analyseFile(bandai("walk_tired"));
  Result<StyleVector> style = measureStyle(normal.target, tired.target, "tired");
  ASSERT_TRUE(style.ok()) << style.message();
  const TargetMotion same = applyStyles(normal.target, {{&style.value(), 0.0}}).value();
  EXPECT_EQ(harmonicDistance(same, normal.target), 0.0);
  EXPECT_EQ(poseDistanceDeg(same, normal.target), 0.0);
  EXPECT_FALSE(applyStyles(normal.target, {{&style.value(), 2.5}}).ok());
}

TEST(StyleTest, TiredStyleBringsTheNormalWalkCloserToTheTiredWalk) {
  SINEW_REQUIRE_SHARED_DATA();
  const Analysed normal = analyseFile(bandai("walk_normal"));
  const Analysed tired = analyseFile(bandai("walk_tired"));
  const StyleVector style = measureStyle(normal.target, tired.target, "tired").value();
  // Compare with phase origins aligned on the same gait event.
  TargetMotion reference = tired.target;
  const auto [joint, axis] = phaseReference(normal.target);
  alignPhase(reference, joint, axis);
  for (double w : {0.5, 1.0}) {
    TargetMotion styled = applyStyles(normal.target, {{&style, w}}).value();
    TargetMotion before = normal.target;
    alignPhase(styled, joint, axis);
    alignPhase(before, joint, axis);
    const double h_before = harmonicDistance(before, reference);
    const double h_after = harmonicDistance(styled, reference);
    const double p_before = poseDistanceDeg(before, reference);
    const double p_after = poseDistanceDeg(styled, reference);
    std::printf("  tired style w=%.1f on the normal walk: harmonic distance %.4f -> %.4f, "
                "pose distance %.2f -> %.2f deg, stride %.3f -> %.3f s (tired %.3f s)\n",
                w, h_before, h_after, p_before, p_after, normal.target.period(), styled.period(),
                tired.target.period());
    EXPECT_LT(h_after, h_before);
    EXPECT_LT(p_after, p_before);
  }
}

std::vector<std::pair<std::string, TargetMotion>> walkLibrary() {
  std::vector<std::pair<std::string, TargetMotion>> library;
  for (const char* style : {"normal", "happy", "tired", "angry"}) {
    library.emplace_back(style, analyseFile(bandai(std::string("walk_") + style)).target);
  }
  return library;
}

double scoreOf(const StyleScores& scores, const std::string& label) {
  for (const auto& [name, score] : scores.scores) {
    if (name == label) return score;
  }
  return -1.0;
}

StyleScores measureRun(const std::string& run,
                       const std::vector<std::pair<std::string, TargetMotion>>& library) {
  const Analysed clip = analyseFile(bandai("run_" + run));
  Result<StyleScores> scores = scoreStyle(clip.asset.skeleton, clip.target, library);
  EXPECT_TRUE(scores.ok()) << scores.message();
  std::printf("  run_%s:", run.c_str());
  for (const auto& [label, score] : scores.value().scores) std::printf(" %s %.3f", label.c_str(), score);
  std::printf(" -> %s\n", scores.value().closest.c_str());
  return scores.value();
}

// The carriage: trunk, neck and each limb down to its first long bone; not the head, the joints
// above the pelvis, or the distal joints.
TEST(StyleTest, CarriageIsTheTrunkNeckAndProximalLimbs) {
  const motion::MotionAsset walk = test_util::analyseFile(test::sourceDir() / "assets" / "biped_walk.bvh").asset;
  std::vector<std::string> names;
  for (int j : carriageJoints(walk.skeleton)) names.push_back(walk.skeleton.names[j]);
  const std::vector<std::string> expected = {"Spine",     "Spine1",        "Chest",    "Neck",
                                             "LeftShoulder", "LeftArm",    "RightShoulder",
                                             "RightArm",  "LeftUpLeg",     "RightUpLeg"};
  EXPECT_EQ(names, expected);
}

// Every walk of the library measures as itself.
TEST(StyleTest, MeasurementNamesEachWalkItself) {
  SINEW_REQUIRE_SHARED_DATA();
  const auto library = walkLibrary();
  for (const auto& [label, target] : library) {
    Result<StyleScores> scores = scoreStyle(analyseFile(bandai("walk_" + label)).asset.skeleton,
                                            target, library);
    ASSERT_TRUE(scores.ok()) << scores.message();
    std::printf("  walk_%s:", label.c_str());
    for (const auto& [name, score] : scores.value().scores) std::printf(" %s %.3f", name.c_str(), score);
    std::printf(" -> %s\n", scores.value().closest.c_str());
    EXPECT_EQ(scores.value().closest, label);
  }
}

// Measured against the four walks, the tired run scores as tired far more than the normal run
// does, and the normal run as normal more than the tired run does.
TEST(StyleTest, MeasurementTellsTheTiredRunFromTheNormalRun) {
  SINEW_REQUIRE_SHARED_DATA();
  const auto library = walkLibrary();
  const StyleScores normal = measureRun("normal", library);
  const StyleScores tired = measureRun("tired", library);
  EXPECT_EQ(tired.closest, "tired");
  EXPECT_GT(scoreOf(tired, "tired"), 2.0 * scoreOf(normal, "tired"));
  EXPECT_GT(scoreOf(normal, "normal"), scoreOf(tired, "normal"));
}

// The normal run's carriage is 5.6 degrees (RMS) from the normal walk's and 6.4 from the happy
// walk's: normal and happy walks differ in dynamics more than in carriage (2.4 degrees apart),
// so this margin is the smallest of the measurement (docs/spectral.md).
TEST(StyleTest, MeasurementNamesTheNormalRunNormal) {
  SINEW_REQUIRE_SHARED_DATA();
  EXPECT_EQ(measureRun("normal", walkLibrary()).closest, "normal");
}

}  // namespace
}  // namespace sinew::spectral
