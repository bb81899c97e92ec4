// The editor's command and state model without a window: projects (load, save, round trip, bad
// files), undo and redo of settings, unsaved changes, the recovery file and the preferences.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <span>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "editor/camera.h"
#include "editor/editor_state.h"
#include "editor/evolution.h"
#include "editor/ghost.h"
#include "editor/history.h"
#include "editor/preferences.h"
#include "editor/project_model.h"
#include "editor/scene.h"
#include "project/project.h"
#include "sinew/spectral/target_io.h"
#include "support/test_support.h"

namespace sinew {
namespace {

std::filesystem::path defaultProject() {
  return test::sourceDir() / "assets" / "default.sinew.json";
}

int jointIndex(const editor::EditorState& state, const std::string& name) {
  return state.asset->skeleton.findJoint(name);
}

// The typed settings of a terrain or push as the project file writes them.
physics::TerrainSettings terrainOf(const std::string& text) {
  Result<physics::TerrainSettings> terrain = app::parseTerrain(text);
  EXPECT_TRUE(terrain.ok()) << terrain.message();
  return terrain.ok() ? terrain.value() : physics::TerrainSettings();
}

physics::Push pushOf(const std::string& text) {
  Result<physics::Push> push = app::parsePush(text);
  EXPECT_TRUE(push.ok()) << push.message();
  return push.ok() ? push.value() : physics::Push();
}

TEST(ProjectFileTest, TheBundledVersion1ProjectLoadsWithDefaults) {
  Result<app::Project> project = app::loadProject(defaultProject());
  ASSERT_TRUE(project.ok()) << project.message();
  const app::Project& p = project.value();
  EXPECT_EQ(std::filesystem::path(p.rig), test::sourceDir() / "assets" / "biped_walk.bvh");
  EXPECT_EQ(p.harmonics, 5);
  EXPECT_EQ(app::terrainText(p.physics.terrain), "flat");
  EXPECT_EQ(p.physics.window_s, 10.0);
  EXPECT_TRUE(p.joint_k.empty());
  EXPECT_EQ(p.search, app::SearchSettings());
  EXPECT_EQ(p.view, app::ViewSettings());
}

TEST(ProjectFileTest, EverySettingSurvivesASaveAndALoad) {
  test::TempDir dir;
  app::Project p;
  p.rig = (test::sourceDir() / "assets" / "biped_walk.bvh").string();
  p.animation = "biped_walk";
  p.harmonics = 4;
  p.joint_k = {{"LeftUpLeg", 7}, {"Head", 0}};
  p.physics.terrain = terrainOf("slope:3");
  p.physics.window_s = 6.5;
  p.physics.pushes = {pushOf("1.5,-30,0,0,Spine"), pushOf("3,0,0,20")};
  p.physics.body.masses = {{"Head", 6.5}};
  p.physics.body.fixed = {"LeftToe"};
  p.physics.body.hinge_limits = {{"LeftLeg", -150.0, 5.0}};
  p.search.minutes = 7.5;
  p.search.population = 24;
  p.search.no_prior = true;
  p.search.optimizer = search::OptimizerKind::kGa;
  p.search.seed = 42;
  p.search.weights.fall = 3.0;
  p.search.weights.energy = 0.01;
  p.search.trials = 3;
  p.search.trial_push_m_s = 0.45;
  p.search.robust_push_m_s = 0.25;
  p.search.restart_after = 6;
  p.search.start_generations = 7;
  p.edits.band_gains[2][1] = 0.5;
  p.edits.styles.push_back({"tired", (test::sourceDir() / "assets" / "a.bvh").string(),
                            (dir.path() / "b.bvh").string(), 0.75});
  p.edits.secondary.push_back({"Chest", 0, true, 0.3, 2.0, 7});
  p.view.speed = 0.5;
  p.view.loop = false;
  p.view.show_grid = false;
  p.view.show_population = false;
  p.view.show_ghost = false;
  const std::filesystem::path file = dir / "walk.sinew.json";
  ASSERT_TRUE(app::saveProject(p, file).ok());
  // The rig is written relative to the project's folder, so the pair can move together.
  EXPECT_NE(test::readText(file).find("\"version\": 2"), std::string::npos);
  Result<app::Project> back = app::loadProject(file);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back.value(), p);
}

TEST(ProjectFileTest, BadProjectsNameTheFileAndTheField) {
  test::TempDir dir;
  struct Case {
    std::string json, expected;
  };
  const std::vector<Case> cases = {
      {R"({"format": "sinew.project", "version": 9, "rig": "a.bvh"})", "version: 9 is newer"},
      {R"({"format": "other", "version": 1, "rig": "a.bvh"})", "format: expected"},
      {R"({"format": "sinew.project", "version": 2})", "rig: missing"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "harmonics": 0})",
       "harmonics: must be 1..64"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "harmonics": "five"})",
       "harmonics: expected a number"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "terrain": "lava"})",
       "terrain: unknown kind 'lava'"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "search": {"trials": 12}})",
       "search.trials: must be 1..9"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "pushes": ["1,2"]})",
       "pushes '1,2': expected TIME,X,Y,Z"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "body": {"masses": ["Head"]}})",
       "--mass 'Head': expected NAME=VALUE"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "search": {"weights": {"grace": 1}}})",
       "search.weights: unknown term 'grace'"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "search": {"optimizer": "sgd"}})",
       "search.optimizer: expected"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "joint_harmonics": {"Head": -1}})",
       "joint_harmonics.Head: expected a whole number"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "view": {"speed": 9}})",
       "view.speed: must be 0.1..4"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "styles": [{"neutral": "n.bvh"}]})",
       "styles[0].neutral/styled: both clips are needed"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "styles": [{"neutral": "n.bvh", "styled": "s.bvh", "weight": 3}]})",
       "styles[0].weight: must be -1..2"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "secondary": [{"joint": "Chest", "kind": "wobble"}]})",
       "secondary[0].kind: expected"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "band_gains": {"gait": {"tail": 1}}})",
       "band_gains.gait: unknown group 'tail'"},
      {R"({"format": "sinew.project", "version": 2, "rig": )", "not JSON"},
      // project_fuzz's first finding: a number past double's range escaped as an exception.
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "window_s": 1e603})",
       "not JSON: [json.exception.out_of_range.406] number overflow"},
      {R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "rig_encoding": "koi8"})",
       "rig_encoding: expected \"latin1\""},
      {R"({"format": "sinew.project", "version": 2, "rig": "\u20ac.bvh", "rig_encoding": "latin1"})",
       "rig: not Latin-1 text"},
  };
  for (const Case& c : cases) {
    const std::filesystem::path file = dir / "bad.sinew.json";
    test::writeText(file, c.json);
    Result<app::Project> project = app::loadProject(file);
    ASSERT_FALSE(project.ok()) << c.json;
    EXPECT_NE(project.message().find(file.string() + ": "), std::string::npos) << project.message();
    EXPECT_NE(project.message().find(c.expected), std::string::npos)
        << "expected '" << c.expected << "' in: " << project.message();
  }
}

