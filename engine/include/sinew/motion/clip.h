// A clip: a frame time and, per frame and joint, the local rotation and translation (and scale,
// only when a glTF file animates it). Engine units: metres, Y-up, seconds.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/skeleton.h"

namespace sinew::motion {

struct Clip {
  std::string name;           // animation name (glTF) or file stem (BVH)
  double frame_time = 0.0;    // seconds per frame, > 0
  int frame_count = 0;        // >= 1
  int joint_count = 0;        // equals the skeleton's joint count
  std::vector<glm::dquat> rotations;     // (frames x joints) local rotation, unit quaternions
  std::vector<glm::dvec3> translations;  // (frames x joints) local translation, metres
  std::vector<glm::dvec3> scales;        // (frames x joints) local scale, or empty when all 1
  // How the source BVH wrote Euler angles, so that export writes them the same way and curves in
  // other tools look as they did: (joints) the first frame's angles, radians, in each joint's
  // channel order (empty unless the clip came from BVH), and whether any angle went beyond
  // +-180 degrees (unwrapped curves) or all were wrapped into (-180, 180].
  std::vector<glm::dvec3> euler_start;
  EulerRange euler_range = EulerRange::kPrincipal;

  double duration() const { return frame_time * (frame_count > 0 ? frame_count - 1 : 0); }
  double fps() const { return frame_time > 0.0 ? 1.0 / frame_time : 0.0; }

  const glm::dquat& rotation(int frame, int joint) const {
    return rotations[static_cast<size_t>(frame) * joint_count + joint];
  }
  const glm::dvec3& translation(int frame, int joint) const {
    return translations[static_cast<size_t>(frame) * joint_count + joint];
  }
  glm::dvec3 scale(int frame, int joint) const {
    return scales.empty() ? glm::dvec3(1.0) : scales[static_cast<size_t>(frame) * joint_count + joint];
  }

  // Sizes agree with the skeleton, frame time positive, values finite, quaternions unit length.
  Status validate(const Skeleton& skeleton) const;
};

// Frames needed to cover `duration` seconds at `frame_time`, both ends included. Times within 0.1%
// of a frame past a whole frame count as whole: files round frame times (0.0333333 for 1/30 s)
// and glTF stores key times as floats, and neither should lose the last frame to rounding.
int frameCountFor(double duration, double frame_time);

// Frames [first, first + count) of `clip` (clamped to the clip, at least one frame), as a clip of
// their own with the same frame time; the BVH Euler start is kept only when first is 0.
Clip clipFrames(const Clip& clip, int first, int count);

// A clip of `frame_count` frames holding the skeleton's rest pose.
Clip restClip(const Skeleton& skeleton, int frame_count, double frame_time);

// Forward kinematics for one frame: world transforms (joints) into `out`, metres.
// Precondition: out.size() == skeleton.jointCount(), clip validated against skeleton.
void worldTransforms(const Skeleton& skeleton, const Clip& clip, int frame,
                     std::span<glm::dmat4> out);

// World positions of every joint for one frame, metres.
std::vector<glm::dvec3> worldPositions(const Skeleton& skeleton, const Clip& clip, int frame);

}  // namespace sinew::motion
