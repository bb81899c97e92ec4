// Glitch repair: a joint that flips away for a few frames is found and put back by slerp; real
// motion (a run's ankle, the dog's tail, the iClone fingers) is never called a glitch.
#include "sinew/motion/glitch.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "sinew/spectral/analysis.h"
#include "support/test_support.h"

namespace sinew::motion {
namespace {

double angleDeg(const glm::dquat& a, const glm::dquat& b) {
  return glm::degrees(2.0 * std::acos(std::min(1.0, std::abs(glm::dot(a, b)))));
}

// A joint swinging +-40 degrees about X at 1 Hz, 30 fps, on a one-joint skeleton.
struct Swing {
  Skeleton skeleton;
  Clip clip;
};
Swing swing(int frames = 90, double fps = 30.0) {
  Swing s;
  s.skeleton.addJoint("Foot", kNoParent, glm::dvec3(0.0));
  s.skeleton.channels[0].types = {ChannelType::kZrotation, ChannelType::kXrotation,
                                  ChannelType::kYrotation};
  s.clip = restClip(s.skeleton, frames, 1.0 / fps);
  for (int f = 0; f < frames; ++f) {
    const double angle = glm::radians(40.0) * std::sin(2.0 * std::numbers::pi * f / fps);
    s.clip.rotations[f] = glm::angleAxis(angle, glm::dvec3(1.0, 0.0, 0.0));
  }
  return s;
}

// Turns frames first..first+count-1 of `joint` by 180 degrees about its local `axis`.
void flip(Clip& clip, int joint, int first, int count, const glm::dvec3& axis) {
  const glm::dquat half_turn = glm::angleAxis(std::numbers::pi, axis);
  for (int f = first; f < first + count; ++f) {
    glm::dquat& q = clip.rotations[static_cast<size_t>(f) * clip.joint_count + joint];
    q = glm::normalize(q * half_turn);
  }
}

TEST(Glitch, RefusesInvalidSettings) {
  EXPECT_TRUE(GlitchSettings{}.validate().ok());
  const auto refused = [](GlitchSettings s, const char* field) {
    const Status status = s.validate();
    EXPECT_FALSE(status.ok()) << field;
    EXPECT_NE(status.message().find(field), std::string::npos) << status.message();
  };
  GlitchSettings s;
  s.relative_size = 0.0;
  refused(s, "relative_size");
  s = {};
  s.step_quantile = 1.5;
  refused(s, "step_quantile");
  s = {};
  s.min_size_deg = NAN;
  refused(s, "min_size_deg");
  s = {};
  s.max_duration_s = -1.0;
  refused(s, "max_duration_s");
  s = {};
  s.max_across_ratio = INFINITY;
  refused(s, "max_across_ratio");
}

TEST(Glitch, FindsAndRepairsFlipsOfOneToThreeFrames) {
  for (int count = 1; count <= 3; ++count) {
    Swing s = swing();
    const Clip clean = s.clip;
    flip(s.clip, 0, 40, count, glm::dvec3(0.0, 1.0, 0.0));
    const std::vector<Glitch> found = findGlitches(s.clip);
    ASSERT_EQ(found.size(), 1u) << count << " frames";
    EXPECT_EQ(found[0].joint, 0);
    EXPECT_EQ(found[0].first_frame, 40);
    EXPECT_EQ(found[0].frame_count, count);
    EXPECT_GT(found[0].size_deg, 150.0);
    EXPECT_EQ(describeGlitch(s.skeleton, found[0]).rfind("Foot frame", 0), 0u);
    repairGlitches(s.clip, found);
    for (int f = 0; f < clean.frame_count; ++f) {
      if (f < 40 || f >= 40 + count) {  // only the bad frames change
        EXPECT_EQ(s.clip.rotations[f], clean.rotations[f]) << "frame " << f;
      } else {  // a chord of the swing's curve: 40 deg at 1 Hz misses it by 3 deg over 4 frames
        EXPECT_LT(angleDeg(s.clip.rotations[f], clean.rotations[f]), 3.0) << "frame " << f;
      }
    }
    EXPECT_TRUE(findGlitches(s.clip).empty());
  }
}

TEST(Glitch, SmoothFastMotionAndEndsAreNotGlitches) {
  // A 4 Hz, +-80 degree swing at 30 fps: 67 degrees a frame at its fastest, and reversing.
  Swing s = swing(90, 30.0);
  for (int f = 0; f < 90; ++f) {
    const double angle = glm::radians(80.0) * std::sin(2.0 * std::numbers::pi * 4.0 * f / 30.0);
    s.clip.rotations[f] = glm::angleAxis(angle, glm::dvec3(1.0, 0.0, 0.0));
  }
  EXPECT_TRUE(findGlitches(s.clip).empty());
  // A flip of the first or last frame has one neighbour: left alone.
  Swing ends = swing();
  flip(ends.clip, 0, 0, 1, glm::dvec3(1.0, 0.0, 0.0));
  flip(ends.clip, 0, 89, 1, glm::dvec3(1.0, 0.0, 0.0));
  EXPECT_TRUE(findGlitches(ends.clip).empty());
  // Longer than max_duration_s (0.125 s = 3 frames at 30 fps): a pose held, not a glitch.
  Swing held = swing();
  flip(held.clip, 0, 40, 4, glm::dvec3(0.0, 1.0, 0.0));
  EXPECT_TRUE(findGlitches(held.clip).empty());
  // The same 4 frames at 120 fps last 1/30 s: a glitch.
  Swing fast = swing(360, 120.0);
  flip(fast.clip, 0, 160, 4, glm::dvec3(0.0, 1.0, 0.0));
  EXPECT_EQ(findGlitches(fast.clip).size(), 1u);
}

// Every motion file in ../shared/data and assets/, every clip.
struct NamedAsset {
  std::string name;
  MotionAsset asset;
};
std::vector<NamedAsset> realAssets(bool repair) {
  std::vector<std::filesystem::path> paths = test::sharedFiles("bvh", ".bvh");
  for (const auto& p : test::sharedFiles("gltf", ".glb")) paths.push_back(p);
  ImportOptions options;
  options.repair_glitches = repair;
  std::vector<NamedAsset> out;
  for (const auto& path : paths) {
    Result<MotionAsset> asset = importMotion(path, options);
    EXPECT_TRUE(asset.ok()) << asset.message();
    if (asset.ok()) out.push_back({path.filename().string(), std::move(asset).value()});
  }
  return out;
}

TEST(Glitch, CleanRealClipsReportNoneAndComeOutBitUnchanged) {
  SINEW_REQUIRE_SHARED_DATA();
  const std::vector<NamedAsset> kept = realAssets(false);
  const std::vector<NamedAsset> repaired = realAssets(true);
  ASSERT_EQ(kept.size(), repaired.size());
  ASSERT_GE(kept.size(), 11u);
  for (size_t a = 0; a < kept.size(); ++a) {
    const MotionAsset& raw = kept[a].asset;
    ASSERT_EQ(raw.glitches.size(), raw.clips.size());
    for (size_t c = 0; c < raw.clips.size(); ++c) {
      // Real glitches: CMU 131_01's right thumb turns 180 degrees for 6 to 14 frames (0.05 to
      // 0.12 s) four times, each as its X angle passes 90 degrees (the conversion's Euler angles
      // take the other branch: at frame 809 X goes +78 -> -88 ... -78 -> +78, Z and Y jumping by
      // about 110 and 180 degrees).
      const bool thumb = kept[a].name == "cmu_131_01.bvh";
      for (const Glitch& g : raw.glitches[c]) {
        if (thumb && raw.skeleton.names[g.joint] == "RThumb" && g.size_deg > 170.0) {
          std::printf("  %s: %s (a real glitch)\n", kept[a].name.c_str(),
                      describeGlitch(raw.skeleton, g).c_str());
          continue;
        }
        ADD_FAILURE() << kept[a].name << " '" << raw.clips[c].name
                      << "': " << describeGlitch(raw.skeleton, g);
      }
      if (thumb) {
        EXPECT_EQ(raw.glitches[c].size(), 4u);
      }
      const Clip& x = raw.clips[c];
      const Clip& y = repaired[a].asset.clips[c];
      ASSERT_EQ(x.rotations.size(), y.rotations.size());
      if (raw.glitches[c].empty()) {
        EXPECT_EQ(std::memcmp(x.rotations.data(), y.rotations.data(),
                              x.rotations.size() * sizeof(glm::dquat)),
                  0)
            << kept[a].name;
      }
    }
  }
}

TEST(Glitch, BundledClipsReportNone) {
  for (const char* name :
       {"biped_walk.bvh", "hopper_hop.bvh", "quadruped_trot.bvh", "stepper_step.bvh"}) {
    Result<MotionAsset> asset = importMotion(test::sourceDir() / "assets" / name);
    ASSERT_TRUE(asset.ok()) << asset.message();
    ASSERT_EQ(asset.value().glitches.size(), 1u);
    EXPECT_TRUE(asset.value().glitches[0].empty()) << name;
  }
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// A toe joint (or failing that a foot, ankle, paw) that rotates in the clip.
int toeOrFoot(const Skeleton& skeleton, const Clip& clip) {
  for (const char* word : {"toe", "foot", "ankle", "paw"}) {
    for (int j = 0; j < skeleton.jointCount(); ++j) {
      if (lower(skeleton.names[j]).find(word) == std::string::npos) continue;
      double moved = 0.0;
      for (int f = 1; f < clip.frame_count; ++f) {
        moved = std::max(moved, angleDeg(clip.rotation(0, j), clip.rotation(f, j)));
      }
      if (moved > 1.0) return j;
    }
  }
  return -1;
}

// The case on every real clip: a toe or foot turned 180 degrees for 1, 2 or 3 frames in
// the middle of the analysed window is found (joint and frames exact) and repaired: the joint's
// K = 5 error falls from tens of degrees (the issue: 46.8 against 0.7) to a third or less, the
// clip's error comes back within 0.2 degrees, and the repaired clip's model is within 2 degrees
// RMS of the clean clip's at that joint (measured: within 0.5 in 23 of 36 cases, at most 1.61).
// The misses are the repairs of 2-3 frames of a toe-off at 24-30 fps: the repaired frames are
// 2.3-7.3 degrees from the true ones, and the model moves by about a fifth of that. The Fox's
// Walk and Run are single cycles (no stride to copy from), so only the cubic is there to fill
// a snap it did not see. The clean clips are as imported (CMU 131_01's thumb repaired).
TEST(Glitch, InjectedFlipsInRealClipsAreFoundAndRepaired) {
  SINEW_REQUIRE_SHARED_DATA();
  int checked = 0;
  int within = 0;
  for (const NamedAsset& named : realAssets(true)) {
    const MotionAsset& asset = named.asset;
    for (const Clip& clean : asset.clips) {
      if (clean.frame_count < 12) continue;  // RiggedFigure: two keys, nothing to analyse
      const int joint = toeOrFoot(asset.skeleton, clean);
      ASSERT_GE(joint, 0) << named.name << ": no moving toe or foot";
      Result<spectral::MotionSpectrum> model = spectral::analyze(asset.skeleton, clean);
      ASSERT_TRUE(model.ok()) << model.message();
      const spectral::MotionSpectrum& s = model.value();
      const int window_start = static_cast<int>(std::lround(s.window.start_s / clean.frame_time));
      const int window_frames = static_cast<int>(s.window.strides * s.period_s / clean.frame_time);
      for (int count = 1; count <= 3; ++count) {
        Clip glitched = clean;
        const int first =
            std::clamp(window_start + window_frames / 2, 1, clean.frame_count - 1 - count);
        flip(glitched, joint, first, count, glm::dvec3(1.0, 0.0, 0.0));
        const std::vector<Glitch> found = findGlitches(glitched);
        ASSERT_EQ(found.size(), 1u) << named.name << " '" << clean.name << "' " << count;
        EXPECT_EQ(found[0].joint, joint);
        EXPECT_EQ(found[0].first_frame, first);
        EXPECT_EQ(found[0].frame_count, count);
        Result<spectral::MotionSpectrum> kept = spectral::analyze(asset.skeleton, glitched);
        repairGlitches(glitched, found);
        Result<spectral::MotionSpectrum> again = spectral::analyze(asset.skeleton, glitched);
        ASSERT_TRUE(again.ok() && kept.ok()) << again.message() << kept.message();
        double worst_frame = 0.0;
        for (int k = 0; k < count; ++k) {
          worst_frame = std::max(worst_frame, angleDeg(glitched.rotation(first + k, joint),
                                                       clean.rotation(first + k, joint)));
        }
        // The joint's and the clip's K = 5 error (the figures), and how far the repaired
        // clip's model is from the clean clip's at that joint (RMS over the window, when the same
        // window wins).
        const double joint_clean = s.joint_errors[joint].rot_err_deg_rms;
        const double joint_repaired = again.value().joint_errors[joint].rot_err_deg_rms;
        const double joint_kept = kept.value().joint_errors[joint].rot_err_deg_rms;
        const Clip a = spectral::reconstruct(asset.skeleton, s);
        const Clip b = spectral::reconstruct(asset.skeleton, again.value());
        double apart = -1.0;
        if (a.frame_count == b.frame_count &&
            std::abs(s.window.start_s - again.value().window.start_s) < 1e-9) {
          apart = 0.0;
          for (int f = 0; f < a.frame_count; ++f) {
            const double d = angleDeg(a.rotation(f, joint), b.rotation(f, joint));
            apart += d * d;
          }
          apart = std::sqrt(apart / a.frame_count);
        }
        std::printf(
            "  %-36s %-8s %-16s %d frame(s) at %3d: %5.1f deg; K=5 error %.2f clean, %.2f "
            "repaired (%.2f kept), clip %.2f / %.2f; repair %.2f deg from the clean "
            "frames, models %.2f deg apart\n",
            named.name.c_str(), clean.name.c_str(), asset.skeleton.names[joint].c_str(), count,
            first, found[0].size_deg, joint_clean, joint_repaired, joint_kept,
            s.total.rot_err_deg_rms, again.value().total.rot_err_deg_rms, worst_frame, apart);
        // (Unless analysis of the glitched clip chose a window without it: the dog's.)
        if (joint_kept > 5.0) {
          EXPECT_GT(joint_kept, 3.0 * joint_repaired) << named.name << " " << count;
        }
        EXPECT_LT(std::abs(again.value().total.rot_err_deg_rms - s.total.rot_err_deg_rms), 0.2)
            << named.name << " " << count;
        EXPECT_LT(apart, 2.0) << named.name << " " << count;
        within += apart >= 0.0 && apart < 0.5 ? 1 : 0;
        ++checked;
      }
    }
  }
  std::printf("  repaired models within 0.5 deg of the clean clip's: %d of %d\n", within, checked);
  EXPECT_GE(checked, 3 * 11);
}

}  // namespace
}  // namespace sinew::motion
