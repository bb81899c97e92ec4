#include "sinew/pipeline/settings.h"

#include <cmath>

namespace sinew::pipeline {
namespace {

constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

bool sameTerrain(const physics::TerrainSettings& a, const physics::TerrainSettings& b) {
  return a.kind == b.kind && a.slope_deg == b.slope_deg && a.step_height_m == b.step_height_m &&
         a.step_depth_m == b.step_depth_m && a.step_count == b.step_count &&
         a.step_start_m == b.step_start_m && a.amplitude_m == b.amplitude_m &&
         a.cell_m == b.cell_m && a.seed == b.seed;
}

bool samePush(const physics::Push& a, const physics::Push& b) {
  return a.time_s == b.time_s && a.impulse_ns == b.impulse_ns && a.link == b.link;
}

}  // namespace

Status MotionEdits::validate() const {
  for (const auto& band : band_gains) {
    for (double gain : band) {
      if (!(gain >= 0.0 && gain <= 10.0)) return Status::error("band_gains: must be 0..10");
    }
  }
  for (size_t i = 0; i < styles.size(); ++i) {
    const StylePair& pair = styles[i];
    const std::string in = "styles[" + std::to_string(i) + "].";
    if (pair.neutral.empty() || pair.styled.empty())
      return Status::error(in + "neutral/styled: both clips are needed");
    if (!(pair.weight >= -1.0 && pair.weight <= 2.0))
      return Status::error(in + "weight: must be -1..2");
  }
  for (size_t i = 0; i < secondary.size(); ++i) {
    const SecondaryMotion& m = secondary[i];
    const std::string in = "secondary[" + std::to_string(i) + "].";
    if (m.joint.empty()) return Status::error(in + "joint: missing");
    if (m.axis < 0 || m.axis > 2) return Status::error(in + "axis: must be 0, 1 or 2");
    if (!(m.frequency_hz > 0.0 && m.frequency_hz <= 30.0))
      return Status::error(in + "frequency_hz: must be in (0, 30]");
    if (!(m.amplitude_deg >= 0.0 && m.amplitude_deg <= 30.0))
      return Status::error(in + "amplitude_deg: must be 0..30");
  }
  return Status();
}

Result<physics::BodyPlanSettings> BodyOverrides::planSettings() const {
  physics::BodyPlanSettings s;
  for (const MassOverride& m : masses) s.mass_overrides.emplace_back(m.link, m.kg);
  for (const std::string& f : fixed) s.type_overrides.emplace_back(f, physics::JointType::kFixed);
  for (const HingeLimitOverride& h : hinge_limits) {
    s.hinge_limit_overrides.emplace_back(
        h.link, std::make_pair(h.lo_deg * kRadPerDeg, h.hi_deg * kRadPerDeg));
  }
  if (Status v = s.validate(); !v.ok()) return Status::error("body overrides: " + v.message());
  return s;
}

bool PhysicsSettings::operator==(const PhysicsSettings& other) const {
  if (window_s != other.window_s || !sameTerrain(terrain, other.terrain) ||
      pushes.size() != other.pushes.size() || !(body == other.body))
    return false;
  for (size_t i = 0; i < pushes.size(); ++i) {
    if (!samePush(pushes[i], other.pushes[i])) return false;
  }
  return true;
}

Status PhysicsSettings::validate() const {
  if (!(window_s >= 0.5 && window_s <= 600.0))
    return Status::error("window_s: must be 0.5..600 seconds");
  if (Status t = terrain.validate(); !t.ok()) return Status::error("terrain: " + t.message());
  for (size_t i = 0; i < pushes.size(); ++i) {
    const physics::Push& p = pushes[i];
    if (!(std::isfinite(p.time_s) && p.time_s >= 0.0) || !std::isfinite(p.impulse_ns.x) ||
        !std::isfinite(p.impulse_ns.y) || !std::isfinite(p.impulse_ns.z))
      return Status::error("pushes[" + std::to_string(i) +
                           "]: the time must be >= 0 s and the impulse finite");
  }
  if (Result<physics::BodyPlanSettings> b = body.planSettings(); !b.ok())
    return Status::error("body: " + b.message());
  return Status();
}

Status SearchSettings::validate() const {
  if (!(minutes > 0.0 && minutes <= 10000.0))
    return Status::error("search.minutes: must be more than 0 (and at most 10000)");
  if (population < 0 || population > 100000)
    return Status::error("search.population: must be 0 (the optimiser's default) or more");
  if (Status w = weights.validate(); !w.ok())
    return Status::error("search.weights: " + w.message());
  if (trials < 1 || trials > search::kMaxTrials)
    return Status::error("search.trials: must be 1.." + std::to_string(search::kMaxTrials));
  if (!(std::isfinite(trial_push_m_s) && trial_push_m_s > 0.0 && trial_push_m_s <= 10.0))
    return Status::error("search.trial_push_m_s: must be in (0, 10] m/s");
  if (!(std::isfinite(robust_push_m_s) && robust_push_m_s >= 0.0 && robust_push_m_s <= 10.0))
    return Status::error("search.robust_push_m_s: must be in [0, 10] m/s");
  if (restart_after < 0 || restart_after > 100000)
    return Status::error("search.restart_after: must be 0 (never) to 100000 generations");
  if (start_generations < 0 || start_generations > 100000)
    return Status::error("search.start_generations: must be 0 (one start) to 100000 generations");
  return Status();
}

Status ProjectSettings::validate() const {
  if (harmonics < 1 || harmonics > 64)
    return Status::error("harmonics: must be 1..64, got " + std::to_string(harmonics));
  for (const auto& [joint, k] : joint_k) {
    if (k < 0 || k > 64)
      return Status::error("joint_harmonics." + joint + ": expected a whole number 0..64");
  }
  if (Status s = physics.validate(); !s.ok()) return s;
  if (Status s = search.validate(); !s.ok()) return s;
  return edits.validate();
}

}  // namespace sinew::pipeline
