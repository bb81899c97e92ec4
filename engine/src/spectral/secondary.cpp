#include "sinew/spectral/secondary.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace sinew::spectral {
namespace {

// Uniform in [0, 1) from the engine's raw output, which the standard fixes for mt19937_64
// (the standard library's distributions are not the same on every platform).
double uniform(std::mt19937_64& engine) {
  return static_cast<double>(engine() >> 11) * 0x1.0p-53;
}

}  // namespace

Result<TargetMotion> addSecondaryMotion(const TargetMotion& target,
                                        const motion::Skeleton& skeleton,
                                        const SecondarySettings& settings) {
  if (settings.loop_strides < 1) return Status::error("secondary motion: loop_strides must be >= 1");
  if (settings.noise_terms < 1) return Status::error("secondary motion: noise_terms must be >= 1");
  if (!(target.omega0 > 0.0)) return Status::error("secondary motion: the target has no tempo");
  const double step = target.omega0 / settings.loop_strides;  // rad/s between allowed frequencies
  TargetMotion out = target;
  for (size_t s = 0; s < settings.sources.size(); ++s) {
    const SecondarySource& source = settings.sources[s];
    const std::string label = "secondary source " + std::to_string(s) + " ('" + source.joint + "')";
    const int joint = skeleton.findJoint(source.joint);
    if (joint < 0) return Status::error(label + ": no such joint");
    if (source.axis < 0 || source.axis > 2) return Status::error(label + ": axis must be 0, 1 or 2");
    if (!(source.frequency_hz > 0.0) || !std::isfinite(source.frequency_hz)) {
      return Status::error(label + ": frequency_hz must be > 0");
    }
    if (!(source.amplitude_deg >= 0.0 && source.amplitude_deg <= 30.0)) {
      return Status::error(label + ": amplitude_deg must be in [0, 30]");
    }
    const double amplitude = source.amplitude_deg * std::numbers::pi / 180.0;
    const double omega = 2.0 * std::numbers::pi * source.frequency_hz;
    if (source.kind == SecondarySource::Kind::kPeriodic) {
      const double multiple = std::max(1.0, std::round(omega / step));
      out.secondary.push_back({joint, source.axis, multiple * step, amplitude, 0.0});
      continue;
    }
    // Band-limited noise: sinusoids at random allowed frequencies up to the band's edge, random
    // phases, their amplitudes sharing the RMS (a sinusoid of amplitude a has RMS a / sqrt 2).
    std::mt19937_64 engine(source.seed);
    const int highest = std::max(1, static_cast<int>(std::floor(omega / step)));
    const double each = amplitude * std::sqrt(2.0 / settings.noise_terms);
    for (int n = 0; n < settings.noise_terms; ++n) {
      const int multiple = 1 + static_cast<int>(uniform(engine) * highest);
      const double phase = 2.0 * std::numbers::pi * uniform(engine);
      out.secondary.push_back({joint, source.axis, std::min(multiple, highest) * step, each, phase});
    }
  }
  return out;
}

}  // namespace sinew::spectral
