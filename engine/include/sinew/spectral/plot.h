// Plots of a MotionSpectrum for people who would rather look than read: one row per joint, its
// rotation over the analysed window (the original and the K-harmonic model, degrees) beside the
// amplitudes of its harmonics. Plain SVG 1.1 written by hand: no dependency, and any browser,
// Inkscape or rsvg-convert shows it.
#pragma once

#include <string>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/spectral/analysis.h"

namespace sinew::spectral {

struct PlotSettings {
  std::vector<std::string> joints;  // joint names, one row each in this order; empty: the
                                    // `default_joint_count` joints of largest rotation amplitude,
                                    // in skeleton order
  int default_joint_count = 4;      // >= 1
  int max_harmonic = 12;            // bars for n = 1..max_harmonic (fewer when the spectrum has
                                    // fewer), >= 1

  Status validate() const;  // the message names the offending field
};

// One rotation channel of a joint, as plotted.
struct PlotChannel {
  int channel = 0;                    // index into spectrum.signals.channels
  int axis = 0;                       // 0 X, 1 Y, 2 Z of the rotation vector
  std::vector<double> original_deg;   // (frames) the signal at the window's frames, degrees
  std::vector<double> model_deg;      // (frames) the joint's K kept harmonics at the same
                                      // times, degrees
  std::vector<double> amplitude_deg;  // (harmonics) B_n for n = 1, 2, ..., degrees
  std::vector<bool> kept;             // (harmonics) among the joint's K strongest
};

struct PlotRow {
  int joint = 0;                      // skeleton joint index
  std::string name;                   // its name
  int k = 0;                          // harmonics kept
  JointError error;                   // the model's error for this joint
  std::vector<PlotChannel> channels;  // X, Y, Z
};

// What the SVG draws, so that it can be checked without parsing the drawing.
struct PlotData {
  std::string clip_name;
  int first_frame = 0;          // the window's first frame in the clip
  std::vector<double> times_s;  // (frames) seconds from the window start, frame * dt - start_s
  int harmonics = 0;            // bars per channel
  std::vector<PlotRow> rows;
};

// The curves and bars for `settings.joints`. Refused: invalid settings, a spectrum that was not
// analysed from this clip, an unknown joint name or one that does not rotate (the message names
// it).
Result<PlotData> preparePlot(const motion::Skeleton& skeleton, const motion::Clip& clip,
                             const MotionSpectrum& spectrum, const PlotSettings& settings = {});

// The SVG document (UTF-8), 1200 px wide and 260 px per row below a title block.
std::string renderPlotSvg(const MotionSpectrum& spectrum, const PlotData& plot);

// preparePlot, then renderPlotSvg.
Result<std::string> plotSvg(const motion::Skeleton& skeleton, const motion::Clip& clip,
                            const MotionSpectrum& spectrum, const PlotSettings& settings = {});

}  // namespace sinew::spectral
