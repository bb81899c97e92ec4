// Style through physics, exported as a clean loop (issue 15), on the bundled walk and a synthetic
// "tired" made from it: the style measures (amount along a pair, harmonic distance of a run), the
// physical loop of a simulated run (seam, planted feet, in place), and `sinew evolve --style` at
// weights 0 and 1 (the measured style moves the right way; the written loop re-imports and loops).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sinew/core/rotation.h"
#include "sinew/motion/anatomy.h"
#include "sinew/motion/asset.h"
#include "sinew/physics/simulation.h"
#include "sinew/pipeline/physical_loop.h"
#include "sinew/pipeline/pipeline.h"
#include "sinew/search/controller_io.h"
#include "sinew/search/session.h"
#include "sinew/spectral/style.h"
#include "support/test_support.h"

namespace sinew {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::filesystem::path walkPath() {
  return test::sourceDir() / "assets" / "biped_walk.bvh";
}

motion::MotionAsset walk() {
  Result<motion::MotionAsset> asset = motion::importMotion(walkPath());
  EXPECT_TRUE(asset.ok()) << asset.message();
  return std::move(asset).value();
}

// A tired walk made from the bundled one: the trunk bent forward 5 degrees at each of four
// joints, the arms swinging at 60%, the stride 7% slower.
spectral::TargetMotion tiredOf(const motion::Skeleton& skeleton, spectral::TargetMotion target) {
  for (const char* name : {"Spine", "Spine1", "Chest", "Neck"}) {
    const int j = skeleton.findJoint(name);
    target.base_rotations[j] =
        target.base_rotations[j] * glm::angleAxis(5.0 * kDeg, glm::dvec3(1.0, 0.0, 0.0));
  }
  for (spectral::ChannelModel& channel : target.channels) {
    const std::string& name = skeleton.names[channel.joint];
    if (name.find("Arm") == std::string::npos || channel.kind != spectral::SignalKind::kRotation)
      continue;
    for (spectral::Harmonic& h : channel.terms) h.amplitude *= 0.6;
  }
  target.omega0 *= 0.93;
  target.name = "tired";
  return target;
}

// The tired walk written as a clip (4 strides at 30 fps), the style pair's styled file.
std::filesystem::path writeTired(const test::TempDir& dir) {
  const motion::MotionAsset asset = walk();
  Result<spectral::TargetMotion> neutral =
      pipeline::styleTarget(asset.skeleton, asset.clips.front(), "biped_walk");
  EXPECT_TRUE(neutral.ok()) << neutral.message();
  const std::filesystem::path path = dir / "tired.bvh";
  const Status written = motion::exportMotion(
      path, asset, tiredOf(asset.skeleton, neutral.value()).sample(30.0, 4));
  EXPECT_TRUE(written.ok()) << written.message();
  return path;
}

TEST(StyleAmount, ThePairsEndsAreZeroAndOneAndAHalfStyleIsHalfway) {
  test::TempDir dir;
  const motion::MotionAsset asset = walk();
  const std::filesystem::path tired_path = writeTired(dir);
  Result<spectral::TargetMotion> neutral =
      pipeline::styleClipTarget(walkPath().string(), asset.skeleton);
  Result<spectral::TargetMotion> tired = pipeline::styleClipTarget(tired_path.string(), asset.skeleton);
  ASSERT_TRUE(neutral.ok() && tired.ok()) << neutral.message() << tired.message();
  Result<spectral::StyleVector> style = spectral::measureStyle(neutral.value(), tired.value(), "tired");
  ASSERT_TRUE(style.ok()) << style.message();
  Result<spectral::TargetMotion> half = spectral::applyStyles(neutral.value(), {{&style.value(), 0.5}});
  ASSERT_TRUE(half.ok()) << half.message();
  const auto amount = [&](const spectral::TargetMotion& m) {
    return spectral::styleAmount(asset.skeleton, m, neutral.value(), tired.value());
  };
  EXPECT_NEAR(amount(neutral.value()), 0.0, 1e-9);
  EXPECT_NEAR(amount(tired.value()), 1.0, 1e-9);
  EXPECT_NEAR(amount(half.value()), 0.5, 0.1);
}

TEST(RunStyleDistance, ATargetsOwnClipIsNearItAndAnotherStyleIsFar) {
  const motion::MotionAsset asset = walk();
  Result<spectral::TargetMotion> neutral =
      pipeline::styleTarget(asset.skeleton, asset.clips.front(), "biped_walk");
  ASSERT_TRUE(neutral.ok()) << neutral.message();
  const spectral::TargetMotion tired = tiredOf(asset.skeleton, neutral.value());
  const motion::Clip own = neutral.value().sample(30.0, 5);
  const double omega = neutral.value().omega0;
  const double near = spectral::runStyleDistance(asset.skeleton, own, neutral.value(), omega, 1.0);
  const double far = spectral::runStyleDistance(asset.skeleton, tired.sample(30.0, 5),
                                                neutral.value(), tired.omega0, 1.0);
  std::printf("style distance: own clip %.4f rad, the tired walk %.4f rad\n", near, far);
  EXPECT_LT(near, 0.01);
  EXPECT_GT(far, 3.0 * near);
  EXPECT_GT(far, 0.02);
  // A run too short for one period counts as still: far from a moving target.
  const motion::Clip still = motion::clipFrames(own, 0, 10);
  EXPECT_GT(spectral::runStyleDistance(asset.skeleton, still, neutral.value(), omega, 0.0), far);
}

TEST(StyleWeight, ACheckpointKeepsItAndOneFromBeforeTheTermReadsAsZero) {
  pipeline::ProjectSettings settings;
  settings.rig = walkPath().string();
  settings.physics.window_s = 1.0;
  settings.search.weights.style = 2.5;
  const motion::MotionAsset asset = walk();
  Result<pipeline::SearchSetup> setup = pipeline::prepareSearch(asset.skeleton, asset.clips.front(), settings);
  ASSERT_TRUE(setup.ok()) << setup.message();
  search::EvolveSettings evolve;
  evolve.generations = 1;
  Result<std::unique_ptr<search::Session>> session = search::Session::create(setup.value().problem, evolve);
  ASSERT_TRUE(session.ok()) << session.message();
  nlohmann::json checkpoint = session.value()->checkpoint();
  EXPECT_EQ(checkpoint["weights"]["style"].get<double>(), 2.5);
  Result<std::unique_ptr<search::Session>> resumed = search::Session::resume(setup.value().problem, checkpoint);
  ASSERT_TRUE(resumed.ok()) << resumed.message();
  EXPECT_EQ(resumed.value()->problem().weights.style, 2.5);
  checkpoint["weights"].erase("style");
  resumed = search::Session::resume(setup.value().problem, checkpoint);
  ASSERT_TRUE(resumed.ok()) << resumed.message();
  EXPECT_EQ(resumed.value()->problem().weights.style, 0.0);
  // A controller's fitness from before the term reads with style 0.
  nlohmann::json fitness = search::fitnessJson(search::FitnessTerms{});
  fitness.erase("style");
  Result<search::FitnessTerms> terms = search::fitnessFromJson(fitness);
  ASSERT_TRUE(terms.ok()) << terms.message();
  EXPECT_EQ(terms.value().style, 0.0);
}

// The largest joint rotation change between two frames, degrees.
double poseStepDeg(const motion::Clip& clip, int a, int b) {
  double deg = 0.0;
  for (int j = 0; j < clip.joint_count; ++j)
    deg = std::max(deg, angleBetween(clip.rotation(a, j), clip.rotation(b, j)) / kDeg);
  return deg;
}

nlohmann::json evolveStyled(const test::TempDir& dir, const std::filesystem::path& tired,
                            const std::string& weight) {
  const std::filesystem::path out = dir / ("w" + weight);
  const test::CommandResult run = test::runSinew(
      "evolve --rig " + test::quote(walkPath()) + " --style " + test::quote(walkPath()) + "," +
      test::quote(tired) + ":" + weight +
      " --window 4.5 --generations 2 --population 6 --threads 2 --seed 1 --out " + test::quote(out));
  EXPECT_EQ(run.exit_code, 0) << run.err << run.out;
  std::printf("%s", run.out.c_str());
  EXPECT_NE(run.out.find("style tired (weight"), std::string::npos) << run.out;
  nlohmann::json result = nlohmann::json::parse(test::readText(out / "style.json"));
  result["loop"] = nlohmann::json::parse(test::readText(out / "loop.json"));
  result["out"] = out.string();
  return result;
}

// The two searches, once for the suite: the tired style at weights 0 and 1.
class EvolveStyle : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    const std::filesystem::path tired = writeTired(*dir_);
    w0_ = new nlohmann::json(evolveStyled(*dir_, tired, "0"));
    w1_ = new nlohmann::json(evolveStyled(*dir_, tired, "1"));
  }
  static void TearDownTestSuite() {
    delete w0_;
    delete w1_;
    delete dir_;
  }
  static test::TempDir* dir_;
  static nlohmann::json* w0_;
  static nlohmann::json* w1_;
};
test::TempDir* EvolveStyle::dir_ = nullptr;
nlohmann::json* EvolveStyle::w0_ = nullptr;
nlohmann::json* EvolveStyle::w1_ = nullptr;

