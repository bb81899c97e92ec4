// Indirect signals: what the joint rotations imply without stating it. Which joints are feet,
// when each foot is on the ground, where it lands (steps and strides), and where the centre of
// mass goes. The stride measured from foot contacts cross-checks the one analyze() found in the
// rotation signals, and the signals get harmonic spectra of their own over the same window.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/anatomy.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/spectral/analysis.h"
#include "sinew/spectral/harmonics.h"

namespace sinew::spectral {

// Anatomy lives in motion (anatomy.h); these names stay here for the analysis code that reads them.
using motion::centreOfMass;
using motion::findFeet;
using motion::Foot;
using motion::FootPoint;
using motion::MassDistribution;
using motion::massDistribution;
using motion::Segment;
using motion::SegmentMassTable;
using motion::segmentName;
using motion::Side;
using motion::sideName;




struct ContactSettings {
  double height_tolerance_m = 0.05;  // a foot is down while its contact point is within this of
                                     // the foot's own ground level, metres, > 0
  double speed_tolerance_m_s = 0.4;  // ... and the contact point moves horizontally slower than
                                     // this, metres per second, > 0
  double ground_quantile = 0.25;     // the foot's ground level: this quantile of its contact
                                     // point's height over the frames where it moves slower than
                                     // speed_tolerance_m_s (where it rests), 0..1
  double max_gap_s = 0.07;           // breaks in a contact up to this long are filled, s, >= 0
  double min_contact_s = 0.07;       // contacts shorter than this are dropped, s, >= 0

  Status validate() const;  // the message names the offending field
};



struct IndirectSettings {
  ContactSettings contacts;
  SegmentMassTable masses;

  Status validate() const;
};

struct Footfall {
  int foot = 0;              // index into IndirectSignals::feet
  int frame = 0;             // first frame of the contact
  double time_s = 0.0;       // seconds from the clip's first frame
  double duration_s = 0.0;   // how long the foot stays down (to the clip's end if it does)
  glm::dvec3 position{0.0};  // the contact point at touchdown, world metres
};

// From one foot's footfall to the next footfall of its pair's other foot.
struct Step {
  int from = 0;  // index into IndirectSignals::footfalls
  int to = 0;
  double length_m = 0.0;    // along the travel direction, metres
  double width_m = 0.0;     // across it, metres (>= 0)
  double duration_s = 0.0;  // seconds
};

// A signal other than a joint channel, fitted over the analysed window like the joints.
struct IndirectSeries {
  std::string name;  // "com height", "com lateral", "LeftFoot contact", ...
  std::string unit;  // "m", or "" for the 0/1 contact indicator
  HarmonicSeries series;
  double aperiodic_energy = 0.0;  // what changes from stride to stride, unit squared
};

struct GaitFigures {
  double stride_period_s = 0.0;    // mean interval between successive touchdowns of the same
                                   // foot, seconds; 0 when no foot lands twice
  int stride_intervals = 0;        // intervals averaged
  double analysis_period_s = 0.0;  // analyze()'s stride (0 when it found none)
  double period_difference = 0.0;  // stride_period_s / analysis_period_s - 1 (0 when either is 0)
  double stride_length_m = 0.0;    // mean horizontal distance between successive touchdowns of the
                                   // same foot, metres
  double step_length_m = 0.0;      // means over the steps
  double step_width_m = 0.0;
  double step_duration_s = 0.0;
  double duty_factor = 0.0;        // mean fraction of the time a foot is down, 0..1
  double speed_m_s = 0.0;          // horizontal speed of the centre of mass over the analysed
                                   // window, m/s
  double contact_speed_m_s = 0.0;  // stride_length_m / stride_period_s: the speed the footfalls
                                   // imply over the whole clip, m/s (0 without strides)
};

struct IndirectSignals {
  double frame_time = 0.0;  // the clip's, seconds
  std::vector<Foot> feet;
  std::vector<double> ground_levels_m;               // (feet) each foot's ground level, metres
  std::vector<std::vector<double>> foot_heights_m;   // (feet x frames) contact point above the
                                                     // foot's ground level, metres
  std::vector<std::vector<double>> foot_speeds_m_s;  // (feet x frames) its horizontal speed
  std::vector<std::vector<std::uint8_t>> contacts;   // (feet x frames) 1 while the foot is down
  std::vector<Footfall> footfalls;  // in time order; a contact already under way in the first
                                    // frame has no touchdown and is not one
  std::vector<Step> steps;          // in time order
  MassDistribution masses;
  std::vector<glm::dvec3> com;        // (frames) centre of mass, world metres
  glm::dvec3 forward{0.0, 0.0, 1.0};  // horizontal unit travel direction over the window (the
                                      // hips' facing when the clip runs in place)
  glm::dvec3 left{1.0, 0.0, 0.0};     // horizontal unit vector to the figure's left
  GaitFigures gait;
  std::vector<IndirectSeries> spectra;  // com height, lateral and forward sway, then per foot
                                        // its contact indicator and height
  std::vector<std::string> notes;       // what the user should know
};

// Every indirect signal of `clip`, whose harmonic analysis is `spectrum` (analyze() of the same
// skeleton and clip): its window is the one the spectra cover.
Result<IndirectSignals> analyzeIndirect(const motion::Skeleton& skeleton, const motion::Clip& clip,
                                        const MotionSpectrum& spectrum,
                                        const IndirectSettings& settings = {});

}  // namespace sinew::spectral
