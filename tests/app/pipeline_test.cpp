// One pipeline from a project to a search (sinew/pipeline): the command line and the editor's
// model build the same Problem from the same project and reach the same best cost; unknown
// project keys are named; K per joint by name fails the same way in both.
#include <chrono>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "editor/editor_state.h"
#include "editor/evolution.h"
#include "editor/project_model.h"
#include "project/project.h"
#include "sinew/motion/asset.h"
#include "sinew/pipeline/pipeline.h"
#include "sinew/spectral/target_io.h"
#include "support/test_support.h"

namespace sinew {
namespace {

// A small project that sets something in every stage: K per joint, a band gain, terrain, a
// push, a body override, the population and the seed.
std::filesystem::path writeProject(const test::TempDir& dir) {
  const std::filesystem::path file = dir / "small.sinew.json";
  const nlohmann::json project = {
      {"format", "sinew.project"},
      {"version", 2},
      {"rig", (test::sourceDir() / "assets" / "biped_walk.bvh").string()},
      {"harmonics", 4},
      {"joint_harmonics", {{"LeftUpLeg", 6}}},
      {"band_gains", {{"gait", {{"legs", 1.2}}}}},
      {"terrain", "slope:2"},
      {"window_s", 1.0},
      {"pushes", {"0.5,-20,0,0"}},
      {"body", {{"masses", {"Head=6"}}}},
      {"search", {{"population", 6}, {"seed", 3}}}};
  test::writeText(file, project.dump(2));
  return file;
}

std::string coefficients(const spectral::TargetMotion& target, const motion::Skeleton& skeleton) {
  return spectral::targetToJson(target, skeleton);
}

TEST(PipelineTest, TheCommandLineAndTheEditorBuildTheSameProblemAndReachTheSameCost) {
  test::TempDir dir;
  const std::filesystem::path file = writeProject(dir);

  // The command line's path: the project's settings, the rig, the engine's prepareSearch.
  Result<app::Project> project = app::loadProject(file);
  ASSERT_TRUE(project.ok()) << project.message();
  Result<motion::MotionAsset> rig = motion::importMotion(project.value().rig);
  ASSERT_TRUE(rig.ok()) << rig.message();
  Result<pipeline::SearchSetup> setup =
      pipeline::prepareSearch(rig.value().skeleton, rig.value().clips.front(), project.value());
  ASSERT_TRUE(setup.ok()) << setup.message();
  const search::Problem& cli = setup.value().problem;

  // The editor model's path: open the project, press Start (two generations).
  editor::EditorState state;
  ASSERT_TRUE(editor::openProject(state, file));
  ASSERT_TRUE(editor::startEvolution(state, 2));
  const search::Problem& ed = state.evolution.session->problem();
  const motion::Skeleton& skeleton = rig.value().skeleton;

  ASSERT_EQ(ed.layout.size(), cli.layout.size());
  EXPECT_GT(cli.layout.size(), 50);
  EXPECT_EQ(ed.layout.names(), cli.layout.names());
  EXPECT_EQ(coefficients(ed.seed, skeleton), coefficients(cli.seed, skeleton));
  // The bounds: the controllers at the corners and the middle of the normalised box.
  for (double x : {0.0, 0.5, 1.0}) {
    const std::vector<double> point(static_cast<size_t>(cli.layout.size()), x);
    EXPECT_EQ(coefficients(ed.layout.decodeTarget(point), skeleton),
              coefficients(cli.layout.decodeTarget(point), skeleton))
        << x;
    physics::BalanceGains a = ed.layout.decodeGains(point), b = cli.layout.decodeGains(point);
    for (int g = 0; g < physics::kBalanceGainCount; ++g)
      EXPECT_EQ(physics::balanceGain(a, g), physics::balanceGain(b, g)) << physics::balanceGainName(g);
  }
  EXPECT_EQ(ed.layout.startPoint(3), cli.layout.startPoint(3));
  EXPECT_EQ(ed.simulation.seconds, 1.0);
  EXPECT_EQ(ed.simulation.world.terrain.slope_deg, cli.simulation.world.terrain.slope_deg);
  ASSERT_EQ(ed.simulation.pushes.size(), 1u);
  EXPECT_EQ(ed.simulation.pushes[0].impulse_ns, cli.simulation.pushes[0].impulse_ns);
  EXPECT_EQ(ed.plan.total_mass_kg, cli.plan.total_mass_kg);
  EXPECT_TRUE(ed.weights == cli.weights);
  EXPECT_EQ(ed.reference_speed_m_s, cli.reference_speed_m_s);

  // Two generations with the project's seed: the same best cost as `sinew evolve`, and the same
  // best.json.
  for (int i = 0; i < 1200 && !search::ended(editor::evolutionState(state)); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    editor::pollEvolution(state);
  }
  editor::pollEvolution(state);
  ASSERT_EQ(state.evolution.snapshot->generation, 2);
  const std::filesystem::path from_editor = dir / "editor";
  ASSERT_TRUE(editor::exportEvolutionResults(state, from_editor));
  const std::filesystem::path from_cli = dir / "cli";
  const test::CommandResult run = test::runSinew("evolve " + test::quote(file) +
                                                 " --generations 2 --out " + test::quote(from_cli));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // The project's band gain edits the model: the joint lines say what was tracked.
  EXPECT_NE(run.out.find("furthest from the edited clip: "), std::string::npos) << run.out;
  const nlohmann::json best = nlohmann::json::parse(test::readText(from_cli / "best.json"));
  EXPECT_EQ(best.at("fitness").at("total").get<double>(),
            state.evolution.snapshot->best_terms.total);
  EXPECT_EQ(test::readText(from_editor / "best.json"), test::readText(from_cli / "best.json"));
  for (const char* name : {"best.bvh", "best.glb", "history.csv", "checkpoint.json"})
    EXPECT_TRUE(std::filesystem::exists(from_editor / name)) << name;
}

TEST(PipelineTest, TheTrackedMotionIsNamedAsTheSearchBuildsIt) {
  pipeline::ProjectSettings settings;
  EXPECT_STREQ(pipeline::trackedName(settings), "the clip");
  settings.edits.band_gains[0][1] = 1.2;
  EXPECT_STREQ(pipeline::trackedName(settings), "the edited clip");
  settings.edits = {};
  settings.edits.styles.push_back({});
  EXPECT_STREQ(pipeline::trackedName(settings), "the edited clip");
  settings.target = "tired.json";  // tracked as it is, edits or not (pipeline::trackedMotion)
  EXPECT_STREQ(pipeline::trackedName(settings), "the coefficients");
}

TEST(PipelineTest, KPerJointByAnUnknownNameIsAnErrorNamingItInBothPaths) {
  Result<motion::MotionAsset> rig =
      motion::importMotion(test::sourceDir() / "assets" / "biped_walk.bvh");
  ASSERT_TRUE(rig.ok()) << rig.message();
  Result<std::vector<int>> k =
      pipeline::resolveJointK(rig.value().skeleton, 5, {{"Tail", 1}}, "walk.bvh");
  ASSERT_FALSE(k.ok());
  EXPECT_NE(k.message().find("joint_harmonics: walk.bvh has no joint called 'Tail'"),
            std::string::npos)
      << k.message();
  Result<std::vector<int>> known =
      pipeline::resolveJointK(rig.value().skeleton, 5, {{"Head", 2}}, "walk.bvh");
  ASSERT_TRUE(known.ok());
  EXPECT_EQ(known.value()[static_cast<size_t>(rig.value().skeleton.findJoint("Head"))], 2);
  EXPECT_EQ(known.value()[0], 5);

  test::TempDir dir;
  const std::filesystem::path file = dir / "tail.sinew.json";
  test::writeText(
      file, nlohmann::json({{"format", "sinew.project"},
                            {"version", 2},
                            {"rig", (test::sourceDir() / "assets" / "biped_walk.bvh").string()},
                            {"joint_harmonics", {{"Tail", 1}}}})
                .dump());
  editor::EditorState state;
  editor::openProject(state, file);
  bool named = false;
  for (const editor::LogLine& line : state.log.lines())
    named = named || (line.level == editor::LogLevel::kError &&
                      line.text.find("no joint called 'Tail'") != std::string::npos);
  EXPECT_TRUE(named);
}

TEST(PipelineTest, UnknownProjectKeysAreWarnedNamingTheKeyAndTheFile) {
  std::vector<std::string> warnings;
  Result<app::Project> project = app::parseProject(
      R"({"format": "sinew.project", "version": 2, "rig": "a.bvh", "colour": "red",
          "windw_s": 4, "search": {"seed": 2, "speed": 3}, "view": {"zoom": 1}})",
      "/tmp", "mine.sinew.json", &warnings);
  ASSERT_TRUE(project.ok()) << project.message();
  EXPECT_EQ(project.value().search.seed, 2u);
  EXPECT_EQ(project.value().physics.window_s, 10.0);  // a misspelt key sets nothing
  const std::vector<std::string> expected = {
      "mine.sinew.json: unknown key 'colour' (ignored)",
      "mine.sinew.json: unknown key 'windw_s' (ignored)",
      "mine.sinew.json: unknown key 'search.speed' (ignored)",
      "mine.sinew.json: unknown key 'view.zoom' (ignored)"};
  EXPECT_EQ(warnings, expected);
}

