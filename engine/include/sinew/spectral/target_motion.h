// TargetMotion: what the artist wants, as a continuous, seamlessly looping function of time.
// Built from an analysed clip's harmonic model, then edited (band gains, styles); the physics
// controller tracks it and the exporters sample it. Each joint's rotation is its base rotation
// times the exponential of a rotation vector whose three channels are harmonic series; joints
// that translate add series (plus a constant travel velocity) to their base translation.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/spectral/analysis.h"
#include "sinew/spectral/harmonics.h"
#include "sinew/spectral/signals.h"

namespace sinew::spectral {

struct ChannelModel {
  int joint = 0;                     // skeleton joint index
  SignalKind kind = SignalKind::kRotation;
  int axis = 0;                      // 0 X, 1 Y, 2 Z
  double mean = 0.0;                 // A: radians (rotation vector) or metres
  std::vector<Harmonic> terms;       // the harmonics kept (n, B_n, D_n), any order
  double trend = 0.0;                // metres per second (travel); 0 for rotations
};

// Secondary motion (breathing, sway): a sinusoid on one rotation axis of a joint at a frequency
// that need not be a harmonic of the stride (breathing is slower), added to that axis's channel.
struct SecondaryTerm {
  int joint = 0;               // skeleton joint index
  int axis = 0;                // 0 X, 1 Y, 2 Z of the joint's rotation vector
  double omega = 0.0;          // rad/s, > 0
  double amplitude = 0.0;      // radians, >= 0
  double phase = 0.0;          // radians
};

struct TargetMotion {
  std::string name;                         // for exported files
  double omega0 = 0.0;                      // rad/s: 2 pi / stride period, > 0
  std::vector<glm::dquat> base_rotations;   // (joints) rotation the channels are relative to
  std::vector<glm::dvec3> base_translations;  // (joints) metres
  std::vector<glm::dvec3> base_scales;      // (joints) or empty when all 1
  std::vector<ChannelModel> channels;       // at most one per (joint, kind, axis)
  std::vector<SecondaryTerm> secondary;     // breathing and sway, on top of the channels

  double period() const { return omega0 > 0.0 ? 2.0 * 3.14159265358979323846 / omega0 : 0.0; }
  int jointCount() const { return static_cast<int>(base_rotations.size()); }

  // Sizes agree with the skeleton, omega0 positive, every number finite, channels unique.
  Status validate(const motion::Skeleton& skeleton) const;

  // The pose at time t seconds (t = 0 is the model's phase origin): local rotations and
  // translations for every joint. Preconditions: spans hold jointCount() entries.
  void pose(double t, std::span<glm::dquat> rotations, std::span<glm::dvec3> translations) const;

  // `strides` whole strides sampled at exactly `fps`: the tempo is stretched (by at most half a
  // frame per stride) so that the strides fill whole frames and the loop closes exactly; the
  // last frame repeats the first (plus travel). Precondition: validated, fps > 0, strides >= 1.
  motion::Clip sample(double fps, int strides) const;
};

// The analysed clip's model with `joint_k` harmonics per joint (spectrum.joint_k when empty),
// its phase origin at the analysed window's start.
TargetMotion targetFromSpectrum(const MotionSpectrum& spectrum, const std::vector<int>& joint_k = {},
                                const std::string& name = "target");

// Harmonic-space distance between two targets on the same skeleton with aligned phase origins:
// the RMS over channels of the L2 distance of their complex coefficients (B e^{iD}) and means.
double harmonicDistance(const TargetMotion& a, const TargetMotion& b);

// Joint-angle distance: RMS geodesic angle (degrees) between the two targets' rotations at the
// same phase of the stride (each at its own tempo), over `samples` phases and every joint.
double poseDistanceDeg(const TargetMotion& a, const TargetMotion& b, int samples = 64);

// Shifts the phase origin by `seconds` (the motion at new t = 0 is the old motion at `seconds`).
void shiftPhase(TargetMotion& target, double seconds);

}  // namespace sinew::spectral
