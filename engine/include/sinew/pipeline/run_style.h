// How much of the requested style survived the physics: a simulated run's style measured against
// the project's style pairs, beside the tracked target's, the way `sinew style --measure
// --neutral` measures a clip (each motion analysed with pipeline::kStyleHarmonics, scored against
// a library of the pairs and their neutral; and its amount along each pair's style).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/pipeline/settings.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::pipeline {

struct MeasuredStyle {
  double score = 0.0;   // spectral::scoreStyleRelative's score of the label, 0..1
  double amount = 0.0;  // spectral::styleAmount along the pair: 0 the neutral, 1 the styled clip
};

struct StyleSurvival {
  std::string label;
  double weight = 0.0;        // as requested
  MeasuredStyle target;       // the motion the search tracked
  bool simulated_measured = false;
  MeasuredStyle simulated;    // the run (valid when simulated_measured)
  std::string not_measured;   // why the run could not be measured (too short, no stride)
};

struct RunStyleReport {
  std::vector<StyleSurvival> styles;  // (edits.styles) in order
  std::string target_closest, simulated_closest;  // "neutral" or a label; empty: not measured

  // "tired (weight 1.00): target score 1.00 amount 1.00, simulated score 0.83 amount 0.71", a
  // line per style.
  std::vector<std::string> lines() const;
  nlohmann::json json() const;
};

// The style of `run` (what the simulation did, on `skeleton`, from its start; the first
// `skip_s` seconds, the settling stride, left out; its stride looked for near `stride_s`, the
// controller's) and of `tracked`, against each pair of
// `edits.styles` (the library: "neutral" and every pair). The message names a pair that cannot be
// measured; a run that cannot be analysed is reported as not measured, not as an error.
Result<RunStyleReport> measureRunStyle(const motion::Skeleton& skeleton,
                                       const spectral::TargetMotion& tracked,
                                       const motion::Clip& run, double skip_s,
                                       double stride_s, const MotionEdits& edits);

}  // namespace sinew::pipeline
