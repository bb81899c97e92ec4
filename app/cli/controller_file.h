// Shared by `sinew simulate` and `sinew evolve`: loading a rig and the clip to track, and the body
// overrides' flags. What is tracked and the search are the engine's (sinew/pipeline/pipeline.h);
// terrain and push grammars and projects: project/project.h.
#pragma once

#include <string>
#include <vector>

#include "cli/commands.h"
#include "project/project.h"
#include "sinew/motion/asset.h"

namespace sinew::app {

// A rig and the clip to track: the rig's own, or one of another file with the same skeleton.
struct LoadedRig {
  motion::MotionAsset asset;  // the rig: its skeleton is the character's
  motion::MotionAsset other;  // the clip's file, when it is not the rig
  bool from_other = false;
  int clip_index = 0;
  const motion::Clip& clip() const {
    return (from_other ? other : asset).clips[static_cast<size_t>(clip_index)];
  }
};
// Loads `settings.rig` and, when given, `settings.clip` (its skeleton must be the rig's), and
// chooses `settings.animation`.
Result<LoadedRig> loadRig(const pipeline::ProjectSettings& settings, const ImportFlags& import);

// The body plan's overrides from the command line: --mass NAME=KG, --fixed NAME,
// --hinge-limits NAME=LO,HI (degrees); each repeatable.
struct BodyFlags {
  std::vector<std::string> masses;
  std::vector<std::string> fixed;
  std::vector<std::string> hinge_limits;
  void addTo(CLI::App& command);
  Result<BodyOverrides> overrides() const;  // the message names the flag
};

inline constexpr const char* kDefaultProject = SINEW_ASSET_DIR "/default.sinew.json";

}  // namespace sinew::app
