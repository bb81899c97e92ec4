#include "sinew/spectral/blend.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <numbers>
#include <tuple>

#include "sinew/spectral/style.h"

namespace sinew::spectral {
namespace {

using ChannelKey = std::tuple<int, int, int>;  // joint, kind, axis

ChannelKey keyOf(const ChannelModel& channel) {
  return {channel.joint, static_cast<int>(channel.kind), channel.axis};
}

std::map<int, Harmonic> byNumber(const ChannelModel& channel) {
  std::map<int, Harmonic> terms;
  for (const Harmonic& h : channel.terms) terms[h.n] = h;
  return terms;
}

// Travel velocity per translation channel is part of the blend; so is the rest.
ChannelModel blendChannel(const ChannelModel* a, const ChannelModel* b, double u) {
  const ChannelModel& any = a != nullptr ? *a : *b;
  ChannelModel out{any.joint, any.kind, any.axis, 0.0, {}, 0.0};
  const double wa = a != nullptr ? 1.0 - u : 0.0;
  const double wb = b != nullptr ? u : 0.0;
  out.mean = (a ? wa * a->mean : 0.0) + (b ? wb * b->mean : 0.0);
  out.trend = (a ? wa * a->trend : 0.0) + (b ? wb * b->trend : 0.0);
  const std::map<int, Harmonic> ta = a ? byNumber(*a) : std::map<int, Harmonic>{};
  const std::map<int, Harmonic> tb = b ? byNumber(*b) : std::map<int, Harmonic>{};
  std::map<int, bool> numbers;
  for (const auto& [n, h] : ta) numbers[n] = true;
  for (const auto& [n, h] : tb) numbers[n] = true;
  for (const auto& [n, unused] : numbers) {
    const auto ia = ta.find(n);
    const auto ib = tb.find(n);
    const double amplitude = (ia != ta.end() ? (1.0 - u) * ia->second.amplitude : 0.0) +
                             (ib != tb.end() ? u * ib->second.amplitude : 0.0);
    double phase = ia != ta.end() ? ia->second.phase : ib->second.phase;
    if (ia != ta.end() && ib != tb.end()) {
      phase += u * std::remainder(ib->second.phase - ia->second.phase, 2.0 * std::numbers::pi);
    }
    out.terms.push_back({n, amplitude, std::remainder(phase, 2.0 * std::numbers::pi)});
  }
  return out;
}

}  // namespace

Result<TargetMotion> blendTargets(const TargetMotion& a, const TargetMotion& b_in, double u) {
  if (!(u >= 0.0 && u <= 1.0)) {
    return Status::error("blend weight must be in [0, 1], got " + std::to_string(u));
  }
  if (a.jointCount() != b_in.jointCount()) {
    return Status::error("blend: the clips have " + std::to_string(a.jointCount()) + " and " +
                         std::to_string(b_in.jointCount()) + " joints; blending needs one skeleton");
  }
  if (u == 0.0) return a;
  TargetMotion b = b_in;
  const auto [joint, axis] = phaseReference(a);
  if (joint >= 0) {
    // b's stride starts at the same gait event as a's: shift b so that its reference fundamental
    // has a's phase.
    alignPhase(b, joint, axis);
    double offset = 0.0;  // a's shift to its aligned origin
    for (const ChannelModel& channel : a.channels) {
      if (channel.joint != joint || channel.kind != SignalKind::kRotation || channel.axis != axis) continue;
      for (const Harmonic& h : channel.terms) {
        if (h.n == 1) offset = -h.phase / a.omega0;
      }
    }
    shiftPhase(b, -offset * a.omega0 / b.omega0);
  }
  TargetMotion out;
  out.name = a.name + "+" + b.name;
  out.omega0 = std::exp((1.0 - u) * std::log(a.omega0) + u * std::log(b.omega0));
  out.base_translations.resize(a.jointCount());
  for (int j = 0; j < a.jointCount(); ++j) {
    out.base_rotations.push_back(glm::normalize(glm::slerp(a.base_rotations[j], b.base_rotations[j], u)));
    out.base_translations[j] = glm::mix(a.base_translations[j], b.base_translations[j], u);
  }
  if (!a.base_scales.empty() && !b.base_scales.empty()) {
    for (int j = 0; j < a.jointCount(); ++j) {
      out.base_scales.push_back(glm::mix(a.base_scales[j], b.base_scales[j], u));
    }
  }
  std::map<ChannelKey, std::pair<const ChannelModel*, const ChannelModel*>> pairs;
  for (const ChannelModel& channel : a.channels) pairs[keyOf(channel)].first = &channel;
  for (const ChannelModel& channel : b.channels) pairs[keyOf(channel)].second = &channel;
  for (const auto& [key, pair] : pairs) {
    ChannelModel channel = blendChannel(pair.first, pair.second, u);
    // Along a travel axis the position only says where each clip was captured: keep a's, so
    // the mix does not slide towards b's capture space.
    const bool travels = (pair.first && std::abs(pair.first->trend) > 1e-3) ||
                         (pair.second && std::abs(pair.second->trend) > 1e-3);
    if (channel.kind == SignalKind::kTranslation && travels && pair.first != nullptr) {
      channel.mean = pair.first->mean;
      out.base_translations[channel.joint][channel.axis] =
          a.base_translations[channel.joint][channel.axis];
    }
    out.channels.push_back(std::move(channel));
  }
  for (SecondaryTerm term : a.secondary) {
    term.amplitude *= 1.0 - u;
    out.secondary.push_back(term);
  }
  for (SecondaryTerm term : b.secondary) {
    term.amplitude *= u;
    out.secondary.push_back(term);
  }
  return out;
}

Result<motion::Clip> transitionClip(const TargetMotion& a, const TargetMotion& b,
                                    const Transition& transition) {
  if (!(transition.start_s >= 0.0) || !(transition.duration_s > 0.0) ||
      !(transition.total_s > 0.0) || !(transition.fps > 0.0)) {
    return Status::error("transition: needs start_s >= 0, duration_s > 0, total_s > 0, fps > 0");
  }
  const double dt = 1.0 / transition.fps;
  const int frames = static_cast<int>(std::floor(transition.total_s * transition.fps + 1e-9)) + 1;
  const int joints = a.jointCount();
  motion::Clip clip;
  clip.name = a.name + "_to_" + b.name;
  clip.frame_time = dt;
  clip.frame_count = frames;
  clip.joint_count = joints;
  clip.rotations.resize(static_cast<size_t>(frames) * joints);
  clip.translations.resize(clip.rotations.size());
  double phase = 0.0;  // stride phase, radians of the fundamental, integrated through the tempo
  std::vector<glm::dvec3> travel(joints, glm::dvec3(0.0));  // integrated trend, metres
  for (int f = 0; f < frames; ++f) {
    const double t = f * dt;
    const double x = std::clamp((t - transition.start_s) / transition.duration_s, 0.0, 1.0);
    const double u = x * x * (3.0 - 2.0 * x);  // smoothstep
    Result<TargetMotion> mixed = blendTargets(a, b, u);
    if (!mixed.ok()) return mixed.status();
    TargetMotion pose_model = std::move(mixed).value();
    // Periodic part at the integrated phase; travel from the integrated speed.
    std::vector<double> trends;
    for (ChannelModel& channel : pose_model.channels) {
      trends.push_back(channel.trend);
      channel.trend = 0.0;
    }
    const size_t at = static_cast<size_t>(f) * joints;
    pose_model.pose(phase / pose_model.omega0,
                    std::span<glm::dquat>(clip.rotations.data() + at, joints),
                    std::span<glm::dvec3>(clip.translations.data() + at, joints));
    for (size_t c = 0; c < pose_model.channels.size(); ++c) {
      const ChannelModel& channel = pose_model.channels[c];
      if (channel.kind != SignalKind::kTranslation) continue;
      clip.translations[at + channel.joint][channel.axis] += travel[channel.joint][channel.axis];
      travel[channel.joint][channel.axis] += trends[c] * dt;
    }
    phase += pose_model.omega0 * dt;
  }
  return clip;
}

}  // namespace sinew::spectral