TEST(ProjectFileTest, AFailedSaveKeepsThePreviousFile) {
  test::TempDir dir;
  const std::filesystem::path file = dir / "keep.sinew.json";
  test::writeText(file, "previous contents");
  app::Project p;
  p.rig = "walk.bvh";
  p.physics.terrain.kind = physics::TerrainSettings::Kind::kSlope;
  p.physics.terrain.slope_deg = 80.0;  // does not validate: nothing is written
  const Status saved = app::saveProject(p, file);
  ASSERT_FALSE(saved.ok());
  EXPECT_NE(saved.message().find("terrain: terrain.slope_deg"), std::string::npos)
      << saved.message();
  EXPECT_EQ(test::readText(file), "previous contents");
  // A folder that cannot be written: refused with the path, the old file untouched elsewhere.
  p.physics.terrain = physics::TerrainSettings();
  EXPECT_FALSE(app::saveProject(p, dir / "no" / "such" / "folder" / "x.sinew.json").ok());
}

TEST(HistoryTest, RecordsStepsUndoesAndRedoesThemAndForgetsRedoOnANewChange) {
  editor::History history;
  app::Project a;
  a.rig = "walk.bvh";
  history.reset(a);
  EXPECT_FALSE(history.record(a));  // nothing changed
  app::Project b = a;
  b.joint_k["LeftUpLeg"] = 3;
  EXPECT_TRUE(history.record(b));
  app::Project c = b;
  c.search.weights.fall = 4.0;
  EXPECT_TRUE(history.record(c));
  EXPECT_EQ(history.undoLabel(), "weight fall 10 -> 4");
  std::optional<editor::History::Step> step = history.undo();
  ASSERT_TRUE(step);
  EXPECT_EQ(step->value, b);
  EXPECT_EQ(step->what, "weight fall 10 -> 4");
  step = history.undo();
  ASSERT_TRUE(step);
  EXPECT_EQ(step->value, a);
  EXPECT_EQ(step->what, "K of LeftUpLeg 5 -> 3");
  EXPECT_FALSE(history.undo());
  step = history.redo();
  ASSERT_TRUE(step);
  EXPECT_EQ(step->value, b);
  app::Project d = b;
  d.view.show_grid = false;
  EXPECT_TRUE(history.record(d));
  EXPECT_FALSE(history.canRedo());  // a new change after undo drops the redo branch
  EXPECT_EQ(history.undoLabel(), "grid off");
}

TEST(HistoryTest, KeepsAtMostItsLimit) {
  editor::History history(3);
  app::Project p;
  history.reset(p);
  for (int seed = 2; seed <= 10; ++seed) {
    p.search.seed = static_cast<std::uint64_t>(seed);
    history.record(p);
  }
  int undone = 0;
  while (history.undo()) ++undone;
  EXPECT_EQ(undone, 3);
  EXPECT_EQ(history.current().search.seed, 7u);
}

class EditorModelTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(editor::openProject(state, defaultProject()));
    ASSERT_TRUE(state.analysis);
  }
  // A search of `generations` on the open clip, population 6, a `window_s` window, polled to its
  // end (at most a minute) as the editor's frames would.
  void runSearch(double window_s, int generations) {
    state.evolution.settings.physics.window_s = window_s;
    state.evolution.settings.search.population = 6;
    ASSERT_TRUE(editor::startEvolution(state, generations));
    for (int i = 0; i < 1200 && !search::ended(editor::evolutionState(state)); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      editor::pollEvolution(state);
    }
    editor::pollEvolution(state);
  }
  editor::EditorState state;
};

