// Bad input on the command line and in the files it reads (issue 14), run as a user runs it:
// exit 1 and one line on stderr, or the right result; never an abort, a hang, null or nan.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sinew/core/text.h"
#include "support/test_support.h"

namespace sinew {
namespace {

std::filesystem::path walkPath() {
  return test::sourceDir() / "assets" / "biped_walk.bvh";
}
std::string walk() {
  return test::quote(walkPath());
}

// The bundled walk with its Spine1 renamed to "Hüfte" in Latin-1 (one byte for ü), as European
// capture software writes it, saved under a Latin-1 file name too.
std::filesystem::path latin1Walk(const test::TempDir& dir) {
  std::string text = test::readText(walkPath());
  text.replace(text.find("JOINT Spine1"), 12,
               "JOINT H\xFC"
               "fte");
  const std::filesystem::path path = dir / "walk_\xE9.bvh";
  test::writeText(path, text);
  return path;
}

bool oneLine(const std::string& err) {
  return !err.empty() && err.find('\n') == err.size() - 1 && err.rfind("sinew: ", 0) == 0;
}

TEST(CliBadInput, Latin1NamesAndPathsGiveValidUtf8Json) {
  test::TempDir dir;
  const std::string file = test::quote(latin1Walk(dir));
  const test::CommandResult info = test::runSinew("info --json " + file);
  ASSERT_EQ(info.exit_code, 0) << info.err;  // was 134 (an uncaught JSON exception)
  const nlohmann::json json = nlohmann::json::parse(info.out);
  EXPECT_EQ(json["joints"][2]["name"],
            "H\xC3\xBC"
            "fte");
  EXPECT_NE(json["file"].get<std::string>().find("walk_\xC3\xA9.bvh"), std::string::npos);

  const test::CommandResult analyze =
      test::runSinew("analyze " + file + " --json " + test::quote(dir / "a.json"));
  ASSERT_EQ(analyze.exit_code, 0) << analyze.err;
  const std::string written = test::readText(dir / "a.json");
  EXPECT_FALSE(nlohmann::json::parse(written, nullptr, false).is_discarded());
  EXPECT_EQ(written.find("null"), std::string::npos);

  const test::CommandResult simulate = test::runSinew(
      "simulate --rig " + file + " --seconds 1 --json " + test::quote(dir / "s.json"));
  ASSERT_EQ(simulate.exit_code, 0) << simulate.err;
  const std::string report = test::readText(dir / "s.json");
  EXPECT_EQ(report.find("null"), std::string::npos) << report;
  EXPECT_EQ(nlohmann::json::parse(report)["diverged"], false);
}

TEST(CliBadInput, EvolveOnALatin1RigWritesItsResults) {
  test::TempDir dir;
  const test::CommandResult evolve = test::runSinew(
      "evolve --rig " + test::quote(latin1Walk(dir)) +
      " --generations 2 --population 4 --window 1 --threads 1 --out " + test::quote(dir / "out"));
  ASSERT_EQ(evolve.exit_code, 0) << evolve.out << evolve.err;  // was an abort after generation 1
  for (const char* name : {"best.json", "best.bvh", "best.glb", "checkpoint.json", "history.csv"})
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / name)) << name;
  const std::string best = test::readText(dir / "out" / "best.json");
  EXPECT_NE(best.find("H\xC3\xBC"
                      "fte"),
            std::string::npos);
  const std::string history = test::readText(dir / "out" / "history.csv");
  EXPECT_EQ(history.find("inf"), std::string::npos);
  EXPECT_EQ(history.find("nan"), std::string::npos);
}

// best.json of a short search on `rig`, in dir/out.
std::filesystem::path evolvedController(const std::filesystem::path& rig,
                                        const test::TempDir& dir) {
  const test::CommandResult evolve = test::runSinew(
      "evolve --rig " + test::quote(rig) +
      " --generations 1 --population 4 --window 0.5 --threads 1 --out " + test::quote(dir / "out"));
  EXPECT_EQ(evolve.exit_code, 0) << evolve.out << evolve.err;
  return dir / "out" / "best.json";
}

