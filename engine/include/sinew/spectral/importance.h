// Joint importance: which joints could be removed (held still) at little cost. Two measures per
// moving joint: the energy of its kept harmonics, and the position error a viewer would see if
// the joint were frozen at its mean rotation while everything else follows the harmonic model.
#pragma once

#include <vector>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/spectral/analysis.h"

namespace sinew::spectral {

enum class ImportanceRank {
  kFrozenError,     // by frozen_cm_mean (default: what a viewer sees)
  kEnergy,          // by energy_rad2
  kWeightedEnergy,  // by weighted_energy_m2 (energy x lever arm squared)
};

struct ImportanceSettings {
  ImportanceRank rank_by = ImportanceRank::kFrozenError;  // how the report is ordered

  Status validate() const;  // the message names the offending field
};

struct JointImportance {
  int joint = 0;                    // skeleton joint index
  double energy_rad2 = 0.0;         // sum of squared amplitudes of the kept harmonics over the
                                    // joint's three rotation channels, radians^2
  double lever_m = 0.0;             // distance from the joint to the furthest joint or End Site
                                    // it carries, in the mean pose, metres
  double weighted_energy_m2 = 0.0;  // energy_rad2 x lever_m^2: roughly the squared sway its
                                    // rotation gives its furthest point, m^2
  double frozen_cm_mean = 0.0;      // position error of every joint and End Site against the
                                    // original frames with this joint frozen, cm, mean over points
                                    // and frames
  double frozen_cm_max = 0.0;       // ... and worst
};

struct ImportanceReport {
  std::vector<JointImportance> joints;  // moving joints (rotation channels), most important first
  double model_cm_mean = 0.0;           // the unfrozen model's error, for comparison, cm
  double model_cm_max = 0.0;
};

// For each joint with rotation channels in `spectrum` (analyze() of the same skeleton and clip):
// reconstruct() the model, overwrite that joint's rotation with its mean (the chordal mean and
// the series' constant terms) in every frame, and measureError() against the window's frames.
Result<ImportanceReport> jointImportance(const motion::Skeleton& skeleton, const motion::Clip& clip,
                                         const MotionSpectrum& spectrum,
                                         const ImportanceSettings& settings = {});

}  // namespace sinew::spectral
