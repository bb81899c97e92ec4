#include "sinew/motion/leg_ik.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "sinew/core/assert.h"
#include "sinew/core/rotation.h"

namespace sinew::motion {
namespace {

constexpr double kStraightMargin_m = 1e-3;  // the leg never quite straight: the knee keeps its way

// World rotation of `joint` in `frame`: the local rotations chained from the root.
glm::dquat worldRotation(const Skeleton& skeleton, const Clip& clip, int frame, int joint) {
  glm::dquat q(1.0, 0.0, 0.0, 0.0);
  for (int j = joint; j != kNoParent; j = skeleton.parents[j]) q = clip.rotation(frame, j) * q;
  return q;
}

// The shortest rotation taking direction a onto direction b (both non-zero).
glm::dquat rotationBetween(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 u = glm::normalize(a), v = glm::normalize(b);
  const glm::dvec3 axis = glm::cross(u, v);
  const double s = glm::length(axis);
  if (s < 1e-12) return glm::dquat(1.0, 0.0, 0.0, 0.0);  // parallel (opposite never happens here)
  return fromRotationVector(axis / s * std::atan2(s, glm::dot(u, v)));
}

glm::dquat& local(Clip& clip, int frame, int joint) {
  return clip.rotations[static_cast<size_t>(frame) * clip.joint_count + joint];
}

}  // namespace

LegIkResult placeAnkle(const Skeleton& skeleton, Clip& clip, int frame, int foot,
                       const glm::dvec3& target) {
  SINEW_ASSERT(frame >= 0 && frame < clip.frame_count, "placeAnkle: a frame of the clip");
  LegIkResult result;
  const int knee = skeleton.parents[foot];
  const int hip = knee == kNoParent ? kNoParent : skeleton.parents[knee];
  if (hip == kNoParent) return result;
  const std::vector<glm::dvec3> p = worldPositions(skeleton, clip, frame);
  const glm::dvec3 ph = p[hip], pk = p[knee], pa = p[foot];
  const double upper = glm::length(pk - ph), lower = glm::length(pa - pk);
  if (upper < 1e-9 || lower < 1e-9) return result;
  const glm::dquat parent_w =
      skeleton.parents[hip] == kNoParent ? glm::dquat(1.0, 0.0, 0.0, 0.0)
                                         : worldRotation(skeleton, clip, frame, skeleton.parents[hip]);
  const glm::dquat hip_w = parent_w * clip.rotation(frame, hip);
  const glm::dquat knee_w = hip_w * clip.rotation(frame, knee);
  const glm::dquat foot_w = knee_w * clip.rotation(frame, foot);
  // The knee: bend (or unbend) in the leg's plane until hip-to-ankle is the wanted distance.
  const double want = std::clamp(glm::length(target - ph), std::abs(upper - lower) + kStraightMargin_m,
                                 upper + lower - kStraightMargin_m);
  glm::dvec3 axis = glm::cross(pa - pk, ph - pk);
  if (glm::length(axis) < 1e-9) axis = knee_w * glm::dvec3(1.0, 0.0, 0.0);  // straight: its X
  axis = glm::normalize(axis);
  const double now = std::acos(std::clamp(glm::dot(glm::normalize(ph - pk), glm::normalize(pa - pk)), -1.0, 1.0));
  const double inner = std::acos(std::clamp((upper * upper + lower * lower - want * want) / (2.0 * upper * lower), -1.0, 1.0));
  // Turning the shank about `axis` by +x closes the knee's angle by x.
  const glm::dquat bend = fromRotationVector(axis * (now - inner));
  const glm::dvec3 ankle = pk + bend * (pa - pk);
  // The hip: the shortest turn taking the bent leg's ankle onto the target's direction.
  const glm::dquat swing = target == ph ? glm::dquat(1.0, 0.0, 0.0, 0.0)
                                        : rotationBetween(ankle - ph, target - ph);
  const glm::dquat hip_new = glm::normalize(swing * hip_w);
  const glm::dquat knee_new = glm::normalize(swing * bend * knee_w);
  const glm::dquat old_hip = clip.rotation(frame, hip), old_knee = clip.rotation(frame, knee),
                   old_foot = clip.rotation(frame, foot);
  local(clip, frame, hip) = glm::normalize(glm::conjugate(parent_w) * hip_new);
  local(clip, frame, knee) = glm::normalize(glm::conjugate(hip_new) * knee_new);
  local(clip, frame, foot) = glm::normalize(glm::conjugate(knee_new) * foot_w);
  result.solved = true;
  result.correction_rad = std::max({angleBetween(old_hip, clip.rotation(frame, hip)),
                                    angleBetween(old_knee, clip.rotation(frame, knee)),
                                    angleBetween(old_foot, clip.rotation(frame, foot))});
  result.residual_m = glm::length(worldPositions(skeleton, clip, frame)[foot] - target);
  return result;
}

}  // namespace sinew::motion