// best.json names its rig as text; a Latin-1 path is kept as its Latin-1 reading with
// "rig_encoding": "latin1" (it stored U+FFFD in place of the byte), and the controller replays.
TEST(CliBadInput, AControllerKeepsItsLatin1RigPathAndReplays) {
  test::TempDir dir;
  const std::filesystem::path rig = latin1Walk(dir);
  const std::filesystem::path best = evolvedController(rig, dir);
  const nlohmann::json json = nlohmann::json::parse(test::readText(best));
  EXPECT_EQ(json["rig_encoding"], "latin1");
  EXPECT_EQ(json["rig"], toUtf8(rig.string()));
  EXPECT_EQ(json["clip_encoding"], "latin1");
  const test::CommandResult replay =
      test::runSinew("simulate --seconds 0.5 --rig " + test::quote(rig) + " --controller " +
                     test::quote(best) + " --json " + test::quote(dir / "s.json"));
  ASSERT_EQ(replay.exit_code, 0) << replay.err;
  EXPECT_EQ(replay.err, "");  // no warning: rig_encoding is a known key
  EXPECT_NE(replay.out.find("tracking " + best.string()), std::string::npos) << replay.out;
  EXPECT_EQ(test::readText(dir / "s.json").find("null"), std::string::npos);
}

// A controller is for one rig: another joint count, other names or another hierarchy are refused
// with one line naming the file and the field, as is a genome with one harmonic index twice.
TEST(CliBadInput, AControllerForAnotherRigIsRefusedNamingTheMismatch) {
  test::TempDir dir;
  const std::filesystem::path best = evolvedController(walkPath(), dir);
  const std::string file = best.string();
  const auto replay = [&](const std::filesystem::path& rig, const std::filesystem::path& c) {
    return test::runSinew("simulate --seconds 0.5 --rig " + test::quote(rig) + " --controller " +
                          test::quote(c));
  };
  const test::CommandResult count = replay(test::sourceDir() / "assets" / "hopper_hop.bvh", best);
  EXPECT_EQ(count.exit_code, 1);
  EXPECT_EQ(count.err,
            "sinew: " + file + ": target: joints: expected 7 joints for this skeleton, found 22\n");

  const test::CommandResult names = replay(latin1Walk(dir), best);
  EXPECT_EQ(names.exit_code, 1);
  EXPECT_EQ(names.err, "sinew: " + file +
                           ": target: joints[2].name: expected 'H\xC3\xBC"
                           "fte', found 'Spine1' (the coefficients are for another rig)\n");

  std::string text = test::readText(walkPath());  // Head moved from the Neck to the Chest
  const std::string head = "\t\t\t\t\tJOINT Head";
  const std::string close = "\t\t\t\t\t}\n\t\t\t\t}\n\t\t\t\tJOINT LeftShoulder";
  text.replace(text.find(close), close.size(), "\t\t\t\t\t}\n\t\t\t\tJOINT LeftShoulder");
  text.replace(text.find(head), head.size(), "\t\t\t\t}\n\t\t\t\tJOINT Head");
  test::writeText(dir / "other.bvh", text);
  const test::CommandResult tree = replay(dir / "other.bvh", best);
  EXPECT_EQ(tree.exit_code, 1);
  EXPECT_TRUE(oneLine(tree.err)) << tree.err;
  EXPECT_NE(tree.err.find(": target: joints["), std::string::npos) << tree.err;
  EXPECT_NE(tree.err.find("].parent: expected 'Chest', found 'Neck' (the coefficients are for a "
                          "rig with another hierarchy)"),
            std::string::npos)
      << tree.err;

  nlohmann::json json = nlohmann::json::parse(test::readText(best));
  nlohmann::json& terms = json["target"]["channels"][0]["harmonics"];
  ASSERT_GE(terms.size(), 2u);
  terms[1]["n"] = terms[0]["n"];
  test::writeText(dir / "twice.json", json.dump(2));
  const test::CommandResult twice = replay(walkPath(), dir / "twice.json");
  EXPECT_EQ(twice.exit_code, 1);
  EXPECT_EQ(twice.err, "sinew: " + (dir / "twice.json").string() +
                           ": target: channels[0].harmonics[1].n: harmonic " +
                           terms[0]["n"].dump() + " appears twice in this channel\n");
}

