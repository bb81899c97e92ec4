// sinew simulate --rig FILE: the rig's physical character tracks the harmonic model of a clip (the
// rig's own motion unless --clip) on a chosen terrain, with scheduled pushes; reports whether and
// when it fell, how far it went, how well it tracked and what it cost, and can write what it did
// as BVH/glTF on the rig's skeleton and the figures as JSON.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/controller_file.h"
#include "cli/report_lines.h"
#include "sinew/core/file_io.h"
#include "sinew/core/path_json.h"
#include "sinew/core/text.h"
#include "sinew/physics/body_plan.h"
#include "sinew/physics/simulation.h"
#include "sinew/pipeline/pipeline.h"
#include "sinew/search/controller_io.h"

namespace sinew::app {
namespace {

struct SimulateArgs {
  std::string rig;
  std::string clip;
  std::string target_path;
  std::string controller_path;
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
  std::string trace_path;
  ImportFlags import;
  BodyFlags body;
};

nlohmann::json reportJson(const physics::SimulationReport& r, const SimulateArgs& args) {
  nlohmann::json feet = nlohmann::json::array();
  for (size_t f = 0; f < r.feet.size(); ++f)
    feet.push_back({{"link", r.feet[f]}, {"contact_share", r.contact_share[f]}});
  nlohmann::json footfalls = nlohmann::json::array();
  for (const physics::Footfall& f : r.footfalls)
    footfalls.push_back({{"foot", r.feet[static_cast<size_t>(f.foot)]},
                         {"time_s", f.time_s},
                         {"position_m", {f.position.x, f.position.y, f.position.z}}});
  nlohmann::json limited = nlohmann::json::array();
  nlohmann::json tracking = nlohmann::json::array();
  for (size_t li = 1; li < r.links.size(); ++li) {
    limited.push_back({{"link", toUtf8(r.links[li])}, {"share", r.torque_limited_share[li]}});
    tracking.push_back({{"link", toUtf8(r.links[li])}, {"rad_rms", r.track_err_by_link_rad[li]}});
  }
  return {
      {"rig", toUtf8(args.rig)},
      {"clip", toUtf8(args.clip.empty() ? args.rig : args.clip)},
      {"terrain", args.terrain},
      {"feedback", !args.no_feedback},
      {"seconds", r.seconds},
      {"fell", r.fell},
      {"fall_time_s", r.fell ? r.fall_time_s : -1.0},  // -1: did not fall (never null)
      {"fall_reason", r.fall_reason},
      {"diverged", r.diverged},
      {"diverged_reason", r.diverged_reason},
      {"distance_m", r.distance_m},
      {"speed_m_s", r.speed_m_s},
      {"track_err_rad_rms", r.track_err_rad_rms},
      {"track_err_by_link", tracking},
      {"energy_j", r.energy_j},
      {"torque_sq_per_kg", r.torque_sq_per_kg},
      {"min_uprightness", r.min_uprightness},
      {"mass_kg", r.mass_kg},
      {"pushed_impulse_ns", {r.pushed_impulse_ns.x, r.pushed_impulse_ns.y, r.pushed_impulse_ns.z}},
      {"feet", feet},
      {"footfalls", footfalls},
      {"torque_limited", limited}};
}

// The flags as the pipeline's settings; the engine makes the target and the body from them.
Result<pipeline::ProjectSettings> settingsFromFlags(const SimulateArgs& args) {
  pipeline::ProjectSettings chosen;
  chosen.rig = args.rig;
  chosen.clip = args.clip;
  chosen.target = args.target_path;
  chosen.animation = args.animation;
  chosen.harmonics = args.harmonics;
  chosen.physics.window_s = args.seconds;
  Result<physics::TerrainSettings> terrain = parseTerrain(args.terrain);
  if (!terrain.ok()) return terrain.status();
  chosen.physics.terrain = terrain.value();
  for (const std::string& text : args.pushes) {
    Result<physics::Push> push = parsePush(text);
    if (!push.ok()) return push.status();
    chosen.physics.pushes.push_back(push.value());
  }
  Result<BodyOverrides> body = args.body.overrides();
  if (!body.ok()) return body.status();
  chosen.physics.body = std::move(body).value();
  return chosen;
}

// The rig an evolved controller was made on (its "rig", bytes as written): what --controller
// replays on when --rig is not given. Empty when the file does not name one; loading the
// controller then says what is wrong with it.
std::string controllerRig(const std::string& path) {
  Result<std::string> text = readFile(path);
  if (!text.ok()) return {};
  const nlohmann::json document = nlohmann::json::parse(text.value(), nullptr, false);
  std::string rig;
  if (document.is_object() && !readPathJson(document, "rig", rig, path + ": ").ok()) return {};
  return rig;
}

// --balance CD_SAGITTAL,CV_SAGITTAL,CD_CORONAL,CV_CORONAL,TORSO[,...] into the gains.
Status applyBalanceFlag(const std::vector<double>& balance, physics::BalanceGains& b) {
  if (balance.size() != 5 && balance.size() != 8 && balance.size() != 9 && balance.size() != 12 &&
      balance.size() != 13 && balance.size() != 14)
    return Status::error(
        "--balance: expected 5 numbers CD_SAGITTAL,CV_SAGITTAL,CD_CORONAL,CV_CORONAL,TORSO (or "
        "8, then ANKLE_SAGITTAL,ANKLE_CORONAL,SWING_LIFT, or 9, then HEADING, or 12, then "
        "STANCE_SAGITTAL,STANCE_CORONAL,STANCE_VERTICAL, or 13, then STANCE_YAW, or 14, then "
        "STANCE_YIELD), got " +
        std::to_string(balance.size()));
  for (size_t i = 0; i < balance.size(); ++i) {
    const int g = static_cast<int>(i);
    const double v = balance[i];
    const double limit = physics::balanceGainLimit(g, search::kMaxBalanceGain);
    const bool share = physics::balanceGainIsShare(g);
    if (share ? !(v >= 0.0 && v <= limit) : !(std::abs(v) <= limit))
      return Status::error("--balance: " + std::string(physics::balanceGainName(g)) + " (value " +
                           std::to_string(i + 1) + ") must be " + (share ? "a share " : "") +
                           physics::balanceGainRule(g, search::kMaxBalanceGain));
    physics::balanceGain(b, g) = v;
  }
  return {};
}

void printReport(const physics::SimulationReport& r) {
  if (r.diverged)
    std::printf("diverged at %.2f s: %s; figures up to then\n", r.fall_time_s,
                r.diverged_reason.c_str());
  else if (r.fell)
    std::printf("fell at %.2f s: %s\n", r.fall_time_s, r.fall_reason.c_str());
  else
    std::printf("stayed up for %.2f s\n", r.seconds);
  std::printf(
      "travelled %.2f m (%.2f m/s); tracking error %.2f deg RMS; energy %.0f J; "
      "torque^2 %.0f N^2 m^2 s/kg\n",
      r.distance_m, r.speed_m_s, r.track_err_rad_rms * 57.29577951308232, r.energy_j,
      r.torque_sq_per_kg);
  for (size_t f = 0; f < r.feet.size(); ++f)
    std::printf("  %-16s on the ground %3.0f%% of the time\n", r.feet[f].c_str(),
                100.0 * r.contact_share[f]);
  std::printf("  %zu footfalls\n", r.footfalls.size());
  printJointLines(physics::jointFigures(r), "the target");
}

// A CSV header cell: quoted when the name holds a comma, a quote or a line break.
std::string csvCell(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// --trace: one row per step (physics::TraceStep), the feet and joints by name in the header.
std::string traceCsv(const physics::SimulationReport& r) {
  std::ostringstream csv;
  csv.precision(6);
  csv << "time_s,com_x_m,com_y_m,com_z_m,com_vx_m_s,com_vy_m_s,com_vz_m_s,target_com_x_m,"
         "target_com_y_m,target_com_z_m,target_vx_m_s,target_vy_m_s,target_vz_m_s,stance_foot";
  for (const std::string& foot : r.feet) {
    const std::string f = toUtf8(foot);
    for (const char* column : {"_contacts", "_x_m", "_y_m", "_z_m", "_force_n", "_target_x_m",
                               "_target_y_m", "_target_z_m"})
      csv << ',' << csvCell(f + column);
  }
  for (size_t li = 1; li < r.links.size(); ++li) {
    const std::string link = toUtf8(r.links[li]);
    csv << ',' << csvCell(link + "_torque_nm") << ',' << csvCell(link + "_at_limit") << ','
        << csvCell(link + "_error_deg");
  }
  csv << '\n';
  auto vec = [&](const glm::dvec3& v) { csv << ',' << v.x << ',' << v.y << ',' << v.z; };
  for (const physics::TraceStep& step : r.trace) {
    csv << step.time_s;
    vec(step.com);
    vec(step.com_velocity);
    vec(step.target_com);
    vec(step.target_velocity);
    csv << ',' << (step.stance_foot >= 0 ? csvCell(toUtf8(r.feet[static_cast<size_t>(step.stance_foot)])) : "");
    for (size_t f = 0; f < step.foot_contacts.size(); ++f) {
      csv << ',' << static_cast<int>(step.foot_contacts[f]);
      vec(step.foot_positions[f]);
      csv << ',' << step.foot_forces_n[f];
      vec(step.target_foot_positions[f]);
    }
    for (size_t li = 1; li < step.torques_nm.size(); ++li)
      csv << ',' << step.torques_nm[li] << ',' << static_cast<int>(step.at_limit[li]) << ','
          << step.errors_rad[li] * 180.0 / std::numbers::pi;
    csv << '\n';
  }
  return csv.str();
}

// --output (the run on the rig's skeleton), --json (the figures) and --trace (every step).
Status writeOutputs(const SimulateArgs& args, const motion::MotionAsset& asset,
                    const physics::SimulationReport& r) {
  if (!args.output.empty()) {
    if (Status status = motion::exportMotion(args.output, asset, r.motion); !status.ok())
      return status;
    std::printf("wrote %s: %d frames at %.0f fps\n", args.output.c_str(), r.motion.frame_count,
                r.motion.fps());
  }
  if (!args.json_path.empty()) {
    Status status = writeFileAtomically(
        args.json_path,
        reportJson(r, args).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
    if (!status.ok()) return status;
    std::printf("wrote %s\n", args.json_path.c_str());
  }
  if (!args.trace_path.empty()) {
    if (Status status = writeFileAtomically(args.trace_path, traceCsv(r)); !status.ok())
      return status;
    std::printf("wrote %s: %zu steps\n", args.trace_path.c_str(), r.trace.size());
  }
  return {};
}

int runSimulate(const SimulateArgs& args) {
  if (!args.controller_path.empty() && !args.target_path.empty())
    return fail("--controller and --target both give the coefficients: choose one");
  if (!args.trace_path.empty() && args.seconds > physics::kMaxTracedSeconds)
    return fail("--trace records every step, so at most " +
                std::to_string(static_cast<int>(physics::kMaxTracedSeconds)) + " s (asked " +
                std::to_string(static_cast<int>(std::ceil(args.seconds))) + " s)");
  Result<pipeline::ProjectSettings> flags = settingsFromFlags(args);
  if (!flags.ok()) return fail(flags.message());
  const pipeline::ProjectSettings& chosen = flags.value();
  Result<LoadedRig> loaded = loadRig(chosen, args.import);
  if (!loaded.ok()) return fail(loaded.message());
  LoadedRig& rig = loaded.value();
  const motion::Skeleton& skeleton = rig.asset.skeleton;
  Result<physics::BodyPlan> built =
      pipeline::bodyPlan(skeleton, rig.clip(), chosen.physics.body, chosen.rig);
  if (!built.ok()) return fail(built.message());
  Result<pipeline::TrackedMotion> tracked = pipeline::trackedMotion(skeleton, rig.clip(), chosen);
  if (!tracked.ok()) return fail(tracked.message());
  spectral::TargetMotion target = std::move(tracked.value().target);
  std::string what = std::move(tracked.value().what);
  physics::SimulationSettings settings = pipeline::simulationSettings(chosen.physics);
  settings.tracking.feedback = !args.no_feedback;
  if (!args.controller_path.empty()) {
    // An evolved controller: its coefficients and its balance gains.
    Result<search::ControllerFile> controller =
        search::loadController(args.controller_path, skeleton);
    if (!controller.ok()) return fail(controller.message());
    for (const std::string& warning : controller.value().warnings)
      std::fprintf(stderr, "sinew: warning: %s\n", warning.c_str());
    target = controller.value().target;
    what = args.controller_path;
    search::applyController(controller.value(), settings.tracking);
  }
  if (!args.balance.empty()) {
    if (Status status = applyBalanceFlag(args.balance, settings.tracking.balance); !status.ok())
      return fail(status.message());
  }
  settings.start_moving = !args.from_standing;
  settings.trace = !args.trace_path.empty();
  const physics::BodyPlan& plan = built.value();
  std::printf(
      "%s: %zu links, %d degrees of freedom, %.1f kg; tracking %s, stride %.3f s, for "
      "%.1f s on %s terrain, balance feedback %s\n",
      args.rig.c_str(), plan.links.size(), plan.dofCount(), plan.total_mass_kg, what.c_str(),
      target.period(), args.seconds, physics::terrainKindName(settings.world.terrain.kind),
      args.no_feedback ? "off" : "on");
  Result<physics::SimulationReport> run = physics::simulate(plan, skeleton, target, settings);
  if (!run.ok()) return fail(run.message());
  printReport(run.value());
  if (Status status = writeOutputs(args, rig.asset, run.value()); !status.ok())
    return fail(status.message());
  return 0;
}

}  // namespace

void addSimulateCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* command = app.add_subcommand(
      "simulate",
      "Make the rig's physical character track a clip's harmonic model with joint "
      "torques; report falls, distance, tracking error and energy");
  command->add_option("--rig", args->rig,
                      "The rig (.bvh, .glb, .gltf); default: the controller's own rig with "
                      "--controller, else the bundled biped");
  command->add_option("--clip", args->clip,
                      "The motion to track (same skeleton); default: the rig's own");
  command->add_option("--target", args->target_path,
                      "Track these harmonic coefficients (.json from sinew style) instead of the "
                      "clip's; the clip still shapes the body (joint types and limits)");
  command->add_option("--controller", args->controller_path,
                      "Replay an evolved controller (best.json from sinew evolve)");
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
  command
      ->add_option("--balance", args->balance,
                   "Balance feedback gains CD_SAGITTAL,CV_SAGITTAL,CD_CORONAL,CV_CORONAL,TORSO "
                   "(rad/m, rad/(m/s), rad/m, rad/(m/s), share 0..1), optionally then "
                   "ANKLE_SAGITTAL,ANKLE_CORONAL (rad/(m/s)),SWING_LIFT (per rig size, 0..0.1) "
                   "and then HEADING (share 0..1), then STANCE_SAGITTAL,STANCE_CORONAL,"
                   "STANCE_VERTICAL (s), then STANCE_YAW (rad/rad), then STANCE_YIELD (share 0..0.9)")
      ->delimiter(',');
  command->add_flag("--from-standing", args->from_standing,
                    "Start standing at rest and blend into the motion over 1 s (default: start "
                    "in the motion's first pose and velocities)");
  command->add_option("--harmonics", args->harmonics, "Harmonics per joint of the target")
      ->check(CLI::Range(1, 64));
  command->add_option("-o,--output", args->output,
                      "Write what the character did (.bvh, .glb, .gltf) on the rig's skeleton");
  command->add_option("--json", args->json_path, "Write the figures as JSON");
  command->add_option("--trace", args->trace_path,
                      "Write every step as CSV (.csv): centre of mass and velocity against the "
                      "target's, the stance foot, each foot's contacts, position and load, each "
                      "joint's torque and whether it is at its limit; runs of at most 120 s");
  args->import.addTo(*command);
  args->body.addTo(*command);
  command->callback([args, &exit_code]() {
    if (args->rig.empty() && !args->controller_path.empty())
      args->rig = controllerRig(args->controller_path);
    if (args->rig.empty()) args->rig = SINEW_ASSET_DIR "/biped_walk.bvh";
    exit_code = runSimulate(*args);
  });
}

}  // namespace sinew::app
