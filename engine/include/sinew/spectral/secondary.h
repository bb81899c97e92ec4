// Secondary motion: breathing and sway as low-amplitude periodic motion or band-limited noise on
// chosen joints, deterministic by seed (the paper's "mixing in random higher frequencies").
// Frequencies are snapped to multiples of omega0 / loop_strides, so that a sampled loop of
// loop_strides strides (or a multiple) still closes exactly, even for breathing slower than
// the stride.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/motion/skeleton.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::spectral {

struct SecondarySource {
  enum class Kind { kPeriodic, kNoise };
  Kind kind = Kind::kPeriodic;
  std::string joint;            // joint name
  int axis = 0;                 // 0 X, 1 Y, 2 Z of the joint's rotation vector
  double frequency_hz = 0.25;   // periodic: the frequency; noise: the band's upper edge; > 0
  double amplitude_deg = 1.0;   // periodic: amplitude; noise: RMS; degrees, in [0, 30]
  std::uint64_t seed = 1;       // noise: the same seed gives the same motion everywhere
};

struct SecondarySettings {
  int loop_strides = 4;                  // loops close every this many strides, >= 1
  int noise_terms = 6;                   // sinusoids per noise source, >= 1
  std::vector<SecondarySource> sources;
};

// `target` with the sources' terms added (replacing none). The message names a bad source.
Result<TargetMotion> addSecondaryMotion(const TargetMotion& target,
                                        const motion::Skeleton& skeleton,
                                        const SecondarySettings& settings);

}  // namespace sinew::spectral