TEST_F(EditorModelTest, OpeningTheDefaultProjectLeavesNoUnsavedChanges) {
  EXPECT_EQ(state.project_path, defaultProject());
  EXPECT_FALSE(editor::hasUnsavedChanges(state));
  EXPECT_FALSE(state.history.canUndo());
  const app::Project now = editor::captureProject(state);
  EXPECT_EQ(now.harmonics, 5);
  EXPECT_TRUE(now.joint_k.empty());
}

TEST_F(EditorModelTest, UndoAndRedoRestoreTheModelAndItsError) {
  const double error_k5 = state.analysis->total.rot_err_deg_rms;
  const int leg = jointIndex(state, "LeftUpLeg");
  ASSERT_GE(leg, 0);
  std::vector<int> k = state.analysis->joint_k;
  k[static_cast<size_t>(leg)] = 1;
  editor::setJointK(state, k);
  editor::recordHistory(state);
  const double error_k1 = state.analysis->total.rot_err_deg_rms;
  EXPECT_GT(error_k1, error_k5 + 0.05);  // the thigh with one harmonic is visibly worse
  EXPECT_TRUE(editor::hasUnsavedChanges(state));
  EXPECT_EQ(state.history.undoLabel(), "K of LeftUpLeg 5 -> 1");

  ASSERT_TRUE(editor::undo(state));
  EXPECT_EQ(state.analysis->joint_k[static_cast<size_t>(leg)], 5);
  EXPECT_DOUBLE_EQ(state.analysis->total.rot_err_deg_rms, error_k5);
  EXPECT_FALSE(editor::hasUnsavedChanges(state));
  EXPECT_EQ(state.log.lines().back().text, "undo: K of LeftUpLeg 5 -> 1");

  ASSERT_TRUE(editor::redo(state));
  EXPECT_EQ(state.analysis->joint_k[static_cast<size_t>(leg)], 1);
  EXPECT_DOUBLE_EQ(state.analysis->total.rot_err_deg_rms, error_k1);
  editor::recordHistory(state);  // the main loop's next frame: applying a step is not a new step
  EXPECT_TRUE(state.history.canRedo() == false && state.history.canUndo());
}

TEST_F(EditorModelTest, EverySettingIsOneUndoStepAndADragIsOne) {
  // Several changes between two records (a slider dragged over many frames) are one step.
  state.evolution.settings.search.weights.tracking = 1.0;
  state.evolution.settings.search.weights.tracking = 2.0;
  state.evolution.settings.search.weights.tracking = 3.0;
  editor::recordHistory(state);
  state.view.show_grid = false;
  editor::recordHistory(state);
  state.playback.speed = 0.25;
  editor::recordHistory(state);
  state.evolution.settings.physics.terrain = terrainOf("steps:0.05,0.6");
  editor::recordHistory(state);
  state.evolution.settings.physics.pushes.push_back(pushOf("1,-40,0,0"));
  editor::recordHistory(state);
  state.evolution.settings.search.optimizer = search::OptimizerKind::kGa;
  editor::recordHistory(state);
  // Playback position and play/pause are not settings: no step.
  state.playback.time_s = 1.0;
  state.playback.playing = false;
  editor::recordHistory(state);

  std::vector<std::string> undone;
  while (state.history.canUndo()) {
    undone.push_back(state.history.undoLabel());
    ASSERT_TRUE(editor::undo(state));
  }
  EXPECT_EQ(undone,
            (std::vector<std::string>{"optimizer ga", "pushes", "terrain steps:0.05,0.6",
                                      "speed 0.25x", "grid off", "weight tracking 10 -> 3"}));
  EXPECT_EQ(state.evolution.settings.search.weights.tracking, 10.0);
  EXPECT_TRUE(state.view.show_grid);
  EXPECT_EQ(state.playback.speed, 1.0);
  EXPECT_EQ(app::terrainText(state.evolution.settings.physics.terrain), "flat");
  EXPECT_TRUE(state.evolution.settings.physics.pushes.empty());
  EXPECT_EQ(state.evolution.settings.search.optimizer, search::OptimizerKind::kCmaes);
  EXPECT_FALSE(editor::hasUnsavedChanges(state));
}

TEST_F(EditorModelTest, ASavedProjectReopensAsItWasLeft) {
  test::TempDir dir;
  const int head = jointIndex(state, "Head");
  std::vector<int> k = state.analysis->joint_k;
  k[static_cast<size_t>(head)] = 2;
  editor::setJointK(state, k);
  state.evolution.settings.search.weights.energy = 0.01;
  state.evolution.settings.physics.terrain = terrainOf("slope:2");
  state.evolution.settings.physics.window_s = 6.0;
  state.view.model_beside = false;
  const double error = state.analysis->total.rot_err_deg_rms;
  const std::filesystem::path file = dir / "mine.sinew.json";
  ASSERT_TRUE(editor::saveProjectAs(state, file));
  EXPECT_FALSE(editor::hasUnsavedChanges(state));
  EXPECT_EQ(state.recent_files.front(), file.string());

  editor::EditorState reopened;
  ASSERT_TRUE(editor::openProject(reopened, file));
  EXPECT_EQ(editor::captureProject(reopened), editor::captureProject(state));
  EXPECT_EQ(reopened.analysis->joint_k, k);
  EXPECT_DOUBLE_EQ(reopened.analysis->total.rot_err_deg_rms, error);
  EXPECT_EQ(app::terrainText(reopened.evolution.settings.physics.terrain), "slope:2");
  EXPECT_FALSE(reopened.view.model_beside);
  EXPECT_FALSE(editor::hasUnsavedChanges(reopened));
}

