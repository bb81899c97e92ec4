// Continuous signals from a clip, ready for a DFT. Raw BVH Euler channels are never used: they
// wrap at +-180 degrees and their order varies per joint. Each moving joint's rotation becomes
// three channels, the rotation vector of its rotation relative to its mean rotation over the clip
// (quaternion signs made continuous first); each joint whose translation moves (the root, Bandai's
// Hips) gets three translation channels.
#pragma once

#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "sinew/core/rotation.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"

namespace sinew::spectral {

enum class SignalKind { kRotation, kTranslation };

struct SignalChannel {
  int joint = 0;                    // skeleton joint index
  SignalKind kind = SignalKind::kRotation;
  int axis = 0;                     // 0 X, 1 Y, 2 Z of the rotation vector or translation
  std::vector<double> values;       // (frames) radians, or metres relative to the mean
};

struct MotionSignals {
  double frame_time = 0.0;          // seconds
  int frame_count = 0;
  std::vector<glm::dquat> mean_rotations;      // (joints) chordal mean of the local rotations
  std::vector<glm::dvec3> mean_translations;   // (joints) mean local translation, metres
  std::vector<glm::dvec3> mean_scales;         // (joints) mean local scale; empty when the clip
                                               // has no scales (all 1)
  std::vector<SignalChannel> channels;         // moving joints only, joint order, X Y Z
  int travel_joint = -1;  // the first joint whose translation moves (carries root travel), or -1

  // Index into channels, or -1.
  int find(int joint, SignalKind kind, int axis) const;
};

// Rotations that move less than `min_rotation_rad` from their mean, and translations that move
// less than `min_translation_m`, are left out (static joints have nothing to analyse).
MotionSignals extractSignals(const motion::Skeleton& skeleton, const motion::Clip& clip,
                             double min_rotation_rad = 1e-4, double min_translation_m = 1e-4);

// A signal's value at a fractional frame: Catmull-Rom through the frame values, clamped at the
// ends. How the analysis resamples windows, so everything that resamples agrees with it.
// Precondition: values not empty.
double catmullRomAt(const std::vector<double>& values, double frame);

}  // namespace sinew::spectral
