// The stride: the period of a full gait cycle (left and right foot both step), never a single
// step. Left/right asymmetric channels decide: a leg's rotation half a stride later is the other
// leg's, not its own, so only the full stride makes every channel repeat.
#pragma once

#include <string>
#include <vector>

#include "sinew/spectral/signals.h"

namespace sinew::spectral {

struct CycleSettings {
  double min_period_s = 0.25;    // shortest stride looked for, seconds
  double max_period_s = 4.0;     // longest stride looked for, seconds
  double min_similarity = 0.6;   // below this at the best lag: no stride (0..1)
};

struct StrideEstimate {
  bool found = false;
  double period_s = 0.0;     // the stride, seconds (sub-frame precision)
  double similarity = 0.0;   // 1 - (mean squared change over one period) / (2 * variance), 0..1
  double foot_similarity = 0.0;  // the same for the feet's heights (0 without feet)
  bool feet_checked = false;     // the feet's heights took part in choosing the stride
  std::string message;       // why no stride was found, for the user
};

// Finds the shortest lag at which the whole pose repeats: the first strong peak of the
// variance-weighted similarity of every rotation channel with itself shifted by that lag,
// refined between frames by a parabola and on the repeats while they stay as strong.
//
// `foot_heights` (feet x frames, metres; may be empty) cross-checks the choice: a foot's height
// repeats only over the whole stride (half a stride later the other foot is the one in the air),
// so when several peaks are nearly as strong, the first whose mean of the pose's and the feet's
// similarity is nearly the best wins. That decides a slow walk whose every large channel moves
// twice a stride (trunk, arms, knees) and whose stride-to-stride variation makes the step look
// as periodic as the stride.
StrideEstimate estimateStride(const MotionSignals& signals, const CycleSettings& settings = {},
                              const std::vector<std::vector<double>>& foot_heights = {});

struct AnalysisWindow {
  double start_s = 0.0;   // window start, seconds from the clip's first frame
  int strides = 1;        // whole strides in the window
  double period_s = 0.0;  // this window's stride length: real strides vary, so it may differ
                          // from the clip's average stride by up to `period_slack`
  double seam = 0.0;      // RMS change of the rotation channels from start to end, radians
};

// Windows of 1..max_strides whole strides that fit in the clip, with a stride length within
// period_slack (a fraction) of `period_s`, and at least half the activity (gait-channel
// variance) of the most active such window (a still stretch would fit any model), ranked by their
// loop seam (value and slope of every gait channel at the end against the start), lowest first;
// at most `count`, with starts at least two frames apart so that the candidates differ.
std::vector<AnalysisWindow> candidateWindows(const MotionSignals& signals, double period_s,
                                             int max_strides, double period_slack = 0.05,
                                             int count = 12);

}  // namespace sinew::spectral
