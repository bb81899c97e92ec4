// Bad input to the search and its files (issue 14): controllers without a target, with unknown
// keys or absurd gains; diverged simulations scored as failures and never written as numbers; a
// search that finds nothing finite stops with a message; old checkpoints with null.
#include <cmath>
#include <cstdio>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "physics/physics_test_util.h"
#include "sinew/core/file_io.h"
#include "sinew/physics/divergence.h"
#include "sinew/search/controller_io.h"
#include "sinew/search/session.h"

namespace sinew::search {
namespace {

physics::test_util::Character biped() {
  return physics::test_util::loadCharacter("biped_walk.bvh");
}

// best.json for the walk, then edited by `edit`, loaded back.
Result<ControllerFile> editedController(const physics::test_util::Character& c,
                                        void (*edit)(nlohmann::json&), const test::TempDir& dir) {
  ControllerFile file;
  file.target = c.target;
  EXPECT_TRUE(saveController(dir / "best.json", file, c.asset.skeleton).ok());
  nlohmann::json json = nlohmann::json::parse(test::readText(dir / "best.json"));
  edit(json);
  test::writeText(dir / "edited.json", json.dump(2));
  return loadController(dir / "edited.json", c.asset.skeleton);
}

TEST(SearchBadInput, ControllerFilesGiveOneLineNamingTheField) {
  const physics::test_util::Character c = biped();
  test::TempDir dir;
  const std::string file = (dir / "edited.json").string();
  Result<ControllerFile> same = editedController(
      c, [](nlohmann::json&) {}, dir);
  ASSERT_TRUE(same.ok()) << same.message();
  EXPECT_TRUE(same.value().warnings.empty());
  Result<ControllerFile> no_target = editedController(
      c, [](nlohmann::json& j) { j.erase("target"); }, dir);
  EXPECT_EQ(no_target.message(), file +
                                     ": target: missing (the controller's coefficients; a "
                                     "best.json from sinew evolve has them)");
  Result<ControllerFile> gains = editedController(
      c, [](nlohmann::json& j) { j["balance"]["cv_coronal"] = 1e308; }, dir);
  EXPECT_EQ(gains.message(), file + ": balance: cv_coronal: expected a gain within +-100");
  Result<ControllerFile> seed = editedController(
      c, [](nlohmann::json& j) { j["settings"]["seed"] = -1; }, dir);
  EXPECT_EQ(seed.message(), file + ": settings: seed: expected an unsigned 64-bit integer");
  Result<ControllerFile> n = editedController(
      c, [](nlohmann::json& j) { j["target"]["channels"][0]["harmonics"][0]["n"] = 1e9; }, dir);
  EXPECT_EQ(n.message(), file +
                             ": target: channels[0].harmonics[0].n: expected a whole number "
                             "from 1 to 1024");
  test::writeText(dir / "edited.json", "{\"format\": \"sinew.controller\", \"version\": 1,");
  EXPECT_EQ(loadController(dir / "edited.json", c.asset.skeleton).message(),
            file + ": not valid JSON (a sinew.controller object)");
}

// The gains added after version 1's first files (ankle_sagittal, ankle_coronal, swing_lift,
// heading, the stance gains, the stance yield): saved and read back; a file without them replays
// with them off; a lift or a yield beyond its range is refused naming the field.
TEST(SearchBadInput, LaterBalanceGainsRoundTripAndAreOffInOlderFiles) {
  const physics::test_util::Character c = biped();
  test::TempDir dir;
  Result<ControllerFile> same = editedController(
      c,
      [](nlohmann::json& j) {
        j["balance"]["ankle_sagittal"] = 0.25;
        j["balance"]["swing_lift"] = 0.03;
        j["balance"]["heading"] = 0.7;
        j["balance"]["stance_vertical"] = -0.04;
        j["balance"]["stance_yaw"] = 0.6;
        j["balance"]["stance_yield"] = 0.45;
      },
      dir);
  ASSERT_TRUE(same.ok()) << same.message();
  EXPECT_EQ(same.value().balance.ankle_sagittal, 0.25);
  EXPECT_EQ(same.value().balance.ankle_coronal, physics::BalanceGains{}.ankle_coronal);
  EXPECT_EQ(same.value().balance.swing_lift, 0.03);
  EXPECT_EQ(same.value().balance.heading, 0.7);
  EXPECT_EQ(same.value().balance.stance_vertical, -0.04);
  EXPECT_EQ(same.value().balance.stance_yaw, 0.6);
  EXPECT_EQ(same.value().balance.stance_yield, 0.45);
  Result<ControllerFile> older = editedController(
      c,
      [](nlohmann::json& j) {
        for (const char* key : {"ankle_sagittal", "ankle_coronal", "swing_lift", "heading",
                                "stance_sagittal", "stance_coronal", "stance_vertical",
                                "stance_yaw", "stance_yield"})
          j["balance"].erase(key);
      },
      dir);
  ASSERT_TRUE(older.ok()) << older.message();
  EXPECT_TRUE(older.value().warnings.empty());
  EXPECT_EQ(older.value().balance.ankle_sagittal, 0.0);
  EXPECT_EQ(older.value().balance.swing_lift, 0.0);
  EXPECT_EQ(older.value().balance.heading, 0.0);
  EXPECT_EQ(older.value().balance.stance_vertical, 0.0);
  EXPECT_EQ(older.value().balance.stance_yaw, 0.0);
  EXPECT_EQ(older.value().balance.stance_yield, 0.0);
  EXPECT_EQ(older.value().balance.torso, physics::BalanceGains{}.torso);
  Result<ControllerFile> high = editedController(
      c, [](nlohmann::json& j) { j["balance"]["swing_lift"] = 0.5; }, dir);
  EXPECT_EQ(high.message(),
            (dir / "edited.json").string() + ": balance: swing_lift: expected a share from 0 to 0.1");
  Result<ControllerFile> stiff = editedController(
      c, [](nlohmann::json& j) { j["balance"]["stance_yield"] = 1.0; }, dir);
  EXPECT_EQ(stiff.message(), (dir / "edited.json").string() +
                                 ": balance: stance_yield: expected a share from 0 to 0.9");
}

// The servo lead the search ran with: saved and read back and given to a replay; a file from
// before it replays without one (as it was searched); a lead beyond a second is refused.
TEST(SearchBadInput, TheServoLeadRoundTripsAndIsNoneInOlderFiles) {
  const physics::test_util::Character c = biped();
  test::TempDir dir;
  Result<ControllerFile> led = editedController(
      c,
      [](nlohmann::json& j) {
        j["settings"]["servo_lead_s"] = 0.02;
        j["settings"]["lead_yielding_legs"] = true;
      },
      dir);
  ASSERT_TRUE(led.ok()) << led.message();
  EXPECT_EQ(led.value().servo_lead_s, 0.02);
  EXPECT_TRUE(led.value().lead_yielding_legs);
  physics::TrackingSettings tracking;
  applyController(led.value(), tracking);
  EXPECT_EQ(tracking.servo_lead_s, 0.02);
  EXPECT_TRUE(tracking.lead_yielding_legs);
  // Searched with the lead before the yielding legs were led further: without that.
  Result<ControllerFile> led_before = editedController(
      c,
      [](nlohmann::json& j) {
        j["settings"]["servo_lead_s"] = 0.02;
        j["settings"].erase("lead_yielding_legs");
      },
      dir);
  ASSERT_TRUE(led_before.ok()) << led_before.message();
  EXPECT_TRUE(led_before.value().warnings.empty());
  EXPECT_EQ(led_before.value().servo_lead_s, 0.02);
  EXPECT_FALSE(led_before.value().lead_yielding_legs);
  Result<ControllerFile> older = editedController(
      c, [](nlohmann::json& j) { j["settings"].erase("servo_lead_s"); }, dir);
  ASSERT_TRUE(older.ok()) << older.message();
  EXPECT_TRUE(older.value().warnings.empty());
  EXPECT_EQ(older.value().servo_lead_s, 0.0);
  Result<ControllerFile> not_bool = editedController(
      c, [](nlohmann::json& j) { j["settings"]["lead_yielding_legs"] = 1; }, dir);
  ASSERT_FALSE(not_bool.ok());
  EXPECT_NE(not_bool.message().find("settings: lead_yielding_legs"), std::string::npos)
      << not_bool.message();
  Result<ControllerFile> far = editedController(
      c, [](nlohmann::json& j) { j["settings"]["servo_lead_s"] = 2.0; }, dir);
  EXPECT_EQ(far.message(), (dir / "edited.json").string() +
                               ": settings: servo_lead_s: expected seconds in [0, 1]");
}

// Paths are bytes: a Latin-1 rig or clip path comes back as the same bytes (core's path_json, the
// project's and the checkpoint's code); a wrong encoding is refused naming the field.
TEST(SearchBadInput, ControllerPathsRoundTripAsBytes) {
  const physics::test_util::Character c = biped();
  test::TempDir dir;
  ControllerFile file;
  file.target = c.target;
  file.rig =
      "/captures/H\xFC"
      "fte/walk_\xE9.bvh";
  file.clip = "/captures/plain.bvh";
  ASSERT_TRUE(saveController(dir / "best.json", file, c.asset.skeleton).ok());
  const nlohmann::json json = nlohmann::json::parse(test::readText(dir / "best.json"));
  EXPECT_EQ(json["rig"],
            "/captures/H\xC3\xBC"
            "fte/walk_\xC3\xA9.bvh");
  EXPECT_EQ(json["rig_encoding"], "latin1");
  EXPECT_FALSE(json.contains("clip_encoding"));
  Result<ControllerFile> back = loadController(dir / "best.json", c.asset.skeleton);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back.value().rig, file.rig);
  EXPECT_EQ(back.value().clip, file.clip);
  EXPECT_TRUE(back.value().warnings.empty());
  Result<ControllerFile> wrong = editedController(
      c, [](nlohmann::json& j) { j["rig"] = "a.bvh", j["rig_encoding"] = "utf16"; }, dir);
  EXPECT_EQ(wrong.message(),
            (dir / "edited.json").string() + ": rig_encoding: expected \"latin1\", got \"utf16\"");
}

TEST(SearchBadInput, UnknownControllerKeysAreWarnings) {
  const physics::test_util::Character c = biped();
  test::TempDir dir;
  Result<ControllerFile> r = editedController(
      c,
      [](nlohmann::json& j) {
        j["balanse"] = 1;
        j["settings"]["windw_s"] = 4;
      },
      dir);
  ASSERT_TRUE(r.ok()) << r.message();
  const std::string file = (dir / "edited.json").string();
  ASSERT_EQ(r.value().warnings.size(), 2u);
  EXPECT_EQ(r.value().warnings[0], file + ": unknown key 'balanse' (ignored)");
  EXPECT_EQ(r.value().warnings[1], file + ": settings: unknown key 'windw_s' (ignored)");
}

// A problem whose every evaluation fails: the push names no link, found only when simulating.
Problem failingProblem(const physics::test_util::Character& c) {
  physics::SimulationSettings simulation;
  simulation.seconds = 0.5;
  simulation.pushes.push_back({0.1, glm::dvec3(1.0, 0.0, 0.0), "NoSuchLink"});
  Result<Problem> p = Problem::create(c.plan, c.asset.skeleton, c.target, {}, simulation);
  EXPECT_TRUE(p.ok()) << p.message();
  return std::move(p).value();
}

TEST(SearchBadInput, ASearchFindingNothingFiniteStopsWithAMessageAndWritesNoInfOrNull) {
  const physics::test_util::Character c = biped();
  EvolveSettings settings;
  settings.population = 4;
  settings.generations = 40;
  settings.threads = 1;
  std::unique_ptr<Session> session = Session::create(failingProblem(c), settings).value();
  int generations = 0;
  while (session->runGeneration()) ++generations;
  EXPECT_EQ(generations, kGenerationsWithoutScore);  // not 40
  const auto snap = session->snapshot();
  EXPECT_TRUE(snap->best_point.empty());
  EXPECT_NE(snap->failure.find("every evaluation of the first 3 generations failed (4 of 4 in "
                               "the last diverged): nothing finite to keep"),
            std::string::npos)
      << snap->failure;
  ASSERT_EQ(snap->history.size(), 3u);
  EXPECT_EQ(snap->history[0].scored, 0);
  EXPECT_EQ(snap->history[0].diverged, 4);
  const std::string text = session->checkpoint().dump();
  EXPECT_EQ(text.find("null"), std::string::npos) << text.substr(0, 400);
  EXPECT_EQ(text.find("Infinity"), std::string::npos);
  for (const GenerationRecord& r : snap->history) EXPECT_TRUE(std::isfinite(r.total.best));
}

TEST(SearchBadInput, ACheckpointWithNullInItsHistoryGivesAClearMessage) {
  const physics::test_util::Character c = biped();
  EvolveSettings settings;
  settings.population = 4;
  settings.generations = 1;
  settings.threads = 1;
  std::unique_ptr<Session> session = Session::create(failingProblem(c), settings).value();
  ASSERT_TRUE(session->runGeneration());
  nlohmann::json checkpoint = session->checkpoint();
  checkpoint["history"][0]["total"] = {nullptr, 0.0, nullptr};  // what older versions wrote
  Result<std::unique_ptr<Session>> resumed = Session::resume(failingProblem(c), checkpoint);
  ASSERT_FALSE(resumed.ok());
  EXPECT_EQ(resumed.message(),
            "checkpoint: history[0].total: expected [best, mean, worst], three finite numbers");
}

TEST(SearchBadInput, EvolveSettingsRefuseAbsurdPopulations) {
  EvolveSettings settings;
  settings.population = 1000000000;
  EXPECT_EQ(settings.validate().message(),
            "population must be 0 (the optimiser's default) to 100000");
}

}  // namespace
}  // namespace sinew::search
