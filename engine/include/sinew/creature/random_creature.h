// Random articulated creatures, after the "random hopping creatures" of the physics issue: from a
// seed, a torso with a few legs of random lengths, attachment points and joint kinds, and a
// default periodic clip to go with it. Every creature builds a valid physics body plan: each leg
// ends in a joint named "...Foot" (so motion::findFeet finds it and the plan gives it a box
// sole), hinges are named "...Knee" (so the plan makes them hinges), and no name uses a word the
// body plan or the mass model reads as something else (hand, head, hip, toe, ...).
//
// Units: metres, seconds, radians. Y up; the creature faces +Z, its left is +X. The rest pose (all
// rotations identity) is the creature standing with every toe tip at y = 0.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"

namespace sinew::creature {

struct CreatureSettings {
  std::uint64_t seed = 1;  // any value; the same seed gives the same creature, bit for bit
  int min_limbs = 2;       // legs, 1..8, min_limbs <= max_limbs; the count is drawn uniformly
  int max_limbs = 6;
  int min_segments = 1;  // bones per leg above the foot, 1..3, min_segments <= max_segments
  int max_segments = 3;
  double frame_rate_hz = 30.0;  // frames per second of the clip, (0, 1000]
  int strides = 4;              // strides in the clip, 1..100; one more frame closes the loop

  Status validate() const;  // the message names the offending field
};

enum class JointKind : std::uint8_t {
  kBall,   // moves about all three axes (only the joint at the torso)
  kHinge,  // moves about its X axis only (left-right at rest); named "...Knee" above the foot
  kFixed,  // does not move
};
const char* jointKindName(JointKind kind);  // "ball", "hinge", "fixed"

struct Limb {
  std::string name;         // name prefix of its joints ("LeftLimb1", "RightLimb1", "MidLimb3")
  std::vector<int> joints;  // skeleton joints from the one at the torso down to the foot
  std::vector<JointKind> kinds;  // (joints) how each moves in the clip
  int foot = -1;                 // the "...Foot" joint (the last of `joints`); its End Site is the
                                 // toe tip
};

struct Creature {
  motion::Skeleton skeleton;  // "Torso" (root, the pelvis) and the legs, depth first
  motion::Clip clip;          // the default clip: `strides` strides + 1 frame, the last frame equal
                              // to the first; the torso stays above the origin in x and z and its
                              // height keeps the lowest point of the body on y = 0 in every frame
  std::vector<Limb> limbs;
  int frames_per_stride = 0;    // whole frames, so the loop closes exactly
  double stride_s = 0.0;        // seconds
  double torso_height_m = 0.0;  // root height at rest, metres
};

// Generates the creature for `settings.seed`. Reproducible: the generator is std::mt19937_64,
// whose output the standard fixes, mapped to numbers without the standard distributions (which
// differ between library versions). Fails, naming the field, only on invalid settings.
//
// Legs: 1..3 bones of random lengths splayed out and down from random points under the torso
// (in left-right pairs, mirrored three times in four, and one on the midline when the count is
// odd), then the foot. The joint at the torso is a ball, hinge or fixed; the joints below it and
// the foot are hinges or fixed (ball joints on light lower bones made many creatures blow up
// under the PD controller). Each joint moves as a sum of one or two sinusoids (the stride
// frequency and its double) with random phases and amplitudes within ranges that keep legs from
// folding through the body (up to 15 degrees per sinusoid for ball joints, 20 for hinges, half
// that for feet); every sinusoid is offset so that the clip starts in the rest pose.
Result<Creature> randomCreature(const CreatureSettings& settings);

}  // namespace sinew::creature
