// Shared by `sinew simulate` and `sinew evolve`: loading a rig with the motion to track and the
// body overrides' flags. (Terrain and push grammars and projects: project/project.h.)
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "project/project.h"
#include "sinew/physics/body_plan.h"
#include "sinew/physics/simulation.h"
#include "sinew/search/controller_io.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::app {

// A rig, its body plan (from the clip) and the motion to track: the clip's harmonic model with K
// per joint, or coefficients from a JSON file (`target_path`).
struct LoadedRig {
  motion::MotionAsset asset;
  physics::BodyPlan plan;
  spectral::TargetMotion target;
  std::string what;  // for messages: "'walk' (K = 5)" or the coefficient file
};
// The body plan's overrides from the command line: --mass NAME=KG, --fixed NAME,
// --hinge-limits NAME=LO,HI (degrees); each repeatable.
struct BodyFlags {
  std::vector<std::string> masses;
  std::vector<std::string> fixed;
  std::vector<std::string> hinge_limits;
  void addTo(CLI::App& command);
  Result<physics::BodyPlanSettings> settings() const;  // the message names the flag
};

inline constexpr const char* kDefaultProject = SINEW_ASSET_DIR "/default.sinew.json";

Result<LoadedRig> loadRigAndTarget(const std::string& rig_path, const std::string& clip_path,
                                   const std::string& target_path, const std::string& animation,
                                   int harmonics, const ImportFlags& import,
                                   const BodyFlags& body = {},
                                   const std::map<std::string, int>& joint_k = {});

}  // namespace sinew::app