TEST_F(EditorModelTest, ABrokenProjectChangesNothingAndIsNamedInTheLog) {
  test::TempDir dir;
  const std::filesystem::path file = dir / "broken.sinew.json";
  test::writeText(
      file, R"({"format": "sinew.project", "version": 2, "rig": "walk.bvh", "window_s": 0.1})");
  const app::Project before = editor::captureProject(state);
  EXPECT_FALSE(editor::openProject(state, file));
  EXPECT_EQ(editor::captureProject(state), before);
  EXPECT_EQ(state.project_path, defaultProject());
  EXPECT_EQ(state.log.lines().back().level, editor::LogLevel::kError);
  EXPECT_NE(state.log.lines().back().text.find(file.string() + ": window_s"), std::string::npos)
      << state.log.lines().back().text;
  // A project whose rig is missing: the open fails, the state stays.
  test::writeText(file, R"({"format": "sinew.project", "version": 2, "rig": "missing.bvh"})");
  EXPECT_FALSE(editor::openProject(state, file));
  EXPECT_EQ(editor::captureProject(state), before);
}

TEST_F(EditorModelTest, TheSearchUsesTheProjectsPhysics) {
  editor::EvolutionSettings& settings = state.evolution.settings;
  settings.physics.terrain = terrainOf("slope:2");
  settings.physics.pushes = {pushOf("0.5,-20,0,0")};
  settings.physics.body.masses = {{"Head", 9.0}};
  settings.physics.window_s = 2.0;
  settings.search.minutes = 0.05;
  settings.search.optimizer = search::OptimizerKind::kGa;
  ASSERT_TRUE(editor::startEvolution(state));
  const search::Problem& problem = state.evolution.session->problem();
  EXPECT_EQ(problem.simulation.world.terrain.kind, physics::TerrainSettings::Kind::kSlope);
  EXPECT_EQ(problem.simulation.world.terrain.slope_deg, 2.0);
  ASSERT_EQ(problem.simulation.pushes.size(), 1u);
  EXPECT_EQ(problem.simulation.pushes[0].impulse_ns.x, -20.0);
  EXPECT_EQ(state.evolution.session->settings().optimizer, search::OptimizerKind::kGa);
  editor::stopEvolution(state);
  // A bad setting is refused with its field, and nothing starts.
  settings.physics.terrain.slope_deg = 80.0;
  EXPECT_FALSE(editor::startEvolution(state));
  EXPECT_NE(state.log.lines().back().text.find("terrain: terrain.slope_deg"), std::string::npos)
      << state.log.lines().back().text;
}

TEST_F(EditorModelTest, BodyOverridesRebuildTheBodyAndUndo) {
  const physics::BodyPlan* plan = editor::bodyPlan(state);
  ASSERT_NE(plan, nullptr) << state.body_cache.error;
  const double total = plan->total_mass_kg;
  const int dofs = plan->dofCount();
  int head = -1;
  for (size_t i = 0; i < plan->links.size(); ++i)
    if (plan->links[i].name == "Head") head = static_cast<int>(i);
  ASSERT_GE(head, 0);
  const double head_kg = plan->links[static_cast<size_t>(head)].mass_kg;
  ASSERT_EQ(plan->links[static_cast<size_t>(head)].type, physics::JointType::kBall);

  editor::setBodyMass(state, "Head", 8.0);
  editor::setBodyMass(state, "Head", 9.0);  // replaces, does not add
  editor::recordHistory(state);
  editor::setBodyWelded(state, "Head", true);
  editor::recordHistory(state);
  EXPECT_EQ(state.evolution.settings.physics.body.masses,
            (std::vector<app::MassOverride>{{"Head", 9.0}}));
  plan = editor::bodyPlan(state);
  ASSERT_NE(plan, nullptr) << state.body_cache.error;
  EXPECT_NEAR(plan->total_mass_kg, total - head_kg + 9.0, 1e-9);
  EXPECT_EQ(plan->links[static_cast<size_t>(head)].type, physics::JointType::kFixed);
  EXPECT_EQ(plan->dofCount(), dofs - 3);

  ASSERT_TRUE(editor::undo(state));  // the weld
  plan = editor::bodyPlan(state);
  EXPECT_EQ(plan->dofCount(), dofs);
  ASSERT_TRUE(editor::undo(state));  // the mass
  plan = editor::bodyPlan(state);
  EXPECT_NEAR(plan->total_mass_kg, total, 1e-9);
  // A link the plan does not have: no body, and the reason names it.
  editor::setBodyMass(state, "Tail", 2.0);
  EXPECT_EQ(editor::bodyPlan(state), nullptr);
  EXPECT_NE(state.body_cache.error.find("Tail"), std::string::npos) << state.body_cache.error;
  editor::clearBodyMass(state, "Tail");
  EXPECT_NE(editor::bodyPlan(state), nullptr);
}