TEST_F(EvolveStyle, WeightOneEvolvesARunMoreTiredThanWeightZero) {
  const nlohmann::json& w0 = *w0_;
  const nlohmann::json& w1 = *w1_;
  const nlohmann::json& s0 = w0["styles"][0];
  const nlohmann::json& s1 = w1["styles"][0];
  ASSERT_TRUE(s0.contains("simulated") && s1.contains("simulated")) << w0.dump() << w1.dump();
  EXPECT_NEAR(s0["target"]["amount"].get<double>(), 0.0, 0.15);
  EXPECT_NEAR(s1["target"]["amount"].get<double>(), 1.0, 0.15);
  EXPECT_GT(s1["simulated"]["amount"].get<double>(), s0["simulated"]["amount"].get<double>() + 0.25);
  EXPECT_GT(s1["simulated"]["score"].get<double>(), s0["simulated"]["score"].get<double>());
  // The loop keeps what the run has.
  EXPECT_GT(w1["loop"]["style"]["styles"][0]["simulated"]["amount"].get<double>(),
            w0["loop"]["style"]["styles"][0]["simulated"]["amount"].get<double>() + 0.25);
}

TEST_F(EvolveStyle, TheWrittenLoopReimportsLoopsAndKeepsItsFeetPlanted) {
  const nlohmann::json& w1 = *w1_;
  const nlohmann::json& loop = w1["loop"];
  std::printf("loop.json: %s\n", loop.dump().c_str());
  const std::filesystem::path out = w1["out"].get<std::string>();
  Result<motion::MotionAsset> file = motion::importMotion(out / "best_loop.bvh");
  ASSERT_TRUE(file.ok()) << file.message();
  EXPECT_EQ(file.value().skeleton.names, walk().skeleton.names);
  const motion::Clip& clip = file.value().clips.front();
  EXPECT_EQ(clip.frame_count, loop["frames"].get<int>());
  double step_max = 0.0;
  for (int f = 0; f + 1 < clip.frame_count; ++f) step_max = std::max(step_max, poseStepDeg(clip, f, f + 1));
  // The seam is one more step of the motion (the BVH text rounds angles to 1e-4 degrees).
  EXPECT_LE(poseStepDeg(clip, clip.frame_count - 1, 0), step_max + 1e-3);
  EXPECT_LE(loop["seam_deg"].get<double>(), loop["step_deg_max"].get<double>() + 1e-9);
  EXPECT_LE(loop["seam_cm"].get<double>(), loop["step_cm_max"].get<double>() + 1e-9);
  EXPECT_LT(loop["slide_after_cm_mean"].get<double>(), 1.0);
  EXPECT_LT(loop["slide_after_cm_mean"].get<double>(), loop["slide_before_cm_mean"].get<double>());
  EXPECT_GE(loop["contacts"].size(), 4u);  // two feet, two strides
  EXPECT_LT(loop["deviation_from_run_deg_rms"].get<double>(), 10.0);
  Result<motion::MotionAsset> glb = motion::importMotion(out / "best_loop.glb");
  ASSERT_TRUE(glb.ok()) << glb.message();
  EXPECT_EQ(glb.value().skeleton.names, file.value().skeleton.names);
}

