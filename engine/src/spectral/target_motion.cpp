#include "sinew/spectral/target_motion.h"

#include <cmath>
#include <complex>
#include <numbers>
#include <set>
#include <tuple>

#include "sinew/spectral/limits.h"
#include "sinew/core/assert.h"

namespace sinew::spectral {
namespace {

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::complex<double> coefficient(const ChannelModel& channel, int n) {
  std::complex<double> sum = 0.0;
  for (const Harmonic& h : channel.terms) {
    if (h.n == n) sum += std::polar(h.amplitude, h.phase);
  }
  return sum;
}

int highestHarmonic(const ChannelModel& channel) {
  int highest = 0;
  for (const Harmonic& h : channel.terms) highest = std::max(highest, h.n);
  return highest;
}

}  // namespace

Status TargetMotion::validate(const motion::Skeleton& skeleton) const {
  const int joints = skeleton.jointCount();
  if (!(omega0 > 0.0 && omega0 <= kMaxOmega_rad_s)) {
    return Status::error("target '" + name + "': omega0 must be in (0, 10000] rad/s");
  }
  if (jointCount() != joints || static_cast<int>(base_translations.size()) != joints ||
      (!base_scales.empty() && static_cast<int>(base_scales.size()) != joints)) {
    return Status::error("target '" + name + "' has " + std::to_string(jointCount()) +
                         " joints, the skeleton " + std::to_string(joints));
  }
  std::set<std::tuple<int, int, int>> seen;
  for (const ChannelModel& channel : channels) {
    const std::string label = "target '" + name + "', channel of joint " + std::to_string(channel.joint);
    if (channel.joint < 0 || channel.joint >= joints || channel.axis < 0 || channel.axis > 2) {
      return Status::error(label + ": joint or axis out of range");
    }
    if (!seen.insert({channel.joint, static_cast<int>(channel.kind), channel.axis}).second) {
      return Status::error(label + ": appears twice");
    }
    if (!(std::abs(channel.mean) <= kMaxCoefficient) ||
        !(std::abs(channel.trend) <= kMaxCoefficient)) {
      return Status::error(label + ": mean or trend is not a number within 1e6");
    }
    if (channel.terms.size() > static_cast<size_t>(kMaxHarmonicsPerChannel)) {
      return Status::error(label + ": more than 1024 harmonics");
    }
    for (const Harmonic& h : channel.terms) {
      if (h.n < 1 || h.n > kMaxHarmonicIndex || !(h.amplitude >= 0.0) ||
          !(h.amplitude <= kMaxCoefficient) || !(std::abs(h.phase) <= kMaxCoefficient)) {
        return Status::error(
            label + ": harmonic " + std::to_string(h.n) +
            " needs n in 1..1024, an amplitude in [0, 1e6] and a phase within 1e6");
      }
    }
  }
  for (size_t n = 0; n < secondary.size(); ++n) {
    const SecondaryTerm& term = secondary[n];
    if (term.joint < 0 || term.joint >= joints || term.axis < 0 || term.axis > 2 ||
        !(term.omega > 0.0 && term.omega <= kMaxOmega_rad_s) || !(term.amplitude >= 0.0) ||
        !(term.amplitude <= kMaxCoefficient) || !(std::abs(term.phase) <= kMaxCoefficient)) {
      return Status::error("target '" + name + "', secondary term " + std::to_string(n) +
                           ": needs a joint and axis in range, omega > 0, amplitude >= 0");
    }
  }
  for (int j = 0; j < joints; ++j) {
    const glm::dvec3& t = base_translations[j];
    if (!finite(t) || !(std::abs(glm::length(base_rotations[j]) - 1.0) < 1e-6) ||
        !(std::abs(t.x) <= kMaxCoefficient && std::abs(t.y) <= kMaxCoefficient &&
          std::abs(t.z) <= kMaxCoefficient)) {
      return Status::error("target '" + name + "': base pose of joint '" + skeleton.names[j] +
                           "' is not finite or beyond 1e6 m");
    }
  }
  return {};
}

void TargetMotion::pose(double t, std::span<glm::dquat> rotations,
                        std::span<glm::dvec3> translations) const {
  const int joints = jointCount();
  SINEW_ASSERT(rotations.size() == static_cast<size_t>(joints) &&
                   translations.size() == static_cast<size_t>(joints),
               "TargetMotion::pose: spans of jointCount() entries");
  std::vector<glm::dvec3> vectors(joints, glm::dvec3(0.0));
  std::vector<bool> rotates(joints, false);
  for (int j = 0; j < joints; ++j) translations[j] = base_translations[j];
  for (const ChannelModel& channel : channels) {
    const double value = evaluate(channel.mean, channel.terms, omega0, t);
    if (channel.kind == SignalKind::kRotation) {
      vectors[channel.joint][channel.axis] = value;
      rotates[channel.joint] = true;
    } else {
      translations[channel.joint][channel.axis] += value + channel.trend * t;
    }
  }
  for (const SecondaryTerm& term : secondary) {
    vectors[term.joint][term.axis] += sinusoid(term.amplitude, term.omega, term.phase, t);
    rotates[term.joint] = true;
  }
  for (int j = 0; j < joints; ++j) {
    rotations[j] = rotates[j] ? glm::normalize(base_rotations[j] * fromRotationVector(vectors[j]))
                              : base_rotations[j];
  }
}

motion::Clip TargetMotion::sample(double fps, int strides) const {
  SINEW_ASSERT(fps > 0.0 && strides >= 1, "TargetMotion::sample: fps > 0, strides >= 1");
  const double length = strides * period();
  const int intervals = std::max(1, static_cast<int>(std::lround(length * fps)));
  // Frames exactly at the chosen rate; the motion's tempo is stretched (by at most half a frame
  // per stride) so that the strides fill whole frames and the loop closes.
  const double model_step = length / intervals;
  motion::Clip clip;
  clip.name = name;
  clip.frame_time = 1.0 / fps;
  clip.frame_count = intervals + 1;
  clip.joint_count = jointCount();
  clip.rotations.resize(static_cast<size_t>(clip.frame_count) * clip.joint_count);
  clip.translations.resize(clip.rotations.size());
  for (int f = 0; f < clip.frame_count; ++f) {
    const size_t at = static_cast<size_t>(f) * clip.joint_count;
    pose(f * model_step,
         std::span<glm::dquat>(clip.rotations.data() + at, clip.joint_count),
         std::span<glm::dvec3>(clip.translations.data() + at, clip.joint_count));
    if (!base_scales.empty()) clip.scales.insert(clip.scales.end(), base_scales.begin(), base_scales.end());
  }
  return clip;
}

TargetMotion targetFromSpectrum(const MotionSpectrum& spectrum, const std::vector<int>& joint_k,
                                const std::string& name) {
  const std::vector<int>& k = joint_k.empty() ? spectrum.joint_k : joint_k;
  TargetMotion target;
  target.name = name;
  target.omega0 = spectrum.omega0;
  target.base_rotations = spectrum.signals.mean_rotations;
  target.base_translations = spectrum.signals.mean_translations;
  target.base_scales = spectrum.signals.mean_scales;
  for (size_t c = 0; c < spectrum.signals.channels.size(); ++c) {
    const SignalChannel& signal = spectrum.signals.channels[c];
    ChannelModel channel;
    channel.joint = signal.joint;
    channel.kind = signal.kind;
    channel.axis = signal.axis;
    channel.mean = spectrum.series[c].mean;
    channel.terms = spectrum.series[c].strongest(k[signal.joint]);
    channel.trend = spectrum.trends[c];
    target.channels.push_back(std::move(channel));
  }
  // t = 0 is the analysed window's start: the fit was of x(start + t) - mean - trend t, so the
  // travel already starts where the window does.
  return target;
}

double harmonicDistance(const TargetMotion& a, const TargetMotion& b) {
  double sum = 0.0;
  int count = 0;
  for (const ChannelModel& ca : a.channels) {
    const ChannelModel* cb = nullptr;
    for (const ChannelModel& candidate : b.channels) {
      if (candidate.joint == ca.joint && candidate.kind == ca.kind && candidate.axis == ca.axis) {
        cb = &candidate;
      }
    }
    if (cb == nullptr || ca.kind != SignalKind::kRotation) continue;
    // Means compared in a common frame: both rotation vectors are relative to their own base.
    const glm::dquat ra = a.base_rotations[ca.joint];
    const glm::dquat rb = b.base_rotations[ca.joint];
    const glm::dvec3 offset = rotationVector(glm::conjugate(ra) * rb);
    double squared = (ca.mean - cb->mean - offset[ca.axis]) * (ca.mean - cb->mean - offset[ca.axis]);
    const int highest = std::max(highestHarmonic(ca), highestHarmonic(*cb));
    for (int n = 1; n <= highest; ++n) squared += std::norm(coefficient(ca, n) - coefficient(*cb, n));
    sum += squared;
    ++count;
  }
  return count > 0 ? std::sqrt(sum / count) : 0.0;
}

double poseDistanceDeg(const TargetMotion& a, const TargetMotion& b, int samples) {
  const int joints = std::min(a.jointCount(), b.jointCount());
  std::vector<glm::dquat> ra(a.jointCount());
  std::vector<glm::dquat> rb(b.jointCount());
  std::vector<glm::dvec3> ta(a.jointCount());
  std::vector<glm::dvec3> tb(b.jointCount());
  double sum = 0.0;
  for (int s = 0; s < samples; ++s) {
    const double phase = static_cast<double>(s) / samples;
    a.pose(phase * a.period(), ra, ta);
    b.pose(phase * b.period(), rb, tb);
    for (int j = 0; j < joints; ++j) {
      const double degrees = glm::degrees(angleBetween(ra[j], rb[j]));
      sum += degrees * degrees;
    }
  }
  return std::sqrt(sum / (static_cast<double>(samples) * std::max(joints, 1)));
}

void shiftPhase(TargetMotion& target, double seconds) {
  for (SecondaryTerm& term : target.secondary) {
    term.phase = std::remainder(term.phase + term.omega * seconds, 2.0 * std::numbers::pi);
  }
  for (ChannelModel& channel : target.channels) {
    for (Harmonic& h : channel.terms) {
      h.phase = std::remainder(h.phase + h.n * target.omega0 * seconds, 2.0 * std::numbers::pi);
    }
    channel.mean += channel.trend * seconds;
  }
}

}  // namespace sinew::spectral
