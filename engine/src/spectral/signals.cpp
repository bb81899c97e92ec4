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

int MotionSignals::find(int joint, SignalKind kind, int axis) const {
  for (size_t c = 0; c < channels.size(); ++c) {
    if (channels[c].joint == joint && channels[c].kind == kind && channels[c].axis == axis) {
      return static_cast<int>(c);
    }
  }
  return -1;
}

// Frame-major: the clip stores frames one after another, so walking every joint of a frame
// before the next frame reads memory in order (joint-major strides by a whole frame per step and
// misses the cache on every read of a long clip). Per joint the arithmetic is the same, in the
// same order, as one joint at a time.
MotionSignals extractSignals(const motion::Skeleton& skeleton, const motion::Clip& clip,
                             double min_rotation_rad, double min_translation_m) {
  MotionSignals signals;
  signals.frame_time = clip.frame_time;
  signals.frame_count = clip.frame_count;
  const int joints = skeleton.jointCount();
  const int frames = clip.frame_count;
  const double count = static_cast<double>(frames);
  signals.mean_rotations.resize(joints);
  signals.mean_translations.assign(joints, glm::dvec3(0.0));
  if (!clip.scales.empty()) {
    signals.mean_scales.assign(joints, glm::dvec3(0.0));
    for (int f = 0; f < frames; ++f) {
      for (int j = 0; j < joints; ++j) signals.mean_scales[j] += clip.scale(f, j) / count;
    }
  }
  // Pass 1: quaternion signs continuous frame to frame, their sum (the chordal mean), and the
  // mean translation. A joint whose rotation or translation is the same in every frame cannot
  // pass a threshold of 1e-9 or more (its deviation from its own mean is rounding, under 1e-12):
  // pass 2 skips it.
  std::vector<glm::dquat> previous(joints);
  std::vector<glm::dvec4> sum(joints, glm::dvec4(0.0));
  std::vector<char> rotates(joints, min_rotation_rad < 1e-9 ? 1 : 0);
  std::vector<char> translates(joints, min_translation_m < 1e-9 ? 1 : 0);
  for (int f = 0; f < frames; ++f) {
    const glm::dquat* rotations = &clip.rotation(f, 0);
    const glm::dvec3* translations = &clip.translation(f, 0);
    for (int j = 0; j < joints; ++j) {
      glm::dquat q = rotations[j];
      if (!rotates[j]) rotates[j] = q != clip.rotation(0, j);
      if (!translates[j]) translates[j] = translations[j] != clip.translation(0, j);
      if (f > 0 && glm::dot(q, previous[j]) < 0.0) q = -q;
      previous[j] = q;
      sum[j] += glm::dvec4(q.x, q.y, q.z, q.w);
      signals.mean_translations[j] += translations[j];
    }
  }
  for (glm::dvec3& mean : signals.mean_translations) mean /= count;
  for (int j = 0; j < joints; ++j) {
    const double norm = glm::length(sum[j]);
    const glm::dvec4& s = sum[j];
    signals.mean_rotations[j] = norm > 1e-9 * frames
                                    ? glm::dquat(s.w / norm, s.x / norm, s.y / norm, s.z / norm)
                                    : clip.rotation(0, j);  // frame 0 is never sign-flipped
  }
  // Pass 2: every joint's rotation vector relative to its mean (the same continuous signs,
  // recomputed) and translation relative to its mean, written straight into the channels; joints
  // that turn out not to move are dropped at the end. Sizes are compared squared.
  std::vector<std::vector<double>> rotation_values(static_cast<size_t>(joints) * 3);
  std::vector<std::vector<double>> translation_values(static_cast<size_t>(joints) * 3);
  for (int j = 0; j < joints; ++j) {
    for (int axis = 0; axis < 3; ++axis) {
      if (rotates[j]) rotation_values[static_cast<size_t>(j) * 3 + axis].resize(frames);
      if (translates[j]) translation_values[static_cast<size_t>(j) * 3 + axis].resize(frames);
    }
  }
  std::vector<glm::dquat> continuous(joints);
  std::vector<glm::dquat> relative_before(joints, glm::dquat(1.0, 0.0, 0.0, 0.0));
  std::vector<glm::dquat> inverse_mean(joints);
  for (int j = 0; j < joints; ++j) inverse_mean[j] = glm::conjugate(signals.mean_rotations[j]);
  std::vector<double> largest(joints, 0.0);  // squared, radians^2
  std::vector<double> reach(joints, 0.0);    // squared, metres^2
  const auto squared = [](double threshold) { return threshold > 0.0 ? threshold * threshold : -1.0; };
  for (int f = 0; f < frames; ++f) {
    const glm::dquat* rotations = &clip.rotation(f, 0);
    const glm::dvec3* translations = &clip.translation(f, 0);
    for (int j = 0; j < joints; ++j) {
      const size_t c = static_cast<size_t>(j) * 3;
      if (rotates[j]) {
        glm::dquat q = rotations[j];
        if (f > 0 && glm::dot(q, continuous[j]) < 0.0) q = -q;
        continuous[j] = q;
        glm::dquat relative = inverse_mean[j] * q;
        if (glm::dot(relative, relative_before[j]) < 0.0) relative = -relative;
        relative_before[j] = relative;
        const glm::dvec3 v = rotationVector(relative);
        largest[j] = std::max(largest[j], glm::dot(v, v));
        for (int axis = 0; axis < 3; ++axis) rotation_values[c + axis][f] = v[axis];
      }
      if (translates[j]) {
        const glm::dvec3 t = translations[j] - signals.mean_translations[j];
        reach[j] = std::max(reach[j], glm::dot(t, t));
        for (int axis = 0; axis < 3; ++axis) translation_values[c + axis][f] = t[axis];
      }
    }
  }
  for (int j = 0; j < joints; ++j) {
    const size_t c = static_cast<size_t>(j) * 3;
    if (rotates[j] && largest[j] >= squared(min_rotation_rad)) {
      for (int axis = 0; axis < 3; ++axis) {
        signals.channels.push_back({j, SignalKind::kRotation, axis, std::move(rotation_values[c + axis])});
      }
    }
    if (translates[j] && reach[j] >= squared(min_translation_m)) {
      if (signals.travel_joint < 0) signals.travel_joint = j;
      for (int axis = 0; axis < 3; ++axis) {
        signals.channels.push_back(
            {j, SignalKind::kTranslation, axis, std::move(translation_values[c + axis])});
      }
    }
  }
  return signals;
}

}  // namespace sinew::spectral
