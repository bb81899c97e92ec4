// The sinew command line, run as a user runs it: exit codes, one-line errors, JSON that parses.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "support/test_support.h"

namespace sinew {
namespace {

std::string walk() { return test::quote(test::sourceDir() / "assets" / "biped_walk.bvh"); }

TEST(CliTest, InfoDescribesTheBundledWalk) {
  const test::CommandResult result = test::runSinew("info " + walk());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("22 (+5 end sites), 69 channels"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("129 frames at 30 fps"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("units      cm, up Y"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("LeftUpLeg  [Zrotation Xrotation Yrotation]"), std::string::npos);
}

TEST(CliTest, InfoJsonCarriesTheFacts) {
  const test::CommandResult result = test::runSinew("info --json " + walk());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json info = nlohmann::json::parse(result.out);
  EXPECT_EQ(info["joint_count"], 22);
  EXPECT_EQ(info["channel_count"], 69);
  EXPECT_EQ(info["frames"], 129);
  EXPECT_NEAR(info["fps"].get<double>(), 30.0, 1e-3);
  EXPECT_EQ(info["units"], "cm");
  EXPECT_EQ(info["up_axis"], "Y");
  EXPECT_EQ(info["joints"][0]["name"], "Hips");
  EXPECT_EQ(info["joints"][0]["rotation_order"], "ZXY");
  EXPECT_EQ(info["joints"][1]["parent"], 0);
}

TEST(CliTest, FailuresExitNonZeroWithOneLineNamingTheFile) {
  test::TempDir dir;
  test::writeText(dir / "bad.bvh", "HIERARCHY\nROOT a\n{\n OFFSET 0 0 0\n CHANNELS 3 Xrotation\n");
  const test::CommandResult bad = test::runSinew("info " + test::quote(dir / "bad.bvh"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_EQ(bad.err, "sinew: " + (dir / "bad.bvh").string() +
                         ":5: CHANNELS count 3 does not match the 1 channel names that follow, "
                         "in joint 'a'\n");
  const test::CommandResult missing = test::runSinew("info " + test::quote(dir / "none.bvh"));
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("none.bvh: no such file"), std::string::npos);
  const test::CommandResult animation = test::runSinew("info " + walk() + " --animation Run");
  EXPECT_NE(animation.exit_code, 0);
  EXPECT_NE(animation.err.find("no animation named 'Run'; the file has: biped_walk"),
            std::string::npos)
      << animation.err;
  const test::CommandResult usage = test::runSinew("info");
  EXPECT_NE(usage.exit_code, 0);
}

TEST(CliTest, ConvertBvhToBvhKeepsChannelsAndCanResample) {
  test::TempDir dir;
  const test::CommandResult same = test::runSinew("convert " + walk() + " " +
                                                  test::quote(dir / "copy.bvh"));
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_NE(same.out.find("wrote"), std::string::npos);
  const test::CommandResult info = test::runSinew("info --json " + test::quote(dir / "copy.bvh"));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_EQ(nlohmann::json::parse(info.out)["channel_count"], 69);

  const test::CommandResult fast = test::runSinew("convert " + walk() + " " +
                                                  test::quote(dir / "fast.bvh") + " --fps 60");
  ASSERT_EQ(fast.exit_code, 0) << fast.err;
  const nlohmann::json resampled =
      nlohmann::json::parse(test::runSinew("info --json " + test::quote(dir / "fast.bvh")).out);
  EXPECT_EQ(resampled["frames"], 257);  // 128 intervals at 30 fps -> 256 at 60 fps
  EXPECT_NEAR(resampled["fps"].get<double>(), 60.0, 1e-6);
}

TEST(CliTest, ConvertRefusesUnknownFormatsAndKeepsTheOldFile) {
  test::TempDir dir;
  const auto target = dir / "keep.bvh";
  test::writeText(target, "precious");
  // A failed import must not touch the target.
  test::writeText(dir / "bad.bvh", "not a bvh");
  const test::CommandResult result =
      test::runSinew("convert " + test::quote(dir / "bad.bvh") + " " + test::quote(target));
  EXPECT_NE(result.exit_code, 0);
  EXPECT_EQ(test::readText(target), "precious");
  const test::CommandResult fbx = test::runSinew("convert " + walk() + " " +
                                                 test::quote(dir / "out.fbx"));
  EXPECT_NE(fbx.exit_code, 0);
  EXPECT_NE(fbx.err.find("unknown file type '.fbx'"), std::string::npos) << fbx.err;
}

TEST(CliTest, AnalyzeReportsStrideErrorsAndJson) {
  test::TempDir dir;
  const auto json_path = dir / "walk.json";
  const test::CommandResult result =
      test::runSinew("analyze " + walk() + " --json " + test::quote(json_path));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("stride     1.06"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("LeftUpLeg"), std::string::npos);
  const nlohmann::json json = nlohmann::json::parse(test::readText(json_path));
  // The bundled walk is authored at exactly 32 frames per 30 fps stride.
  EXPECT_NEAR(json["period_s"].get<double>(), 32.0 / 30.0, 0.01);
  EXPECT_TRUE(json["stride_found"].get<bool>());
  EXPECT_GE(json["strides"].get<int>(), 1);
  EXPECT_NEAR(json["travel_velocity_m_s"][2].get<double>(), 1.30, 0.01);
  for (const char* key : {"rot_err_deg_rms", "rot_err_deg_max", "pos_err_cm_mean", "pos_err_cm_max"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  bool found = false;
  for (const auto& joint : json["joints"]) {
    for (const char* key : {"name", "k", "rot_err_deg_rms", "rot_err_deg_max", "pos_err_cm_mean",
                            "pos_err_cm_max"}) {
      EXPECT_TRUE(joint.contains(key)) << key;
    }
    if (joint["name"] == "LeftUpLeg") {
      found = true;
      EXPECT_EQ(joint["k"], 5);
      ASSERT_EQ(joint["channels"].size(), 3u);
      EXPECT_EQ(joint["channels"][0]["harmonics"].size(), 5u);
    }
  }
  EXPECT_TRUE(found);
  const test::CommandResult bad = test::runSinew("analyze " + walk() + " --harmonics lots");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("--harmonics: expected a whole number or 'auto'"), std::string::npos)
      << bad.err;
}

TEST(CliTest, StyleTransfersAndMeasures) {
  SINEW_REQUIRE_SHARED_DATA();
  test::TempDir dir;
  const auto bandai = [](const std::string& what) {
    return test::quote(test::sharedData() / "bvh" / ("bandai_dataset-1_" + what + "_001.bvh"));
  };
  const test::CommandResult transfer = test::runSinew(
      "style --neutral " + bandai("walk_normal") + " --styled " + bandai("walk_tired") +
      " --label tired --strides 2 -o " + test::quote(dir / "tired.bvh"));
  ASSERT_EQ(transfer.exit_code, 0) << transfer.err;
  EXPECT_NE(transfer.out.find("style 'tired' (weight 1.00)"), std::string::npos) << transfer.out;
  const nlohmann::json info =
      nlohmann::json::parse(test::runSinew("info --json " + test::quote(dir / "tired.bvh")).out);
  EXPECT_NEAR(info["fps"].get<double>(), 30.0, 1e-3);
  EXPECT_EQ(info["joint_count"], 22);
  // Two tired strides of about 1.22 s, at 30 fps, closing the loop.
  EXPECT_NEAR(info["frames"].get<int>(), 2 * 1.219 * 30 + 1, 2);

  const test::CommandResult measure = test::runSinew(
      "style --measure " + bandai("run_tired") + " --library normal=" + bandai("walk_normal") +
      " tired=" + bandai("walk_tired") + " --json " + test::quote(dir / "scores.json"));
  ASSERT_EQ(measure.exit_code, 0) << measure.err;
  const nlohmann::json scores = nlohmann::json::parse(test::readText(dir / "scores.json"));
  EXPECT_EQ(scores["closest"], "tired");
  EXPECT_GT(scores["scores"]["tired"].get<double>(), scores["scores"]["normal"].get<double>());

  const test::CommandResult bad = test::runSinew("style --neutral " + bandai("walk_normal") +
                                                 " --styled " + bandai("walk_tired") +
                                                 " --weight 3 -o x.bvh");
  EXPECT_NE(bad.exit_code, 0);
}

// Styles are matched by joint names and hierarchy, not joint count: the Bandai rig and the bundled
// biped both have 22 joints. Relative measurement takes pairs; a repeated label is several
// examples of one label.
TEST(CliTest, StylePairsAreMatchedByJointNamesAndMeasuredAgainstANeutral) {
  SINEW_REQUIRE_SHARED_DATA();
  test::TempDir dir;
  const auto bandai = [](const std::string& what) {
    return test::quote(test::sharedData() / "bvh" / ("bandai_dataset-1_" + what + "_001.bvh"));
  };
  const std::string bandai_path =
      (test::sharedData() / "bvh" / "bandai_dataset-1_walk_tired_001.bvh").string();
  const test::CommandResult foreign = test::runSinew("style --neutral " + walk() + " --styled " +
                                                     bandai("walk_tired") + " -o " +
                                                     test::quote(dir / "x.bvh"));
  EXPECT_EQ(foreign.exit_code, 1);
  EXPECT_EQ(foreign.err.rfind("sinew: " + bandai_path + ": not the skeleton of ", 0), 0u) << foreign.err;
  EXPECT_NE(foreign.err.find("joint 0 is 'joint_Root'"), std::string::npos) << foreign.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.bvh"));
  const test::CommandResult apply = test::runSinew("style --neutral " + bandai("walk_normal") +
                                                   " --styled " + bandai("walk_tired") +
                                                   " --apply-to " + walk() + " -o " +
                                                   test::quote(dir / "x.bvh"));
  EXPECT_EQ(apply.exit_code, 1);
  EXPECT_NE(apply.err.find("biped_walk.bvh: not the skeleton of"), std::string::npos) << apply.err;

  const test::CommandResult measure = test::runSinew(
      "style --measure " + bandai("walk_angry") + " --neutral " + bandai("walk_normal") +
      " --library normal=" + bandai("walk_normal") + "," + bandai("walk_normal") +
      " tired=" + bandai("walk_normal") + "," + bandai("walk_tired") + " angry=" +
      bandai("walk_normal") + "," + bandai("walk_angry") + " tired=" + bandai("walk_normal") +
      "," + bandai("run_tired") + " --json " + test::quote(dir / "scores.json"));
  ASSERT_EQ(measure.exit_code, 0) << measure.err;
  EXPECT_NE(measure.out.find("2 examples"), std::string::npos) << measure.out;
  const nlohmann::json scores = nlohmann::json::parse(test::readText(dir / "scores.json"));
  EXPECT_EQ(scores["closest"], "angry");
  EXPECT_EQ(scores["relative"], true);
  ASSERT_EQ(scores["labels"].size(), 3u);
  double total = 0.0;
  for (const auto& label : scores["labels"]) total += label["score"].get<double>();
  EXPECT_NEAR(total, 1.0, 1e-9);
  const test::CommandResult unpaired = test::runSinew(
      "style --measure " + bandai("walk_angry") + " --neutral " + bandai("walk_normal") +
      " --library tired=" + bandai("walk_tired"));
  EXPECT_EQ(unpaired.exit_code, 1);
  EXPECT_NE(unpaired.err.find("has no neutral"), std::string::npos) << unpaired.err;
}

// A toe flipped 180 degrees for two frames: info and analyze name it and repair it;
// --keep-glitches keeps it and still reports it.
TEST(CliTest, GlitchesAreReportedAndRepairedUnlessKept) {
  SINEW_REQUIRE_SHARED_DATA();
  test::TempDir dir;
  const std::filesystem::path source = test::sharedData() / "bvh" / "bandai_dataset-1_walk_normal_001.bvh";
  std::string text = test::readText(source);
  // Frame 100's and 101's Toes_L rotation: the joint's 6 channels are position then Z X Y.
  const test::CommandResult info = test::runSinew("info --json " + test::quote(source));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const nlohmann::json clean = nlohmann::json::parse(info.out);
  EXPECT_TRUE(clean["glitches"].empty());
  int toe = -1, channel = 0;
  for (size_t j = 0; j < clean["joints"].size(); ++j) {
    if (clean["joints"][j]["name"] == "Toes_L") toe = static_cast<int>(j);
    if (toe < 0) channel += static_cast<int>(clean["joints"][j]["channels"].size());
  }
  ASSERT_GE(toe, 0);
  const size_t motion = text.find("Frame Time:");
  size_t line = text.find('\n', motion) + 1;
  std::string out = text.substr(0, line);
  for (int frame = 0; line < text.size(); ++frame) {
    const size_t end = text.find('\n', line);
    std::string row = text.substr(line, end == std::string::npos ? std::string::npos : end - line + 1);
    if (frame == 100 || frame == 101) {
      std::istringstream in(row);
      std::vector<std::string> values;
      for (std::string v; in >> v;) values.push_back(v);
      values[static_cast<size_t>(channel + 4)] = std::to_string(std::stod(values[static_cast<size_t>(channel + 4)]) + 180.0);
      row.clear();
      for (const std::string& v : values) row += v + " ";
      row += "\n";
    }
    out += row;
    if (end == std::string::npos) break;
    line = end + 1;
  }
  test::writeText(dir / "glitch.bvh", out);
  const test::CommandResult found = test::runSinew("info --json " + test::quote(dir / "glitch.bvh"));
  ASSERT_EQ(found.exit_code, 0) << found.err;
  const nlohmann::json glitches = nlohmann::json::parse(found.out)["glitches"];
  ASSERT_EQ(glitches.size(), 1u) << found.out;
  EXPECT_EQ(glitches[0]["joint"], "Toes_L");
  EXPECT_EQ(glitches[0]["first_frame"], 100);
  EXPECT_EQ(glitches[0]["frames"], 2);
  EXPECT_GT(glitches[0]["size_deg"].get<double>(), 150.0);
  EXPECT_EQ(glitches[0]["repaired"], true);
  const test::CommandResult analyzed = test::runSinew("analyze " + test::quote(dir / "glitch.bvh"));
  ASSERT_EQ(analyzed.exit_code, 0) << analyzed.err;
  EXPECT_NE(analyzed.out.find("glitches   1 in Toes_L, repaired"), std::string::npos) << analyzed.out;
  EXPECT_NE(analyzed.out.find("glitch   Toes_L frames 100-101 (2)"), std::string::npos) << analyzed.out;
  const test::CommandResult kept = test::runSinew("info --keep-glitches " + test::quote(dir / "glitch.bvh"));
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  EXPECT_NE(kept.out.find("glitches   1 in Toes_L, kept"), std::string::npos) << kept.out;
}

TEST(CliTest, CreatureWritesTheSameFileForTheSameSeed) {
  test::TempDir dir;
  const test::CommandResult made =
      test::runSinew("creature --random --seed 7 -o " + test::quote(dir / "a.bvh"));
  ASSERT_EQ(made.exit_code, 0) << made.err;
  EXPECT_NE(made.out.find("wrote " + (dir / "a.bvh").string() + ": creature seed 7: "),
            std::string::npos)
      << made.out;
  EXPECT_NE(made.out.find("DOF"), std::string::npos) << made.out;
  ASSERT_EQ(test::runSinew("creature --random --seed 7 -o " + test::quote(dir / "b.bvh")).exit_code,
            0);
  ASSERT_EQ(test::runSinew("creature --random --seed 8 -o " + test::quote(dir / "c.bvh")).exit_code,
            0);
  EXPECT_EQ(test::readText(dir / "a.bvh"), test::readText(dir / "b.bvh"));
  EXPECT_NE(test::readText(dir / "a.bvh"), test::readText(dir / "c.bvh"));

  // The file reads back as a centimetre, Y-up rig whose clip has a stride.
  const test::CommandResult info = test::runSinew("info --json " + test::quote(dir / "a.bvh"));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const nlohmann::json parsed = nlohmann::json::parse(info.out);
  EXPECT_EQ(parsed["units"], "cm");
  EXPECT_EQ(parsed["up_axis"], "Y");
  EXPECT_EQ(parsed["joints"][0]["name"], "Torso");
  const test::CommandResult analyzed = test::runSinew("analyze " + test::quote(dir / "a.bvh") +
                                                      " --json " + test::quote(dir / "a.json"));
  ASSERT_EQ(analyzed.exit_code, 0) << analyzed.err;
  EXPECT_TRUE(nlohmann::json::parse(test::readText(dir / "a.json"))["stride_found"].get<bool>());

  // glTF too, with the leg count asked for.
  const test::CommandResult glb =
      test::runSinew("creature --random --seed 7 --limbs 4 -o " + test::quote(dir / "four.glb"));
  ASSERT_EQ(glb.exit_code, 0) << glb.err;
  EXPECT_NE(glb.out.find(": 4 legs"), std::string::npos) << glb.out;
  const test::CommandResult glb_info =
      test::runSinew("info --json " + test::quote(dir / "four.glb"));
  ASSERT_EQ(glb_info.exit_code, 0) << glb_info.err;
  EXPECT_EQ(nlohmann::json::parse(glb_info.out)["format"], "gltf");
}

TEST(CliTest, CreatureRefusesBadArgumentsInOneLineAndKeepsTheOldFile) {
  test::TempDir dir;
  const auto keep = dir / "keep.bvh";
  test::writeText(keep, "precious");
  const auto refused = [](const std::string& arguments, const std::string& message) {
    const test::CommandResult r = test::runSinew("creature " + arguments);
    EXPECT_NE(r.exit_code, 0) << arguments;
    EXPECT_EQ(r.err, "sinew: " + message + "\n") << arguments;
  };
  refused("--random --seed 1", "creature: -o FILE is required (.bvh, .glb or .gltf)");
  refused("--seed 1 -o " + test::quote(keep),
          "creature: --random is required (random creatures are the only kind so far)");
  refused("--random -o " + test::quote(keep),
          "creature: --seed N is required (a whole number >= 0)");
  refused("--random --seed one -o " + test::quote(keep),
          "--seed: expected a whole number >= 0, got 'one'");
  refused("--random --seed 1 --limbs 0..3 -o " + test::quote(keep),
          "--limbs: expected N or MIN..MAX with 1 <= MIN <= MAX <= 8, got '0..3'");
  refused("--random --seed 1 --limbs 5..2 -o " + test::quote(keep),
          "--limbs: expected N or MIN..MAX with 1 <= MIN <= MAX <= 8, got '5..2'");
  refused("--random --seed 1 -o " + test::quote(dir / "x.fbx"),
          (dir / "x.fbx").string() + ": unknown file type '.fbx', expected .bvh, .glb or .gltf");
  refused("--random --seed 1 -o " + test::quote(dir / "missing" / "x.bvh"),
          (dir / "missing" / "x.bvh").string() + ": cannot write: No such file or directory");
  EXPECT_EQ(test::readText(keep), "precious");
  EXPECT_FALSE(std::filesystem::exists(dir / "x.fbx"));
  // A write that fails at the rename (the target is a folder) leaves the folder and no temporary.
  std::filesystem::create_directories(dir / "taken.bvh" / "inside");
  const test::CommandResult taken =
      test::runSinew("creature --random --seed 1 -o " + test::quote(dir / "taken.bvh"));
  EXPECT_NE(taken.exit_code, 0);
  EXPECT_NE(taken.err.find((dir / "taken.bvh").string()), std::string::npos) << taken.err;
  EXPECT_EQ(std::count(taken.err.begin(), taken.err.end(), '\n'), 1) << taken.err;
  EXPECT_TRUE(std::filesystem::is_directory(dir / "taken.bvh" / "inside"));
  size_t entries = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path()))
    ++entries;
  EXPECT_EQ(entries, 2u);  // keep.bvh and taken.bvh, nothing left over
}

TEST(CliTest, InfoAndConvertWorkOnEveryRealFile) {
  SINEW_REQUIRE_SHARED_DATA();
  test::TempDir dir;
  std::vector<std::filesystem::path> files = test::sharedFiles("bvh", ".bvh");
  for (const auto& glb : test::sharedFiles("gltf", ".glb")) files.push_back(glb);
  ASSERT_GE(files.size(), 11u);
  for (const auto& path : files) {
    SCOPED_TRACE(path.filename().string());
    const test::CommandResult info = test::runSinew("info --json " + test::quote(path));
    ASSERT_EQ(info.exit_code, 0) << info.err;
    const nlohmann::json parsed = nlohmann::json::parse(info.out);
    EXPECT_GT(parsed["joint_count"].get<int>(), 0);
    for (const char* extension : {".bvh", ".glb", ".gltf"}) {
      const auto out = dir / (path.stem().string() + extension);
      const test::CommandResult convert =
          test::runSinew("convert " + test::quote(path) + " " + test::quote(out));
      ASSERT_EQ(convert.exit_code, 0) << convert.err;
      const test::CommandResult back = test::runSinew("info --json " + test::quote(out));
      ASSERT_EQ(back.exit_code, 0) << back.err;
      EXPECT_EQ(nlohmann::json::parse(back.out)["joint_count"], parsed["joint_count"]) << extension;
    }
  }
}

// sinew simulate: the figures pipelines read, what the character did as a BVH that reads back,
// pushes on named bodies, and one-line refusals of bad terrain and pushes.
TEST(CliTest, SimulateReportsJsonAndWritesWhatTheCharacterDid) {
  test::TempDir dir;
  const auto json_path = dir / "run.json";
  const auto bvh_path = dir / "run.bvh";
  const test::CommandResult result =
      test::runSinew("simulate --rig " + walk() + " --seconds 2 --push 1,0,0,-20,Chest -o " +
                     test::quote(bvh_path) + " --json " + test::quote(json_path));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("28 degrees of freedom"), std::string::npos) << result.out;
  const nlohmann::json json = nlohmann::json::parse(test::readText(json_path));
  for (const char* key : {"fell", "fall_time_s", "distance_m", "track_err_rad_rms", "energy_j"})
    EXPECT_TRUE(json.contains(key)) << key;
  EXPECT_GT(json["distance_m"].get<double>(), 0.5);  // it starts walking at 1.3 m/s
  EXPECT_GT(json["energy_j"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(json["pushed_impulse_ns"][2].get<double>(), -20.0);
  EXPECT_EQ(json["feet"].size(), 2u);
  const nlohmann::json info =
      nlohmann::json::parse(test::runSinew("info --json " + test::quote(bvh_path)).out);
  EXPECT_EQ(info["joint_count"], 22);
  const double seconds = json["seconds"].get<double>();
  EXPECT_EQ(info["frames"].get<int>(), static_cast<int>(std::lround(seconds * 30.0)) + 1);

  const test::CommandResult terrain = test::runSinew("simulate --rig " + walk() + " --terrain hills:3");
  EXPECT_NE(terrain.exit_code, 0);
  EXPECT_NE(terrain.err.find("unknown kind 'hills'"), std::string::npos) << terrain.err;
  const test::CommandResult push = test::runSinew("simulate --rig " + walk() + " --push 1,0,0,5,Tail");
  EXPECT_NE(push.exit_code, 0);
  EXPECT_NE(push.err.find("no link named \"Tail\""), std::string::npos) << push.err;
  const test::CommandResult slope = test::runSinew("simulate --rig " + walk() + " --terrain slope:80");
  EXPECT_NE(slope.exit_code, 0);
  EXPECT_NE(slope.err.find("slope_deg"), std::string::npos) << slope.err;
}

// Where the tracking error lies: simulate's JSON gives every joint's RMS, whose squares average
// (over the joints that turn) to the whole run's, and the summary names the largest.
TEST(CliTest, SimulateNamesTheJointsFurthestFromTheTarget) {
  test::TempDir dir;
  const auto json_path = dir / "run.json";
  const test::CommandResult result = test::runSinew(
      "simulate --rig " + walk() + " --seconds 1 --json " + test::quote(json_path));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(test::readText(json_path));
  double squares = 0.0, most = 0.0;
  int turning = 0;
  std::string furthest;
  for (const nlohmann::json& joint : json["track_err_by_link"]) {
    const double rad = joint["rad_rms"].get<double>();
    if (rad <= 0.0) continue;  // a welded joint
    squares += rad * rad;
    ++turning;
    if (rad > most) {
      most = rad;
      furthest = joint["link"].get<std::string>();
    }
  }
  ASSERT_GT(turning, 10);
  EXPECT_NEAR(std::sqrt(squares / turning), json["track_err_rad_rms"].get<double>(), 1e-9);
  char expected[96];
  std::snprintf(expected, sizeof(expected), "furthest from the target: %s %.1f", furthest.c_str(),
                most * 180.0 / std::numbers::pi);
  EXPECT_NE(result.out.find(expected), std::string::npos) << expected << "\n" << result.out;
}

// sinew simulate --trace: a CSV with one row per step, as many cells in every row as the header
// names (a foot's five, a joint's two), finite numbers; too long a traced run is refused before
// any work.
TEST(CliTest, SimulateTracesEveryStepAsCsv) {
  test::TempDir dir;
  const auto csv_path = dir / "trace.csv";
  const test::CommandResult result = test::runSinew("simulate --rig " + walk() +
                                                    " --seconds 0.5 --trace " + test::quote(csv_path));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("120 steps"), std::string::npos) << result.out;
  std::istringstream lines(test::readText(csv_path));
  std::string header, line;
  ASSERT_TRUE(std::getline(lines, header));
  auto cells = [](const std::string& row) {
    std::vector<std::string> out;
    std::stringstream in(row);
    for (std::string cell; std::getline(in, cell, ',');) out.push_back(cell);
    if (!row.empty() && row.back() == ',') out.emplace_back();
    return out;
  };
  const std::vector<std::string> names = cells(header);
  EXPECT_EQ(names.front(), "time_s");
  // 14 columns, eight per foot (2: contacts, pivot, force, the target's pivot), three per joint
  // (12 joints below the pelvis: torque, at the limit, error).
  EXPECT_EQ(names.size(), 14u + 8u * 2u + 3u * 12u) << header;
  int rows = 0;
  for (; std::getline(lines, line); ++rows) {
    const std::vector<std::string> row = cells(line);
    ASSERT_EQ(row.size(), names.size()) << line;
    for (size_t c = 0; c < row.size(); ++c) {
      if (names[c] == "stance_foot") continue;
      const double value = std::stod(row[c]);
      EXPECT_TRUE(std::isfinite(value)) << names[c];
    }
  }
  EXPECT_EQ(rows, 120);
  const test::CommandResult too_long = test::runSinew("simulate --rig " + walk() +
                                                      " --seconds 200 --trace " + test::quote(csv_path));
  EXPECT_NE(too_long.exit_code, 0);
  EXPECT_NE(too_long.err.find("--trace records every step, so at most 120 s"), std::string::npos)
      << too_long.err;
}

// sinew evolve: the files a pipeline picks up, a controller that replays with sinew simulate, a
// resumed run that continues the generations, and clear refusals.
TEST(CliTest, EvolveWritesTheBestControllerAndResumes) {
  test::TempDir dir;
  const auto out = dir / "evolved";
  const test::CommandResult run = test::runSinew(
      "evolve --generations 2 --population 4 --window 1.5 --threads 2 --weights energy=0 --out " +
      test::quote(out));
  ASSERT_EQ(run.exit_code, 0) << run.err << run.out;
  EXPECT_NE(run.out.find("seeded from the DFT"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("gen   2"), std::string::npos) << run.out;
  // The search says which start it is on: the prior walks the 1.5 s window at once, so it is kept
  // (--start-generations, docs/search.md "Trying starts").
  EXPECT_NE(run.out.find("search: start 1 of 2 (the prior) kept"), std::string::npos) << run.out;
  for (const char* name : {"best.bvh", "best.glb", "best.json", "history.csv", "checkpoint.json"})
    EXPECT_TRUE(std::filesystem::exists(out / name)) << name;
  const std::string csv = test::readText(out / "history.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3) << csv;  // header + 2 generations
  EXPECT_NE(csv.find("fall_best"), std::string::npos);
  const nlohmann::json best = nlohmann::json::parse(test::readText(out / "best.json"));
  EXPECT_EQ(best["format"], "sinew.controller");
  EXPECT_TRUE(best["fitness"].contains("total"));
  EXPECT_EQ(best["fitness"]["energy"].get<double>(), 0.0);  // --weights energy=0
  // The servos led their targets by their lag (240 Hz, rate 0.2), and the replay below does too.
  EXPECT_NEAR(best["settings"]["servo_lead_s"].get<double>(), 1.0 / 48.0, 1e-12);
  EXPECT_TRUE(best["settings"]["lead_yielding_legs"].get<bool>());
  const double survived = best["fitness"]["survived_s"].get<double>();
  // The controller replays: the same window, the same fall (or none).
  const auto replay_json = dir / "replay.json";
  const test::CommandResult replay =
      test::runSinew("simulate --controller " + test::quote(out / "best.json") +
                     " --seconds 1.5 --json " + test::quote(replay_json));
  ASSERT_EQ(replay.exit_code, 0) << replay.err;
  const nlohmann::json figures = nlohmann::json::parse(test::readText(replay_json));
  const double replay_survived =
      figures["fell"].get<bool>() ? figures["fall_time_s"].get<double>() : figures["seconds"].get<double>();
  EXPECT_NEAR(replay_survived, survived, 1e-9);
  // Bit for bit, not only the same fall: a marginal gait diverges from a last-bit difference (a
  // reloaded controller's base rotations once were re-normalised, and an evolved stepper that
  // walked its 10 s window fell at 7.55 s on replay).
  EXPECT_EQ(figures["distance_m"].get<double>(), best["fitness"]["distance_m"].get<double>());
  // The search's summary names the joints at their torque limit as the replay measures them.
  double most = 0.0;
  std::string busiest;
  for (const nlohmann::json& joint : figures["torque_limited"])
    if (joint["share"].get<double>() > most) {
      most = joint["share"].get<double>();
      busiest = joint["link"].get<std::string>();
    }
  // This short search's best has its hips there 13% of the steps: the line must show.
  ASSERT_GE(most, 0.05) << "no joint at its limit 5% of the steps: the check below would not run";
  char expected[96];
  std::snprintf(expected, sizeof(expected), "at the torque limit: %s %.0f%%", busiest.c_str(),
                100.0 * most);
  EXPECT_NE(run.out.find(expected), std::string::npos) << expected << "\n" << run.out;
  // And the joints furthest from the clip (the replay above measures against the evolved target,
  // so only the line's presence is checked here; SimulateNamesTheJointsFurthestFromTheTarget
  // checks its figures).
  EXPECT_NE(run.out.find("furthest from the clip: "), std::string::npos) << run.out;
  // Resumed without a new budget: refused, saying why; with one, it continues at generation 3.
  const test::CommandResult spent =
      test::runSinew("evolve --resume " + test::quote(out / "checkpoint.json") +
                     " --out " + test::quote(dir / "more"));
  EXPECT_NE(spent.exit_code, 0);
  EXPECT_NE(spent.err.find("budget"), std::string::npos) << spent.err << spent.out;
  // A flag that shapes the search is the checkpoint's: refused by name, not silently ignored.
  const test::CommandResult shaped =
      test::runSinew("evolve --resume " + test::quote(out / "checkpoint.json") +
                     " --generations 3 --window 5 --seed 2 --out " + test::quote(dir / "more"));
  EXPECT_EQ(shaped.exit_code, 1);
  EXPECT_EQ(shaped.err,
            "sinew: --resume continues the search as it was: --window and --seed come from the "
            "checkpoint (--minutes, --generations, --weights, --style-weight, --threads, "
            "--trials, --trial-push and --robust-push may change; start a new search to change "
            "the rest)\n");
  const test::CommandResult body =
      test::runSinew("evolve --resume " + test::quote(out / "checkpoint.json") +
                     " --generations 3 --mass Hips=30 --out " + test::quote(dir / "more"));
  EXPECT_NE(body.err.find(": --mass comes from the checkpoint"), std::string::npos) << body.err;
  // The robustness may change (hardening a found gait); the checkpoint written keeps it.
  const test::CommandResult hardened =
      test::runSinew("evolve --resume " + test::quote(out / "checkpoint.json") +
                     " --generations 3 --trials 2 --trial-push 0.5 --out " +
                     test::quote(dir / "hard"));
  ASSERT_EQ(hardened.exit_code, 0) << hardened.err << hardened.out;
  EXPECT_NE(hardened.out.find("2 runs a point (1 pushed"), std::string::npos) << hardened.out;
  const nlohmann::json hard =
      nlohmann::json::parse(test::readText(dir / "hard" / "checkpoint.json"));
  EXPECT_EQ(hard["problem"]["search"]["trials"], 2);
  EXPECT_EQ(hard["problem"]["search"]["trial_push_m_s"], 0.5);
  const test::CommandResult more =
      test::runSinew("evolve --resume " + test::quote(out / "checkpoint.json") +
                     " --generations 3 --out " + test::quote(dir / "more"));
  ASSERT_EQ(more.exit_code, 0) << more.err << more.out;
  EXPECT_NE(more.out.find("gen   3"), std::string::npos) << more.out;
  EXPECT_EQ(more.out.find("gen   2"), std::string::npos) << more.out;

  const test::CommandResult bad_weight = test::runSinew(
      "evolve --weights grace=2 --out " + test::quote(dir / "x"));
  EXPECT_NE(bad_weight.exit_code, 0);
  EXPECT_NE(bad_weight.err.find("--weights 'grace=2'"), std::string::npos) << bad_weight.err;
  const test::CommandResult bad = test::runSinew("evolve --out " + test::quote(dir / "x") +
                                                 " --controller nope.json");
  EXPECT_NE(bad.exit_code, 0);
  const test::CommandResult garbage_json = test::runSinew(
      "simulate --controller " + test::quote(out / "history.csv"));
  EXPECT_NE(garbage_json.exit_code, 0);
  EXPECT_NE(garbage_json.err.find("history.csv"), std::string::npos) << garbage_json.err;
}

// A controller replays on the rig it was evolved for without --rig (best.json names it); one
// that names none is matched against the bundled biped, as before, and refused naming the file.
TEST(CliTest, SimulateControllerDefaultsToTheControllersRig) {
  test::TempDir dir;
  const auto out = dir / "hop";
  const std::string rig = (test::sourceDir() / "assets" / "hopper_hop.bvh").string();
  const test::CommandResult run = test::runSinew(
      "evolve --rig " + test::quote(rig) +
      " --generations 1 --population 4 --window 1 --threads 2 --out " + test::quote(out));
  ASSERT_EQ(run.exit_code, 0) << run.err << run.out;
  const test::CommandResult replay =
      test::runSinew("simulate --controller " + test::quote(out / "best.json") + " --seconds 1");
  ASSERT_EQ(replay.exit_code, 0) << replay.err << replay.out;
  EXPECT_NE(replay.out.find("hopper_hop.bvh"), std::string::npos) << replay.out;
  nlohmann::json broken = nlohmann::json::parse(test::readText(out / "best.json"));
  broken.erase("rig");
  test::writeText(dir / "norig.json", broken.dump());
  const test::CommandResult missing =
      test::runSinew("simulate --controller " + test::quote(dir / "norig.json"));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("norig.json: target: "), std::string::npos) << missing.err;
}

// A project names the rig and the search's settings in one file; broken projects are refused
// naming the file and the field.
TEST(CliTest, EvolveReadsAProject) {
  test::TempDir dir;
  const auto project = dir / "walk.sinew.json";
  test::writeText(project, "{\"format\": \"sinew.project\", \"version\": 1, \"rig\": " +
                               nlohmann::json((test::sourceDir() / "assets" / "biped_walk.bvh").string()).dump() +
                               ", \"window_s\": 1.5, \"body\": {\"fixed\": [\"LeftArm\"]}}");
  const test::CommandResult run = test::runSinew("evolve " + test::quote(project) +
                                                 " --generations 1 --population 4 --out " +
                                                 test::quote(dir / "out"));
  ASSERT_EQ(run.exit_code, 0) << run.err << run.out;
  EXPECT_NE(run.out.find("window 1.5 s"), std::string::npos) << run.out;
  const nlohmann::json checkpoint = nlohmann::json::parse(test::readText(dir / "out" / "checkpoint.json"));
  // The checkpoint's problem is the project's JSON (what the project file writes).
  EXPECT_EQ(checkpoint["problem"]["format"], "sinew.project");
  EXPECT_EQ(checkpoint["problem"]["body"]["fixed"][0], "LeftArm");
  const auto broken = dir / "broken.sinew.json";
  test::writeText(broken, "{\"format\": \"sinew.project\", \"version\": 1}");
  const test::CommandResult refused =
      test::runSinew("evolve " + test::quote(broken) + " --out " + test::quote(dir / "x"));
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.err.find("broken.sinew.json: rig: missing"), std::string::npos) << refused.err;
}

// A version 2 project (as the editor saves it) carries the search's settings and K per joint;
// the command line's flags still win.
TEST(CliTest, EvolveTakesTheSearchSettingsOfAVersion2Project) {
  test::TempDir dir;
  const auto project = dir / "v2.sinew.json";
  test::writeText(project, "{\"format\": \"sinew.project\", \"version\": 2, \"rig\": " +
                               nlohmann::json((test::sourceDir() / "assets" / "biped_walk.bvh").string()).dump() +
                               ", \"window_s\": 1, \"joint_harmonics\": {\"Head\": 1}, \"search\": "
                               "{\"optimizer\": \"ga\", \"population\": 6, \"seed\": 9}}");
  const test::CommandResult run = test::runSinew("evolve " + test::quote(project) +
                                                 " --generations 1 --seed 3 --out " + test::quote(dir / "out"));
  ASSERT_EQ(run.exit_code, 0) << run.err << run.out;
  EXPECT_NE(run.out.find("genetic algorithm"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("population 6"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("seed 3"), std::string::npos) << run.out;  // the flag wins
  EXPECT_NE(run.out.find("1 joint with its own K"), std::string::npos) << run.out;
  test::writeText(project, "{\"format\": \"sinew.project\", \"version\": 2, \"rig\": " +
                               nlohmann::json((test::sourceDir() / "assets" / "biped_walk.bvh").string()).dump() +
                               ", \"joint_harmonics\": {\"Tail\": 1}}");
  const test::CommandResult refused =
      test::runSinew("evolve " + test::quote(project) + " --generations 1 --out " + test::quote(dir / "x"));
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.err.find("joint_harmonics: "), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("no joint called 'Tail'"), std::string::npos) << refused.err;
}

// The editor's edits of the model in a project (band gains, secondary motion) are evolved too,
// and a resumed search keeps them.
TEST(CliTest, EvolveAppliesTheProjectsEditsAndKeepsThemOnResume) {
  test::TempDir dir;
  const auto project = dir / "edited.sinew.json";
  test::writeText(project, "{\"format\": \"sinew.project\", \"version\": 2, \"rig\": " +
                               nlohmann::json((test::sourceDir() / "assets" / "biped_walk.bvh").string()).dump() +
                               ", \"window_s\": 1, \"band_gains\": {\"detail\": {\"arms\": 0}}, "
                               "\"secondary\": [{\"joint\": \"Chest\", \"frequency_hz\": 0.25, "
                               "\"amplitude_deg\": 2}], \"search\": {\"population\": 4}}");
  const test::CommandResult run = test::runSinew("evolve " + test::quote(project) +
                                                 " --generations 1 --out " + test::quote(dir / "out"));
  ASSERT_EQ(run.exit_code, 0) << run.err << run.out;
  EXPECT_NE(run.out.find("with the project's edits"), std::string::npos) << run.out;
  const nlohmann::json checkpoint = nlohmann::json::parse(test::readText(dir / "out" / "checkpoint.json"));
  EXPECT_EQ(checkpoint["problem"]["band_gains"]["detail"]["arms"], 0.0);
  const test::CommandResult resumed =
      test::runSinew("evolve --resume " + test::quote(dir / "out" / "checkpoint.json") +
                     " --generations 2 --out " + test::quote(dir / "out2"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err << resumed.out;
  EXPECT_NE(resumed.out.find("with the project's edits"), std::string::npos) << resumed.out;
}

}  // namespace
}  // namespace sinew