TEST_F(EditorModelTest, ExportWritesTheModelThatReimportsAndReloads) {
  test::TempDir dir;
  const int leg = jointIndex(state, "LeftUpLeg");
  std::vector<int> k = state.analysis->joint_k;
  k[static_cast<size_t>(leg)] = 2;
  editor::setJointK(state, k);  // the export is of the model as edited
  state.exporting.folder = (dir / "out").string();
  state.exporting.name = "walk_k2";
  state.exporting.fps = 24.0;
  state.exporting.strides = 3;
  ASSERT_TRUE(editor::exportChosen(state));
  const spectral::TargetMotion& target = state.analysis->target;
  for (const char* extension : {".bvh", ".glb"}) {
    Result<motion::MotionAsset> back =
        motion::importMotion(dir / "out" / (std::string("walk_k2") + extension));
    ASSERT_TRUE(back.ok()) << back.message();
    const motion::Clip& clip = back.value().clips.front();
    EXPECT_NEAR(clip.fps(), 24.0, 1e-6) << extension;
    // Three whole strides, the last frame repeating the first (the loop closes).
    EXPECT_NEAR((clip.frame_count - 1) / 24.0, 3.0 * target.period(), 0.5 / 24.0 * 3 + 1e-9)
        << extension;
  }
  Result<spectral::TargetMotion> coefficients =
      spectral::loadTarget(dir / "out" / "walk_k2.json", state.asset->skeleton);
  ASSERT_TRUE(coefficients.ok()) << coefficients.message();
  EXPECT_LT(spectral::harmonicDistance(coefficients.value(), target), 1e-9);
  EXPECT_NE(state.log.lines().back().text.find("3 strides"), std::string::npos);
  // Nothing chosen: refused, said why.
  state.exporting.bvh = state.exporting.gltf = state.exporting.coefficients = false;
  EXPECT_FALSE(editor::exportChosen(state));
  EXPECT_NE(state.log.lines().back().text.find("choose at least one"), std::string::npos);
  // The fittest run before any search: refused, said why.
  state.exporting.simulated = true;
  EXPECT_FALSE(editor::exportChosen(state));
  EXPECT_NE(state.log.lines().back().text.find("no generation has finished"), std::string::npos);
  state.exporting.loop = true;  // and its loop
  EXPECT_FALSE(editor::exportChosen(state));
  EXPECT_NE(state.log.lines().back().text.find("no generation has finished"), std::string::npos);
}

TEST_F(EditorModelTest, ExportWritesTheFittestRunAsALoopInPlace) {
  runSearch(4.5, 2);  // a first stride to settle and two for the loop
  if (HasFatalFailure()) return;
  ASSERT_TRUE(state.evolution.snapshot && !state.evolution.snapshot->best_point.empty());
  test::TempDir dir;
  state.exporting.folder = (dir / "out").string();
  state.exporting.simulated = true;
  state.exporting.loop = true;
  state.exporting.in_place = true;
  ASSERT_TRUE(editor::exportChosen(state)) << state.log.lines().back().text;
  EXPECT_NE(state.log.lines().back().text.find("best_loop.bvh"), std::string::npos);
  const nlohmann::json loop = nlohmann::json::parse(test::readText(dir / "out" / "loop.json"));
  EXPECT_TRUE(loop["in_place"].get<bool>());
  EXPECT_EQ(loop["strides"].get<int>(), 2);
  Result<motion::MotionAsset> back = motion::importMotion(dir / "out" / "best_loop.glb");
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back.value().clips.front().frame_count, loop["frames"].get<int>());
}

TEST_F(EditorModelTest, AClickOnAnIndividualPicksItAndTheGroundPicksNothing) {
  editor::EvolutionSettings& settings = state.evolution.settings;
  settings.physics.window_s = 1.0;
  settings.search.population = 8;
  settings.search.minutes = 1.0;
  ASSERT_TRUE(editor::startEvolution(state));
  for (int i = 0;
       i < 600 && (!state.evolution.snapshot || state.evolution.snapshot->generation < 1); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    editor::pollEvolution(state);
  }
  editor::stopEvolution(state);
  ASSERT_GE(state.evolution.snapshot->generation, 1);
  // Polling never waited for the search: a generation is published without holding the UI.
  EXPECT_EQ(state.evolution.slow_polls, 0) << state.evolution.longest_poll_wait_s << " s";
  const editor::Scene scene = editor::buildScene(state);
  ASSERT_EQ(scene.individuals.size(), 8u);  // the whole population is drawn (shown 8)
  // Each in its own lane: no two runs' footprints on the ground overlap.
  for (size_t i = 0; i < scene.individuals.size(); ++i) {
    for (size_t j = i + 1; j < scene.individuals.size(); ++j) {
      const editor::PickBox& a = scene.individuals[i];
      const editor::PickBox& b = scene.individuals[j];
      const bool apart = a.hi.x < b.lo.x || b.hi.x < a.lo.x || a.hi.z < b.lo.z || b.hi.z < a.lo.z;
      EXPECT_TRUE(apart) << "runs " << a.individual << " and " << b.individual << " overlap";
    }
  }
  editor::OrbitCamera camera;
  camera.pitch = 1.5f;  // from above, so that neighbours do not hide one another
  camera.distance = 6.0f;
  const float aspect = 1.5f;
  for (const editor::PickBox& box : scene.individuals) {
    // The camera over this individual: a click at the middle of the view picks it, a click at a
    // point projected from its box's middle too.
    camera.target = 0.5f * (box.lo + box.hi);
    EXPECT_EQ(editor::pickIndividual(scene, camera.eye(), camera.rayDirection(0.0f, 0.0f, aspect)),
              box.individual);
    const glm::vec4 clip =
        camera.projection(aspect) * camera.view() * glm::vec4(camera.target, 1.0f);
    const glm::vec3 direction = camera.rayDirection(clip.x / clip.w, clip.y / clip.w, aspect);
    EXPECT_LT(glm::length(direction - glm::normalize(camera.target - camera.eye())), 1e-3f);
  }
  // Straight up from the camera: nobody.
  EXPECT_EQ(editor::pickIndividual(scene, camera.eye(), glm::vec3(0.0f, 1.0f, 0.0f)), -1);
}

