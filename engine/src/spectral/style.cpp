#include "sinew/spectral/style.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <complex>
#include <map>
#include <numbers>

#include "sinew/spectral/bands.h"

namespace sinew::spectral {
namespace {

constexpr double kMaxLogRatio = 2.0794415416798357;  // ln 8
constexpr double kWeakFraction = 0.02;  // harmonics under 2% of the channel's strongest

const ChannelModel* findChannel(const TargetMotion& target, int joint, SignalKind kind, int axis) {
  for (const ChannelModel& channel : target.channels) {
    if (channel.joint == joint && channel.kind == kind && channel.axis == axis) return &channel;
  }
  return nullptr;
}

std::complex<double> coefficient(const ChannelModel& channel, int n) {
  std::complex<double> sum = 0.0;
  for (const Harmonic& h : channel.terms) {
    if (h.n == n) sum += std::polar(h.amplitude, h.phase);
  }
  return sum;
}

// Travel speed: the largest translation trend of any joint, m/s.
double speed(const TargetMotion& target) {
  std::map<int, double> squared;
  for (const ChannelModel& channel : target.channels) {
    if (channel.kind == SignalKind::kTranslation) squared[channel.joint] += channel.trend * channel.trend;
  }
  double fastest = 0.0;
  for (const auto& [joint, value] : squared) fastest = std::max(fastest, std::sqrt(value));
  return fastest;
}

glm::dquat chordalMean(const std::vector<glm::dquat>& rotations) {
  glm::dvec4 sum(0.0);
  for (const glm::dquat& q : rotations) {
    const double sign = glm::dot(q, rotations.front()) < 0.0 ? -1.0 : 1.0;
    sum += sign * glm::dvec4(q.x, q.y, q.z, q.w);
  }
  const double norm = glm::length(sum);
  return norm > 0.0 ? glm::dquat(sum.w / norm, sum.x / norm, sum.y / norm, sum.z / norm)
                    : rotations.front();
}

// A limb's proximal share of its length: its joints from the root down to the first whose bone
// is at least this fraction of the limb (the clavicle and the upper arm; the hip and the thigh).
constexpr double kProximalBone = 0.25;

// Length of the longest chain of bones below each joint (End Sites included), metres.
std::vector<double> reaches(const motion::Skeleton& skeleton) {
  const int joints = skeleton.jointCount();
  std::vector<double> reach(joints, 0.0);
  for (int j = joints - 1; j >= 0; --j) {  // children come after their parents
    if (skeleton.end_sites[j]) reach[j] = std::max(reach[j], glm::length(*skeleton.end_sites[j]));
    const int parent = skeleton.parents[j];
    if (parent != motion::kNoParent) {
      reach[parent] = std::max(reach[parent], glm::length(skeleton.offsets[j]) + reach[j]);
    }
  }
  return reach;
}

}  // namespace

std::vector<int> carriageJoints(const motion::Skeleton& skeleton) {
  const int joints = skeleton.jointCount();
  const std::vector<JointGroup> groups = jointGroups(skeleton);
  const int pelvis = motion::pelvisJoint(skeleton);
  std::vector<bool> above_pelvis(joints, false);
  for (int j = pelvis; j != motion::kNoParent; j = skeleton.parents[j]) above_pelvis[j] = true;
  const std::vector<double> reach = reaches(skeleton);
  const auto limb = [&groups](int j) {
    return groups[j] == JointGroup::kArms || groups[j] == JointGroup::kLegs;
  };
  std::vector<bool> chosen(joints, false);
  for (int j = 0; j < joints; ++j) {
    if (above_pelvis[j]) continue;
    const int parent = skeleton.parents[j];
    if (groups[j] == JointGroup::kSpine) {
      chosen[j] = true;
    } else if (groups[j] == JointGroup::kHead) {
      // The neck, not the head (nor the jaw and face below it).
      std::string name = skeleton.names[j];
      std::transform(name.begin(), name.end(), name.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      chosen[j] = name.find("neck") != std::string::npos;
    } else if (limb(j) && (parent == motion::kNoParent || !limb(parent))) {
      // A limb's root: follow its longest chain down to the first long bone.
      const double length = reach[j];
      for (int k = j; k >= 0;) {
        chosen[k] = true;
        int next = -1;
        double longest = -1.0;
        for (int child = k + 1; child < joints; ++child) {
          if (skeleton.parents[child] != k) continue;
          const double through = glm::length(skeleton.offsets[child]) + reach[child];
          if (through > longest) {
            longest = through;
            next = child;
          }
        }
        const double bone = next >= 0 ? glm::length(skeleton.offsets[next]) : reach[k];
        if (next < 0 || bone >= kProximalBone * length) break;
        k = next;
      }
    }
  }
  std::vector<int> out;
  for (int j = 0; j < joints; ++j) {
    if (chosen[j]) out.push_back(j);
  }
  return out;
}

std::pair<int, int> phaseReference(const TargetMotion& target) {
  std::pair<int, int> best{-1, 0};
  double strongest = 0.0;
  for (const ChannelModel& channel : target.channels) {
    if (channel.kind != SignalKind::kRotation) continue;
    const double fundamental = std::abs(coefficient(channel, 1));
    if (fundamental > strongest) {
      strongest = fundamental;
      best = {channel.joint, channel.axis};
    }
  }
  return best;
}

void alignPhase(TargetMotion& target, int joint, int axis) {
  const ChannelModel* channel = findChannel(target, joint, SignalKind::kRotation, axis);
  if (channel == nullptr) return;
  const std::complex<double> fundamental = coefficient(*channel, 1);
  if (std::abs(fundamental) <= 0.0) return;
  shiftPhase(target, -std::arg(fundamental) / target.omega0);
}

Result<StyleVector> measureStyle(const TargetMotion& neutral_in, const TargetMotion& styled_in,
                                 const std::string& label) {
  if (neutral_in.jointCount() != styled_in.jointCount()) {
    return Status::error("style '" + label + "': the clips have " +
                         std::to_string(neutral_in.jointCount()) + " and " +
                         std::to_string(styled_in.jointCount()) +
                         " joints; a style needs two clips of one skeleton");
  }
  // Strides aligned: both start where the neutral's strongest channel starts its cycle.
  TargetMotion neutral = neutral_in;
  TargetMotion styled = styled_in;
  const auto [joint, axis] = phaseReference(neutral);
  if (joint < 0) return Status::error("style '" + label + "': the neutral clip does not move");
  alignPhase(neutral, joint, axis);
  alignPhase(styled, joint, axis);

  StyleVector style;
  style.label = label;
  style.joint_count = neutral.jointCount();
  style.log_tempo = std::log(styled.omega0 / neutral.omega0);
  const double v_neutral = speed(neutral);
  const double v_styled = speed(styled);
  style.log_speed = v_neutral > 0.01 && v_styled > 0.01 ? std::log(v_styled / v_neutral) : 0.0;
  for (int j = 0; j < neutral.jointCount(); ++j) {
    style.posture.push_back(
        rotationVector(glm::conjugate(neutral.base_rotations[j]) * styled.base_rotations[j]));
  }
  for (const ChannelModel& n_channel : neutral.channels) {
    const ChannelModel* s_channel =
        findChannel(styled, n_channel.joint, n_channel.kind, n_channel.axis);
    if (s_channel == nullptr) continue;
    ChannelStyle channel{n_channel.joint, n_channel.kind, n_channel.axis,
                         s_channel->mean - n_channel.mean, {}};
    double strongest = 0.0;
    int highest = 0;
    for (const Harmonic& h : n_channel.terms) {
      strongest = std::max(strongest, h.amplitude);
      highest = std::max(highest, h.n);
    }
    for (const Harmonic& h : s_channel->terms) highest = std::max(highest, h.n);
    for (int n = 1; n <= highest; ++n) {
      const std::complex<double> zn = coefficient(n_channel, n);
      const std::complex<double> zs = coefficient(*s_channel, n);
      if (std::abs(zn) < kWeakFraction * strongest || std::abs(zs) <= 0.0) continue;
      channel.harmonics.push_back(
          {n, std::clamp(std::log(std::abs(zs) / std::abs(zn)), -kMaxLogRatio, kMaxLogRatio),
           std::remainder(std::arg(zs) - std::arg(zn), 2.0 * std::numbers::pi)});
    }
    style.channels.push_back(std::move(channel));
  }
  return style;
}

Result<TargetMotion> applyStyles(const TargetMotion& target,
                                 const std::vector<std::pair<const StyleVector*, double>>& styles) {
  TargetMotion out = target;
  double log_tempo = 0.0;
  double log_speed = 0.0;
  std::vector<glm::dvec3> posture(target.jointCount(), glm::dvec3(0.0));
  // (joint, kind, axis) -> mean offset, and per n the summed log ratio and phase shift.
  std::map<std::tuple<int, int, int>, double> mean_offset;
  std::map<std::tuple<int, int, int, int>, std::pair<double, double>> harmonic;
  for (const auto& [style, weight] : styles) {
    if (weight == 0.0) continue;  // exactly no change, not a change of rounding size
    if (!(weight >= -1.0 && weight <= 2.0)) {
      return Status::error("style '" + style->label + "': weight " + std::to_string(weight) +
                           " is outside [-1, 2]");
    }
    if (style->joint_count != target.jointCount()) {
      return Status::error("style '" + style->label + "' was measured on a skeleton of " +
                           std::to_string(style->joint_count) + " joints; this clip has " +
                           std::to_string(target.jointCount()));
    }
    log_tempo += weight * style->log_tempo;
    log_speed += weight * style->log_speed;
    for (int j = 0; j < target.jointCount(); ++j) posture[j] += weight * style->posture[j];
    for (const ChannelStyle& channel : style->channels) {
      const int kind = static_cast<int>(channel.kind);
      mean_offset[{channel.joint, kind, channel.axis}] += weight * channel.mean_offset;
      for (const HarmonicStyle& h : channel.harmonics) {
        auto& [ratio, shift] = harmonic[{channel.joint, kind, channel.axis, h.n}];
        ratio += weight * h.log_ratio;
        shift += weight * h.phase_shift;
      }
    }
  }
  if (mean_offset.empty() && harmonic.empty() && log_tempo == 0.0 && log_speed == 0.0) return out;
  out.omega0 = target.omega0 * std::exp(log_tempo);
  for (int j = 0; j < out.jointCount(); ++j) {
    out.base_rotations[j] = glm::normalize(out.base_rotations[j] * fromRotationVector(posture[j]));
  }
  for (ChannelModel& channel : out.channels) {
    const int kind = static_cast<int>(channel.kind);
    if (const auto it = mean_offset.find({channel.joint, kind, channel.axis}); it != mean_offset.end()) {
      channel.mean += it->second;
    }
    if (channel.kind == SignalKind::kTranslation) channel.trend *= std::exp(log_speed);
    for (Harmonic& h : channel.terms) {
      const auto it = harmonic.find({channel.joint, kind, channel.axis, h.n});
      if (it == harmonic.end()) continue;
      h.amplitude *= std::exp(it->second.first);
      h.phase = std::remainder(h.phase + it->second.second, 2.0 * std::numbers::pi);
    }
  }
  return out;
}

Status sameJoints(const motion::Skeleton& reference, const motion::Skeleton& other) {
  const int joints = std::max(reference.jointCount(), other.jointCount());
  const auto describe = [](const motion::Skeleton& s, int j) {
    if (j >= s.jointCount()) return std::string("no joint ") + std::to_string(j);
    const int parent = s.parents[j];
    return "'" + s.names[j] + "' (parent " +
           (parent == motion::kNoParent ? std::string("none") : "'" + s.names[parent] + "'") + ")";
  };
  for (int j = 0; j < joints; ++j) {
    const bool same = j < reference.jointCount() && j < other.jointCount() &&
                      reference.names[j] == other.names[j] &&
                      reference.parents[j] == other.parents[j];
    if (!same) {
      return Status::error("joint " + std::to_string(j) + " is " + describe(other, j) +
                           ", where the other skeleton has " + describe(reference, j));
    }
  }
  return {};
}

namespace {

// Scores from each entry's distance (in Gaussian widths), merged per label: the nearest example
// of a label is its distance.
StyleScores scoresFromDistances(const std::vector<std::string>& labels,
                                const std::vector<double>& distances) {
  StyleScores scores;
  std::vector<double> nearest;
  for (size_t n = 0; n < labels.size(); ++n) {
    size_t at = 0;
    while (at < scores.scores.size() && scores.scores[at].first != labels[n]) ++at;
    if (at == scores.scores.size()) {
      scores.scores.emplace_back(labels[n], 0.0);
      nearest.push_back(distances[n]);
      scores.examples.push_back(0);
    }
    nearest[at] = std::min(nearest[at], distances[n]);
    ++scores.examples[at];
  }
  double total = 0.0;
  std::vector<double> raw;
  for (double d : nearest) {
    raw.push_back(std::exp(-0.5 * d * d));
    total += raw.back();
  }
  for (size_t n = 0; n < raw.size(); ++n) {
    scores.scores[n].second = total > 0.0 ? raw[n] / total : 1.0 / static_cast<double>(raw.size());
  }
  // The nearest label (the highest score; also when every Gaussian underflows).
  const auto at = std::min_element(nearest.begin(), nearest.end()) - nearest.begin();
  scores.closest = scores.scores[static_cast<size_t>(at)].first;
  scores.distances = nearest;
  return scores;
}

double rms(const std::vector<double>& a, const std::vector<double>& b) {
  double squared = 0.0;
  for (size_t i = 0; i < a.size(); ++i) squared += (a[i] - b[i]) * (a[i] - b[i]);
  return a.empty() ? 0.0 : std::sqrt(squared / static_cast<double>(a.size()));
}

// Root-sum-square amplitude of each joint's rotation harmonics, radians.
std::vector<double> jointAmplitudes(const TargetMotion& target) {
  std::vector<double> squared(static_cast<size_t>(target.jointCount()), 0.0);
  for (const ChannelModel& channel : target.channels) {
    if (channel.kind != SignalKind::kRotation) continue;
    for (const Harmonic& h : channel.terms) squared[channel.joint] += h.amplitude * h.amplitude;
  }
  for (double& v : squared) v = std::sqrt(v);
  return squared;
}

constexpr double kPostureScale = 0.0873;     // 5 degrees, radians
constexpr double kAmplitudeScale = 0.2231;   // ln 1.25
constexpr double kTempoScale = 0.0953;       // ln 1.1
constexpr double kAmplitudeFloor = 0.02;     // radians

}  // namespace

Result<StyleScores> scoreStyle(const motion::Skeleton& skeleton, const TargetMotion& clip,
                               const std::vector<std::pair<std::string, TargetMotion>>& library) {
  if (library.empty()) return Status::error("style library is empty");
  const int joints = clip.jointCount();
  if (skeleton.jointCount() != joints) {
    return Status::error("style measurement: the clip has " + std::to_string(joints) +
                         " joints, its skeleton " + std::to_string(skeleton.jointCount()));
  }
  for (const auto& [label, entry] : library) {
    if (entry.jointCount() != joints) {
      return Status::error("style library entry '" + label + "' has " +
                           std::to_string(entry.jointCount()) + " joints; the clip has " +
                           std::to_string(joints));
    }
  }
  // Features: the carriage (carriageJoints): each trunk, neck and proximal limb joint's posture
  // relative to the library's mean, radians. See carriageJoints for why those joints.
  const std::vector<int> carriage = carriageJoints(skeleton);
  std::vector<glm::dquat> mean_posture(joints);
  for (int j : carriage) {
    std::vector<glm::dquat> bases;
    for (const auto& [label, entry] : library) bases.push_back(entry.base_rotations[j]);
    mean_posture[j] = chordalMean(bases);
  }
  const auto features = [&](const TargetMotion& target) {
    std::vector<double> f;
    for (int j : carriage) {
      // The short way (q and -q are one rotation).
      const glm::dvec3 v =
          shortRotationVector(glm::conjugate(mean_posture[j]) * target.base_rotations[j]);
      f.insert(f.end(), {v.x, v.y, v.z});
    }
    return f;
  };
  const std::vector<double> probe = features(clip);
  // Every feature is an angle, so distances need no scaling: the RMS angular difference, in
  // units of 5 degrees (the size of a visible change of attitude).
  std::vector<std::string> labels;
  std::vector<double> distances;
  for (const auto& [label, entry] : library) {
    labels.push_back(label);
    distances.push_back(rms(probe, features(entry)) / kPostureScale);
  }
  return scoresFromDistances(labels, distances);
}

RelativeStyle relativeStyle(const motion::Skeleton& skeleton, const TargetMotion& neutral,
                            const TargetMotion& styled) {
  RelativeStyle style;
  for (int j : carriageJoints(skeleton)) {
    const glm::dvec3 v =
        shortRotationVector(glm::conjugate(neutral.base_rotations[j]) * styled.base_rotations[j]);
    style.posture.insert(style.posture.end(), {v.x, v.y, v.z});
  }
  const int pelvis = motion::pelvisJoint(skeleton);
  std::vector<bool> above(static_cast<size_t>(skeleton.jointCount()), false);
  for (int j = pelvis; j != motion::kNoParent; j = skeleton.parents[j]) above[j] = true;
  const std::vector<double> a = jointAmplitudes(neutral);
  const std::vector<double> b = jointAmplitudes(styled);
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    if (above[j]) continue;  // the heading, not the style
    style.amplitude.push_back(std::log(std::max(b[j], kAmplitudeFloor) / std::max(a[j], kAmplitudeFloor)));
  }
  style.log_tempo = std::log(styled.omega0 / neutral.omega0);
  return style;
}

Result<StyleScores> scoreStyleRelative(const motion::Skeleton& skeleton, const TargetMotion& clip,
                                       const TargetMotion& neutral,
                                       const std::vector<StyleExample>& library) {
  if (library.empty()) return Status::error("style library is empty");
  const int joints = skeleton.jointCount();
  const auto check = [joints](const TargetMotion& target, const std::string& what) -> Status {
    if (target.jointCount() != joints || !(target.omega0 > 0.0)) {
      return Status::error(what + " has " + std::to_string(target.jointCount()) +
                           " joints; the skeleton has " + std::to_string(joints));
    }
    return {};
  };
  if (Status status = check(clip, "the clip"); !status.ok()) return status;
  if (Status status = check(neutral, "the neutral"); !status.ok()) return status;
  for (const StyleExample& example : library) {
    if (Status status = check(example.neutral, "style '" + example.label + "': the neutral"); !status.ok()) return status;
    if (Status status = check(example.styled, "style '" + example.label + "': the styled clip"); !status.ok()) return status;
  }
  const RelativeStyle probe = relativeStyle(skeleton, neutral, clip);
  std::vector<std::string> labels;
  std::vector<double> distances;
  for (const StyleExample& example : library) {
    const RelativeStyle entry = relativeStyle(skeleton, example.neutral, example.styled);
    const double posture = rms(probe.posture, entry.posture) / kPostureScale;
    const double amplitude = rms(probe.amplitude, entry.amplitude) / kAmplitudeScale;
    const double tempo = std::abs(probe.log_tempo - entry.log_tempo) / kTempoScale;
    labels.push_back(example.label);
    distances.push_back(std::sqrt((posture * posture + amplitude * amplitude + tempo * tempo) / 3.0));
  }
  return scoresFromDistances(labels, distances);
}

}  // namespace sinew::spectral
