#include "sinew/spectral/importance.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "support/test_support.h"

namespace sinew::spectral {
namespace {

struct Walk {
  motion::MotionAsset asset;
  MotionSpectrum spectrum;
};

Walk bundledWalk(const AnalysisSettings& settings = {}) {
  Walk w;
  Result<motion::MotionAsset> asset =
      motion::importMotion(test::sourceDir() / "assets" / "biped_walk.bvh");
  EXPECT_TRUE(asset.ok()) << asset.message();
  if (!asset.ok()) return w;
  w.asset = std::move(asset).value();
  Result<MotionSpectrum> spectrum = analyze(w.asset.skeleton, w.asset.clips[0], settings);
  EXPECT_TRUE(spectrum.ok()) << spectrum.message();
  if (spectrum.ok()) w.spectrum = std::move(spectrum).value();
  return w;
}

// Rank (0 = most important) of a joint by name, or -1 when it is not listed.
int rankOf(const motion::Skeleton& skeleton, const ImportanceReport& report,
           const std::string& name) {
  for (size_t r = 0; r < report.joints.size(); ++r) {
    if (skeleton.names[report.joints[r].joint] == name) return static_cast<int>(r);
  }
  return -1;
}

const JointImportance& entry(const motion::Skeleton& skeleton, const ImportanceReport& report,
                             const std::string& name) {
  return report.joints[rankOf(skeleton, report, name)];
}

TEST(ImportanceTest, RefusesInvalidInput) {
  const Walk w = bundledWalk();
  ImportanceSettings bad;
  bad.rank_by = static_cast<ImportanceRank>(7);
  Result<ImportanceReport> result =
      jointImportance(w.asset.skeleton, w.asset.clips[0], w.spectrum, bad);
  EXPECT_NE(result.message().find("rank_by"), std::string::npos) << result.message();
  MotionSpectrum other = w.spectrum;
  other.joint_k.pop_back();
  result = jointImportance(w.asset.skeleton, w.asset.clips[0], other);
  EXPECT_NE(result.message().find("not this clip's analysis"), std::string::npos)
      << result.message();
}

TEST(ImportanceTest, LegsMatterMoreThanHandsToesAndHead) {
  const Walk w = bundledWalk();
  const motion::Skeleton& skeleton = w.asset.skeleton;
  Result<ImportanceReport> result = jointImportance(skeleton, w.asset.clips[0], w.spectrum);
  ASSERT_TRUE(result.ok()) << result.message();
  const ImportanceReport& report = result.value();
  std::printf("  biped_walk: the model alone %.3f cm mean; frozen, most important first:\n",
              report.model_cm_mean);
  for (size_t r = 0; r < std::min<size_t>(5, report.joints.size()); ++r) {
    const JointImportance& j = report.joints[r];
    std::printf("  %zu. %-14s %.3f cm mean, %.2f cm max, energy %.4f rad^2, lever %.3f m\n", r + 1,
                skeleton.names[j.joint].c_str(), j.frozen_cm_mean, j.frozen_cm_max, j.energy_rad2,
                j.lever_m);
  }
  // The walk holds the wrists still: a joint that does not move is not listed, below them all.
  const auto rankOrLast = [&](const char* name) {
    const int rank = rankOf(skeleton, report, name);
    return rank >= 0 ? rank : static_cast<int>(report.joints.size());
  };
  for (const char* leg : {"LeftUpLeg", "RightUpLeg", "LeftLeg", "RightLeg"}) {
    ASSERT_GE(rankOf(skeleton, report, leg), 0) << leg;
    for (const char* small : {"LeftHand", "RightHand", "LeftToe", "RightToe", "Head"}) {
      EXPECT_LT(rankOf(skeleton, report, leg), rankOrLast(small)) << leg << " vs " << small;
    }
  }
  ASSERT_GE(rankOf(skeleton, report, "Head"), 0);
  ASSERT_GE(rankOf(skeleton, report, "LeftToe"), 0);
  const JointImportance& hip = entry(skeleton, report, "LeftUpLeg");
  const JointImportance& head = entry(skeleton, report, "Head");
  EXPECT_GT(hip.frozen_cm_mean, 5.0 * head.frozen_cm_mean);
  EXPECT_GT(hip.frozen_cm_max, 20.0);  // the swinging foot is left behind by tens of cm
  // Freezing any joint can only add to the model's own error, here.
  for (const JointImportance& j : report.joints)
    EXPECT_GE(j.frozen_cm_mean, report.model_cm_mean - 1e-9);
  // The thigh carries the whole leg: a lever about as long as the leg (84 cm + foot).
  EXPECT_NEAR(hip.lever_m, 0.93, 0.05);
}

TEST(ImportanceTest, AJointWithoutHarmonicsCostsNothingToFreeze) {
  AnalysisSettings settings;
  settings.joint_harmonics = {{"LeftForeArm", 0}};
  const Walk w = bundledWalk(settings);
  const motion::Skeleton& skeleton = w.asset.skeleton;
  const ImportanceReport report = jointImportance(skeleton, w.asset.clips[0], w.spectrum).value();
  const JointImportance& elbow = entry(skeleton, report, "LeftForeArm");
  // The model already holds it at its mean: freezing it changes nothing.
  EXPECT_EQ(elbow.energy_rad2, 0.0);
  EXPECT_NEAR(elbow.frozen_cm_mean, report.model_cm_mean, 1e-9);
  EXPECT_GT(entry(skeleton, report, "RightForeArm").frozen_cm_mean, report.model_cm_mean);
  // Ranked by energy instead, the order follows energy_rad2.
  ImportanceSettings by_energy;
  by_energy.rank_by = ImportanceRank::kEnergy;
  const ImportanceReport energy =
      jointImportance(skeleton, w.asset.clips[0], w.spectrum, by_energy).value();
  EXPECT_TRUE(std::is_sorted(energy.joints.begin(), energy.joints.end(),
                             [](const JointImportance& a, const JointImportance& b) {
                               return a.energy_rad2 > b.energy_rad2;
                             }));
}

TEST(ImportanceTest, RealWalksRankTheLegsFirst) {
  SINEW_REQUIRE_SHARED_DATA();
  for (const char* file :
       {"bandai_dataset-1_walk_normal_001.bvh", "bandai_dataset-1_walk_tired_001.bvh"}) {
    SCOPED_TRACE(file);
    Result<motion::MotionAsset> asset = motion::importMotion(test::sharedData() / "bvh" / file);
    ASSERT_TRUE(asset.ok()) << asset.message();
    const motion::Skeleton& skeleton = asset.value().skeleton;
    const motion::Clip& clip = asset.value().clips[0];
    const MotionSpectrum spectrum = analyze(skeleton, clip).value();
    const ImportanceReport report = jointImportance(skeleton, clip, spectrum).value();
    std::printf("  %-40s", file);
    for (size_t r = 0; r < std::min<size_t>(5, report.joints.size()); ++r) {
      std::printf(" %s %.2f cm;", skeleton.names[report.joints[r].joint].c_str(),
                  report.joints[r].frozen_cm_mean);
    }
    std::printf("\n");
    EXPECT_LT(rankOf(skeleton, report, "UpperLeg_L"), rankOf(skeleton, report, "Head"));
    EXPECT_LT(rankOf(skeleton, report, "UpperLeg_R"), rankOf(skeleton, report, "Toes_R"));
    EXPECT_LT(rankOf(skeleton, report, "UpperLeg_R"), 3);
  }
}

}  // namespace
}  // namespace sinew::spectral