// A clip of the target itself, sampled at the simulation's clock (frame f at f x frame_time,
// `shift_s` later): what a run that tracked its target perfectly would have recorded.
motion::Clip targetAsRun(const spectral::TargetMotion& target, const motion::Clip& like,
                         double shift_s) {
  motion::Clip clip = like;
  for (int f = 0; f < clip.frame_count; ++f) {
    const size_t at = static_cast<size_t>(f) * static_cast<size_t>(clip.joint_count);
    target.pose(f * clip.frame_time + shift_s,
                std::span(clip.rotations).subspan(at, static_cast<size_t>(clip.joint_count)),
                std::span(clip.translations).subspan(at, static_cast<size_t>(clip.joint_count)));
  }
  return clip;
}

TEST_F(EditorModelTest, TheGhostMeasuresEachJointOfTheChosenRunAgainstTheTargetAtItsTime) {
  runSearch(2.0, 1);
  if (HasFatalFailure()) return;
  ASSERT_TRUE(state.evolution.snapshot && state.evolution.snapshot->generation >= 1);
  state.playback.time_s = 1.5;  // past the ramp from rest, inside the 2 s run
  const std::optional<editor::Ghost> ghost = editor::currentGhost(state);
  ASSERT_TRUE(ghost);
  EXPECT_EQ(ghost->individual, editor::chosenIndividual(state.evolution));
  const motion::Clip& run =
      state.evolution.snapshot->population_motions[static_cast<size_t>(ghost->individual)];
  EXPECT_NEAR(ghost->time_s, 1.5, run.frame_time);
  ASSERT_EQ(ghost->deviation_rad.size(), static_cast<size_t>(run.joint_count));
  for (double d : ghost->deviation_rad)
    EXPECT_TRUE(std::isfinite(d) && d >= 0.0 && d <= std::numbers::pi);
  const editor::GhostSummary simulated = editor::summarise(*ghost);
  EXPECT_GT(simulated.max_deg, 0.5);  // a simulated run never tracks its target exactly
  EXPECT_GT(simulated.mean_deg, 0.0);
  // The target against itself at the same clock: exactly zero at every joint; half a second
  // off, clearly not (so the ghost samples the target at the run's own time).
  const spectral::TargetMotion& target = state.evolution.session->problem().seed;
  const std::optional<editor::Ghost> self =
      editor::ghostAt(target, targetAsRun(target, run, 0.0), 0, ghost->frame);
  ASSERT_TRUE(self);
  for (double d : self->deviation_rad) EXPECT_EQ(d, 0.0);
  const std::optional<editor::Ghost> late =
      editor::ghostAt(target, targetAsRun(target, run, 0.5), 0, ghost->frame);
  ASSERT_TRUE(late);
  EXPECT_GT(editor::summarise(*late).max_deg, 5.0);
  // Drawn over its run, and gone with the toggle (a project setting, one undo step).
  const size_t with_ghost = editor::buildScene(state).translucent.size();
  state.evolution.show_ghost = false;
  EXPECT_FALSE(editor::currentGhost(state));
  EXPECT_GT(with_ghost, editor::buildScene(state).translucent.size());
  EXPECT_FALSE(editor::captureProject(state).view.show_ghost);
  // Bad input: another rig's run, or a frame past the recording, gives no ghost.
  motion::Clip other = run;
  other.joint_count = run.joint_count - 1;
  EXPECT_FALSE(editor::ghostAt(target, other, 0, 0));
  EXPECT_FALSE(editor::ghostAt(target, run, 0, run.frame_count));
}

