#include "sinew/motion/clip.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "sinew/motion/limits.h"
#include "sinew/core/assert.h"

namespace sinew::motion {

Status Clip::validate(const Skeleton& skeleton) const {
  const std::string label = "clip '" + name + "'";
  if (!(frame_time >= kMinFrameTime_s && frame_time <= kMaxFrameTime_s)) {
    return Status::error(label + ": frame time must be from 0.0001 to 60 seconds");
  }
  if (frame_count < 1) return Status::error(label + ": has no frames");
  if (joint_count != skeleton.jointCount()) {
    return Status::error(label + ": has " + std::to_string(joint_count) + " joints, the skeleton " +
                         std::to_string(skeleton.jointCount()));
  }
  const size_t size = static_cast<size_t>(frame_count) * joint_count;
  if (rotations.size() != size || translations.size() != size ||
      (!scales.empty() && scales.size() != size)) {
    return Status::error(label + ": pose arrays do not hold frames x joints values");
  }
  for (size_t n = 0; n < size; ++n) {
    const glm::dquat& q = rotations[n];
    const glm::dvec3& t = translations[n];
    if (!(std::abs(glm::length(q) - 1.0) < 1e-6) || !std::isfinite(t.x) || !std::isfinite(t.y) ||
        !std::isfinite(t.z)) {
      return Status::error(label + ": frame " + std::to_string(n / joint_count) + ", joint '" +
                           skeleton.names[n % joint_count] + "': not a finite pose");
    }
    if (!withinLength(t) || (!scales.empty() && !withinScale(scales[n]))) {
      return Status::error(label + ": frame " + std::to_string(n / joint_count) + ", joint '" +
                           skeleton.names[n % joint_count] +
                           "': translation or scale beyond the limit of 1e6 (metres)");
    }
  }
  return {};
}

int frameCountFor(double duration, double frame_time) {
  if (!(duration > 0.0) || !(frame_time > 0.0)) return 1;
  // Capped so that absurd inputs stay representable; callers refuse what they cannot hold.
  return static_cast<int>(std::min(std::floor(duration / frame_time + 1e-3) + 1.0, 2e9));
}

Clip clipFrames(const Clip& clip, int first, int count) {
  if (clip.frame_count < 1) return clip;
  first = std::clamp(first, 0, std::max(0, clip.frame_count - 1));
  count = std::clamp(count, 1, clip.frame_count - first);
  Clip out;
  out.name = clip.name;
  out.frame_time = clip.frame_time;
  out.frame_count = count;
  out.joint_count = clip.joint_count;
  const auto begin = static_cast<ptrdiff_t>(first) * clip.joint_count;
  const auto end = begin + static_cast<ptrdiff_t>(count) * clip.joint_count;
  out.rotations.assign(clip.rotations.begin() + begin, clip.rotations.begin() + end);
  out.translations.assign(clip.translations.begin() + begin, clip.translations.begin() + end);
  if (!clip.scales.empty()) out.scales.assign(clip.scales.begin() + begin, clip.scales.begin() + end);
  if (first == 0) out.euler_start = clip.euler_start;
  out.euler_range = clip.euler_range;
  return out;
}

Clip restClip(const Skeleton& skeleton, int frame_count, double frame_time) {
  Clip clip;
  clip.name = "rest";
  clip.frame_time = frame_time;
  clip.frame_count = frame_count;
  clip.joint_count = skeleton.jointCount();
  for (int f = 0; f < frame_count; ++f) {
    clip.rotations.insert(clip.rotations.end(), skeleton.rest_rotations.begin(),
                          skeleton.rest_rotations.end());
    clip.translations.insert(clip.translations.end(), skeleton.offsets.begin(),
                             skeleton.offsets.end());
  }
  return clip;
}

void worldTransforms(const Skeleton& skeleton, const Clip& clip, int frame,
                     std::span<glm::dmat4> out) {
  SINEW_ASSERT(out.size() == static_cast<size_t>(skeleton.jointCount()),
               "worldTransforms: one matrix per joint");
  SINEW_ASSERT(frame >= 0 && frame < clip.frame_count, "worldTransforms: a frame of the clip");
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    glm::dmat4 local = glm::translate(glm::dmat4(1.0), clip.translation(frame, j)) *
                       glm::mat4_cast(clip.rotation(frame, j));
    if (!clip.scales.empty()) local = glm::scale(local, clip.scale(frame, j));
    const int parent = skeleton.parents[j];
    out[j] = parent == kNoParent ? local : out[parent] * local;
  }
}

std::vector<glm::dvec3> worldPositions(const Skeleton& skeleton, const Clip& clip, int frame) {
  std::vector<glm::dmat4> world(skeleton.jointCount());
  worldTransforms(skeleton, clip, frame, world);
  std::vector<glm::dvec3> positions(world.size());
  for (size_t j = 0; j < world.size(); ++j) positions[j] = glm::dvec3(world[j][3]);
  return positions;
}

}  // namespace sinew::motion
