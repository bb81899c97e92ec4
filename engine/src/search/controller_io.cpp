#include "sinew/search/controller_io.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <initializer_list>

#include "sinew/core/file_io.h"
#include "sinew/core/json_keys.h"
#include "sinew/core/path_json.h"
#include "sinew/core/text.h"
#include "sinew/spectral/target_io.h"
#include "state_json.h"

namespace sinew::search {

namespace {

nlohmann::json balanceJson(physics::BalanceGains gains) {
  nlohmann::json json = nlohmann::json::object();
  for (int i = 0; i < physics::kBalanceGainCount; ++i)
    json[physics::balanceGainName(i)] = physics::balanceGain(gains, i);
  return json;
}

}  // namespace

void applyController(const ControllerFile& controller, physics::TrackingSettings& tracking) {
  tracking.balance = controller.balance;
  tracking.servo_lead_s = controller.servo_lead_s;
  tracking.lead_yielding_legs = controller.lead_yielding_legs;
}

Status saveController(const std::filesystem::path& path, const ControllerFile& c,
                      const motion::Skeleton& skeleton) {
  nlohmann::json json = {
      {"format", "sinew.controller"},
      {"version", 1},
      {"target", nlohmann::json::parse(spectral::targetToJson(c.target, skeleton))},
      {"balance", balanceJson(c.balance)},
      {"settings",
       {{"window_s", c.window_s},
        {"terrain", c.terrain},
        {"seed", c.seed},
        {"optimizer", c.optimizer},
        {"no_prior", c.no_prior},
        {"servo_lead_s", c.servo_lead_s},
        {"lead_yielding_legs", c.lead_yielding_legs}}},
      {"fitness", fitnessJson(c.fitness)}};
  writePathJson(json, "rig", c.rig);
  writePathJson(json, "clip", c.clip);
  return writeFileAtomically(
      path, json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

namespace {

// The first five gains are required; the ankle gains, swing_lift, heading and the stance gains
// (stance_yaw, then stance_yield) came later: a file without them replays with them off (0).
Status readBalance(const nlohmann::json& json, const std::string& name, ControllerFile& c) {
  using namespace state_json;
  Result<const nlohmann::json*> b = field(json, "balance", name);
  if (!b.ok()) return b.status();
  const std::string where = name + ": balance";
  std::vector<const char*> known;
  for (int i = 0; i < physics::kBalanceGainCount; ++i) known.push_back(physics::balanceGainName(i));
  unknownKeys(*b.value(), known, where, &c.warnings);
  for (int i = 0; i < physics::kBalanceGainCount; ++i) {
    const char* key = physics::balanceGainName(i);
    double& gain = physics::balanceGain(c.balance, i);
    if (i >= 5 && b.value()->is_object() && !b.value()->contains(key)) {
      gain = 0.0;
      continue;
    }
    if (Status s = readNumber(*b.value(), key, where, gain); !s.ok()) return s;
    const double limit = physics::balanceGainLimit(i, kMaxBalanceGain);
    const bool share = physics::balanceGainIsShare(i);
    if (share ? !(gain >= 0.0 && gain <= limit) : !(std::abs(gain) <= limit))
      return Status::error(where + ": " + key + ": expected " + (share ? "a share " : "a gain ") +
                           physics::balanceGainRule(i, kMaxBalanceGain));
  }
  return {};
}

Status readSettings(const nlohmann::json& json, const std::string& name, ControllerFile& c) {
  using namespace state_json;
  Result<const nlohmann::json*> found = field(json, "settings", name);
  if (!found.ok()) return found.status();
  const nlohmann::json& s = *found.value();
  const std::string where = name + ": settings";
  unknownKeys(s,
              {"window_s", "terrain", "seed", "optimizer", "no_prior", "servo_lead_s",
               "lead_yielding_legs"},
              where, &c.warnings);
  if (Status st = readNumber(s, "window_s", where, c.window_s); !st.ok()) return st;
  if (!(c.window_s > 0.0 && c.window_s <= 3600.0))
    return Status::error(where + ": window_s: expected seconds in (0, 3600]");
  if (Status st = readString(s, "terrain", where, c.terrain); !st.ok()) return st;
  if (Status st = readUint64(s, "seed", where, c.seed); !st.ok()) return st;
  if (Status st = readString(s, "optimizer", where, c.optimizer); !st.ok()) return st;
  if (Status st = readBool(s, "no_prior", where, c.no_prior); !st.ok()) return st;
  // Searched before the servos led their targets: replayed without a lead (ControllerFile's 0),
  // as it was searched; before the yielding legs were led further, without that.
  if (!s.contains("servo_lead_s")) return {};
  if (Status st = readNumber(s, "servo_lead_s", where, c.servo_lead_s); !st.ok()) return st;
  if (!physics::validServoLead(c.servo_lead_s))
    return Status::error(where + ": servo_lead_s: expected seconds in [0, 1]");
  if (!s.contains("lead_yielding_legs")) return {};
  return readBool(s, "lead_yielding_legs", where, c.lead_yielding_legs);
}

}  // namespace

Result<ControllerFile> loadController(const std::filesystem::path& path,
                                      const motion::Skeleton& skeleton) {
  Result<std::string> text = readFile(path);
  if (!text.ok()) return text.status();
  return controllerFromJson(text.value(), skeleton, path.string());
}

Result<ControllerFile> controllerFromJson(std::string_view text, const motion::Skeleton& skeleton,
                                          const std::string& name) {
  try {  // nothing below throws on purpose; a library surprise still becomes a message
    const nlohmann::json json = nlohmann::json::parse(withoutBom(text), nullptr, false);
    if (json.is_discarded() || !json.is_object())
      return Status::error(name + ": not valid JSON (a sinew.controller object)");
    if (json.value("format", nlohmann::json()) != "sinew.controller")
      return Status::error(name +
                           ": format: expected \"sinew.controller\" (a best.json from "
                           "sinew evolve)");
    int version = 0;
    if (Status s = state_json::readInt(json, "version", name, 1, 1, version); !s.ok()) return s;
    ControllerFile c;
    unknownKeys(json,
                {"format", "version", "rig", "rig_encoding", "clip", "clip_encoding", "target",
                 "balance", "settings", "fitness"},
                name, &c.warnings);
    if (!json.contains("target"))
      return Status::error(name +
                           ": target: missing (the controller's coefficients; a best.json "
                           "from sinew evolve has them)");
    Result<spectral::TargetMotion> target = spectral::targetFromJson(
        json.at("target").dump(), skeleton, name + ": target", &c.warnings);
    if (!target.ok()) return target.status();
    c.target = std::move(target).value();
    if (Status s = readBalance(json, name, c); !s.ok()) return s;
    if (Status s = readSettings(json, name, c); !s.ok()) return s;
    if (json.contains("fitness")) {
      Result<FitnessTerms> fitness = fitnessFromJson(json.at("fitness"));
      if (!fitness.ok()) return Status::error(name + ": fitness: " + fitness.message());
      c.fitness = fitness.value();
    }
    if (Status s = readPathJson(json, "rig", c.rig, name + ": "); !s.ok()) return s;
    if (Status s = readPathJson(json, "clip", c.clip, name + ": "); !s.ok()) return s;
    return c;
  } catch (const std::exception& e) {
    return Status::error(name + ": " + e.what());
  }
}

Status exportBest(const Problem& problem, std::span<const double> point,
                  const FitnessTerms& fitness, const motion::MotionAsset& rig,
                  const std::filesystem::path& dir, ControllerFile meta) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Status::error(dir.string() + ": cannot create the folder: " + ec.message());
  meta.target = problem.layout.decodeTarget(point);
  meta.balance = problem.layout.decodeGains(point);
  meta.window_s = problem.simulation.seconds;
  meta.servo_lead_s = problem.simulation.tracking.servo_lead_s;
  meta.lead_yielding_legs = problem.simulation.tracking.lead_yielding_legs;
  meta.fitness = fitness;
  if (Status s = saveController(dir / "best.json", meta, rig.skeleton); !s.ok()) return s;
  const Evaluation replay = evaluate(problem, point, nullptr, true);
  for (const char* name : {"best.bvh", "best.glb"})
    if (Status s = motion::exportMotion(dir / name, rig, replay.report.motion); !s.ok()) return s;
  return Status();
}

}  // namespace sinew::search