// The weight-1 search's best replayed through the engine: its loop in place, played twice, and
// what the loop refuses.
TEST_F(EvolveStyle, TheEnginesLoopOfTheBestRunInPlaceAndItsLimits) {
  const motion::MotionAsset asset = walk();
  const std::filesystem::path out = (*w1_)["out"].get<std::string>();
  Result<search::ControllerFile> controller = search::loadController(out / "best.json", asset.skeleton);
  ASSERT_TRUE(controller.ok()) << controller.message();
  Result<physics::BodyPlan> plan = pipeline::bodyPlan(asset.skeleton, asset.clips.front(), {}, "walk");
  ASSERT_TRUE(plan.ok()) << plan.message();
  physics::SimulationSettings settings;
  settings.seconds = controller.value().window_s;
  search::applyController(controller.value(), settings.tracking);
  Result<physics::SimulationReport> run =
      physics::simulate(plan.value(), asset.skeleton, controller.value().target, settings);
  ASSERT_TRUE(run.ok()) << run.message();
  const double stride = controller.value().target.period();

  Result<pipeline::PhysicalLoop> travelling = pipeline::physicalLoop(asset.skeleton, run.value(), stride);
  ASSERT_TRUE(travelling.ok()) << travelling.message();
  EXPECT_NEAR(travelling.value().slideAfterMeanCm(), (*w1_)["loop"]["slide_after_cm_mean"].get<double>(), 1e-6);
  const pipeline::PhysicalLoop& loop = travelling.value();
  EXPECT_EQ(loop.clip.frame_count, static_cast<int>(std::lround(2 * loop.period_s * 30.0)));
  EXPECT_GE(loop.run_start_s, stride - 0.05);
  EXPECT_GT(glm::length(loop.travel_m), 1.0);  // walking, about 1.3 m/s for 2 strides
  // Played twice, the second lap starts where the first left off, travelled.
  const motion::Clip twice = loop.played(2);
  ASSERT_EQ(twice.frame_count, 2 * loop.clip.frame_count);
  const int n = loop.clip.frame_count;
  EXPECT_NEAR(glm::length(twice.translation(n, 0) - loop.clip.translation(0, 0) - loop.travel_m), 0.0, 1e-9);

  pipeline::LoopSettings in_place;
  in_place.in_place = true;
  Result<pipeline::PhysicalLoop> still = pipeline::physicalLoop(asset.skeleton, run.value(), stride, in_place);
  ASSERT_TRUE(still.ok()) << still.message();
  EXPECT_NEAR(std::hypot(still.value().travel_m.x, still.value().travel_m.z), 0.0, 1e-9);
  EXPECT_NEAR(std::hypot(still.value().clip.translation(n - 1, 0).x - still.value().clip.translation(0, 0).x,
                         still.value().clip.translation(n - 1, 0).z - still.value().clip.translation(0, 0).z),
              0.0, 0.1);  // the root sways, it does not travel
  EXPECT_LE(still.value().seam_cm, still.value().step_cm_max + 1e-9);
  EXPECT_NEAR(still.value().slideAfterMeanCm(), loop.slideAfterMeanCm(), 1e-9);  // planted alike

  pipeline::LoopSettings many;
  many.strides = 5;
  Result<pipeline::PhysicalLoop> too_long = pipeline::physicalLoop(asset.skeleton, run.value(), stride, many);
  ASSERT_FALSE(too_long.ok());
  EXPECT_NE(too_long.message().find("5 strides"), std::string::npos) << too_long.message();
  pipeline::LoopSettings none;
  none.strides = 0;
  EXPECT_NE(pipeline::physicalLoop(asset.skeleton, run.value(), stride, none).message().find("strides"),
            std::string::npos);
  EXPECT_FALSE(pipeline::physicalLoop(asset.skeleton, run.value(), 10.0).ok());  // nothing after it
}

}  // namespace
}  // namespace sinew
