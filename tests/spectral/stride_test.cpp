// The stride on the worst cases: a slow walk whose every large channel moves twice a stride, a
// long 120 fps walk whose tempo drifts; and on every real walk and run, against the stride the
// foot contacts give (the table in docs/spectral.md is printed here).
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "sinew/spectral/analysis.h"
#include "sinew/spectral/indirect.h"
#include "support/test_support.h"

namespace sinew::spectral {
namespace {

constexpr double kPi = std::numbers::pi;

struct Gait {
  double fps = 30.0;
  double seconds = 10.0;
  std::function<double(double)> cycles;  // strides completed by time t (the stride phase / 2 pi)
  double hip1 = 0.45;                    // thigh swing, first harmonic, radians
  double hip2 = 0.08;                    // thigh, second harmonic
  double trunk2 = 0.05;    // trunk, neck and arms, twice a stride (once a step), radians
  double knee = 0.9;       // knee flexion in swing, radians
  double variation = 0.0;  // stride-to-stride change of every amplitude (slow, fraction)
  double noise = 0.0;      // white noise on every angle, radians
};

struct Walker {
  motion::Skeleton skeleton;
  motion::Clip clip;
};

// A biped: hips travelling along +Z with a bob; thighs in antiphase; knees flexing in swing (the
// foot lifts once a stride); spine, chest, neck and both arms moving once a step.
Walker makeWalker(const Gait& g) {
  Walker w;
  motion::Skeleton& s = w.skeleton;
  const int hips = s.addJoint("Hips", motion::kNoParent, {0, 0.92, 0});
  const int spine = s.addJoint("Spine", hips, {0, 0.1, 0});
  const int chest = s.addJoint("Chest", spine, {0, 0.2, 0});
  const int neck = s.addJoint("Neck", chest, {0, 0.2, 0});
  s.end_sites[neck] = glm::dvec3(0, 0.2, 0);
  const int larm = s.addJoint("LeftArm", chest, {0.18, 0.15, 0});
  s.end_sites[larm] = glm::dvec3(0, -0.55, 0);
  const int rarm = s.addJoint("RightArm", chest, {-0.18, 0.15, 0});
  s.end_sites[rarm] = glm::dvec3(0, -0.55, 0);
  int leg[2][3];
  for (int side = 0; side < 2; ++side) {
    const double x = side == 0 ? 0.1 : -0.1;
    const std::string name = side == 0 ? "Left" : "Right";
    leg[side][0] = s.addJoint(name + "UpLeg", hips, {x, -0.05, 0});
    leg[side][1] = s.addJoint(name + "Leg", leg[side][0], {0, -0.42, 0});
    leg[side][2] = s.addJoint(name + "Foot", leg[side][1], {0, -0.42, 0});
    s.end_sites[leg[side][2]] = glm::dvec3(0, -0.03, 0.14);
  }
  motion::Clip& c = w.clip;
  c.frame_time = 1.0 / g.fps;
  c.frame_count = static_cast<int>(g.seconds * g.fps) + 1;
  c.joint_count = s.jointCount();
  c.rotations.assign(static_cast<size_t>(c.frame_count) * c.joint_count, glm::dquat(1, 0, 0, 0));
  c.translations.resize(c.rotations.size());
  std::mt19937_64 random(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  const glm::dvec3 x(1, 0, 0), z(0, 0, 1);
  for (int f = 0; f < c.frame_count; ++f) {
    const double t = f / g.fps;
    const double p = 2 * kPi * g.cycles(t);
    const double m = 1.0 + g.variation * std::sin(2 * kPi * g.cycles(t) / 2.7);
    const auto n = [&]() { return g.noise * noise(random); };
    const auto set = [&](int j, const glm::dquat& q) {
      c.rotations[static_cast<size_t>(f) * c.joint_count + j] = q;
    };
    for (int j = 0; j < c.joint_count; ++j) {
      c.translations[static_cast<size_t>(f) * c.joint_count + j] = s.offsets[j];
    }
    c.translations[static_cast<size_t>(f) * c.joint_count + hips] = {
        0.0, 0.92 + 0.02 * std::sin(2 * p), 1.2 * t};
    set(spine, glm::angleAxis(m * g.trunk2 * std::sin(2 * p) + n(), x));
    set(chest, glm::angleAxis(m * g.trunk2 * std::sin(2 * p + 0.7) + n(), z));
    set(neck, glm::angleAxis(-m * g.trunk2 * std::sin(2 * p + 0.3) + n(), x));
    set(larm, glm::angleAxis(m * 1.5 * g.trunk2 * std::sin(2 * p + 1.0) + n(), x));
    set(rarm, glm::angleAxis(m * 1.5 * g.trunk2 * std::sin(2 * p + 1.0) + n(), x));
    for (int side = 0; side < 2; ++side) {
      const double q = p + side * kPi;
      set(leg[side][0],
          glm::angleAxis(m * (g.hip1 * std::sin(q) + g.hip2 * std::sin(2 * q + 1.0)) + n(), x));
      const double swing = std::max(0.0, std::sin(q - 0.6));  // the knee bends in swing only
      set(leg[side][1], glm::angleAxis(-0.1 - m * g.knee * swing * swing + n(), x));
      set(leg[side][2], glm::angleAxis(0.2 * std::sin(q + 2.0) + n(), x));
    }
  }
  return w;
}

// The slow walk of the issue: a 1.6 s stride whose trunk, arms and knees carry most of the
// variance at twice the stride frequency, changing from stride to stride. The pose half a stride
// later is nearly as similar as a stride later; the feet decide.
TEST(StrideTest, SlowWalkWithAStrongSecondHarmonicReadsTheFullStride) {
  Gait g;
  g.seconds = 14.0;
  g.cycles = [](double t) { return t / 1.6; };
  g.hip1 = 0.12;
  g.hip2 = 0.1;
  g.trunk2 = 0.9;
  g.knee = 0.35;
  g.variation = 0.3;
  g.noise = 0.02;
  const Walker w = makeWalker(g);
  Result<MotionSpectrum> result = analyze(w.skeleton, w.clip);
  ASSERT_TRUE(result.ok()) << result.message();
  const StrideEstimate& stride = result.value().stride;
  std::printf(
      "  slow walk: stride %.4f s (similarity %.3f, feet %.3f), window %.4f s; true 1.6 s\n",
      stride.period_s, stride.similarity, stride.foot_similarity, result.value().period_s);
  ASSERT_TRUE(stride.found) << stride.message;
  EXPECT_TRUE(stride.feet_checked);
  EXPECT_NEAR(stride.period_s, 1.6, 0.03 * 1.6);
  EXPECT_NEAR(result.value().period_s, 1.6, 0.03 * 1.6);
  // Without the feet (signals alone) the step wins: the case the cross-check is for.
  const StrideEstimate blind = estimateStride(result.value().signals);
  std::printf("  slow walk without the feet: %.4f s\n", blind.period_s);
  EXPECT_LT(blind.period_s, 0.6 * 1.6);
}

// A long 120 fps walk slowing down: the stride grows from 1.0 to 1.2 s over a minute.
TEST(StrideTest, LongWalkWhoseTempoDriftsReadsItsMeanStride) {
  constexpr double kFirst = 1.0, kLast = 1.2, kSeconds = 60.0;
  const auto period = [&](double t) { return kFirst + (kLast - kFirst) * t / kSeconds; };
  Gait g;
  g.fps = 120.0;
  g.seconds = kSeconds;
  g.cycles = [&](double t) { return kSeconds / (kLast - kFirst) * std::log(period(t) / kFirst); };
  g.noise = 0.005;
  const Walker w = makeWalker(g);
  Result<MotionSpectrum> result = analyze(w.skeleton, w.clip);
  ASSERT_TRUE(result.ok()) << result.message();
  const MotionSpectrum& s = result.value();
  ASSERT_TRUE(s.stride.found) << s.stride.message;
  const double mean = kSeconds / g.cycles(kSeconds);  // what the footfalls average to
  const double local = period(s.window.start_s + 0.5 * s.window.strides * s.period_s);
  std::printf(
      "  drifting walk: stride %.4f s (mean of the clip %.4f s), window at %.1f s: %.4f s "
      "(there %.4f s)\n",
      s.stride.period_s, mean, s.window.start_s, s.period_s, local);
  EXPECT_NEAR(s.stride.period_s, mean, 0.03 * mean);
  EXPECT_NEAR(s.period_s, local, 0.03 * local);
}

// Every real walk and run: analyze()'s stride against the foot contacts' (and the table for
// docs/spectral.md: K = 5 error and the glitches import found).
TEST(StrideTest, RealWalksAndRunsMatchTheirFootContacts) {
  SINEW_REQUIRE_SHARED_DATA();
  std::vector<std::filesystem::path> files = test::sharedFiles("bvh", ".bvh");
  for (const auto& p : test::sharedFiles("gltf", ".glb")) files.push_back(p);
  std::printf(
      "| clip | stride (analysis) | foot contacts | difference | K = 5 deg RMS | glitches |\n");
  std::printf("| --- | --- | --- | --- | --- | --- |\n");
  for (const auto& path : files) {
    Result<motion::MotionAsset> asset = motion::importMotion(path);
    ASSERT_TRUE(asset.ok()) << asset.message();
    for (size_t c = 0; c < asset.value().clips.size(); ++c) {
      const motion::Clip& clip = asset.value().clips[c];
      const std::string name =
          path.stem().string() + (asset.value().clips.size() > 1 ? " " + clip.name : "");
      if (clip.frame_count < 12) {
        std::printf("| %s | (%d frames: nothing to analyse) | | | | |\n", name.c_str(),
                    clip.frame_count);
        continue;
      }
      Result<MotionSpectrum> spectrum = analyze(asset.value().skeleton, clip);
      ASSERT_TRUE(spectrum.ok()) << spectrum.message();
      Result<IndirectSignals> indirect =
          analyzeIndirect(asset.value().skeleton, clip, spectrum.value());
      const GaitFigures gait = indirect.ok() ? indirect.value().gait : GaitFigures{};
      const double stride = spectrum.value().period_s;
      const bool contacts = gait.stride_intervals >= 1 && gait.stride_period_s > 0.0;
      const double difference = contacts ? stride / gait.stride_period_s - 1.0 : 0.0;
      char contact_text[64] = "no foot lands twice";
      if (contacts) {
        std::snprintf(contact_text, sizeof contact_text, "%.4f s (%d intervals)",
                      gait.stride_period_s, gait.stride_intervals);
      }
      char difference_text[32] = "";
      if (contacts)
        std::snprintf(difference_text, sizeof difference_text, "%+.2f%%", 100.0 * difference);
      std::printf("| %s | %.4f s | %s | %s | %.2f | %zu |\n", name.c_str(), stride, contact_text,
                  difference_text, spectrum.value().total.rot_err_deg_rms,
                  asset.value().glitches[c].size());
      const std::string stem = path.stem().string();
      const bool gait_clip = stem.find("walk") != std::string::npos ||
                             stem.find("run") != std::string::npos ||
                             stem.find("iclone") != std::string::npos;
      if (gait_clip && contacts) {
        EXPECT_LT(std::abs(difference), 0.03) << name;
      }
    }
  }
}

}  // namespace
}  // namespace sinew::spectral
