#include "sinew/motion/skeleton.h"

#include <cmath>
#include <unordered_set>

#include <glm/gtc/matrix_transform.hpp>

#include "sinew/motion/limits.h"

namespace sinew::motion {
namespace {

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool within(const glm::dvec3& v, double limit) {
  return std::abs(v.x) <= limit && std::abs(v.y) <= limit && std::abs(v.z) <= limit;
}

}  // namespace

bool withinLength(const glm::dvec3& v) {
  return within(v, kMaxLength_m);
}
bool withinScale(const glm::dvec3& v) {
  return within(v, kMaxScale);
}

const char* channelName(ChannelType type) {
  switch (type) {
    case ChannelType::kXposition: return "Xposition";
    case ChannelType::kYposition: return "Yposition";
    case ChannelType::kZposition: return "Zposition";
    case ChannelType::kXrotation: return "Xrotation";
    case ChannelType::kYrotation: return "Yrotation";
    case ChannelType::kZrotation: return "Zrotation";
  }
  return "?";
}

int ChannelLayout::rotationCount() const {
  int count = 0;
  for (ChannelType type : types) count += isRotation(type) ? 1 : 0;
  return count;
}

int ChannelLayout::positionCount() const {
  return static_cast<int>(types.size()) - rotationCount();
}

EulerOrder ChannelLayout::eulerOrder() const {
  EulerOrder order;
  int n = 0;
  for (ChannelType type : types) {
    if (isRotation(type) && n < 3) order.axes[n++] = channelAxis(type);
  }
  return n == 3 ? order : EulerOrder{};
}

int Skeleton::channelCount() const {
  int count = 0;
  for (const ChannelLayout& layout : channels) count += static_cast<int>(layout.types.size());
  return count;
}

int Skeleton::findJoint(const std::string& name) const {
  for (int j = 0; j < jointCount(); ++j) {
    if (names[j] == name) return j;
  }
  return -1;
}

int Skeleton::depth(int joint) const {
  int depth = 0;
  for (int j = parents[joint]; j != kNoParent; j = parents[j]) ++depth;
  return depth;
}

int Skeleton::addJoint(std::string name, int parent, const glm::dvec3& offset) {
  names.push_back(std::move(name));
  parents.push_back(parent);
  offsets.push_back(offset);
  rest_rotations.emplace_back(1.0, 0.0, 0.0, 0.0);
  rest_scales.emplace_back(1.0);
  end_sites.emplace_back();
  channels.emplace_back();
  return jointCount() - 1;
}

Status Skeleton::validate() const {
  const size_t n = names.size();
  if (n == 0) return Status::error("skeleton has no joints");
  if (parents.size() != n || offsets.size() != n || rest_rotations.size() != n ||
      rest_scales.size() != n || end_sites.size() != n || channels.size() != n) {
    return Status::error("skeleton arrays differ in length (" + std::to_string(n) + " names)");
  }
  std::unordered_set<std::string> seen;
  for (size_t j = 0; j < n; ++j) {
    const std::string label = "joint " + std::to_string(j) + " '" + names[j] + "'";
    if (names[j].empty()) return Status::error("joint " + std::to_string(j) + " has no name");
    if (!seen.insert(names[j]).second) return Status::error(label + ": duplicate joint name");
    if (parents[j] != kNoParent && (parents[j] < 0 || parents[j] >= static_cast<int>(j))) {
      return Status::error(label + ": parent " + std::to_string(parents[j]) +
                           " does not come before it (depth-first order expected)");
    }
    if (!finite(offsets[j]) || !finite(rest_scales[j]) ||
        (end_sites[j] && !finite(*end_sites[j]))) {
      return Status::error(label + ": offset, scale or end site is not a finite number");
    }
    if (!withinLength(offsets[j]) || (end_sites[j] && !withinLength(*end_sites[j])) ||
        !withinScale(rest_scales[j])) {
      return Status::error(
          label +
          ": offset, scale or end site beyond the limit of 1e6 (metres, or times for a scale)");
    }
    const glm::dquat& q = rest_rotations[j];
    if (!(std::abs(glm::length(q) - 1.0) < 1e-6)) {
      return Status::error(label + ": rest rotation is not a unit quaternion");
    }
    if (channels[j].rotationCount() != 0 && channels[j].rotationCount() != 3) {
      return Status::error(label + ": has " + std::to_string(channels[j].rotationCount()) +
                           " rotation channels, expected 0 or 3");
    }
  }
  return {};
}

int pelvisJoint(const Skeleton& skeleton) {
  std::vector<int> children(skeleton.jointCount(), 0);
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    if (skeleton.parents[j] != kNoParent) ++children[skeleton.parents[j]];
  }
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    if (children[j] >= 2) return j;
  }
  return 0;
}

std::vector<glm::dmat4> restWorldTransforms(const Skeleton& skeleton) {
  std::vector<glm::dmat4> world(skeleton.jointCount());
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    glm::dmat4 local = glm::translate(glm::dmat4(1.0), skeleton.offsets[j]) *
                       glm::mat4_cast(skeleton.rest_rotations[j]) *
                       glm::scale(glm::dmat4(1.0), skeleton.rest_scales[j]);
    const int parent = skeleton.parents[j];
    world[j] = parent == kNoParent ? local : world[parent] * local;
  }
  return world;
}

}  // namespace sinew::motion
