// A skeleton is a parent-index array in depth-first order (parents before children), not a tree
// of pointers: loops over joints are plain for-loops. It also keeps each joint's channel layout
// exactly as its file had it, so BVH export can write the file back the way it came.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/euler.h"
#include "sinew/motion/units.h"

namespace sinew::motion {

inline constexpr int kNoParent = -1;

enum class ChannelType : std::uint8_t {
  kXposition,
  kYposition,
  kZposition,
  kXrotation,
  kYrotation,
  kZrotation
};

const char* channelName(ChannelType type);  // "Xposition", ...
inline bool isRotation(ChannelType type) { return type >= ChannelType::kXrotation; }
inline int channelAxis(ChannelType type) { return static_cast<int>(type) % 3; }  // 0 X, 1 Y, 2 Z

// One joint's channels in file order: 0, 3 or 6 entries (BVH); positions and rotations may
// interleave. The rotation channels, in the order they appear, define the joint's Euler order.
struct ChannelLayout {
  std::vector<ChannelType> types;

  int rotationCount() const;
  int positionCount() const;
  EulerOrder eulerOrder() const;  // order of the rotation channels; ZXY when there are none
};

struct Skeleton {
  std::vector<std::string> names;        // (joints) unique, non-empty, no whitespace
  std::vector<int> parents;              // (joints) parent index < own index, or kNoParent
  std::vector<glm::dvec3> offsets;       // (joints) rest translation from the parent, metres
  std::vector<glm::dquat> rest_rotations;  // (joints) rest local rotation; identity from BVH
  std::vector<glm::dvec3> rest_scales;   // (joints) rest local scale; 1 from BVH
  std::vector<std::optional<glm::dvec3>> end_sites;  // (joints) BVH End Site offset, metres
  std::vector<ChannelLayout> channels;   // (joints) layout as in the source file (may be empty)
  SourceFrame source;                    // the source file's units and up axis

  int jointCount() const { return static_cast<int>(names.size()); }
  int channelCount() const;  // sum of all layouts' sizes
  int findJoint(const std::string& name) const;  // index, or -1
  int depth(int joint) const;                    // 0 for a root

  // Appends a joint after its parent's subtree has been started (depth-first); returns its index.
  int addJoint(std::string name, int parent, const glm::dvec3& offset);

  // Every array the same length, parents before children, names unique and non-empty,
  // values finite. The message names the first offending joint.
  Status validate() const;
};

// The pelvis: the first joint with two or more children, or 0 when nothing branches. Joints
// above it (a root at the world origin, Bandai's joint_Root) carry no body and are left out of
// anything that measures the body: its size, its attitude, its centre of mass.
int pelvisJoint(const Skeleton& skeleton);

// Rest pose world transforms (joints), metres.
std::vector<glm::dmat4> restWorldTransforms(const Skeleton& skeleton);

}  // namespace sinew::motion
