// Analysis of a clip into its harmonic model, and the model's error where a viewer sees it:
// joint angles in degrees, joint and end-effector positions in centimetres.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/spectral/cycle.h"
#include "sinew/spectral/harmonics.h"
#include "sinew/spectral/signals.h"

namespace sinew::spectral {

struct AnalysisSettings {
  int harmonics = 5;              // K: harmonics kept per joint, >= 0 (0 keeps only the mean)
  bool auto_harmonics = false;    // instead, the fewest per joint keeping the worst position
                                  // error under tolerance_cm
  double tolerance_cm = 1.0;      // for auto_harmonics, centimetres, > 0
  std::vector<std::pair<std::string, int>> joint_harmonics;  // K per joint name, overrides
  int max_strides = 1;            // whole strides in the analysed window, >= 1
  CycleSettings cycle;

  Status validate() const;  // the message names the offending field
};

struct JointError {
  double rot_err_deg_rms = 0.0;  // angle between original and model rotation, RMS over frames
  double rot_err_deg_max = 0.0;
  double pos_err_cm_mean = 0.0;  // world position error, mean over frames
  double pos_err_cm_max = 0.0;
};

struct MotionSpectrum {
  MotionSignals signals;
  StrideEstimate stride;          // found == false: the whole clip is analysed as one cycle
  AnalysisWindow window;
  double period_s = 0.0;          // the analysed cycle: the window's stride, or the whole clip
                                  // when there is none
  double omega0 = 0.0;            // 2 pi / period_s, rad/s
  int samples_per_stride = 0;     // power of two
  glm::dvec3 travel_velocity{0.0};  // m/s of the travel joint over the window, parent frame
  std::vector<HarmonicSeries> series;    // (signals.channels) full measured spectrum
  std::vector<double> aperiodic_energy;  // (signals.channels) what changes stride to stride
  std::vector<double> trends;            // (signals.channels) linear trend removed before the
                                         // DFT, unit per second (translations; 0 for rotations)
  std::vector<int> joint_k;              // (joints) harmonics kept
  std::vector<JointError> joint_errors;  // (joints) error of the model with joint_k
  JointError total;  // angles over moving joints; positions over all joints and End Sites
  std::vector<std::string> notes;        // what the user should know ("no stride found: ...")

  int coefficientCount() const;  // A + 2 per kept harmonic, over every channel
};

// Where one analyze() call spent its time, seconds of steady clock per stage: what the analysis
// benchmark prints as shares. Filled only when asked for.
struct AnalysisTimings {
  double checks_s = 0.0;     // settings and clip validation
  double signals_s = 0.0;    // extractSignals
  double stride_s = 0.0;     // estimateStride
  double windows_s = 0.0;    // candidateWindows
  double fits_s = 0.0;       // every candidate window resampled and transformed
  double ranking_s = 0.0;    // every candidate's model and its position error (auto: K search)
  double result_s = 0.0;     // the chosen window's series and its full error table
  int candidates = 0;        // windows fitted

  double total() const {
    return checks_s + signals_s + stride_s + windows_s + fits_s + ranking_s + result_s;
  }
};

// `timings` (nullable) receives the time per stage.
Result<MotionSpectrum> analyze(const motion::Skeleton& skeleton, const motion::Clip& clip,
                               const AnalysisSettings& settings = {},
                               AnalysisTimings* timings = nullptr);

// The model's pose at the clip's frame times inside the analysed window: a clip of those frames
// on the same skeleton (joints that do not move keep their mean pose; travel continues at
// travel_velocity). `joint_k` chooses the harmonics per joint (spectrum.joint_k when empty).
motion::Clip reconstruct(const motion::Skeleton& skeleton, const MotionSpectrum& spectrum,
                         const std::vector<int>& joint_k = {});

// The window's original frames, to compare with reconstruct().
motion::Clip windowFrames(const motion::Clip& clip, const MotionSpectrum& spectrum);
// The frames the model describes, first..last inclusive: those whose time lies in
// [window.start_s, window.start_s + strides x period_s), within the clip. windowFrames(),
// reconstruct(), the plots and the editor's curves all take this range.
std::pair<int, int> windowFrameRange(const MotionSpectrum& spectrum);

// Per joint and total error of `model` against `original` (same frames, same skeleton).
std::vector<JointError> measureError(const motion::Skeleton& skeleton,
                                     const motion::Clip& original, const motion::Clip& model,
                                     const MotionSignals& signals, JointError* total);

}  // namespace sinew::spectral
