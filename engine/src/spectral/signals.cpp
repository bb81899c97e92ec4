#include "sinew/spectral/signals.h"

#include <algorithm>
#include <cmath>

namespace sinew::spectral {

double catmullRomAt(const std::vector<double>& values, double frame) {
  const int last = static_cast<int>(values.size()) - 1;
  if (frame <= 0.0) return values[0];
  if (frame >= last) return values[last];
  const int i = static_cast<int>(frame);
  const double u = frame - i;
  const double p0 = values[std::max(i - 1, 0)];
  const double p1 = values[i];
  const double p2 = values[std::min(i + 1, last)];
  const double p3 = values[std::min(i + 2, last)];
  return p1 + 0.5 * u * (p2 - p0 + u * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 +
                                        u * (3.0 * (p1 - p2) + p3 - p0)));
}

double angleBetween(const glm::dquat& a, const glm::dquat& b) {
  const glm::dquat d = glm::conjugate(a) * b;
  return 2.0 * std::atan2(glm::length(glm::dvec3(d.x, d.y, d.z)), std::abs(d.w));
}

glm::dvec3 rotationVector(const glm::dquat& q) {
  const glm::dvec3 xyz(q.x, q.y, q.z);
  const double s = glm::length(xyz);
  if (s < 1e-12) return 2.0 * xyz;  // small-angle limit: angle ~ 2 s, axis xyz / s
  const double angle = 2.0 * std::atan2(s, q.w);
  return xyz * (angle / s);
}

glm::dquat fromRotationVector(const glm::dvec3& v) {
  const double angle = glm::length(v);
  if (angle < 1e-12) return glm::normalize(glm::dquat(1.0, v.x / 2.0, v.y / 2.0, v.z / 2.0));
  const glm::dvec3 axis = v / angle;
  const double s = std::sin(angle / 2.0);
  return glm::dquat(std::cos(angle / 2.0), axis.x * s, axis.y * s, axis.z * s);
}

int MotionSignals::find(int joint, SignalKind kind, int axis) const {
  for (size_t c = 0; c < channels.size(); ++c) {
    if (channels[c].joint == joint && channels[c].kind == kind && channels[c].axis == axis) {
      return static_cast<int>(c);
    }
  }
  return -1;
}

MotionSignals extractSignals(const motion::Skeleton& skeleton, const motion::Clip& clip,
                             double min_rotation_rad, double min_translation_m) {
  MotionSignals signals;
  signals.frame_time = clip.frame_time;
  signals.frame_count = clip.frame_count;
  const int joints = skeleton.jointCount();
  const int frames = clip.frame_count;
  signals.mean_rotations.resize(joints);
  signals.mean_translations.resize(joints);
  if (!clip.scales.empty()) {
    signals.mean_scales.assign(joints, glm::dvec3(0.0));
    for (int f = 0; f < frames; ++f) {
      for (int j = 0; j < joints; ++j) signals.mean_scales[j] += clip.scale(f, j) / static_cast<double>(frames);
    }
  }
  std::vector<glm::dquat> continuous(frames);
  std::vector<glm::dvec3> vectors(frames);
  for (int j = 0; j < joints; ++j) {
    // Rotation: signs continuous frame to frame, chordal mean, log map relative to the mean.
    glm::dvec4 sum(0.0);
    for (int f = 0; f < frames; ++f) {
      glm::dquat q = clip.rotation(f, j);
      if (f > 0 && glm::dot(q, continuous[f - 1]) < 0.0) q = -q;
      continuous[f] = q;
      sum += glm::dvec4(q.x, q.y, q.z, q.w);
    }
    const double norm = glm::length(sum);
    const glm::dquat mean = norm > 1e-9 * frames
                                ? glm::dquat(sum.w / norm, sum.x / norm, sum.y / norm, sum.z / norm)
                                : continuous[0];
    signals.mean_rotations[j] = mean;
    double largest = 0.0;
    glm::dquat previous = glm::dquat(1.0, 0.0, 0.0, 0.0);
    for (int f = 0; f < frames; ++f) {
      glm::dquat relative = glm::conjugate(mean) * continuous[f];
      if (glm::dot(relative, previous) < 0.0) relative = -relative;
      previous = relative;
      vectors[f] = rotationVector(relative);
      largest = std::max(largest, glm::length(vectors[f]));
    }
    if (largest >= min_rotation_rad) {
      for (int axis = 0; axis < 3; ++axis) {
        SignalChannel channel{j, SignalKind::kRotation, axis, std::vector<double>(frames)};
        for (int f = 0; f < frames; ++f) channel.values[f] = vectors[f][axis];
        signals.channels.push_back(std::move(channel));
      }
    }
    // Translation: relative to the mean, for joints that move.
    glm::dvec3 mean_t(0.0);
    for (int f = 0; f < frames; ++f) mean_t += clip.translation(f, j) / static_cast<double>(frames);
    signals.mean_translations[j] = mean_t;
    double reach = 0.0;
    for (int f = 0; f < frames; ++f) reach = std::max(reach, glm::length(clip.translation(f, j) - mean_t));
    if (reach >= min_translation_m) {
      if (signals.travel_joint < 0) signals.travel_joint = j;
      for (int axis = 0; axis < 3; ++axis) {
        SignalChannel channel{j, SignalKind::kTranslation, axis, std::vector<double>(frames)};
        for (int f = 0; f < frames; ++f) channel.values[f] = clip.translation(f, j)[axis] - mean_t[axis];
        signals.channels.push_back(std::move(channel));
      }
    }
  }
  return signals;
}

}  // namespace sinew::spectral
