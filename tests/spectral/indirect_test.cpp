#include "sinew/spectral/indirect.h"

#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "support/test_support.h"

namespace sinew::spectral {
namespace {

struct Loaded {
  motion::MotionAsset asset;
  MotionSpectrum spectrum;
  IndirectSignals indirect;
};

Loaded load(const std::filesystem::path& path) {
  Loaded out;
  Result<motion::MotionAsset> asset = motion::importMotion(path);
  EXPECT_TRUE(asset.ok()) << asset.message();
  if (!asset.ok()) return out;
  out.asset = std::move(asset).value();
  Result<MotionSpectrum> spectrum = analyze(out.asset.skeleton, out.asset.clips[0]);
  EXPECT_TRUE(spectrum.ok()) << spectrum.message();
  if (!spectrum.ok()) return out;
  out.spectrum = std::move(spectrum).value();
  Result<IndirectSignals> indirect =
      analyzeIndirect(out.asset.skeleton, out.asset.clips[0], out.spectrum);
  EXPECT_TRUE(indirect.ok()) << indirect.message();
  if (indirect.ok()) out.indirect = std::move(indirect).value();
  return out;
}

std::string footNames(const Loaded& l) {
  std::string names;
  for (const Foot& foot : l.indirect.feet) {
    names += (names.empty() ? "" : " ") + l.asset.skeleton.names[foot.joint] + "(" +
             sideName(foot.side) + (foot.by_name ? "" : ", geometry") + ")";
  }
  return names;
}

void printFigures(const std::string& file, const Loaded& l) {
  const GaitFigures& g = l.indirect.gait;
  std::printf("  %-36s feet %s\n", file.c_str(), footNames(l).c_str());
  std::printf(
      "  %-36s stride from contacts %.4f s (%d intervals), analysis %.4f s (%+.2f%%); "
      "stride %.1f cm, step %.1f cm x %.1f cm in %.3f s; duty %.2f; com %.3f m/s, "
      "footfalls %.3f m/s\n",
      "", g.stride_period_s, g.stride_intervals, g.analysis_period_s, 100.0 * g.period_difference,
      100.0 * g.stride_length_m, 100.0 * g.step_length_m, 100.0 * g.step_width_m, g.step_duration_s,
      g.duty_factor, g.speed_m_s, g.contact_speed_m_s);
}

TEST(IndirectTest, RefusesInvalidInput) {
  const Loaded l = load(test::sourceDir() / "assets" / "biped_walk.bvh");
  const motion::Skeleton& skeleton = l.asset.skeleton;
  const motion::Clip& clip = l.asset.clips[0];
  const auto refused = [&](const IndirectSettings& settings, const std::string& field) {
    Result<IndirectSignals> result = analyzeIndirect(skeleton, clip, l.spectrum, settings);
    EXPECT_FALSE(result.ok()) << field;
    EXPECT_NE(result.message().find(field), std::string::npos) << result.message();
  };
  IndirectSettings bad;
  bad.contacts.height_tolerance_m = 0.0;
  refused(bad, "height_tolerance_m");
  bad = {};
  bad.contacts.speed_tolerance_m_s = -1.0;
  refused(bad, "speed_tolerance_m_s");
  bad = {};
  bad.contacts.ground_quantile = 1.5;
  refused(bad, "ground_quantile");
  bad = {};
  bad.contacts.max_gap_s = NAN;
  refused(bad, "max_gap_s");
  bad = {};
  bad.contacts.min_contact_s = -0.1;
  refused(bad, "min_contact_s");
  bad = {};
  bad.masses.thigh = -0.1;
  refused(bad, "masses.thigh");
  bad = {};
  bad.masses = {0, 0, 0, 0, 0, 0, 0, 0};
  refused(bad, "sum to 0");

  // A spectrum of another clip.
  MotionSpectrum other = l.spectrum;
  other.signals.frame_count = 7;
  EXPECT_NE(analyzeIndirect(skeleton, clip, other).message().find("not this clip's analysis"),
            std::string::npos);

  // A single chain has no legs.
  motion::Skeleton pole;
  const int base = pole.addJoint("Base", motion::kNoParent, {0, 0, 0});
  const int top = pole.addJoint("Top", base, {0, 1, 0});
  pole.end_sites[top] = glm::dvec3(0, 0.5, 0);
  Result<std::vector<Foot>> feet = findFeet(pole, motion::restClip(pole, 2, 1.0 / 30));
  EXPECT_NE(feet.message().find("no feet found"), std::string::npos) << feet.message();
}

TEST(IndirectTest, ContactsAndStepsOfTheBundledWalk) {
  const Loaded l = load(test::sourceDir() / "assets" / "biped_walk.bvh");
  printFigures("assets/biped_walk.bvh", l);
  const IndirectSignals& in = l.indirect;
  const motion::Skeleton& skeleton = l.asset.skeleton;
  ASSERT_EQ(in.feet.size(), 2u);
  EXPECT_EQ(skeleton.names[in.feet[0].joint], "LeftFoot");
  EXPECT_EQ(skeleton.names[in.feet[1].joint], "RightFoot");
  EXPECT_EQ(in.feet[0].side, Side::kLeft);
  EXPECT_EQ(in.feet[1].side, Side::kRight);
  EXPECT_EQ(in.feet[0].pair, 1);
  // Authored: 32 frames at 30 fps a stride, 138.67 cm, steps of 69.33 cm, 130 cm/s, hips 18 cm
  // apart, toe-off 60% through each leg's cycle.
  EXPECT_NEAR(in.gait.stride_period_s, 32.0 / 30.0, 0.01 * 32.0 / 30.0);
  EXPECT_NEAR(in.gait.stride_length_m, 1.3867, 0.01);
  EXPECT_NEAR(in.gait.step_length_m, 0.6933, 0.01);
  EXPECT_NEAR(in.gait.step_duration_s, 16.0 / 30.0, 0.5 / 30.0);
  EXPECT_NEAR(in.gait.step_width_m, 0.18, 0.02);
  EXPECT_NEAR(in.gait.speed_m_s, 1.30, 0.005);
  EXPECT_NEAR(in.gait.contact_speed_m_s, 1.30, 0.02);
  EXPECT_NEAR(in.gait.duty_factor, 0.6, 0.05);
  EXPECT_LT(std::abs(in.gait.period_difference), 0.01);
  EXPECT_NEAR(in.forward.z, 1.0, 1e-3);  // it walks along +Z, its left is +X
  EXPECT_NEAR(in.left.x, 1.0, 1e-3);
  // Feet alternate: every step goes from one foot to the other.
  ASSERT_GE(in.steps.size(), 6u);
  for (const Step& step : in.steps) {
    EXPECT_NE(in.footfalls[step.from].foot, in.footfalls[step.to].foot);
  }
}

TEST(IndirectTest, CentreOfMassOfTheBundledWalk) {
  const Loaded l = load(test::sourceDir() / "assets" / "biped_walk.bvh");
  const IndirectSignals& in = l.indirect;
  const motion::Skeleton& skeleton = l.asset.skeleton;
  const std::vector<double>& f = in.masses.fractions;
  EXPECT_NEAR(std::accumulate(f.begin(), f.end(), 0.0), 1.0, 1e-12);
  // Every de Leva segment is present once per side, so the table's fractions come back exactly.
  EXPECT_NEAR(f[skeleton.findJoint("LeftUpLeg")], 0.1416, 1e-12);
  EXPECT_NEAR(f[skeleton.findJoint("RightLeg")], 0.0433, 1e-12);
  EXPECT_NEAR(f[skeleton.findJoint("LeftArm")], 0.0271, 1e-12);
  EXPECT_NEAR(f[skeleton.findJoint("LeftForeArm")], 0.0162, 1e-12);
  EXPECT_NEAR(f[skeleton.findJoint("LeftHand")], 0.0061, 1e-12);
  EXPECT_NEAR(f[skeleton.findJoint("LeftFoot")] + f[skeleton.findJoint("LeftToe")], 0.0137, 1e-12);
  EXPECT_EQ(in.masses.segments[skeleton.findJoint("Neck")], Segment::kHead);
  EXPECT_EQ(in.masses.segments[skeleton.findJoint("LeftShoulder")], Segment::kTrunk);
  ASSERT_GE(in.spectra.size(), 3u);
  const HarmonicSeries& bob = in.spectra[0].series;
  const HarmonicSeries& sway = in.spectra[1].series;
  std::printf("  com height %.3f m, bob %.2f cm (harmonic %d), sway %.2f cm (harmonic %d)\n",
              bob.mean, 100.0 * bob.strongest(1)[0].amplitude, bob.strongest(1)[0].n,
              100.0 * sway.strongest(1)[0].amplitude, sway.strongest(1)[0].n);
  // Standing hips at 97 cm: the centre of mass a little above them. It bobs twice a stride (each
  // step) and sways once (over each stance foot in turn).
  EXPECT_GT(bob.mean, 0.9);
  EXPECT_LT(bob.mean, 1.05);
  EXPECT_EQ(bob.strongest(1)[0].n, 2);
  EXPECT_EQ(sway.strongest(1)[0].n, 1);
  EXPECT_GT(sway.strongest(1)[0].amplitude, 0.005);
  // Each foot's contact indicator repeats once a stride.
  for (size_t s = 3; s < in.spectra.size(); s += 2) {
    EXPECT_NE(in.spectra[s].name.find("contact"), std::string::npos);
    EXPECT_EQ(in.spectra[s].series.strongest(1)[0].n, 1) << in.spectra[s].name;
  }
}

TEST(IndirectTest, ContactStrideAgreesWithTheAnalysisOnRealWalks) {
  SINEW_REQUIRE_SHARED_DATA();
  for (const char* file :
       {"bandai_dataset-1_walk_normal_001.bvh", "bandai_dataset-1_walk_happy_001.bvh",
        "bandai_dataset-1_walk_tired_001.bvh", "bandai_dataset-1_walk_angry_001.bvh"}) {
    SCOPED_TRACE(file);
    const Loaded l = load(test::sharedData() / "bvh" / file);
    printFigures(file, l);
    const IndirectSignals& in = l.indirect;
    ASSERT_EQ(in.feet.size(), 2u);
    EXPECT_EQ(l.asset.skeleton.names[in.feet[0].joint], "Foot_L");
    EXPECT_EQ(l.asset.skeleton.names[in.feet[1].joint], "Foot_R");
    ASSERT_TRUE(l.spectrum.stride.found);
    EXPECT_GE(in.gait.stride_intervals, 8);
    EXPECT_LT(std::abs(in.gait.period_difference), 0.03);
    // Walking: both feet down part of the time (duty factor over one half), steps of 0.5-0.8 m.
    EXPECT_GT(in.gait.duty_factor, 0.45);
    EXPECT_GT(in.gait.step_length_m, 0.5);
    EXPECT_LT(in.gait.step_length_m, 0.8);
  }
}

TEST(IndirectTest, FeetOfOtherRigs) {
  SINEW_REQUIRE_SHARED_DATA();
  struct Case {
    const char* file;
    size_t feet;
  };
  for (const Case& c :
       {Case{"mann-dog_D1_009_KAN01_001.bvh", 4}, Case{"cmu_131_01.bvh", 2},
        Case{"cmu-iclone_002_03.bvh", 2}, Case{"bandai_dataset-1_run_tired_001.bvh", 2}}) {
    SCOPED_TRACE(c.file);
    const Loaded l = load(test::sharedData() / "bvh" / c.file);
    printFigures(c.file, l);
    const IndirectSignals& in = l.indirect;
    ASSERT_EQ(in.feet.size(), c.feet);
    int left = 0;
    for (const Foot& foot : in.feet) {
      left += foot.side == Side::kLeft;
      EXPECT_GE(foot.pair, 0);
    }
    EXPECT_EQ(left * 2, static_cast<int>(c.feet));
  }
  // The dog's front legs end in "Hand": geometry finds them, and pairs front with front.
  const Loaded dog = load(test::sharedData() / "bvh" / "mann-dog_D1_009_KAN01_001.bvh");
  ASSERT_EQ(dog.indirect.feet.size(), 4u);
  const motion::Skeleton& s = dog.asset.skeleton;
  EXPECT_EQ(s.names[dog.indirect.feet[0].joint], "LeftHand");
  EXPECT_FALSE(dog.indirect.feet[0].by_name);
  EXPECT_EQ(s.names[dog.indirect.feet[dog.indirect.feet[0].pair].joint], "RightHand");
  EXPECT_EQ(s.names[dog.indirect.feet[2].joint], "LeftFoot");
  EXPECT_TRUE(dog.indirect.feet[2].by_name);
  // Its trot: every foot lands about every 0.56 s, as the rotation signals say.
  EXPECT_GE(dog.indirect.gait.stride_intervals, 30);
  EXPECT_LT(std::abs(dog.indirect.gait.period_difference), 0.03);
  // The iClone rig's feet are CC_Base_L_Foot and CC_Base_R_Foot; both land twice in its 1.4 s.
  const Loaded iclone = load(test::sharedData() / "bvh" / "cmu-iclone_002_03.bvh");
  ASSERT_EQ(iclone.indirect.feet.size(), 2u);
  EXPECT_EQ(iclone.asset.skeleton.names[iclone.indirect.feet[0].joint], "CC_Base_L_Foot");
  EXPECT_EQ(iclone.indirect.footfalls.size(), 4u);
  EXPECT_LT(std::abs(iclone.indirect.gait.period_difference), 0.03);
}

}  // namespace
}  // namespace sinew::spectral
