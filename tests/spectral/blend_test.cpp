#include "sinew/spectral/blend.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "sinew/spectral/secondary.h"
#include "sinew/spectral/target_io.h"
#include "spectral/spectral_test_util.h"
#include "support/test_support.h"

namespace sinew::spectral {
namespace {

using test_util::Analysed;
using test_util::analyseFile;
using test_util::bandai;

TEST(BlendTest, RefusesBadWeightsAndSkeletons) {
  const Analysed walk = analyseFile(test::sourceDir() / "assets" / "biped_walk.bvh");
  EXPECT_FALSE(blendTargets(walk.target, walk.target, 1.5).ok());
  EXPECT_FALSE(blendTargets(walk.target, walk.target, -0.1).ok());
  TargetMotion fewer = walk.target;
  fewer.base_rotations.pop_back();
  EXPECT_NE(blendTargets(walk.target, fewer, 0.5).message().find("one skeleton"), std::string::npos);
  Transition bad;
  bad.duration_s = 0.0;
  EXPECT_FALSE(transitionClip(walk.target, walk.target, bad).ok());
}

TEST(BlendTest, HalfwayBetweenWalkAndRunHasTheMeanTempoAndEndsAreExact) {
  SINEW_REQUIRE_SHARED_DATA();
  const Analysed walk = analyseFile(bandai("walk_normal"));
  const Analysed run = analyseFile(bandai("run_tired"));
  const TargetMotion start = blendTargets(walk.target, run.target, 0.0).value();
  EXPECT_EQ(poseDistanceDeg(start, walk.target), 0.0);
  const TargetMotion half = blendTargets(walk.target, run.target, 0.5).value();
  ASSERT_TRUE(half.validate(walk.asset.skeleton).ok());
  EXPECT_NEAR(half.period(), std::sqrt(walk.target.period() * run.target.period()), 1e-9);
  const TargetMotion end = blendTargets(walk.target, run.target, 1.0).value();
  EXPECT_NEAR(end.omega0, run.target.omega0, 1e-12);
  const double to_walk = poseDistanceDeg(half, walk.target);
  const double to_run = poseDistanceDeg(half, run.target);
  const double apart = poseDistanceDeg(walk.target, run.target);
  std::printf("  walk-run blend at 0.5: %.2f deg from the walk, %.2f from the run (they are %.2f "
              "apart); stride %.3f s between %.3f and %.3f\n",
              to_walk, to_run, apart, half.period(), walk.target.period(), run.target.period());
  EXPECT_LT(to_walk, apart);
  EXPECT_LT(to_run, apart);
}

TEST(BlendTest, TransitionChangesTempoWithoutJumps) {
  SINEW_REQUIRE_SHARED_DATA();
  const Analysed walk = analyseFile(bandai("walk_normal"));
  const Analysed run = analyseFile(bandai("run_tired"));
  Transition transition;
  transition.start_s = 1.0;
  transition.duration_s = 1.5;
  transition.total_s = 4.0;
  const motion::Clip clip = transitionClip(walk.target, run.target, transition).value();
  ASSERT_TRUE(clip.validate(walk.asset.skeleton).ok());
  EXPECT_EQ(clip.frame_count, 121);
  // No frame-to-frame jump larger than the biggest one inside the walk or the run themselves.
  const motion::Clip walk_clip = walk.target.sample(30.0, 2);
  const motion::Clip run_clip = run.target.sample(30.0, 2);
  const auto largestStep = [](const motion::Clip& c) {
    double largest = 0.0;
    for (int f = 1; f < c.frame_count; ++f) {
      for (int j = 0; j < c.joint_count; ++j) {
        largest = std::max(largest, angleBetween(c.rotation(f - 1, j), c.rotation(f, j)));
      }
    }
    return largest;
  };
  const double limit = std::max(largestStep(walk_clip), largestStep(run_clip));
  std::printf("  transition: largest joint step %.2f deg per frame (walk/run alone: %.2f)\n",
              glm::degrees(largestStep(clip)), glm::degrees(limit));
  EXPECT_LE(largestStep(clip), limit * 1.05);
}

TEST(SecondaryTest, RefusesBadSourcesAndIsDeterministic) {
  const Analysed walk = analyseFile(test::sourceDir() / "assets" / "biped_walk.bvh");
  SecondarySettings settings;
  settings.sources.push_back({SecondarySource::Kind::kPeriodic, "Tail", 0, 0.25, 1.0, 1});
  EXPECT_NE(addSecondaryMotion(walk.target, walk.asset.skeleton, settings).message().find("'Tail'): no such joint"),
            std::string::npos);
  settings.sources = {{SecondarySource::Kind::kPeriodic, "Chest", 0, 0.25, 45.0, 1}};
  EXPECT_NE(addSecondaryMotion(walk.target, walk.asset.skeleton, settings).message().find("amplitude_deg"),
            std::string::npos);
  settings.sources = {{SecondarySource::Kind::kPeriodic, "Chest", 0, 0.25, 1.5, 1},
                      {SecondarySource::Kind::kNoise, "Head", 1, 3.0, 2.0, 42}};
  const TargetMotion one = addSecondaryMotion(walk.target, walk.asset.skeleton, settings).value();
  const TargetMotion two = addSecondaryMotion(walk.target, walk.asset.skeleton, settings).value();
  ASSERT_EQ(one.secondary.size(), 7u);
  for (size_t n = 0; n < one.secondary.size(); ++n) {
    EXPECT_EQ(one.secondary[n].omega, two.secondary[n].omega);
    EXPECT_EQ(one.secondary[n].phase, two.secondary[n].phase);
  }
  // Breathing at 0.25 Hz snaps to a quarter of the 0.9375 Hz stride: 0.234 Hz.
  EXPECT_NEAR(one.secondary[0].omega / (2 * 3.14159265358979), 0.9375 / 4, 1e-3);
  settings.sources[1].seed = 43;
  const TargetMotion other = addSecondaryMotion(walk.target, walk.asset.skeleton, settings).value();
  EXPECT_NE(other.secondary[1].phase, one.secondary[1].phase);
}

TEST(SecondaryTest, LoopsStillCloseAndCoefficientsKeepIt) {
  const Analysed walk = analyseFile(test::sourceDir() / "assets" / "biped_walk.bvh");
  SecondarySettings settings;
  settings.sources = {{SecondarySource::Kind::kPeriodic, "Chest", 0, 0.25, 1.5, 1},
                      {SecondarySource::Kind::kNoise, "Head", 1, 3.0, 2.0, 42}};
  const TargetMotion breathing = addSecondaryMotion(walk.target, walk.asset.skeleton, settings).value();
  const motion::Clip clip = breathing.sample(30.0, 4);  // loop_strides = 4
  const int last = clip.frame_count - 1;
  for (int j = 0; j < clip.joint_count; ++j) {
    EXPECT_LT(angleBetween(clip.rotation(0, j), clip.rotation(last, j)), 1e-9);
  }
  // The chest now breathes: its pose differs from the walk's.
  EXPECT_GT(poseDistanceDeg(breathing, walk.target), 0.1);
  test::TempDir dir;
  ASSERT_TRUE(saveTarget(dir / "b.json", breathing, walk.asset.skeleton).ok());
  const TargetMotion loaded = loadTarget(dir / "b.json", walk.asset.skeleton).value();
  EXPECT_EQ(loaded.secondary.size(), breathing.secondary.size());
  EXPECT_LT(poseDistanceDeg(loaded, breathing), 1e-9);
}

}  // namespace
}  // namespace sinew::spectral
