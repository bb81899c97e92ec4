// Simulation speed of the bundled biped: the full run (servo targets from the harmonic model by
// recurrence, balance feedback, recording at 30 fps, tracking error and energy every step) against
// bare Bullet stepping the same bodies through the same motion (the servo targets of that run,
// computed beforehand and replayed: the same contacts, the same solver work), in the same
// process; and the throughput of independent runs on 1 and 2 threads (how the search evaluates).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <cstdlib>
#include <memory>

#include "ratio_reporter.h"
#include "sinew/motion/asset.h"
#include "sinew/physics/body_plan.h"
#include "sinew/physics/simulation.h"
#include "sinew/physics/tracking.h"
#include "sinew/spectral/analysis.h"

namespace {

using namespace sinew;

constexpr double kSeconds = 1.0;  // simulated per iteration

struct Data {
  motion::MotionAsset asset;
  physics::BodyPlan plan;
  spectral::TargetMotion target;
  std::vector<physics::LinkPose> targets;  // the servo targets of one simulated run, per step
};
Data& data() {
  static Data d;
  return d;
}

physics::SimulationSettings runSettings() {
  physics::SimulationSettings settings;
  settings.seconds = kSeconds;
  settings.stop_at_fall = false;
  // As a search runs it (pipeline::simulationSettings): the servos lead by their lag.
  settings.tracking.servo_lead_s =
      physics::servoLag(settings.world.step_hz, settings.tracking.servo_rate);
  return settings;
}

std::unique_ptr<physics::World> startWorld(const Data& d) {
  const physics::MotionState start = physics::targetState(d.plan, d.asset.skeleton, d.target, 0.0);
  auto world = physics::World::create(d.plan, start.pose, runSettings().world).value();
  if (!world->setVelocities(start.base_linear, start.base_angular, start.joint_velocities).ok())
    std::abort();
  return world;
}

// The servo targets the controller gives over one run, as simulate starts it.
std::vector<physics::LinkPose> controllerTargets(const Data& d) {
  auto world = startWorld(d);
  const physics::MotionState start = physics::targetState(d.plan, d.asset.skeleton, d.target, 0.0);
  physics::TrackingSettings tracking = runSettings().tracking;
  tracking.ramp_s = 0.0;
  auto controller = physics::TrackingController::create(*world, d.asset.skeleton, d.target,
                                                        physics::standingPose(d.plan, d.asset.skeleton),
                                                        tracking)
                        .value();
  std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0);
  std::vector<physics::LinkPose> targets;
  const long long n = std::llround(kSeconds / world->dt());
  for (long long s = 0; s < n; ++s) {
    controller->update(*world);
    targets.push_back(controller->target());
    world->step(zero);
  }
  return targets;
}

// Bare Bullet: a fresh world of the same bodies and servos, stepped through the same targets.
void bareBullet(benchmark::State& state) {
  const Data& d = data();
  const physics::TrackingSettings defaults;
  const std::vector<double> limits = physics::jointTorqueLimits(
      d.plan, defaults.support_torque_scale, defaults.limb_torque_scale, defaults.gravity_m_s2);
  long long steps = 0;
  for (auto _ : state) {
    auto world = startWorld(d);
    if (!world->enableServos(limits, defaults.servo_rate).ok()) state.SkipWithError("servos");
    std::vector<double> zero(static_cast<size_t>(world->dofCount()), 0.0);
    for (const physics::LinkPose& target : d.targets) {
      world->setServoTargets(target);
      world->step(zero);
    }
    steps += static_cast<long long>(d.targets.size());
    benchmark::DoNotOptimize(world->centreOfMass());
  }
  state.SetItemsProcessed(steps);
}

// Ours: physics::simulate for the same second (world built, controller, feedback, recording).
void simulateRun(benchmark::State& state) {
  const Data& d = data();
  physics::SimulationSettings settings = runSettings();
  if (state.range(0) == 0) settings.tracking.servo_lead_s = 0.0;
  long long steps = 0;
  for (auto _ : state) {
    auto report = physics::simulate(d.plan, d.asset.skeleton, d.target, settings);
    if (!report.ok()) state.SkipWithError(report.message().c_str());
    steps += std::llround(kSeconds * settings.world.step_hz);
    benchmark::DoNotOptimize(report);
  }
  state.SetItemsProcessed(steps);
}

}  // namespace

int main(int argc, char** argv) {
  Data& d = data();
  const std::filesystem::path rig = std::filesystem::path(SINEW_SOURCE_DIR) / "assets" / "biped_walk.bvh";
  auto asset = motion::importMotion(rig);
  if (!asset.ok()) {
    std::fprintf(stderr, "%s\n", asset.message().c_str());
    return 1;
  }
  d.asset = std::move(asset).value();
  d.plan = physics::buildBodyPlan(d.asset.skeleton, &d.asset.clips[0]).value();
  d.target = spectral::targetFromSpectrum(spectral::analyze(d.asset.skeleton, d.asset.clips[0]).value());
  d.targets = controllerTargets(d);
  std::printf("biped: %zu links, %d degrees of freedom, 240 Hz, %.0f s simulated per iteration\n",
              d.plan.links.size(), d.plan.dofCount(), kSeconds);

  benchmark::RegisterBenchmark("baseline_bare_bullet", bareBullet)->Unit(benchmark::kMillisecond)->UseRealTime();
  benchmark::RegisterBenchmark("simulate", simulateRun)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
  // The servos given the present pose (one evaluation of the target a step, not two).
  benchmark::RegisterBenchmark("simulate_without_lead", simulateRun)
      ->Arg(0)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  benchmark::RegisterBenchmark("simulate_threads", simulateRun)
      ->Arg(1)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Threads(1)
      ->Threads(2);
  const auto options = sinew::bench::consoleOptions(argc, argv);
  benchmark::Initialize(&argc, argv);
  sinew::bench::RatioReporter reporter(options);
  benchmark::RunSpecifiedBenchmarks(&reporter);

  const double bare = reporter.times["baseline_bare_bullet/real_time"];
  const double ours = reporter.times["simulate/1/real_time"];
  const double unled = reporter.times["simulate_without_lead/0/real_time"];
  const double one = reporter.times["simulate_threads/1/real_time/threads:1"];
  const double two = reporter.times["simulate_threads/1/real_time/threads:2"];
  const double steps = kSeconds * 240.0;
  if (bare > 0.0 && ours > 0.0) {
    std::printf("\nsteps per second per core: bare Bullet %.0f, simulate %.0f; our overhead %.1f%% "
                "(aim: at most 15%%)\n",
                steps / (bare * 1e-3), steps / (ours * 1e-3), 100.0 * (ours / bare - 1.0));
  }
  if (ours > 0.0 && unled > 0.0)
    std::printf("the servo lead (a second target evaluation a step) costs %.1f%%\n",
                100.0 * (ours / unled - 1.0));
  if (one > 0.0 && two > 0.0) {
    // With N threads each iteration is one run per thread; the reported time is per iteration.
    std::printf("times real time: %.1fx on 1 thread, %.1fx on 2 threads (%.2fx speed-up)\n",
                kSeconds / (one * 1e-3), 2.0 * kSeconds / (two * 1e-3), 2.0 * one / two);
  }
  return 0;
}