// The checkpoint stores the rig's path as text; a Latin-1 path is kept as its Latin-1 reading
// with "rig_encoding": "latin1", so the resumed search opens the same bytes (it stored U+FFFD
// in place of the byte, and the resume could not find the rig).
TEST(CliBadInput, ResumeFindsALatin1RigThroughItsCheckpoint) {
  test::TempDir dir;
  const std::filesystem::path rig = latin1Walk(dir);
  const test::CommandResult evolve = test::runSinew(
      "evolve --rig " + test::quote(rig) +
      " --generations 1 --population 4 --window 0.5 --threads 1 --out " + test::quote(dir / "out"));
  ASSERT_EQ(evolve.exit_code, 0) << evolve.out << evolve.err;
  const nlohmann::json checkpoint =
      nlohmann::json::parse(test::readText(dir / "out" / "checkpoint.json"));
  EXPECT_EQ(checkpoint["problem"]["rig_encoding"], "latin1");
  EXPECT_NE(checkpoint["problem"]["rig"].get<std::string>().find("walk_\xC3\xA9.bvh"),
            std::string::npos);
  const test::CommandResult resumed = test::runSinew(
      "evolve --resume " + test::quote(dir / "out" / "checkpoint.json") +
      " --generations 2 --threads 1 --out " + test::quote(dir / "more"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err << resumed.out;
  EXPECT_NE(resumed.out.find("gen   2"), std::string::npos) << resumed.out;
  EXPECT_TRUE(std::filesystem::exists(dir / "more" / "best.bvh"));
}

// Style labels come from file names when not given; a Latin-1 name becomes a UTF-8 label.
TEST(CliBadInput, StyleLabelsFromLatin1FileNamesAreUtf8) {
  test::TempDir dir;
  const std::filesystem::path tired = dir / "m\xFC""de.bvh";  // "müde" with ü as one byte
  std::filesystem::copy_file(walkPath(), tired);
  const test::CommandResult transfer =
      test::runSinew("style --neutral " + walk() + " --styled " + test::quote(tired) + " -o " +
                     test::quote(dir / "t.json"));
  ASSERT_EQ(transfer.exit_code, 0) << transfer.err;  // was an abort writing the JSON
  const std::string target = test::readText(dir / "t.json");
  ASSERT_FALSE(nlohmann::json::parse(target, nullptr, false).is_discarded());
  EXPECT_NE(target.find("m\xC3\xBC""de"), std::string::npos);

  const test::CommandResult measure =
      test::runSinew("style --measure " + walk() + " --library " + test::quote(tired) +
                     " --json " + test::quote(dir / "m.json"));
  ASSERT_EQ(measure.exit_code, 0) << measure.err;
  const nlohmann::json scores = nlohmann::json::parse(test::readText(dir / "m.json"));
  EXPECT_EQ(scores["closest"], "m\xC3\xBC""de") << scores.dump();
}

TEST(CliBadInput, ByteOrderMarkIsAccepted) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "bom");
  std::filesystem::create_directories(dir / "plain");  // the same file name: the same clip name
  test::writeText(dir / "bom" / "walk.bvh", "\xEF\xBB\xBF" + test::readText(walkPath()));
  test::writeText(dir / "plain" / "walk.bvh", test::readText(walkPath()));
  const test::CommandResult info =
      test::runSinew("info --json " + test::quote(dir / "bom" / "walk.bvh"));
  ASSERT_EQ(info.exit_code, 0) << info.err;  // was "found '???HIERARCHY'"
  const test::CommandResult plain =
      test::runSinew("info --json " + test::quote(dir / "plain" / "walk.bvh"));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  nlohmann::json with_bom = nlohmann::json::parse(info.out);
  nlohmann::json without = nlohmann::json::parse(plain.out);
  with_bom.erase("file");
  without.erase("file");
  EXPECT_EQ(with_bom, without);  // the same joints, frames and units as the file without it
}

