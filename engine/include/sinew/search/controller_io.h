// An evolved controller on disk (best.json): the coefficients (as a spectral target JSON), the
// balance gains, how it was made and its fitness. Format "sinew.controller", version 1. Written by
// `sinew evolve` and the editor, read by `sinew simulate --controller`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/motion/asset.h"
#include "sinew/motion/skeleton.h"
#include "sinew/physics/tracking.h"
#include "sinew/search/problem.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::search {

// Balance gains a controller file may hold: cd and cv within +-this (rad/m, rad/(m/s)); torso
// is a share in [0, 1]. Searches explore +-GenomeSettings::gain_range (default 1).
inline constexpr double kMaxBalanceGain = 100.0;

struct ControllerFile {
  spectral::TargetMotion target;
  physics::BalanceGains balance;
  double window_s = 10.0;
  std::string terrain = "flat";
  std::uint64_t seed = 1;
  std::string optimizer;
  bool no_prior = false;
  double servo_lead_s = 0.0;  // physics::TrackingSettings::servo_lead_s the search ran with
  bool lead_yielding_legs = false;  // and its lead_yielding_legs
  FitnessTerms fitness;
  std::string rig;
  std::string clip;
  std::vector<std::string> warnings;  // read, not written: unknown keys, with the file and field
};
// What a replay of the controller takes from it besides the target: its balance gains and the
// servo lead it was searched with.
void applyController(const ControllerFile& controller, physics::TrackingSettings& tracking);
// Saved atomically (a failed save keeps the old file); loading names the file and the field.
Status saveController(const std::filesystem::path& path, const ControllerFile& controller,
                      const motion::Skeleton& skeleton);
Result<ControllerFile> loadController(const std::filesystem::path& path,
                                      const motion::Skeleton& skeleton);
// The same from text in memory; `name` is the file in messages.
Result<ControllerFile> controllerFromJson(std::string_view text, const motion::Skeleton& skeleton,
                                          const std::string& name);


// The best of a search, written into `dir` (created if needed): best.json (the controller, with
// `meta`'s provenance and `fitness`), and best.bvh and best.glb (what the controller does when
// replayed over the problem's window, on `rig`'s skeleton; the .glb with the rig's mesh when it
// came from glTF). Fails, naming the file, without touching files already written.
Status exportBest(const Problem& problem, std::span<const double> point, const FitnessTerms& fitness,
                  const motion::MotionAsset& rig, const std::filesystem::path& dir,
                  ControllerFile meta);

}  // namespace sinew::search
