// sinew simulate --rig FILE: the rig's physical character tracks the harmonic model of a clip (the
// rig's own motion unless --clip) on a chosen terrain, with scheduled pushes; reports whether and
// when it fell, how far it went, how well it tracked and what it cost, and can write what it did
// as BVH/glTF on the rig's skeleton and the figures as JSON.
#include <cstdio>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "sinew/core/file_io.h"
#include "sinew/physics/body_plan.h"
#include "sinew/physics/simulation.h"
#include "sinew/spectral/analysis.h"
#include "sinew/spectral/target_io.h"

namespace sinew::app {
namespace {

struct SimulateArgs {
  std::string rig;
  std::string clip;
  std::string target_path;
  std::string animation;
  double seconds = 10.0;
  std::string terrain = "flat";
  std::vector<std::string> pushes;
  bool no_feedback = false;
  std::vector<double> balance;
  bool from_standing = false;
  int harmonics = 5;
  std::string output;
  std::string json_path;
  ImportFlags import;
};

// "slope:5", "steps:0.05,0.6", "rough:0.02,7", "flat".
Result<physics::TerrainSettings> parseTerrain(const std::string& text) {
  physics::TerrainSettings t;
  const size_t colon = text.find(':');
  const std::string kind = text.substr(0, colon);
  std::vector<double> values;
  if (colon != std::string::npos) {
    std::stringstream in(text.substr(colon + 1));
    std::string item;
    while (std::getline(in, item, ',')) {
      try {
        size_t used = 0;
        values.push_back(std::stod(item, &used));
        if (used != item.size()) throw std::invalid_argument(item);
      } catch (const std::exception&) {
        return Status::error("--terrain: '" + item + "' is not a number (in '" + text + "')");
      }
    }
  }
  auto want = [&](size_t most) -> Status {
    if (values.size() > most)
      return Status::error("--terrain " + kind + ": at most " + std::to_string(most) +
                           " values, got " + std::to_string(values.size()));
    return Status();
  };
  using Kind = physics::TerrainSettings::Kind;
  if (kind == "flat") {
    if (Status s = want(0); !s.ok()) return s;
  } else if (kind == "slope") {
    if (Status s = want(1); !s.ok()) return s;
    t.kind = Kind::kSlope;
    if (!values.empty()) t.slope_deg = values[0];
  } else if (kind == "steps") {
    if (Status s = want(2); !s.ok()) return s;
    t.kind = Kind::kSteps;
    if (values.size() > 0) t.step_height_m = values[0];
    if (values.size() > 1) t.step_depth_m = values[1];
  } else if (kind == "rough") {
    if (Status s = want(2); !s.ok()) return s;
    t.kind = Kind::kRough;
    if (values.size() > 0) t.amplitude_m = values[0];
    if (values.size() > 1) {
      if (values[1] < 0.0 || values[1] != static_cast<double>(static_cast<std::uint64_t>(values[1])))
        return Status::error("--terrain rough: the seed must be a whole number >= 0");
      t.seed = static_cast<std::uint64_t>(values[1]);
    }
  } else {
    return Status::error("--terrain: unknown kind '" + kind +
                         "' (flat, slope:DEG, steps:HEIGHT,DEPTH, rough:AMPLITUDE,SEED)");
  }
  if (Status s = t.validate(); !s.ok()) return Status::error("--terrain: " + s.message());
  return t;
}

// "TIME,X,Y,Z[,LINK]": seconds, N s (world, Y up), and a joint name (the base when left out).
Result<physics::Push> parsePush(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) parts.push_back(item);
  if (parts.size() != 4 && parts.size() != 5)
    return Status::error("--push '" + text + "': expected TIME,X,Y,Z[,LINK] (seconds, N s)");
  double v[4];
  for (size_t i = 0; i < 4; ++i) {
    try {
      size_t used = 0;
      v[i] = std::stod(parts[i], &used);
      if (used != parts[i].size()) throw std::invalid_argument(parts[i]);
    } catch (const std::exception&) {
      return Status::error("--push '" + text + "': '" + parts[i] + "' is not a number");
    }
  }
  physics::Push push;
  push.time_s = v[0];
  push.impulse_ns = glm::dvec3(v[1], v[2], v[3]);
  if (parts.size() == 5) push.link = parts[4];
  return push;
}

nlohmann::json reportJson(const physics::SimulationReport& r, const SimulateArgs& args) {
  nlohmann::json feet = nlohmann::json::array();
  for (size_t f = 0; f < r.feet.size(); ++f)
    feet.push_back({{"link", r.feet[f]}, {"contact_share", r.contact_share[f]}});
  nlohmann::json footfalls = nlohmann::json::array();
  for (const physics::Footfall& f : r.footfalls)
    footfalls.push_back({{"foot", r.feet[static_cast<size_t>(f.foot)]},
                         {"time_s", f.time_s},
                         {"position_m", {f.position.x, f.position.y, f.position.z}}});
  return {{"rig", args.rig},
          {"clip", args.clip.empty() ? args.rig : args.clip},
          {"terrain", args.terrain},
          {"feedback", !args.no_feedback},
          {"seconds", r.seconds},
          {"fell", r.fell},
          {"fall_time_s", r.fell ? nlohmann::json(r.fall_time_s) : nlohmann::json(nullptr)},
          {"fall_reason", r.fall_reason},
          {"distance_m", r.distance_m},
          {"speed_m_s", r.speed_m_s},
          {"track_err_rad_rms", r.track_err_rad_rms},
          {"energy_j", r.energy_j},
          {"torque_sq_per_kg", r.torque_sq_per_kg},
          {"min_uprightness", r.min_uprightness},
          {"mass_kg", r.mass_kg},
          {"pushed_impulse_ns", {r.pushed_impulse_ns.x, r.pushed_impulse_ns.y, r.pushed_impulse_ns.z}},
          {"feet", feet},
          {"footfalls", footfalls}};
}

int runSimulate(const SimulateArgs& args) {
  Result<motion::ImportOptions> options = args.import.options();
  if (!options.ok()) return fail(options.message());
  Result<motion::MotionAsset> rig = motion::importMotion(args.rig, options.value());
  if (!rig.ok()) return fail(rig.message());
  motion::MotionAsset motion_source;
  const motion::MotionAsset* source = &rig.value();
  if (!args.clip.empty()) {
    Result<motion::MotionAsset> clip_asset = motion::importMotion(args.clip, options.value());
    if (!clip_asset.ok()) return fail(clip_asset.message());
    motion_source = std::move(clip_asset).value();
    if (motion_source.skeleton.names != rig.value().skeleton.names)
      return fail(args.clip + ": its skeleton is not the rig's (" + args.rig +
                  "): the joints differ in names or order");
    source = &motion_source;
  }
  if (source->clips.empty())
    return fail((args.clip.empty() ? args.rig : args.clip) + ": no motion to track (give --clip)");
  Result<int> clip_index = selectClip(*source, args.animation);
  if (!clip_index.ok()) return fail(clip_index.message());
  const motion::Clip& clip = source->clips[static_cast<size_t>(clip_index.value())];
  const motion::Skeleton& skeleton = rig.value().skeleton;

  Result<physics::TerrainSettings> terrain = parseTerrain(args.terrain);
  if (!terrain.ok()) return fail(terrain.message());
  physics::SimulationSettings settings;
  settings.seconds = args.seconds;
  settings.world.terrain = terrain.value();
  settings.tracking.feedback = !args.no_feedback;
  if (!args.balance.empty()) {
    if (args.balance.size() != 5)
      return fail("--balance: expected 5 numbers CD_SAGITTAL,CV_SAGITTAL,CD_CORONAL,CV_CORONAL,TORSO, got " +
                  std::to_string(args.balance.size()));
    physics::BalanceGains& b = settings.tracking.balance;
    b.cd_sagittal = args.balance[0];
    b.cv_sagittal = args.balance[1];
    b.cd_coronal = args.balance[2];
    b.cv_coronal = args.balance[3];
    b.torso = args.balance[4];
  }
  settings.start_moving = !args.from_standing;
  for (const std::string& text : args.pushes) {
    Result<physics::Push> push = parsePush(text);
    if (!push.ok()) return fail(push.message());
    settings.pushes.push_back(push.value());
  }

  Result<physics::BodyPlan> plan = physics::buildBodyPlan(skeleton, &clip);
  if (!plan.ok()) return fail(args.rig + ": " + plan.message());
  spectral::TargetMotion target;
  std::string what;
  if (!args.target_path.empty()) {
    // Coefficients written by `sinew style -o X.json` (or any edit): tracked as they are.
    Result<spectral::TargetMotion> loaded = spectral::loadTarget(args.target_path, skeleton);
    if (!loaded.ok()) return fail(loaded.message());
    target = std::move(loaded).value();
    what = args.target_path;
  } else {
    spectral::AnalysisSettings analysis;
    analysis.harmonics = args.harmonics;
    Result<spectral::MotionSpectrum> spectrum = spectral::analyze(skeleton, clip, analysis);
    if (!spectrum.ok())
      return fail((args.clip.empty() ? args.rig : args.clip) + ": " + spectrum.message());
    target = spectral::targetFromSpectrum(spectrum.value(), {}, clip.name);
    what = "'" + clip.name + "' (K = " + std::to_string(args.harmonics) + ")";
  }

  std::printf("%s: %zu links, %d degrees of freedom, %.1f kg; tracking %s, stride %.3f s, for "
              "%.1f s on %s terrain, balance feedback %s\n",
              args.rig.c_str(), plan.value().links.size(), plan.value().dofCount(),
              plan.value().total_mass_kg, what.c_str(), target.period(), args.seconds,
              physics::terrainKindName(terrain.value().kind), args.no_feedback ? "off" : "on");
  Result<physics::SimulationReport> run = physics::simulate(plan.value(), skeleton, target, settings);
  if (!run.ok()) return fail(run.message());
  const physics::SimulationReport& r = run.value();
  if (r.fell)
    std::printf("fell at %.2f s: %s\n", r.fall_time_s, r.fall_reason.c_str());
  else
    std::printf("stayed up for %.2f s\n", r.seconds);
  std::printf("travelled %.2f m (%.2f m/s); tracking error %.2f deg RMS; energy %.0f J; "
              "torque^2 %.0f N^2 m^2 s/kg\n",
              r.distance_m, r.speed_m_s, r.track_err_rad_rms * 57.29577951308232, r.energy_j,
              r.torque_sq_per_kg);
  for (size_t f = 0; f < r.feet.size(); ++f)
    std::printf("  %-16s on the ground %3.0f%% of the time\n", r.feet[f].c_str(),
                100.0 * r.contact_share[f]);
  std::printf("  %zu footfalls\n", r.footfalls.size());

  if (!args.output.empty()) {
    Status status = motion::exportMotion(args.output, rig.value(), r.motion);
    if (!status.ok()) return fail(status.message());
    std::printf("wrote %s: %d frames at %.0f fps\n", args.output.c_str(), r.motion.frame_count,
                r.motion.fps());
  }
  if (!args.json_path.empty()) {
    Status status = writeFileAtomically(args.json_path, reportJson(r, args).dump(2) + "\n");
    if (!status.ok()) return fail(status.message());
    std::printf("wrote %s\n", args.json_path.c_str());
  }
  return 0;
}

}  // namespace

void addSimulateCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* command = app.add_subcommand(
      "simulate", "Make the rig's physical character track a clip's harmonic model with joint "
                  "torques; report falls, distance, tracking error and energy");
  command->add_option("--rig", args->rig, "The rig (.bvh, .glb, .gltf)")->required();
  command->add_option("--clip", args->clip,
                      "The motion to track (same skeleton); default: the rig's own");
  command->add_option("--target", args->target_path,
                      "Track these harmonic coefficients (.json from sinew style) instead of the "
                      "clip's; the clip still shapes the body (joint types and limits)");
  command->add_option("--animation", args->animation, "Which glTF animation (by name)");
  command->add_option("--seconds", args->seconds, "Simulated time, seconds")
      ->check(CLI::Range(0.001, 3600.0));
  command->add_option("--terrain", args->terrain,
                      "flat | slope:DEG | steps:HEIGHT,DEPTH | rough:AMPLITUDE,SEED (metres)");
  command->add_option("--push", args->pushes,
                      "A push TIME,X,Y,Z[,LINK]: seconds, impulse in N s (Y up), on the named "
                      "joint's body (default the pelvis); repeatable");
  command->add_flag("--no-feedback", args->no_feedback,
                    "Pure Fourier control: no balance feedback");
  command->add_option("--balance", args->balance,
                      "Balance feedback gains CD_SAGITTAL,CV_SAGITTAL,CD_CORONAL,CV_CORONAL,TORSO "
                      "(rad/m, rad/(m/s), rad/m, rad/(m/s), share 0..1)")
      ->delimiter(',');
  command->add_flag("--from-standing", args->from_standing,
                    "Start standing at rest and blend into the motion over 1 s (default: start "
                    "in the motion's first pose and velocities)");
  command->add_option("--harmonics", args->harmonics, "Harmonics per joint of the target")
      ->check(CLI::Range(1, 64));
  command->add_option("-o,--output", args->output,
                      "Write what the character did (.bvh, .glb, .gltf) on the rig's skeleton");
  command->add_option("--json", args->json_path, "Write the figures as JSON");
  args->import.addTo(*command);
  command->callback([args, &exit_code]() { exit_code = runSimulate(*args); });
}

}  // namespace sinew::app