TEST_F(EditorModelTest, OneSelectionIsWhatTheViewportTheGhostTheTimelineAndExportShow) {
  runSearch(1.5, 1);
  if (HasFatalFailure()) return;
  ASSERT_TRUE(state.evolution.snapshot && state.evolution.snapshot->generation >= 1);
  const search::Snapshot& snap = *state.evolution.snapshot;
  const std::vector<int> order = editor::rankedIndividuals(snap);
  ASSERT_EQ(order.size(), 6u);
  // Nothing clicked: every panel shows the generation's best.
  EXPECT_EQ(editor::chosenIndividual(state.evolution), order.front());
  EXPECT_EQ(editor::chosenRunLabel(state.evolution), "#1 of 6 (best)");
  EXPECT_EQ(editor::currentGhost(state)->individual, order.front());
  EXPECT_EQ(editor::exportedRun(state.evolution)->what, "the best so far");
  // The worst clicked (in the viewport or the list): the same one everywhere.
  const int worst = order.back();
  editor::selectIndividual(state.evolution, worst);
  EXPECT_EQ(editor::chosenIndividual(state.evolution), worst);
  EXPECT_EQ(editor::individualRank(snap, worst), 6);
  EXPECT_EQ(editor::chosenRunLabel(state.evolution), "#6 of 6 (clicked)");
  EXPECT_EQ(editor::currentGhost(state)->individual, worst);
  const editor::Scene scene = editor::buildScene(state);
  EXPECT_EQ(scene.individuals.back().individual, worst);  // drawn, last lane
  const std::optional<editor::ExportedRun> run = editor::exportedRun(state.evolution);
  ASSERT_TRUE(run);
  EXPECT_EQ(run->point, snap.population[static_cast<size_t>(worst)]);
  test::TempDir dir;
  state.exporting.folder = (dir / "out").string();
  state.exporting.simulated = true;
  ASSERT_TRUE(editor::exportChosen(state)) << state.log.lines().back().text;
  const std::filesystem::path written = editor::exportedRun(state.evolution)->dir;
  EXPECT_EQ(written.parent_path(), dir / "out");  // its own folder, not passing for the best
  const nlohmann::json best = nlohmann::json::parse(test::readText(written / "best.json"));
  EXPECT_DOUBLE_EQ(best["fitness"]["total"].get<double>(),
                   snap.population_terms[static_cast<size_t>(worst)].total);
  // An index the snapshot does not have (bad input) goes back to the best.
  editor::selectIndividual(state.evolution, 99);
  EXPECT_EQ(state.evolution.selected, -1);
  EXPECT_EQ(editor::chosenIndividual(state.evolution), order.front());
}

TEST_F(EditorModelTest, ThePopulationFieldShowsWhatTheSearchWillUseAndGenerationsBoundIt) {
  // 0 is "the optimiser's default": resolved to the number the search takes (CMA-ES 4 + 3 ln n).
  editor::resolvePopulation(state);
  const int n = state.evolution.resolved_coordinates;
  ASSERT_GT(n, 0);
  EXPECT_EQ(state.evolution.resolved_population,
            4 + static_cast<int>(std::floor(3.0 * std::log(static_cast<double>(n)))));
  state.evolution.settings.generations = 3;  // beside the minutes: whichever ends first
  ASSERT_TRUE(editor::startEvolution(state));
  EXPECT_EQ(state.evolution.session->population(), state.evolution.resolved_population);
  EXPECT_EQ(state.evolution.session->settings().generations, 3);
  EXPECT_GT(state.evolution.session->settings().minutes, 0.0);
  editor::stopEvolution(state);
  // A K change is another search: fewer coefficients, re-resolved.
  editor::setJointK(state, std::vector<int>(state.analysis->joint_k.size(), 1));
  editor::resolvePopulation(state);
  EXPECT_LT(state.evolution.resolved_coordinates, n);
}

TEST_F(EditorModelTest, AutoKMeetsItsToleranceWithFewerCoefficientsAndTheRankingPutsTheHipsHigh) {
  const int before = [&] {
    int n = 0;
    for (int k : state.analysis->joint_k) n += k;
    return n;
  }();
  ASSERT_TRUE(editor::setAutoK(state, 1.0));
  EXPECT_LE(state.analysis->total.pos_err_cm_max, 1.0);
  int after = 0;
  for (int k : state.analysis->joint_k) after += k;
  EXPECT_LT(after, before);
  EXPECT_TRUE(state.history.record(editor::captureProject(state)));  // an undoable change
  const spectral::ImportanceReport* report = editor::rankJoints(state);
  ASSERT_NE(report, nullptr);
  ASSERT_GE(report->joints.size(), 3u);
  for (size_t i = 1; i < report->joints.size(); ++i)
    EXPECT_GE(report->joints[i - 1].frozen_cm_mean, report->joints[i].frozen_cm_mean);
  // Freezing a thigh costs the walk more than freezing the head.
  auto cost = [&](const std::string& name) {
    for (const spectral::JointImportance& j : report->joints)
      if (state.asset->skeleton.names[static_cast<size_t>(j.joint)] == name)
        return j.frozen_cm_mean;
    return -1.0;
  };
  EXPECT_GT(cost("LeftUpLeg"), cost("Head"));
  EXPECT_EQ(editor::rankJoints(state), report);  // cached
}

TEST_F(EditorModelTest, BandGainsEditTheModelAndUndoRestoresIt) {
  const spectral::TargetMotion model = state.analysis->model;
  EXPECT_LT(spectral::harmonicDistance(state.analysis->target, model), 1e-12);  // no edits
  for (int g = 0; g < app::kGroupCount; ++g)
    state.edits.band_gains[2][static_cast<size_t>(g)] = 0.0;
  editor::recordHistory(state);
  ASSERT_TRUE(editor::applyEdits(state));
  double detail = 0.0, gait = 0.0, gait_model = 0.0;
  for (size_t c = 0; c < state.analysis->target.channels.size(); ++c) {
    for (const spectral::Harmonic& h : state.analysis->target.channels[c].terms) {
      if (h.n >= 6) detail += h.amplitude;
      if (h.n <= 2) gait += h.amplitude;
    }
    for (const spectral::Harmonic& h : model.channels[c].terms)
      if (h.n <= 2) gait_model += h.amplitude;
  }
  EXPECT_EQ(detail, 0.0);
  EXPECT_NEAR(gait, gait_model, 1e-12);
  ASSERT_TRUE(editor::undo(state));
  editor::applyEdits(state);
  EXPECT_LT(spectral::harmonicDistance(state.analysis->target, model), 1e-12);
}

