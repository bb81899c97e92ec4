// Euler angles as BVH stores them: three rotation channels in a per-joint order.
// The channel order left to right is the order of the intrinsic rotation matrices,
// R = R_first(a0) * R_second(a1) * R_third(a2), as every BVH reader and writer agrees.
#pragma once

#include <array>
#include <optional>
#include <string_view>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

namespace sinew::motion {

// The three axes in channel order, 0 = X, 1 = Y, 2 = Z. Always a permutation of {0, 1, 2}.
struct EulerOrder {
  std::array<int, 3> axes{2, 0, 1};  // default ZXY, the most common BVH order

  static std::optional<EulerOrder> fromName(std::string_view name);  // "ZXY", "xyz", ...
  std::array<char, 4> name() const;                                 // "ZXY" + NUL
  bool operator==(const EulerOrder&) const = default;
};

// Angles in radians, in channel order.
glm::dquat eulerToQuat(const EulerOrder& order, const glm::dvec3& angles);

// How angles are written. kPrincipal: the middle angle within [-pi/2, pi/2], the others within
// [-pi, pi], as a plain matrix-to-Euler conversion gives (what most BVH exporters write; curves
// jump at +-180 degrees). kContinuous: unwrapped, so that curves never jump.
enum class EulerRange { kPrincipal, kContinuous };

// The Euler angles of q in the given order, radians, in channel order. Of the equivalent triples
// (two Tait-Bryan branches, each angle plus any multiple of 2 pi) it returns, for kContinuous, the
// one closest to `reference`; for kPrincipal the principal one, with `reference` deciding only
// what the principal range leaves open (+-pi, gimbal lock). Either way a decoded file's angles
// come back as written. Pass the previous frame's angles as reference.
glm::dvec3 quatToEuler(const EulerOrder& order, const glm::dquat& q, const glm::dvec3& reference,
                       EulerRange range = EulerRange::kContinuous);

}  // namespace sinew::motion
