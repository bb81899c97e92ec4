// Rotation maths on unit quaternions (glm::dquat, w first), the one owner for the engine and the
// app: the angle between two rotations, the rotation vector (log map) and back (exp map), the
// sign with w >= 0, slerp the short way. Euler angles are motion/euler.h's.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

namespace sinew {

// The angle between two rotations, radians in [0, pi]; exact for tiny angles (acos is not).
// Precondition: unit quaternions (the conjugate stands for the inverse).
double angleBetween(const glm::dquat& a, const glm::dquat& b);

// The rotation vector (axis * angle, radians) of a unit quaternion, as it is: |v| in [0, pi]
// when q.w >= 0, in (pi, 2 pi] when q.w < 0 (q and -q are the same rotation; see
// shortRotationVector). Near identity (|xyz| < 1e-12) it is 2 xyz, the small-angle limit.
glm::dvec3 rotationVector(const glm::dquat& q);

// The rotation vector of q taken the short way (of q or -q, the one with w >= 0): |v| <= pi.
glm::dvec3 shortRotationVector(const glm::dquat& q);

// The unit quaternion of a rotation vector (the exponential map), w >= 0 for |v| <= pi.
glm::dquat fromRotationVector(const glm::dvec3& v);

// q or -q, whichever has w >= 0 (the same rotation).
glm::dquat positiveW(const glm::dquat& q);

// Slerp from a (t = 0) to b (t = 1) the short way (b's sign flipped when a . b < 0), normalised.
glm::dquat shortSlerp(const glm::dquat& a, glm::dquat b, double t);

}  // namespace sinew
