// Hostile and unlucky input to the motion readers and writers (issue 14): text in Latin-1 or with
// a byte-order mark, names with control characters, numbers beyond the documented limits
// (motion/limits.h), and exports that could not be read back as they were meant.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "sinew/motion/bvh.h"
#include "sinew/motion/gltf.h"
#include "sinew/motion/limits.h"
#include "support/test_support.h"

namespace sinew::motion {
namespace {

std::string walkText() {
  return test::readText(test::sourceDir() / "assets" / "biped_walk.bvh");
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The walk with its first frame line's first number replaced by `value`.
std::string withFirstValue(const std::string& value) {
  std::string text = walkText();
  const size_t frame_time = text.find("Frame Time:");
  const size_t line = text.find('\n', frame_time) + 1;
  const size_t end = text.find_first_of(" \t", line);
  return text.replace(line, end - line, value);
}

TEST(BadInput, Latin1JointNamesBecomeUtf8) {
  const std::string text = replaced(walkText(), "JOINT Spine1",
                                    "JOINT H\xFC"
                                    "fte");
  Result<MotionAsset> asset = readBvh(text, "latin1.bvh");
  ASSERT_TRUE(asset.ok()) << asset.message();
  EXPECT_EQ(asset.value().skeleton.names[2],
            "H\xC3\xBC"
            "fte");
  // Written back as UTF-8, read back the same.
  const std::string written =
      writeBvh(asset.value().skeleton, asset.value().clips[0], asset.value().skeleton.source);
  EXPECT_NE(written.find("JOINT H\xC3\xBC"
                         "fte"),
            std::string::npos);
  EXPECT_EQ(readBvh(written, "again.bvh").value().skeleton.names[2],
            "H\xC3\xBC"
            "fte");
}

TEST(BadInput, Utf8NamesAndByteOrderMarkAreAccepted) {
  const std::string utf8 = replaced(walkText(), "JOINT Spine1",
                                    "JOINT H\xC3\xBC"
                                    "fte");
  Result<MotionAsset> asset = readBvh("\xEF\xBB\xBF" + utf8, "bom.bvh");
  ASSERT_TRUE(asset.ok()) << asset.message();
  EXPECT_EQ(asset.value().skeleton.names[2],
            "H\xC3\xBC"
            "fte");  // not read as Latin-1
  EXPECT_EQ(asset.value().clips[0].frame_count, 129);
}

TEST(BadInput, ClipNameFromALatin1PathIsUtf8) {
  Result<MotionAsset> asset = readBvh(walkText(), "/tmp/walk_\xE9.bvh");
  ASSERT_TRUE(asset.ok()) << asset.message();
  EXPECT_EQ(asset.value().clips[0].name, "walk_\xC3\xA9");
}

TEST(BadInput, ControlCharactersInNamesAreRefused) {
  const std::string text = replaced(walkText(), "JOINT Spine1", std::string("JOINT Sp\0ine1", 13));
  Result<MotionAsset> asset = readBvh(text, "nul.bvh");
  ASSERT_FALSE(asset.ok());
  EXPECT_EQ(asset.message(),
            "nul.bvh:10: joint name 'Sp?ine1' holds control character 0; names must be "
            "printable text");
}

TEST(BadInput, FrameTimesOutsideTheLimitsAreRefused) {
  for (const char* bad : {"1e-300", "1e300", "0.00001", "61"}) {
    const std::string text =
        replaced(walkText(), "Frame Time: 0.0333333", std::string("Frame Time: ") + bad);
    Result<MotionAsset> asset = readBvh(text, "t.bvh");
    ASSERT_FALSE(asset.ok()) << bad;
    EXPECT_EQ(asset.message(), "t.bvh:134: frame time must be from 0.0001 to 60 seconds, found '" +
                                   std::string(bad) + "'");
  }
}

TEST(BadInput, OffsetsAndValuesBeyondTheLimitAreRefused) {
  const std::string offset =
      replaced(walkText(), "OFFSET 0.000000 10.000000 0.000000", "OFFSET 0.000000 1e308 0.000000");
  Result<MotionAsset> a = readBvh(offset, "offset.bvh");
  ASSERT_FALSE(a.ok());
  EXPECT_EQ(a.message(),
            "offset.bvh:8: OFFSET of joint 'Spine': '1e308' is beyond the limit of 1e6 (file "
            "units)");
  Result<MotionAsset> v = readBvh(withFirstValue("1e308"), "value.bvh");
  ASSERT_FALSE(v.ok());
  EXPECT_NE(v.message().find("frame 1: '1e308' (value 1) is beyond the limit of 1e6"),
            std::string::npos)
      << v.message();
  EXPECT_TRUE(readBvh(withFirstValue("999999"), "big.bvh").ok());  // within: a legal file
}

// A clip that round-trips through .glb exactly: frames, rate, joints, finite values.
void expectGlbRoundTrip(int frames) {
  test::TempDir dir;
  MotionAsset asset = readBvh(walkText(), "walk.bvh").value();
  const Clip source = asset.clips[0];  // 129 frames, repeated to `frames`
  Clip& clip = asset.clips[0];
  const int joints = clip.joint_count;
  clip.frame_count = frames;
  clip.rotations.resize(static_cast<size_t>(frames) * joints);
  clip.translations.resize(static_cast<size_t>(frames) * joints);
  for (int f = source.frame_count; f < frames; ++f)
    for (int j = 0; j < joints; ++j) {
      const int from = f % (source.frame_count - 1);
      clip.rotations[static_cast<size_t>(f) * joints + j] = source.rotation(from, j);
      clip.translations[static_cast<size_t>(f) * joints + j] = source.translation(from, j);
    }
  clip.frame_time = 1.0 / 30.0;
  const Status saved = exportMotion(dir / "long.glb", asset, clip);
  ASSERT_TRUE(saved.ok()) << saved.message();
  Result<MotionAsset> back = importMotion(dir / "long.glb");
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back.value().clips[0].frame_count, frames);
  EXPECT_DOUBLE_EQ(back.value().clips[0].fps(), 30.0);
  EXPECT_EQ(back.value().skeleton.names, asset.skeleton.names);
}

TEST(BadInput, LongGlbClipsComeBackWithTheirFramesAndRate) {
  expectGlbRoundTrip(10000);
  expectGlbRoundTrip(20000);  // was 20,001 frames at 30.0015 fps: float32 key times late in a clip
}

TEST(BadInput, ExportRefusesFrameTimesOutsideTheLimitsBeforeWriting) {
  test::TempDir dir;
  MotionAsset asset = readBvh(walkText(), "walk.bvh").value();
  Clip clip = asset.clips[0];
  clip.frame_time = kMinFrameTime_s;  // 10 kHz: the fastest rate allowed, exported and read back
  ASSERT_TRUE(exportMotion(dir / "fast.glb", asset, clip).ok());
  EXPECT_EQ(importMotion(dir / "fast.glb").value().clips[0].frame_count, 129);
  clip.frame_time = 1e-300;  // was written, and read back as one frame
  for (const char* name : {"tiny.glb", "tiny.bvh"}) {
    const Status refused = exportMotion(dir / name, asset, clip);
    EXPECT_FALSE(refused.ok());
    EXPECT_NE(refused.message().find("frame time must be from 0.0001 to 60 seconds"),
              std::string::npos)
        << refused.message();
    EXPECT_FALSE(std::filesystem::exists(dir / name));
  }
}

TEST(BadInput, GlbExportRefusesValuesBeyondFloatRange) {
  test::TempDir dir;
  MotionAsset asset = readBvh(walkText(), "walk.bvh").value();
  Clip clip = asset.clips[0];
  clip.translations[5].y = 1e308;
  const Status refused = exportMotion(dir / "inf.glb", asset, clip);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("beyond the limit of 1e6"), std::string::npos)
      << refused.message();
  EXPECT_FALSE(std::filesystem::exists(dir / "inf.glb"));
}

// The walk exported as .gltf (JSON text), with "Spine1" renamed in that text to `name`.
Result<MotionAsset> gltfWithName(const test::TempDir& dir, const std::string& name) {
  MotionAsset asset = readBvh(walkText(), "walk.bvh").value();
  EXPECT_TRUE(exportMotion(dir / "walk.gltf", asset, asset.clips[0]).ok());
  std::string text = test::readText(dir / "walk.gltf");
  const size_t at = text.find("\"Spine1\"");
  EXPECT_NE(at, std::string::npos);
  text.replace(at, 8, "\"" + name + "\"");
  test::writeText(dir / "renamed.gltf", text);
  return importMotion(dir / "renamed.gltf");
}

TEST(BadInput, GltfNamesAreUtf8WithoutControlCharacters) {
  test::TempDir dir;
  Result<MotionAsset> latin1 = gltfWithName(dir,
                                            "H\xFC"
                                            "fte");  // not UTF-8: read as Latin-1
  ASSERT_TRUE(latin1.ok()) << latin1.message();
  EXPECT_EQ(latin1.value().skeleton.names[2],
            "H\xC3\xBC"
            "fte");
  Result<MotionAsset> nul = gltfWithName(dir, "Sp\\u0000ine1");  // a NUL cut the name in .glb
  ASSERT_TRUE(nul.ok()) << nul.message();
  EXPECT_EQ(nul.value().skeleton.names[2], "Sp_ine1");
  ASSERT_TRUE(exportMotion(dir / "back.glb", nul.value(), nul.value().clips[0]).ok());
  EXPECT_EQ(importMotion(dir / "back.glb").value().skeleton.names[2], "Sp_ine1");
}

}  // namespace
}  // namespace sinew::motion
