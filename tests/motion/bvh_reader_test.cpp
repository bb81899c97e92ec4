#include <cmath>

#include <gtest/gtest.h>

#include "sinew/motion/bvh.h"
#include "support/test_support.h"

namespace sinew::motion {
namespace {

constexpr const char* kTiny =
    "HIERARCHY\n"
    "ROOT mixamorig:Hips\n"
    "{\n"
    "  OFFSET 0 0 0\n"
    "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    "  JOINT mixamorig:LeftUpLeg\n"
    "  {\n"
    "    OFFSET 10 -5 0\n"
    "    CHANNELS 3 Xrotation Zrotation Yrotation\n"
    "    End Site\n"
    "    {\n"
    "      OFFSET 0 -85 0\n"
    "    }\n"
    "  }\n"
    "  JOINT Head {\n"
    "    OFFSET 0 80 0\n"
    "    CHANNELS 3 Yrotation Xrotation Zrotation\n"
    "    End Site { OFFSET 0 10 0 }\n"
    "  }\n"
    "}\n"
    "MOTION\n"
    "Frames:\t2\n"
    "Frame Time: .0083333\n"
    "0 90 0 0 0 0 +1.5e1 0 0 0 0 0 \n"
    "1.0 90 2.5 10 -20 30 0 0 45 -90 0 0\n";

TEST(BvhReaderTest, ReadsTheSyntaxRealFilesUse) {
  Result<MotionAsset> result = readBvh(kTiny, "tiny.bvh");
  ASSERT_TRUE(result.ok()) << result.message();
  const MotionAsset& asset = result.value();
  const Skeleton& skeleton = asset.skeleton;
  ASSERT_EQ(skeleton.jointCount(), 3);
  EXPECT_EQ(skeleton.names[0], "mixamorig:Hips");
  EXPECT_EQ(skeleton.parents[1], 0);
  EXPECT_EQ(skeleton.parents[2], 0);
  EXPECT_EQ(std::string(skeleton.channels[1].eulerOrder().name().data()), "XZY");
  EXPECT_EQ(std::string(skeleton.channels[2].eulerOrder().name().data()), "YXZ");
  ASSERT_TRUE(skeleton.end_sites[1]);
  // Centimetres, Y-up: the end site 85 cm below becomes 0.85 m.
  EXPECT_EQ(asset.detection.frame.unit, LengthUnit::kCentimetres);
  EXPECT_EQ(asset.detection.frame.up, UpAxis::kY);
  EXPECT_NEAR(skeleton.end_sites[1]->y, -0.85, 1e-12);
  const Clip& clip = asset.clips[0];
  EXPECT_EQ(clip.frame_count, 2);
  EXPECT_NEAR(clip.frame_time, 0.0083333, 1e-12);
  EXPECT_EQ(clip.name, "tiny");
  // Frame 0: the leg's X rotation of +15 degrees swings its end site forward (+Z).
  const std::vector<glm::dvec3> pose0 = worldPositions(skeleton, clip, 0);
  EXPECT_NEAR(pose0[0].y, 0.90, 1e-12);
  // Frame 1: root translated 2.5 cm; the leg turned 45 degrees about Y, the head 90 about Y.
  EXPECT_NEAR(clip.translation(1, 0).z, 0.025, 1e-12);
  EXPECT_NEAR(glm::degrees(glm::angle(clip.rotation(1, 1))), 45.0, 1e-9);
  EXPECT_NEAR(glm::axis(clip.rotation(1, 1)).y, 1.0, 1e-12);
  EXPECT_NEAR(glm::degrees(glm::angle(clip.rotation(1, 2))), 90.0, 1e-9);
}

TEST(BvhReaderTest, ReadsEveryRealFile) {
  SINEW_REQUIRE_SHARED_DATA();
  struct Expected {
    const char* file;
    int joints;
    int channels;
    int frames;
    double frame_time;
    UpAxis up;
  };
  const Expected expected[] = {
      {"bandai_dataset-1_walk_normal_001.bvh", 22, 132, 195, 0.0333333, UpAxis::kY},
      {"bandai_dataset-1_run_normal_001.bvh", 22, 132, 24, 0.0333333, UpAxis::kY},
      {"cmu_131_01.bvh", 31, 96, 994, 0.0083333, UpAxis::kY},
      {"cmu-iclone_002_03.bvh", 101, 306, 86, 0.016667, UpAxis::kZ},
      {"mann-dog_D1_009_KAN01_001.bvh", 21, 66, 548, 0.0166667, UpAxis::kY},
  };
  for (const Expected& e : expected) {
    SCOPED_TRACE(e.file);
    Result<MotionAsset> result = importMotion(test::sharedData() / "bvh" / e.file);
    ASSERT_TRUE(result.ok()) << result.message();
    const MotionAsset& asset = result.value();
    EXPECT_EQ(asset.skeleton.jointCount(), e.joints);
    EXPECT_EQ(asset.skeleton.channelCount(), e.channels);
    EXPECT_EQ(asset.clips[0].frame_count, e.frames);
    EXPECT_DOUBLE_EQ(asset.clips[0].frame_time, e.frame_time);
    EXPECT_TRUE(asset.skeleton.validate().ok());
    EXPECT_TRUE(asset.clips[0].validate(asset.skeleton).ok());
  }
}

TEST(BvhReaderTest, CmuKeepsItsMixedRotationOrders) {
  SINEW_REQUIRE_SHARED_DATA();
  Result<MotionAsset> result = importMotion(test::sharedData() / "bvh" / "cmu_131_01.bvh");
  ASSERT_TRUE(result.ok()) << result.message();
  const Skeleton& skeleton = result.value().skeleton;
  int zyx = 0;
  int zxy = 0;
  for (const ChannelLayout& layout : skeleton.channels) {
    const std::string order = layout.eulerOrder().name().data();
    zyx += order == "ZYX";
    zxy += order == "ZXY";
  }
  EXPECT_EQ(zyx, 19);  // root and 18 joints
  EXPECT_EQ(zxy, 12);  // shoulders, arms, hands
}

// Every real character stands on its feet once imported: the head above the hips, the lowest
// point near the ground plane of the first frame, and a plausible size in metres.
TEST(BvhReaderTest, RealCharactersComeOutUprightInMetres) {
  SINEW_REQUIRE_SHARED_DATA();
  const std::vector<std::filesystem::path> files = test::sharedFiles("bvh", ".bvh");
  // An empty (or unreadable) folder checks nothing: that is a failure, not a pass.
  ASSERT_FALSE(files.empty()) << "no .bvh files in " << (test::sharedData() / "bvh");
  for (const auto& path : files) {
    SCOPED_TRACE(path.filename().string());
    Result<MotionAsset> result = importMotion(path);
    ASSERT_TRUE(result.ok()) << result.message();
    const MotionAsset& asset = result.value();
    const std::vector<glm::dvec3> pose = worldPositions(asset.skeleton, asset.clips[0], 0);
    glm::dvec3 lo(1e9);
    glm::dvec3 hi(-1e9);
    for (const glm::dvec3& p : pose) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    const double height = hi.y - lo.y;
    EXPECT_GT(height, 0.2) << asset.detection.reason;
    EXPECT_LT(height, 2.5) << asset.detection.reason;
    // Upright: the vertical extent is at least that of the figure's thinnest horizontal axis.
    EXPECT_GT(height, std::min(hi.x - lo.x, hi.z - lo.z)) << asset.detection.reason;
  }
}

TEST(BvhReaderTest, UserOverridesWinOverDetection) {
  ImportOptions options;
  options.unit = LengthUnit::kMetres;
  options.up = UpAxis::kZ;
  Result<MotionAsset> result = readBvh(kTiny, "tiny.bvh", options);
  ASSERT_TRUE(result.ok()) << result.message();
  EXPECT_EQ(result.value().skeleton.source.unit, LengthUnit::kMetres);
  EXPECT_EQ(result.value().skeleton.source.up, UpAxis::kZ);
  // Z-up: the file's -85 along Y becomes +85 along engine Z.
  EXPECT_NEAR(result.value().skeleton.end_sites[1]->z, 85.0, 1e-12);
  EXPECT_NE(result.value().detection.reason.find("set by the user"), std::string::npos);
}

// Synthetic large file: 120 joints x 10,000 frames parses (and in linear time).
TEST(BvhReaderTest, ReadsHundredsOfJointsAndTenThousandFrames) {
  std::string text =
      "HIERARCHY\nROOT j0\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition "
      "Zposition Zrotation Yrotation Xrotation\n";
  constexpr int kJoints = 120;
  constexpr int kFrames = 10000;
  for (int j = 1; j < kJoints; ++j) {
    text += "JOINT j" + std::to_string(j) +
            "\n{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n";
  }
  text += "End Site\n{\nOFFSET 0 1 0\n}\n";
  for (int j = 0; j < kJoints; ++j) text += "}\n";
  text += "MOTION\nFrames: " + std::to_string(kFrames) + "\nFrame Time: 0.01\n";
  std::string line;
  for (int c = 0; c < 3 + 3 * kJoints; ++c) line += (c % 7 == 0 ? "1.25 " : "0 ");
  line += "\r\n";
  for (int f = 0; f < kFrames; ++f) text += line;
  Result<MotionAsset> result = readBvh(text, "big.bvh");
  ASSERT_TRUE(result.ok()) << result.message();
  EXPECT_EQ(result.value().skeleton.jointCount(), kJoints);
  EXPECT_EQ(result.value().clips[0].frame_count, kFrames);
}

}  // namespace
}  // namespace sinew::motion
