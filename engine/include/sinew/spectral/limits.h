// Limits of a harmonic model that every reader of coefficients (target and controller files,
// checkpoints) checks and TargetMotion::validate enforces (docs/formats.md lists them). Past
// them a model is not a motion, and the highest index sizes per-channel buffers: an index of
// 1e9 would ask for 16 GB.
#pragma once

namespace sinew::spectral {

inline constexpr int kMaxHarmonicIndex = 1024;        // n in C_n = n omega0, whole, 1..this
inline constexpr int kMaxHarmonicsPerChannel = 1024;  // terms in one channel's series
inline constexpr double kMaxOmega_rad_s = 1e4;        // omega0 and secondary omegas, > 0
inline constexpr double kMaxCoefficient = 1e6;        // |mean|, |amplitude|, |trend|, |phase|:
                                                      // radians or metres (per second)

}  // namespace sinew::spectral
