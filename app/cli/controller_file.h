// Shared by `sinew simulate` and `sinew evolve`: loading a rig with the motion to track, parsing
// terrain and pushes, and the evolved controller file (best.json).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/commands.h"
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

// A project (format "sinew.project", version 1, JSON): what to evolve or simulate, so a pipeline
// names one file. Paths inside are relative to the project file. Fields: "rig" (required),
// "clip", "animation", "target" (coefficients .json), "harmonics" (5), "terrain" ("flat"),
// "window_s" (10), "pushes" (["TIME,X,Y,Z[,LINK]"...]), "body": {"masses": ["NAME=KG"...],
// "fixed": [NAME...], "hinge_limits": ["NAME=LO,HI"...]}. The bundled default project
// (assets/default.sinew.json) is the walk the editor opens.
struct ProjectFile {
  std::string rig, clip, animation, target;
  int harmonics = 5;
  std::string terrain = "flat";
  double window_s = 10.0;
  std::vector<std::string> pushes;
  BodyFlags body;
};
Result<ProjectFile> loadProject(const std::filesystem::path& path);
inline constexpr const char* kDefaultProject = SINEW_ASSET_DIR "/default.sinew.json";

Result<LoadedRig> loadRigAndTarget(const std::string& rig_path, const std::string& clip_path,
                                   const std::string& target_path, const std::string& animation,
                                   int harmonics, const ImportFlags& import,
                                   const BodyFlags& body = {});

// "flat", "slope:5", "steps:0.05,0.6", "rough:0.02,7".
Result<physics::TerrainSettings> parseTerrain(const std::string& text);
// "TIME,X,Y,Z[,LINK]".
Result<physics::Push> parsePush(const std::string& text);

}  // namespace sinew::app
