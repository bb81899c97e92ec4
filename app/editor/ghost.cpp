#include "editor/ghost.h"

#include <algorithm>
#include <cmath>

#include "editor/editor_state.h"

namespace sinew::editor {

std::vector<double> rotationDeviation_rad(std::span<const glm::dquat> a,
                                          std::span<const glm::dquat> b) {
  std::vector<double> angles(std::min(a.size(), b.size()), 0.0);
  for (size_t j = 0; j < angles.size(); ++j) {
    // The relative rotation's half-angle from its vector part and |w|: exact 0 for equal inputs
    // (where acos of a rounded dot product reads 1e-8), and q ~ -q.
    const glm::dquat d = glm::conjugate(a[j]) * b[j];
    const double sin_half = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    angles[j] = 2.0 * std::atan2(sin_half, std::abs(d.w));
  }
  return angles;
}

int replayedFrame(const motion::Clip& run, double time_s) {
  if (!(run.frame_time > 0.0) || run.frame_count < 1) return 0;
  const double duration = std::max(run.duration(), run.frame_time);
  const double t = std::fmod(std::max(time_s, 0.0), duration);
  return std::clamp(static_cast<int>(t / run.frame_time), 0, run.frame_count - 1);
}

std::optional<Ghost> ghostAt(const spectral::TargetMotion& target, const motion::Clip& run,
                             int individual, int frame) {
  const int joints = run.joint_count;
  if (joints < 1 || target.jointCount() != joints || frame < 0 || frame >= run.frame_count ||
      run.rotations.size() < static_cast<size_t>(run.frame_count) * static_cast<size_t>(joints))
    return std::nullopt;
  Ghost ghost;
  ghost.individual = individual;
  ghost.frame = frame;
  ghost.time_s = frame * run.frame_time;
  ghost.rotations.resize(static_cast<size_t>(joints));
  ghost.translations.resize(static_cast<size_t>(joints));
  target.pose(ghost.time_s, ghost.rotations, ghost.translations);
  const std::span<const glm::dquat> simulated(&run.rotation(frame, 0), static_cast<size_t>(joints));
  ghost.deviation_rad = rotationDeviation_rad(simulated, ghost.rotations);
  return ghost;
}

GhostSummary summarise(const Ghost& ghost) {
  GhostSummary summary;
  double sum = 0.0;
  for (size_t j = 0; j < ghost.deviation_rad.size(); ++j) {
    const double deg = glm::degrees(ghost.deviation_rad[j]);
    sum += deg;
    if (summary.worst_joint < 0 || deg > summary.max_deg) {
      summary.max_deg = deg;
      summary.worst_joint = static_cast<int>(j);
    }
  }
  if (!ghost.deviation_rad.empty()) summary.mean_deg = sum / ghost.deviation_rad.size();
  return summary;
}

std::optional<Ghost> currentGhost(const EditorState& state) {
  const EvolutionState& evolution = state.evolution;
  if (!evolution.show_ghost || !evolution.show_population || !evolution.session ||
      !evolution.snapshot)
    return std::nullopt;
  const int chosen = chosenIndividual(evolution);
  if (chosen < 0) return std::nullopt;
  const motion::Clip& run = evolution.snapshot->population_motions[static_cast<size_t>(chosen)];
  if (run.frame_count < 1) return std::nullopt;
  return ghostAt(evolution.session->problem().seed, run, chosen,
                 replayedFrame(run, state.playback.time_s));
}

}  // namespace sinew::editor
