// BVH -> engine pose -> BVH: every channel of every real file comes back within 1e-4 (file
// units, degrees), each joint keeping its channel order. The exported text is compared number by
// number with the original text, so the check does not trust our own reader twice.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "sinew/motion/bvh.h"
#include "support/test_support.h"

namespace sinew::motion {
namespace {

// The numbers after "Frame Time:" (the channel values), read independently of the importer.
std::vector<double> motionValues(const std::string& text) {
  const size_t frame_time = text.find("Frame Time:");
  std::vector<double> values;
  if (frame_time == std::string::npos) return values;
  size_t n = text.find_first_of("\r\n", frame_time);
  while (n < text.size()) {
    while (n < text.size() && std::isspace(static_cast<unsigned char>(text[n]))) ++n;
    const size_t start = n;
    while (n < text.size() && !std::isspace(static_cast<unsigned char>(text[n]))) ++n;
    if (start == n) break;
    double value = 0.0;
    std::from_chars(text.data() + start, text.data() + n, value);
    values.push_back(value);
  }
  return values;
}

// "CHANNELS ..." lines of a hierarchy, whitespace-normalised.
std::vector<std::string> channelLines(const std::string& text) {
  std::vector<std::string> lines;
  size_t at = 0;
  while ((at = text.find("CHANNELS", at)) != std::string::npos) {
    const size_t end = text.find_first_of("\r\n", at);
    std::string line;
    bool space = false;
    for (size_t n = at; n < end; ++n) {
      const bool is_space = std::isspace(static_cast<unsigned char>(text[n]));
      if (is_space) {
        space = true;
        continue;
      }
      if (space && !line.empty()) line += ' ';
      space = false;
      line += text[n];
    }
    lines.push_back(line);
    at = end;
  }
  return lines;
}

TEST(BvhRoundTripTest, EveryRealFileComesBackWithinATenThousandth) {
  SINEW_REQUIRE_SHARED_DATA();
  const auto files = test::sharedFiles("bvh", ".bvh");
  ASSERT_GE(files.size(), 9u);
  for (const auto& path : files) {
    SCOPED_TRACE(path.filename().string());
    const std::string original = test::readText(path);
    Result<MotionAsset> asset = readBvh(original, path.string());
    ASSERT_TRUE(asset.ok()) << asset.message();
    const std::string written =
        writeBvh(asset.value().skeleton, asset.value().clips[0], asset.value().skeleton.source);
    EXPECT_EQ(channelLines(written), channelLines(original));
    const std::vector<double> before = motionValues(original);
    const std::vector<double> after = motionValues(written);
    ASSERT_EQ(before.size(), after.size());
    double worst = 0.0;
    size_t worst_at = 0;
    for (size_t n = 0; n < before.size(); ++n) {
      const double error = std::abs(before[n] - after[n]);
      if (error > worst) {
        worst = error;
        worst_at = n;
      }
    }
    EXPECT_LT(worst, 1e-4) << "value " << worst_at << ": " << before[worst_at] << " became "
                           << after[worst_at];
    // And the re-read file has the same skeleton.
    Result<MotionAsset> again = readBvh(written, "written.bvh");
    ASSERT_TRUE(again.ok()) << again.message();
    EXPECT_EQ(again.value().skeleton.names, asset.value().skeleton.names);
    EXPECT_EQ(again.value().skeleton.parents, asset.value().skeleton.parents);
    std::printf("  round trip %-40s %7zu values, worst error %.2e\n",
                path.filename().string().c_str(), before.size(), worst);
  }
}

TEST(BvhRoundTripTest, ZUpFilesGoBackToZUp) {
  const std::string text =
      "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition "
      "Zrotation Yrotation Xrotation\n JOINT LeftLeg\n {\n  OFFSET 10 0 -45\n  CHANNELS 3 "
      "Zrotation Yrotation Xrotation\n  End Site\n  {\n   OFFSET 0 0 -45\n  }\n }\n JOINT "
      "RightLeg\n {\n  OFFSET -10 0 -45\n  CHANNELS 3 Zrotation Yrotation Xrotation\n  End Site\n "
      " {\n   OFFSET 0 0 -45\n  }\n }\n JOINT Head\n {\n  OFFSET 0 0 70\n  CHANNELS 3 Zrotation "
      "Yrotation Xrotation\n  End Site\n  {\n   OFFSET 0 0 10\n  }\n }\n}\nMOTION\nFrames: 2\n"
      "Frame Time: 0.04\n1 2 95 170 -30 12 5 6 7 -8 9 -10 0 0 200\n"
      "1.5 2.5 96 -175 -35 14 5 6 7 -8 9 -10 0 0 -160\n";
  Result<MotionAsset> asset = readBvh(text, "zup.bvh");
  ASSERT_TRUE(asset.ok()) << asset.message();
  EXPECT_EQ(asset.value().skeleton.source.up, UpAxis::kZ);
  EXPECT_EQ(asset.value().skeleton.source.unit, LengthUnit::kCentimetres);
  // In the engine the head is above the hips (Y-up, metres).
  const std::vector<glm::dvec3> pose = worldPositions(asset.value().skeleton,
                                                      asset.value().clips[0], 0);
  EXPECT_GT(pose[0].y, 0.9);
  const std::string written =
      writeBvh(asset.value().skeleton, asset.value().clips[0], asset.value().skeleton.source);
  const std::vector<double> before = motionValues(text);
  const std::vector<double> after = motionValues(written);
  ASSERT_EQ(before.size(), after.size());
  // 170 -> -175 stays continuous: written as 185, the same rotation as -175.
  for (size_t n = 0; n < before.size(); ++n) {
    const double d = std::remainder(before[n] - after[n], 360.0);
    EXPECT_NEAR(d, 0.0, 1e-4) << "value " << n;
  }
  EXPECT_NEAR(after[0 + 3], 170.0, 1e-4);
  EXPECT_NEAR(after[15 + 3], 185.0, 1e-4);
}

TEST(BvhRoundTripTest, ResamplingKeepsDurationAndEndPoses) {
  SINEW_REQUIRE_SHARED_DATA();
  Result<MotionAsset> asset =
      importMotion(test::sharedData() / "bvh" / "bandai_dataset-1_run_normal_001.bvh");
  ASSERT_TRUE(asset.ok()) << asset.message();
  const Clip& clip = asset.value().clips[0];
  const Clip fast = resampleClip(clip, clip.frame_time / 4.0);
  EXPECT_EQ(fast.frame_count, (clip.frame_count - 1) * 4 + 1);
  EXPECT_NEAR(fast.duration(), clip.duration(), 1e-9);
  for (int j = 0; j < clip.joint_count; ++j) {
    EXPECT_NEAR(std::abs(glm::dot(fast.rotation(8, j), clip.rotation(2, j))), 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace sinew::motion