TEST(CliBadInput, OptionsOutOfRangeExitOneWithOneLine) {
  struct Case {
    std::string arguments;
    std::string expected;  // the whole line on stderr
  };
  const std::string out = " --out " + test::quote(std::filesystem::temp_directory_path() / "x");
  const Case cases[] = {
      {"analyze " + walk() + " --harmonics auto --tolerance-cm 0",
       "sinew: --tolerance-cm: expected centimetres in (0, 1000], got 0 (see sinew analyze "
       "--help)"},
      {"evolve --rig " + walk() + " --generations 0" + out,
       "sinew: --generations 0 with no --minutes gives the search no budget"},
      {"evolve --rig " + walk() + " --population 4.5" + out,
       "sinew: --population: expected a whole number from 0 to 10000, got '4.5' (see sinew "
       "evolve --help)"},
      // was "must be 0 or more", which 1e9 is
      {"evolve --rig " + walk() + " --population 1e9" + out,
       "sinew: --population: expected a whole number from 0 to 10000, got '1e9' (see sinew "
       "evolve --help)"},
      {"evolve --rig " + walk() + " --population 1000000000" + out,
       "sinew: --population: expected a whole number from 0 to 10000, got '1000000000' (see "
       "sinew evolve --help)"},
      {"evolve --rig " + walk() + " --seed -1" + out,
       "sinew: --seed: expected a whole number >= 0, got '-1' (see sinew evolve --help)"},
      {"simulate --balance 1e308,0,0,0,0.5",
       "sinew: --balance: cd_sagittal (value 1) must be within +-100"},
      {"simulate --balance 0,0,0,0,0.5,0,0,0.05,0.5,0,0,0,0,0.95",
       "sinew: --balance: stance_yield (value 14) must be a share from 0 to 0.9"},
      {"simulate --balance 0,0,0,0,0.5,0",
       "sinew: --balance: expected 5 numbers CD_SAGITTAL,CV_SAGITTAL,CD_CORONAL,CV_CORONAL,TORSO (or "
       "8, then ANKLE_SAGITTAL,ANKLE_CORONAL,SWING_LIFT, or 9, then HEADING, or 12, then "
       "STANCE_SAGITTAL,STANCE_CORONAL,STANCE_VERTICAL, or 13, then STANCE_YAW, or 14, then "
       "STANCE_YIELD), got 6"},
      {"simulate --push 1,1e6,0,0",
       "sinew: simulation: pushes[0]: time must be >= 0 s, impulse at most 10000 N s"},
      {"info " + walk() + " --fps 0.001",
       "sinew: --fps: Value 0.001 not in range 0.016667 to 1000.000000 (see sinew info --help)"},
  };
  for (const Case& c : cases) {
    const test::CommandResult r = test::runSinew(c.arguments);
    EXPECT_EQ(r.exit_code, 1) << c.arguments << "\n" << r.err;
    EXPECT_EQ(r.err, c.expected + "\n") << c.arguments;
  }
}

TEST(CliBadInput, ConvertReportsTheFramesItWrote) {
  test::TempDir dir;
  const test::CommandResult r =
      test::runSinew("convert " + walk() + " " + test::quote(dir / "fast.bvh") + " --fps 60");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("257 frames at 60 fps"), std::string::npos) << r.out;  // not 129 at 30
}

TEST(CliBadInput, AControllerWithoutTargetIsNamed) {
  test::TempDir dir;
  test::writeText(dir / "c.json", R"({"format": "sinew.controller", "version": 1,
    "balance": {"cd_sagittal": 0, "cv_sagittal": 0, "cd_coronal": 0, "cv_coronal": 0, "torso": 0.5},
    "settings": {"window_s": 10, "terrain": "flat", "seed": 1, "optimizer": "cmaes", "no_prior": false}})");
  const test::CommandResult r =
      test::runSinew("simulate --seconds 1 --controller " + test::quote(dir / "c.json"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "sinew: " + (dir / "c.json").string() +
                       ": target: missing (the controller's coefficients; a best.json from sinew "
                       "evolve has them)\n");
}

TEST(CliBadInput, AClipForARigMustShareItsHierarchy) {
  test::TempDir dir;
  // The same joint names in the same order, with Head moved from the Neck to the Chest.
  std::string text = test::readText(walkPath());
  const std::string head = "\t\t\t\t\tJOINT Head";
  const std::string close = "\t\t\t\t\t}\n\t\t\t\t}\n\t\t\t\tJOINT LeftShoulder";
  ASSERT_NE(text.find(head), std::string::npos);
  ASSERT_NE(text.find(close), std::string::npos);
  text.replace(text.find(close), close.size(), "\t\t\t\t\t}\n\t\t\t\tJOINT LeftShoulder");
  text.replace(text.find(head), head.size(), "\t\t\t\t}\n\t\t\t\tJOINT Head");
  test::writeText(dir / "other.bvh", text);
  const test::CommandResult info = test::runSinew("info " + test::quote(dir / "other.bvh"));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const test::CommandResult r = test::runSinew("simulate --seconds 0.5 --rig " + walk() +
                                               " --clip " + test::quote(dir / "other.bvh"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "sinew: " + (dir / "other.bvh").string() + ": its skeleton is not the rig's (" +
                       walkPath().string() + "): the same joint names in another hierarchy\n");
}

}  // namespace
}  // namespace sinew
