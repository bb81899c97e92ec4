// Style relative to a neutral of the same actor: a library from the first half of each Bandai walk
// names every second half; a style transferred onto another actor's neutral is named when measured
// against that neutral. The scores are printed (docs/spectral.md quotes them).
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "sinew/spectral/bands.h"
#include "sinew/spectral/style.h"
#include "spectral/spectral_test_util.h"
#include "support/test_support.h"

namespace sinew::spectral {
namespace {

using test_util::bandai;

const char* const kStyles[] = {"normal", "happy", "tired", "angry"};

motion::Clip half(const motion::Clip& clip, bool second) {
  const int middle = clip.frame_count / 2;
  const int first = second ? middle : 0;
  const int last = second ? clip.frame_count - 1 : middle;
  motion::Clip out = clip;
  out.frame_count = last - first + 1;
  const auto begin = static_cast<size_t>(first) * clip.joint_count;
  const auto end = static_cast<size_t>(last + 1) * clip.joint_count;
  out.rotations.assign(clip.rotations.begin() + begin, clip.rotations.begin() + end);
  out.translations.assign(clip.translations.begin() + begin, clip.translations.begin() + end);
  return out;
}

TargetMotion targetOf(const motion::Skeleton& skeleton, const motion::Clip& clip,
                      const std::string& name) {
  AnalysisSettings settings;
  settings.harmonics = 10;
  Result<MotionSpectrum> spectrum = analyze(skeleton, clip, settings);
  EXPECT_TRUE(spectrum.ok()) << spectrum.message();
  return targetFromSpectrum(spectrum.value(), {}, name);
}

struct Halves {
  motion::Skeleton skeleton;
  std::vector<TargetMotion> first, second;  // in kStyles order
};

Halves bandaiHalves() {
  Halves h;
  for (const char* style : kStyles) {
    Result<motion::MotionAsset> asset = motion::importMotion(bandai(std::string("walk_") + style));
    EXPECT_TRUE(asset.ok()) << asset.message();
    h.skeleton = asset.value().skeleton;
    const motion::Clip& clip = asset.value().clips[0];
    h.first.push_back(targetOf(h.skeleton, half(clip, false), style));
    h.second.push_back(targetOf(h.skeleton, half(clip, true), style));
  }
  return h;
}

void print(const std::string& what, const StyleScores& scores) {
  std::printf("  %-34s", what.c_str());
  for (size_t n = 0; n < scores.scores.size(); ++n) {
    std::printf(" %s %.3f (%.2f)", scores.scores[n].first.c_str(), scores.scores[n].second,
                scores.distances[n]);
  }
  std::printf(" -> %s\n", scores.closest.c_str());
}

std::vector<StyleExample> firstHalfLibrary(const Halves& h) {
  std::vector<StyleExample> library;
  for (size_t s = 0; s < h.first.size(); ++s)
    library.push_back({kStyles[s], h.first[0], h.first[s]});
  return library;
}

TEST(StyleRelativeTest, SkeletonsAreMatchedByJointNamesAndHierarchy) {
  SINEW_REQUIRE_SHARED_DATA();
  Result<motion::MotionAsset> bandai_walk = motion::importMotion(bandai("walk_normal"));
  Result<motion::MotionAsset> biped =
      motion::importMotion(test::sourceDir() / "assets" / "biped_walk.bvh");
  ASSERT_TRUE(bandai_walk.ok() && biped.ok());
  ASSERT_EQ(bandai_walk.value().skeleton.jointCount(),
            biped.value().skeleton.jointCount());  // 22 each
  const Status status = sameJoints(biped.value().skeleton, bandai_walk.value().skeleton);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("joint 0 is 'joint_Root'"), std::string::npos)
      << status.message();
  EXPECT_TRUE(sameJoints(bandai_walk.value().skeleton, bandai_walk.value().skeleton).ok());
  motion::Skeleton moved = bandai_walk.value().skeleton;
  moved.parents[5] = 0;
  EXPECT_NE(sameJoints(bandai_walk.value().skeleton, moved).message().find("joint 5"),
            std::string::npos);
}

TEST(StyleRelativeTest, DuplicateLabelsAreExamplesOfOneLabel) {
  SINEW_REQUIRE_SHARED_DATA();
  const Halves h = bandaiHalves();
  std::vector<std::pair<std::string, TargetMotion>> library;
  for (size_t s = 0; s < h.first.size(); ++s) {
    library.emplace_back(kStyles[s], h.first[s]);
    library.emplace_back(kStyles[s], h.second[s]);
  }
  Result<StyleScores> scores = scoreStyle(h.skeleton, h.second[2], library);
  ASSERT_TRUE(scores.ok()) << scores.message();
  ASSERT_EQ(scores.value().scores.size(), 4u);
  double total = 0.0;
  for (size_t n = 0; n < 4; ++n) {
    total += scores.value().scores[n].second;
    EXPECT_EQ(scores.value().examples[n], 2);
  }
  EXPECT_NEAR(total, 1.0, 1e-12);
  EXPECT_EQ(scores.value().closest, "tired");
  EXPECT_EQ(scores.value().distances[2], 0.0);  // its own example
}

// The library is the first half of each walk, each against the first half of the normal walk;
// every second half, measured against the normal walk's second half (the neutral of that "take"),
// is named right. The absolute measurement is printed beside it.
TEST(StyleRelativeTest, FirstHalvesNameEverySecondHalf) {
  SINEW_REQUIRE_SHARED_DATA();
  const Halves h = bandaiHalves();
  const std::vector<StyleExample> library = firstHalfLibrary(h);
  std::vector<std::pair<std::string, TargetMotion>> absolute;
  for (size_t s = 0; s < h.first.size(); ++s) absolute.emplace_back(kStyles[s], h.first[s]);
  for (size_t s = 0; s < h.second.size(); ++s) {
    for (int neutral_half = 0; neutral_half < 2; ++neutral_half) {
      const TargetMotion& neutral = neutral_half == 0 ? h.first[0] : h.second[0];
      if (s == 0 && neutral_half == 1) continue;  // itself: no difference at all
      Result<StyleScores> scores = scoreStyleRelative(h.skeleton, h.second[s], neutral, library);
      ASSERT_TRUE(scores.ok()) << scores.message();
      print(std::string("walk_") + kStyles[s] + " 2nd half vs normal " +
                (neutral_half == 0 ? "1st" : "2nd") + " half",
            scores.value());
      EXPECT_EQ(scores.value().closest, kStyles[s]);
    }
    Result<StyleScores> plain = scoreStyle(h.skeleton, h.second[s], absolute);
    ASSERT_TRUE(plain.ok());
    print(std::string("walk_") + kStyles[s] + " 2nd half, absolute", plain.value());
  }
}

// Another actor: the normal walk's second half with another carriage (trunk flexed 8 degrees,
// arms held 10 degrees out), other dynamics (arm swing x 0.7, leg swing x 1.15) and a 7% slower
// tempo. Each style, measured from the first halves, is applied to that actor's neutral and
// measured against it: named right. Measured absolutely (against the styled first halves), the
// new actor's carriage decides instead, and it is printed for comparison.
TEST(StyleRelativeTest, StyleAppliedToAnotherActorIsNamedAgainstThatActorsNeutral) {
  SINEW_REQUIRE_SHARED_DATA();
  const Halves h = bandaiHalves();
  const motion::Skeleton& skeleton = h.skeleton;
  TargetMotion actor = h.second[0];
  actor.omega0 /= 1.07;
  const auto turn = [&](const char* joint, const glm::dvec3& axis, double degrees) {
    const int j = skeleton.findJoint(joint);
    ASSERT_GE(j, 0) << joint;
    actor.base_rotations[j] =
        glm::normalize(actor.base_rotations[j] * glm::angleAxis(glm::radians(degrees), axis));
  };
  turn("Spine", {1, 0, 0}, 8.0);
  turn("UpperArm_L", {0, 0, 1}, 10.0);
  turn("UpperArm_R", {0, 0, 1}, -10.0);
  const std::vector<JointGroup> groups = jointGroups(skeleton);
  for (ChannelModel& channel : actor.channels) {
    const double gain = groups[channel.joint] == JointGroup::kArms   ? 0.7
                        : groups[channel.joint] == JointGroup::kLegs ? 1.15
                                                                     : 1.0;
    for (Harmonic& term : channel.terms) term.amplitude *= gain;
  }
  const std::vector<StyleExample> library = firstHalfLibrary(h);
  std::vector<std::pair<std::string, TargetMotion>> absolute;
  for (size_t s = 0; s < h.first.size(); ++s) absolute.emplace_back(kStyles[s], h.first[s]);
  for (size_t s = 1; s < h.first.size(); ++s) {
    Result<StyleVector> style = measureStyle(h.first[0], h.first[s], kStyles[s]);
    ASSERT_TRUE(style.ok()) << style.message();
    Result<TargetMotion> styled = applyStyles(actor, {{&style.value(), 1.0}});
    ASSERT_TRUE(styled.ok()) << styled.message();
    Result<StyleScores> scores = scoreStyleRelative(skeleton, styled.value(), actor, library);
    ASSERT_TRUE(scores.ok()) << scores.message();
    print(std::string("another actor + ") + kStyles[s], scores.value());
    EXPECT_EQ(scores.value().closest, kStyles[s]);
    Result<StyleScores> plain = scoreStyle(skeleton, styled.value(), absolute);
    ASSERT_TRUE(plain.ok());
    print(std::string("another actor + ") + kStyles[s] + ", absolute", plain.value());
  }
  Result<StyleScores> itself = scoreStyleRelative(skeleton, actor, actor, library);
  ASSERT_TRUE(itself.ok());
  EXPECT_EQ(itself.value().closest, "normal");
}

}  // namespace
}  // namespace sinew::spectral
