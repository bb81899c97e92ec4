// Two-bone leg IK on one frame of a clip: the hip and knee turn so that the ankle (a foot joint)
// reaches a world position, the foot keeping its world rotation. What planting a foot needs
// (pipeline/physical_loop.h); the rest of the body is left as it is.
#pragma once

#include <glm/vec3.hpp>

#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"

namespace sinew::motion {

struct LegIkResult {
  bool solved = false;      // false: the foot has no knee and hip above it (nothing changed)
  double residual_m = 0.0;  // ankle to target after the solve (the leg's reach limits it)
  double correction_rad = 0.0;  // the largest change of the hip's, knee's or foot's rotation
};

// Turns `foot`'s parent (knee) about the leg's bending axis until hip-to-ankle is the distance to
// `target` (world metres; within the leg's reach, 1 mm short of straight), then the knee's parent
// (hip) the shortest way onto it. Precondition: clip validated against the skeleton, `frame` in
// it, `foot` a joint.
LegIkResult placeAnkle(const Skeleton& skeleton, Clip& clip, int frame, int foot,
                       const glm::dvec3& target);

}  // namespace sinew::motion
