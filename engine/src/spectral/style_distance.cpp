// Style measures between motions and runs: styleAmount (a clip along a pair's style) and
// runStyleDistance (a recorded run's amplitude spectrum against its target's, per joint group).
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <numbers>

#include "sinew/core/rotation.h"
#include "sinew/spectral/bands.h"
#include "sinew/spectral/style.h"

namespace sinew::spectral {
namespace {

// The scales scoreStyleRelative divides by (style.cpp): a just-visible change of each part.
constexpr double kPostureScale = 0.0873;    // 5 degrees, radians
constexpr double kAmplitudeScale = 0.2231;  // ln 1.25
constexpr double kTempoScale = 0.0953;      // ln 1.1

// A relative style as one vector whose squared length is scoreStyleRelative's squared distance
// (times 3): each part over its scale and over the root of its size (an RMS).
std::vector<double> scaledStyle(const RelativeStyle& style) {
  std::vector<double> v;
  const auto add = [&v](const std::vector<double>& part, double scale) {
    const double n = std::sqrt(static_cast<double>(std::max<size_t>(1, part.size())));
    for (double x : part) v.push_back(x / (scale * n));
  };
  add(style.posture, kPostureScale);
  add(style.amplitude, kAmplitudeScale);
  v.push_back(style.log_tempo / kTempoScale);
  return v;
}

}  // namespace

double styleAmount(const motion::Skeleton& skeleton, const TargetMotion& clip,
                   const TargetMotion& neutral, const TargetMotion& styled) {
  const std::vector<double> probe = scaledStyle(relativeStyle(skeleton, neutral, clip));
  const std::vector<double> pair = scaledStyle(relativeStyle(skeleton, neutral, styled));
  double dot = 0.0, norm = 0.0;
  for (size_t i = 0; i < pair.size() && i < probe.size(); ++i) {
    dot += probe[i] * pair[i];
    norm += pair[i] * pair[i];
  }
  return norm > 1e-12 ? dot / norm : 0.0;
}

double runStyleDistance(const motion::Skeleton& skeleton, const motion::Clip& run,
                        const TargetMotion& target, double omega, double skip_s) {
  const double dt = run.frame_time;
  const double period = omega > 0.0 ? 2.0 * std::numbers::pi / omega : 0.0;
  const bool frames = run.frame_count >= 2 && dt > 0.0;  // else: still at the target's base
  int first = frames ? std::clamp(static_cast<int>(std::ceil(skip_s / dt - 1e-9)), 0, run.frame_count - 1) : 0;
  if (frames && run.frame_count - first < 2) first = 0;
  const double available = frames ? (run.frame_count - 1 - first) * dt : 0.0;
  const int periods = period > 0.0 ? static_cast<int>(std::floor(available / period + 1e-9)) : 0;
  // Whole periods when there are any; otherwise what there is, counted as still.
  const int count = !frames     ? 0
                    : periods > 0 ? std::max(1, static_cast<int>(std::lround(periods * period / dt)))
                                  : run.frame_count - first;
  const std::vector<JointGroup> groups = jointGroups(skeleton);
  std::array<double, kJointGroupCount> squared{};
  std::array<int, kJointGroupCount> channels{};
  std::vector<glm::dvec3> vectors(static_cast<size_t>(count));
  int cached_joint = -1;
  for (const ChannelModel& channel : target.channels) {
    if (channel.kind != SignalKind::kRotation) continue;
    if (channel.joint != cached_joint) {
      const glm::dquat inverse_base = glm::conjugate(target.base_rotations[channel.joint]);
      for (int k = 0; k < count; ++k)
        vectors[k] = shortRotationVector(inverse_base * run.rotation(first + k, channel.joint));
      cached_joint = channel.joint;
    }
    double mean = 0.0;
    for (int k = 0; k < count; ++k) mean += vectors[k][channel.axis];
    mean = count > 0 ? mean / count : 0.0;
    double distance = (mean - channel.mean) * (mean - channel.mean);
    for (const Harmonic& h : channel.terms) {
      double amplitude = 0.0;
      if (periods > 0) {
        std::complex<double> sum(0.0, 0.0);
        for (int k = 0; k < count; ++k)
          sum += vectors[k][channel.axis] * std::polar(1.0, -h.n * omega * (first + k) * dt);
        amplitude = 2.0 * std::abs(sum) / count;
      }
      distance += (amplitude - h.amplitude) * (amplitude - h.amplitude);
    }
    const auto g = static_cast<size_t>(groups[static_cast<size_t>(channel.joint)]);
    squared[g] += distance;
    ++channels[g];
  }
  double total = 0.0;
  int present = 0;
  for (size_t g = 0; g < squared.size(); ++g) {
    if (channels[g] == 0) continue;
    total += std::sqrt(squared[g] / channels[g]);
    ++present;
  }
  return present > 0 ? total / present : 0.0;
}

}  // namespace sinew::spectral