TEST(PipelineTest, TerrainPushesAndBodyOverridesReadBackAsTheyAreWritten) {
  for (const char* text : {"flat", "slope:-3.5", "steps:0.05,0.6", "rough:0.02,7"}) {
    Result<physics::TerrainSettings> terrain = app::parseTerrain(text);
    ASSERT_TRUE(terrain.ok()) << terrain.message();
    EXPECT_EQ(app::terrainText(terrain.value()), text);
  }
  for (const char* text : {"1.5,-30,0,0,Spine", "3,0,0,20", "0.25,1e-05,2,3"}) {
    Result<physics::Push> push = app::parsePush(text);
    ASSERT_TRUE(push.ok()) << push.message();
    EXPECT_EQ(app::pushText(push.value()), text);
  }
  Result<app::BodyOverrides> body =
      app::parseBodyOverrides({"Head=6.5"}, {"LeftToe"}, {"LeftLeg=-150,5"});
  ASSERT_TRUE(body.ok()) << body.message();
  EXPECT_EQ(app::massText(body.value().masses[0]), "Head=6.5");
  EXPECT_EQ(app::hingeLimitText(body.value().hinge_limits[0]), "LeftLeg=-150,5");
  Result<app::BodyOverrides> light = app::parseBodyOverrides({"Head=-1"}, {}, {});
  ASSERT_FALSE(light.ok());
  EXPECT_NE(light.message().find("Head must be > 0 kg"), std::string::npos) << light.message();
}

}  // namespace
}  // namespace sinew