TEST(EditorStyleTest, TheTiredStyleSlowsTheNormalWalkAndWeightZeroChangesNothing) {
  SINEW_REQUIRE_SHARED_DATA();
  const auto bvh = test::sharedData() / "bvh";
  editor::EditorState state;
  ASSERT_TRUE(editor::openAny(state, bvh / "bandai_dataset-1_walk_normal_001.bvh"));
  const spectral::TargetMotion model = state.analysis->model;
  ASSERT_TRUE(editor::addStyle(state, (bvh / "bandai_dataset-1_walk_normal_001.bvh").string(),
                               (bvh / "bandai_dataset-1_walk_tired_001.bvh").string()));
  ASSERT_EQ(state.edits.styles.size(), 1u);
  EXPECT_EQ(state.edits.styles[0].label, "bandai_dataset-1_walk_tired_001");
  // The tired walk is slower: its stride is the model's stretched by the pair's tempo ratio
  // (the strides of the two clips: about 1.09 s and 1.22 s).
  const Result<spectral::StyleVector>& style = editor::styleOf(state, state.edits.styles[0]);
  ASSERT_TRUE(style.ok());
  const double tempo = std::exp(style.value().log_tempo);  // omega_styled / omega_neutral
  EXPECT_LT(tempo, 0.92);
  EXPECT_NEAR(model.period(), 1.075, 0.01);
  EXPECT_NEAR(state.analysis->target.period(), model.period() / tempo, 1e-6);
  EXPECT_GT(spectral::poseDistanceDeg(state.analysis->target, model), 1.0);
  state.edits.styles[0].weight = 0.0;
  editor::applyEdits(state);
  EXPECT_LT(spectral::poseDistanceDeg(state.analysis->target, model), 1e-9);
  // A pair from another skeleton is refused and named.
  EXPECT_FALSE(editor::addStyle(state, (bvh / "cmu_131_01.bvh").string(),
                                (bvh / "bandai_dataset-1_walk_tired_001.bvh").string()));
  EXPECT_NE(
      state.log.lines().back().text.find("cmu_131_01.bvh: its skeleton is not the open clip's"),
      std::string::npos)
      << state.log.lines().back().text;
  EXPECT_EQ(state.edits.styles.size(), 1u);
}

TEST_F(EditorModelTest, TheRecoveryFileIsTheCurrentProject) {
  test::TempDir dir;
  state.evolution.settings.search.seed = 77;
  const std::filesystem::path file = dir / "recovery.sinew.json";
  ASSERT_TRUE(editor::writeRecovery(state, file).ok());
  Result<app::Project> recovered = app::loadProject(file);
  ASSERT_TRUE(recovered.ok()) << recovered.message();
  EXPECT_EQ(recovered.value(), editor::captureProject(state));
}

TEST(PathCompletionTest, ListsFoldersAndMotionFilesThatStartWithTheTypedName) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "walks");
  std::filesystem::create_directories(dir / ".hidden");
  for (const char* name : {"walk.bvh", "wave.GLB", "wall.txt", "run.bvh", "walk.sinew.json"})
    test::writeText(dir / name, "x");
  const std::string base = dir.path().string() + "/";
  EXPECT_EQ(editor::completePath(base + "wa"),
            (std::vector<std::string>{base + "walk.bvh", base + "walk.sinew.json", base + "walks/",
                                      base + "wave.GLB"}));
  EXPECT_EQ(editor::commonStart(editor::completePath(base + "wa")), base + "wa");
  EXPECT_EQ(editor::completePath(base + "r"), std::vector<std::string>{base + "run.bvh"});
  EXPECT_EQ(editor::completePath(base + "."), std::vector<std::string>{base + ".hidden/"});
  EXPECT_TRUE(editor::completePath(base + "nothing").empty());
  EXPECT_TRUE(editor::completePath(base + "no/such/folder/x").empty());
  EXPECT_EQ(editor::commonStart({"abc", "abd"}), "ab");
}

TEST(PreferencesTest, RoundTripAndDefaultsAndBrokenFiles) {
  test::TempDir dir;
  const std::filesystem::path file = dir / "sub" / "editor.json";
  Result<editor::Preferences> missing = editor::loadPreferences(file);
  ASSERT_TRUE(missing.ok());
  EXPECT_EQ(missing.value(), editor::Preferences());
  editor::Preferences p;
  p.recent_files = {"/a/walk.bvh", "/b/run.sinew.json"};
  p.layout.left_width = 300.0f;
  p.layout.spectrum_fraction = 0.5f;
  p.window_width = 1280;
  p.window_height = 720;
  ASSERT_TRUE(editor::savePreferences(p, file).ok());
  Result<editor::Preferences> back = editor::loadPreferences(file);
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back.value(), p);
  test::writeText(file, R"({"window_width": "wide"})");
  Result<editor::Preferences> broken = editor::loadPreferences(file);
  ASSERT_FALSE(broken.ok());
  EXPECT_NE(broken.message().find(file.string()), std::string::npos);
}

}  // namespace
}  // namespace sinew
