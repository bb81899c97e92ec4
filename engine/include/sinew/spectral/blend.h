// Blending in harmonic space (Unuma et al.'s idea): two clips of one skeleton (walk and run,
// normal and happy) mixed by a weight, or a transition from one to the other over a time span,
// by interpolating phase-aligned coefficients and tempo.
#pragma once

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::spectral {

// The mix at weight u in [0, 1] (0 = a, 1 = b): b is phase-aligned to a first (on a's strongest
// fundamental); tempo and travel speed interpolate in log space, base rotations by slerp,
// amplitudes and means linearly and phases along the shorter way round. Exactly a at u = 0, and
// b (aligned) at u = 1 except that along travel axes the position stays a's: where each clip was
// captured is not part of its motion.
Result<TargetMotion> blendTargets(const TargetMotion& a, const TargetMotion& b, double u);

struct Transition {
  double start_s = 1.0;     // when the change from a to b begins, seconds, >= 0
  double duration_s = 1.0;  // how long it takes (smoothstep), seconds, > 0
  double total_s = 4.0;     // length of the result, seconds, > 0
  double fps = 30.0;        // frames per second, > 0
};

// A clip that plays a, turns into b over the span, then plays b. The stride's phase is integrated
// through the changing tempo and the travel through the changing speed, so nothing jumps.
Result<motion::Clip> transitionClip(const TargetMotion& a, const TargetMotion& b,
                                    const Transition& transition);

}  // namespace sinew::spectral
