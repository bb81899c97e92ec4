#include "sinew/motion/anatomy.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "sinew/motion/asset.h"
#include "sinew/motion/bvh.h"
#include "sinew/physics/body_plan.h"
#include "support/test_support.h"

namespace sinew::motion {
namespace {

// A BVH stick figure whose numbers are a human of `height_m` written in `metres_per_unit`, Y-up:
// pelvis, spine and head, two arms hanging, two legs with a foot and a toe each.
std::string humanBvh(double height_m, double metres_per_unit) {
  const double u = height_m / 1.75 / metres_per_unit;  // file units per metre of a 1.75 m human
  std::ostringstream b;
  auto off = [&](double x, double y, double z) {
    return "OFFSET " + std::to_string(x * u) + " " + std::to_string(y * u) + " " +
           std::to_string(z * u) + "\n";
  };
  b << "HIERARCHY\nROOT Hips\n{\n"
    << off(0, 0.95, 0)
    << "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n";
  b << "JOINT Spine\n{\n" << off(0, 0.5, 0) << "CHANNELS 3 Zrotation Xrotation Yrotation\n";
  b << "JOINT Head\n{\n" << off(0, 0.2, 0) << "CHANNELS 3 Zrotation Xrotation Yrotation\n";
  b << "End Site\n{\n" << off(0, 0.1, 0) << "}\n}\n";
  for (int side : {1, -1}) {
    b << "JOINT Arm" << side + 1 << "\n{\n"
      << off(0.2 * side, 0.0, 0) << "CHANNELS 3 Zrotation Xrotation Yrotation\n";
    b << "End Site\n{\n" << off(0, -0.6, 0) << "}\n}\n";
  }
  b << "}\n";
  for (int side : {1, -1}) {
    b << "JOINT Leg" << side + 1 << "\n{\n"
      << off(0.1 * side, 0, 0) << "CHANNELS 3 Zrotation Xrotation Yrotation\n";
    b << "JOINT Knee" << side + 1 << "\n{\n"
      << off(0, -0.45, 0) << "CHANNELS 3 Zrotation Xrotation Yrotation\n";
    b << "JOINT Ankle" << side + 1 << "\n{\n"
      << off(0, -0.42, 0) << "CHANNELS 3 Zrotation Xrotation Yrotation\n";
    b << "JOINT Toe" << side + 1 << "\n{\n"
      << off(0, -0.08, 0.14) << "CHANNELS 3 Zrotation Xrotation Yrotation\n";
    b << "End Site\n{\n" << off(0, 0, 0.05) << "}\n}\n}\n}\n}\n";
  }
  b << "}\nMOTION\nFrames: 2\nFrame Time: 0.0333333\n";
  for (int f = 0; f < 2; ++f) {
    b << "0 " << 0.95 * u << " 0";
    for (int k = 0; k < 3 + 3 + 3 + 3 * 2 + 3 * 4 * 2; ++k)
      b << " 0";  // root, spine, head, arms, legs
    b << "\n";
  }
  return b.str();
}

TEST(AnatomyTest, AHumanIsABipedAndItsUnitIsFoundInEveryCommonUnit) {
  const std::pair<LengthUnit, double> cases[] = {
      {LengthUnit::kMetres, 1.0},        {LengthUnit::kCentimetres, 0.01},
      {LengthUnit::kMillimetres, 0.001}, {LengthUnit::kInches, 0.0254},
      {LengthUnit::kFeet, 0.3048},       {LengthUnit::kCmu, 0.0254 / 0.45}};
  for (const auto& [unit, metres] : cases) {
    for (double height : {1.5, 1.75, 2.0}) {
      SCOPED_TRACE(std::string(unitName(unit)) + " " + std::to_string(height));
      Result<MotionAsset> asset = readBvh(humanBvh(height, metres), "human.bvh");
      ASSERT_TRUE(asset.ok()) << asset.message();
      const FrameDetection& d = asset.value().detection;
      EXPECT_EQ(d.frame.unit, unit) << d.reason;
      EXPECT_EQ(d.frame.up, UpAxis::kY) << d.reason;
      // The joints' extent: the toes' End Sites to the head's.
      EXPECT_NEAR(d.height_m, height, 0.01) << d.reason;
      EXPECT_NE(d.reason.find("human (2 legs"), std::string::npos) << d.reason;
    }
  }
}

TEST(AnatomyTest, UserUnitOverridesDetectionAndScalesTheHeight) {
  ImportOptions options;
  options.unit = LengthUnit::kMillimetres;
  Result<MotionAsset> asset = readBvh(humanBvh(1.75, 0.01), "human.bvh", options);
  ASSERT_TRUE(asset.ok()) << asset.message();
  EXPECT_EQ(asset.value().detection.frame.unit, LengthUnit::kMillimetres);
  EXPECT_NEAR(asset.value().detection.height_m, 0.175, 0.001);
}

// Every real file: the family, the unit and a plausible size, named per file. Heights are the
// joints' extent in the first frame (the head top is rarely a joint; Bandai's head End Site has
// no length) and the runs lean forward, so Bandai's actors read 1.2-1.4 m.
TEST(AnatomyTest, EveryRealBvhFileGetsItsFamilyUnitAndAPlausibleSize) {
  SINEW_REQUIRE_SHARED_DATA();
  struct Expect {
    BodyFamily family;
    LengthUnit unit;
    double lo_m, hi_m;
  };
  const std::map<std::string, Expect> expected = {
      {"bandai_dataset-1_run_normal_001.bvh",
       {BodyFamily::kBiped, LengthUnit::kCentimetres, 1.1, 1.9}},
      {"bandai_dataset-1_run_tired_001.bvh",
       {BodyFamily::kBiped, LengthUnit::kCentimetres, 1.1, 1.9}},
      {"bandai_dataset-1_walk_angry_001.bvh",
       {BodyFamily::kBiped, LengthUnit::kCentimetres, 1.25, 1.9}},
      {"bandai_dataset-1_walk_happy_001.bvh",
       {BodyFamily::kBiped, LengthUnit::kCentimetres, 1.25, 1.9}},
      {"bandai_dataset-1_walk_normal_001.bvh",
       {BodyFamily::kBiped, LengthUnit::kCentimetres, 1.25, 1.9}},
      {"bandai_dataset-1_walk_tired_001.bvh",
       {BodyFamily::kBiped, LengthUnit::kCentimetres, 1.25, 1.9}},
      {"cmu_131_01.bvh", {BodyFamily::kBiped, LengthUnit::kCmu, 1.3, 1.9}},
      {"cmu-iclone_002_03.bvh", {BodyFamily::kBiped, LengthUnit::kCentimetres, 1.4, 2.0}},
      {"mann-dog_D1_009_KAN01_001.bvh",
       {BodyFamily::kQuadruped, LengthUnit::kCentimetres, 0.4, 1.2}},
  };
  const auto files = test::sharedFiles("bvh", ".bvh");
  ASSERT_FALSE(files.empty()) << "no BVH files in " << test::sharedData();
  for (const auto& path : files) {
    const std::string name = path.filename().string();
    SCOPED_TRACE(name);
    Result<MotionAsset> asset = importMotion(path);
    ASSERT_TRUE(asset.ok()) << asset.message();
    const FrameDetection& d = asset.value().detection;
    std::cout << "  " << name << ": " << unitName(d.frame.unit) << ", " << d.height_m << " m ("
              << d.reason << ")\n";
    const auto it = expected.find(name);
    if (it == expected.end()) {  // a file added later: at least a plausible creature
      EXPECT_GT(d.height_m, 0.1) << d.reason;
      EXPECT_LT(d.height_m, 10.0) << d.reason;
      continue;
    }
    const FigureMeasure figure = measureFigure(asset.value().skeleton, asset.value().clips[0], 1);
    EXPECT_EQ(figure.family, it->second.family) << d.reason;
    EXPECT_EQ(figure.human, it->second.family == BodyFamily::kBiped) << d.reason;
    EXPECT_EQ(d.frame.unit, it->second.unit) << d.reason;
    EXPECT_GE(d.height_m, it->second.lo_m) << d.reason;
    EXPECT_LE(d.height_m, it->second.hi_m) << d.reason;
  }
}

// Every clip of every real file: the family, the size a person means (a human's stature to the
// head top, a quadruped's height at the hips) and the mass, printed and checked against the
// family's plausible range; the body plan weighs the figure as the estimate says (the Fox was
// a 70 kg human once: its front legs are named UpperArm).
TEST(AnatomyTest, EveryRealFileGetsItsFamilysSizeAndMass) {
  SINEW_REQUIRE_SHARED_DATA();
  struct Expect {
    const char* family;
    double size_lo_m, size_hi_m;  // human: stature; quadruped: at the hips
    double mass_lo_kg, mass_hi_kg;
  };
  const Expect bandai{"human", 1.5, 1.8, 45.0, 80.0};
  const std::map<std::string, Expect> expected = {
      {"bandai_dataset-1_run_normal_001.bvh", bandai},
      {"bandai_dataset-1_run_tired_001.bvh", bandai},
      {"bandai_dataset-1_walk_angry_001.bvh", bandai},
      {"bandai_dataset-1_walk_happy_001.bvh", bandai},
      {"bandai_dataset-1_walk_normal_001.bvh", bandai},
      {"bandai_dataset-1_walk_tired_001.bvh", bandai},
      {"cmu_131_01.bvh", {"human", 1.5, 1.8, 45.0, 80.0}},
      {"cmu-iclone_002_03.bvh", {"human", 1.7, 2.1, 60.0, 110.0}},
      // A slight stylised figure (its mesh is 1.45 m): short legs, no head joint.
      {"RiggedFigure.glb", {"human", 1.2, 1.6, 30.0, 70.0}},
      // A large dog; a red fox weighs 4-8 kg.
      {"mann-dog_D1_009_KAN01_001.bvh", {"quadruped", 0.3, 0.7, 20.0, 40.0}},
      {"Fox.glb", {"quadruped", 0.25, 0.5, 4.0, 8.0}},
  };
  std::vector<std::filesystem::path> paths = test::sharedFiles("bvh", ".bvh");
  for (const auto& p : test::sharedFiles("gltf", ".glb")) paths.push_back(p);
  ASSERT_GE(paths.size(), expected.size()) << "files missing in " << test::sharedData();
  for (const auto& path : paths) {
    const std::string name = path.filename().string();
    Result<MotionAsset> imported = importMotion(path);
    ASSERT_TRUE(imported.ok()) << imported.message();
    const MotionAsset& asset = imported.value();
    for (const Clip& clip : asset.clips) {
      SCOPED_TRACE(name + " '" + clip.name + "'");
      std::vector<Foot> feet;
      if (auto found = findFeet(asset.skeleton, clip); found.ok()) feet = found.value();
      const BodyEstimate body = estimateBody(asset.skeleton, clip, feet);
      Result<physics::BodyPlan> plan = physics::buildBodyPlan(asset.skeleton, &clip);
      ASSERT_TRUE(plan.ok()) << plan.message();
      const std::string family = body.figure.human ? "human" : familyName(body.figure.family);
      const double size = body.figure.human ? body.stature_m : body.figure.hip_height;
      std::printf("  %-38s %-12s %-9s %s %.2f m, %.1f kg (plan %.1f kg): %s\n", name.c_str(),
                  clip.name.substr(0, 12).c_str(), family.c_str(),
                  body.figure.human ? "stature" : "at hips", size, body.mass_kg,
                  plan.value().total_mass_kg, body.basis.c_str());
      EXPECT_EQ(plan.value().human, body.figure.human);
      EXPECT_NEAR(plan.value().total_mass_kg, body.mass_kg, 1e-9 * body.mass_kg);
      const auto it = expected.find(name);
      if (it == expected.end()) {  // a file added later: a creature of some size
        EXPECT_GT(plan.value().total_mass_kg, 0.01);
        continue;
      }
      const Expect& e = it->second;
      EXPECT_EQ(family, e.family) << body.basis;
      EXPECT_GE(size, e.size_lo_m) << body.basis;
      EXPECT_LE(size, e.size_hi_m) << body.basis;
      EXPECT_GE(body.mass_kg, e.mass_lo_kg) << body.basis;
      EXPECT_LE(body.mass_kg, e.mass_hi_kg) << body.basis;
    }
  }
}

// A human's mass follows its stature at one body-mass index, and the stature its legs: the same
// stick figure at 1.5 and 2.0 m weighs 70 (H / 1.75)^2 kg.
TEST(AnatomyTest, AHumansMassFollowsItsStature) {
  for (double height : {1.5, 2.0}) {
    Result<MotionAsset> asset = readBvh(humanBvh(height, 0.01), "human.bvh");
    ASSERT_TRUE(asset.ok()) << asset.message();
    const Skeleton& skeleton = asset.value().skeleton;
    const Clip& clip = asset.value().clips[0];
    const BodyEstimate body = estimateBody(skeleton, clip, findFeet(skeleton, clip).value());
    EXPECT_TRUE(body.figure.human);
    // Thigh and shank 0.87 of 1.75 m: Winter's 0.491 of the stature.
    const double legs = 0.87 * height / 1.75;
    EXPECT_NEAR(body.leg_length_m, legs, 1e-6);
    EXPECT_NEAR(body.stature_m, std::max(legs / 0.491, height), 1e-6) << body.basis;
    EXPECT_NEAR(body.mass_kg, 70.0 * std::pow(body.stature_m / 1.75, 2.0), 1e-9);
  }
}

}  // namespace
}  // namespace sinew::motion
