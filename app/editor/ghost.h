// The physics ghost (issue 15): the search's kinematic target, the motion a simulated run
// tracks, sampled at the time of the run's replayed frame and drawn over the run, each bone tinted
// by how far the run's joint turned from the target's. Plain model code: the scene draws it, the
// Evolve panel lists its figures.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "sinew/motion/clip.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::editor {

struct EditorState;

// A deviation of this many degrees or more is drawn fully red; none is the ghost's neutral grey.
inline constexpr double kGhostRedDeg = 30.0;

struct Ghost {
  int individual = -1;                   // index in the snapshot's population
  int frame = 0;                         // of the run's recording
  double time_s = 0.0;                   // simulation time of that frame, seconds from its start
  std::vector<glm::dquat> rotations;     // (joints) the target's local rotations at time_s
  std::vector<glm::dvec3> translations;  // (joints) the target's local translations, metres
  std::vector<double> deviation_rad;     // (joints) angle between the run's and the target's
                                         // local rotation, radians in [0, pi]
};

// Per joint, the angle of the rotation taking a[j] to b[j] (unit quaternions; q and -q are one
// rotation), radians in [0, pi]. Exactly 0 where a[j] == b[j]. Precondition: equal sizes.
std::vector<double> rotationDeviation_rad(std::span<const glm::dquat> a,
                                          std::span<const glm::dquat> b);

// The frame of `run` the viewport replays at playback time `time_s` (each run loops over its own
// recording). Precondition: run.frame_count >= 1.
int replayedFrame(const motion::Clip& run, double time_s);

// The target at the time of the run's frame `frame` (the simulation samples its target at its
// own clock, which starts at 0 with the recording), and the per-joint deviation from the run's
// recorded rotations there. Empty when the run and target do not match (joint counts) or the
// frame is out of range.
std::optional<Ghost> ghostAt(const spectral::TargetMotion& target, const motion::Clip& run,
                             int individual, int frame);

// Over all joints: the mean and the largest deviation, degrees, and the joint with the largest.
struct GhostSummary {
  double mean_deg = 0.0;
  double max_deg = 0.0;
  int worst_joint = -1;  // -1 for a ghost without joints
};
GhostSummary summarise(const Ghost& ghost);

// The ghost of the chosen individual (chosenIndividual) at the playback time: empty when the
// ghost or the population is not shown, no generation has finished, or it does not match.
std::optional<Ghost> currentGhost(const EditorState& state);

}  // namespace sinew::editor
