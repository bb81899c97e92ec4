// The body plan: the articulated rigid bodies a simulated character is made of, built from a
// skeleton (and, when given, the motion it should perform). Joints become links; tiny and leaf
// joints (fingers, toes, hands, zero-length helpers such as CMU's hip joints) merge into their
// parents; knees and elbows become hinges, joints that do not move become fixed, the rest are
// ball joints. Shapes are capsules along limbs and boxes for feet; the total mass follows the
// figure's family and size (motion::estimateBody: a human by stature, a quadruped by trunk,
// others by shape volume), shared by the de Leva fractions for humans and by shape volume
// otherwise. Units: metres, kilograms, seconds.
//
// Frames: a link's frame is its skeleton joint's frame (origin at the pivot). At zero joint
// coordinates a link's frame is `zero_rotation` relative to its parent link's frame; a ball
// joint's coordinate q (unit quaternion) and a hinge's angle a act in the link's own frame:
//   link-relative rotation = zero_rotation * q            (ball)
//                          = zero_rotation * rotate(a, hinge_axis)   (hinge)
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/motion/anatomy.h"

namespace sinew::physics {

enum class JointType : std::uint8_t {
  kBase,   // the floating base (link 0): no joint, no actuator, moved only by contacts and gravity
  kFixed,  // welded to its parent at the observed pose: 0 DOF
  kHinge,  // 1 DOF about hinge_axis
  kBall,   // 3 DOF
};
const char* jointTypeName(JointType type);
int dofCount(JointType type);  // 0, 0, 1, 3

enum class ShapeType : std::uint8_t {
  kCapsule,  // along its local Y axis
  kBox,
  kSphere,
};

struct Shape {
  ShapeType type = ShapeType::kSphere;
  glm::dvec3 center{0.0};                   // in the link frame, metres
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  // shape frame -> link frame
  double radius = 0.05;                     // capsule and sphere radius, metres, > 0
  double half_length = 0.0;                 // capsule: half the cylinder between the caps, m, >= 0
  glm::dvec3 half_extents{0.05};            // box half sizes in the shape frame, metres, > 0
};

struct Link {
  std::string name;        // the skeleton joint's name
  int joint = 0;           // skeleton joint at the pivot
  int parent = -1;         // parent link index (< own index), -1 for the base only
  std::vector<int> chain;  // skeleton joints from just below the parent link's pivot joint down
                           // to `joint` (merged joints between them first); empty for the base
  JointType type = JointType::kBall;
  glm::dvec3 pivot{0.0};                         // pivot in the parent link's frame at zero, m
  glm::dquat zero_rotation{1.0, 0.0, 0.0, 0.0};  // link frame relative to its parent's at zero
  glm::dvec3 hinge_axis{1.0, 0.0, 0.0};          // hinge: unit axis in the link frame
  double hinge_lower = -3.0;  // hinge limits, radians, lower < upper; default from no clip
  double hinge_upper = 3.0;
  // Ball joint range, enforced by the world (a Bullet-solved limit between the link and its
  // parent): the rotation vector v = log(ball_center^-1 q) stays in [ball_lower, ball_upper] per
  // axis. ball_center is the middle of the observed range (the clip's frames and the standing
  // pose) in joint coordinates; the bounds are the observed extremes of v about it plus the
  // margin, radians, lower < upper (see ballRangeCoordinates). Without a clip (or for a joint the
  // clip holds still, made ball by an override): +-3 rad about q = 1, which the limit never
  // reaches (it acts below |v| = 0.9 pi): no limit in effect.
  glm::dquat ball_center{1.0, 0.0, 0.0, 0.0};
  glm::dvec3 ball_lower{-3.0};
  glm::dvec3 ball_upper{3.0};
  Shape shape;
  double mass_kg = 1.0;      // > 0
  glm::dvec3 com{0.0};       // centre of mass in the link frame (the shape's centre), m
  glm::dvec3 inertia{0.01};  // diagonal inertia about the centre of mass in the link
                             // frame, kg m^2 (off-diagonal terms of rotated shapes dropped)
  motion::Segment segment = motion::Segment::kNone;  // anthropometric group of the pivot joint
  bool foot = false;      // a foot (box sole) found by motion::findFeet
  bool supports = false;  // its subtree contains a foot: it carries the body when standing
};

// How joints merge and what the links get. Lengths scale with the rig: a length L in metres applies
// to a rig of size `reference_size_m` and is multiplied by (rig size / reference_size_m) otherwise.
struct BodyPlanSettings {
  double reference_size_m = 1.75;      // human height the lengths below are for, metres, > 0
  double min_segment_length_m = 0.05;  // joints closer than this to their parent, and leaf joints
                                       // shorter than this, merge into the parent, metres, >= 0
  std::vector<std::string> merge_names{
      "finger", "thumb", "index", "middle", "ring", "pinky",
      "toe",    "hand",  "nub",   "eye",    "jaw"};  // name parts (any
  // case) of joints merged into their parents (feet never)
  bool merge_short_trunk = true;  // trunk, neck and head joints (and clavicles) closer to their
                                  // parent link's pivot than that link's diameter merge into it:
                                  // short spine segments make light links that explicit PD cannot
                                  // hold stiffly (a 12 cm spine link of 2.7 kg diverges at 240 Hz)
  double max_lost_displacement = 0.02;  // a short joint whose turning in the clip moves its
                                        // children's pivots this far (a share of the rig size)
                                        // or more keeps a link of its own: merged, that motion
                                        // would be lost, >= 0
  std::vector<std::string> keep_names;  // name parts of joints never merged (overrides the above)
  std::vector<std::string> hinge_names{"knee", "elbow"};  // besides shank and forearm segments
  double hinge_dominance = 0.85;    // a hinge candidate is a hinge when its observed rotation
                                    // vectors' main axis carries this share of their second
                                    // moment, 0..1; otherwise it stays a ball joint
  double fixed_range_rad = 0.0175;  // joints moving less than this (max angle from the first
                                    // frame) over the clip are fixed, radians, >= 0 (1 degree)
  double limit_margin_rad = 0.26;   // added on both sides of the observed range, radians (15 deg)
  double human_mass_kg = 70.0;      // a human of reference_size_m stature, kg, > 0; a human of
                                    // stature H weighs this (H / reference_size_m)^2 (anatomy.h)
  double density_kg_m3 = 1000.0;    // other creatures: mass by shape volume, kg/m^3, > 0
  double min_link_mass_fraction = 0.01;   // no link lighter than this share of the total (tail
                                          // tips and paws by volume would be ~1/600), [0, 0.1)
  motion::SegmentMassTable mass_table;  // de Leva fractions
  // Overrides, applied after the rules above, each naming a link by its pivot joint's name
  // (exactly); a name that is not a link of the plan fails the build, naming it.
  std::vector<std::pair<std::string, double>> mass_overrides;  // link -> kg, > 0 (inertia scales
                                                               // with it; the total follows)
  std::vector<std::pair<std::string, JointType>> type_overrides;  // link -> kFixed or kBall
  std::vector<std::pair<std::string, std::pair<double, double>>> hinge_limit_overrides;  // hinge
                                                               // link -> (lower, upper) radians
  // Capsule radius (box half width for feet) as a fraction of the rig size, per group.
  double radius_head = 0.055, radius_trunk = 0.07, radius_upper_arm = 0.025, radius_forearm = 0.022,
         radius_hand = 0.02, radius_thigh = 0.04, radius_shank = 0.03, radius_foot = 0.028,
         radius_other = 0.02;

  Status validate() const;  // the message names the offending field
};

struct BodyPlan {
  std::vector<Link> links;         // parents before children; link 0 is the floating base
  std::vector<int> link_of_joint;  // (skeleton joints) the link each joint belongs to (merged
                                   // joints: the link that absorbed them; joints above the base:
                                   // the base)
  std::vector<glm::dquat> frozen_rotations;  // (skeleton joints) the local rotation merged and
                                             // fixed joints hold: the clip's first frame, or rest
  std::vector<glm::dquat> standing_rotations;  // (skeleton joints) the local rotations of the
                                              // standing pose when the rest pose does not stand
                                              // (the clip's mean pose); empty: the rest pose
  std::vector<int> base_chain;  // skeleton joints from the root down to the base joint (a root at
                                // the origin above the pelvis carries no body), root first
  double total_mass_kg = 0.0;   // sum of link masses
  double size_m = 0.0;          // the rig's largest extent in its first pose, metres
  bool human = false;           // a human (motion::measureFigure): de Leva masses
  std::vector<std::string> notes;  // what the user should know (joints merged, hinges refused)

  int dofCount() const;                 // sum over links of dofCount(type)
  std::vector<int> dofOffsets() const;  // (links) first DOF index of each link's joint
  Status validate() const;              // the message names the offending link and field
};

// Builds the plan. `observed_motion` may be null (joint types by name, default limits); otherwise
// it must match the skeleton. Fails, saying why, on an invalid skeleton, clip or settings.
Result<BodyPlan> buildBodyPlan(const motion::Skeleton& skeleton,
                               const motion::Clip* observed_motion,
                               const BodyPlanSettings& settings = {});

// Whether `ancestor` is `link` or one of its ancestors (links are stored parents first).
bool isAncestorLink(const BodyPlan& plan, int ancestor, int link);

// A character pose in link coordinates.
struct LinkPose {
  glm::dvec3 base_position{0.0};                 // base link frame origin, world metres
  glm::dquat base_rotation{1.0, 0.0, 0.0, 0.0};  // base link frame -> world
  std::vector<glm::dquat> rotations;  // (links) ball joint coordinate q (identity otherwise)
  std::vector<double> angles;         // (links) hinge angle, radians (0 otherwise)
};

// Maps a skeleton pose (local rotations and translations per joint, as in a Clip frame or
// TargetMotion::pose) to link coordinates: each link's rotation relative to its parent link,
// merged joints included, projected onto its joint type.
// Precondition: both spans have the skeleton's joint count; plan built from this skeleton.
LinkPose linkPoseFromSkeleton(const BodyPlan& plan, const motion::Skeleton& skeleton,
                              std::span<const glm::dquat> rotations,
                              std::span<const glm::dvec3> translations);

// The character standing: the rig's rest pose (every joint at its rest rotation; a T-pose for BVH
// rigs), turned upright (feet below the pelvis) if the rig stores it lying down; or, for a rig
// whose rest pose does not stand (BodyPlan::standing_rotations), the clip's mean pose. The plan's soles
// are level in this pose. The pose the standing tests hold; a simulation starts from it when it
// does not start from the clip.
LinkPose standingPose(const BodyPlan& plan, const motion::Skeleton& skeleton);

// Rotation of a link's frame relative to its parent's for a joint coordinate.
glm::dquat linkRelativeRotation(const Link& link, const glm::dquat& q, double angle);

// The height (world y) of a shape's lowest point when its link is at `link_to_world`, metres.
double lowestPoint(const Shape& shape, const glm::dmat4& link_to_world);

// The coordinates a ball joint's range bounds: log(ball_center^-1 q), radians (|v| <= pi).
// Inside the range when ball_lower <= v <= ball_upper on every axis.
glm::dvec3 ballRangeCoordinates(const Link& link, const glm::dquat& q);
// q itself when inside the ball range, else the range's point nearest to it in those coordinates
// (each axis clamped to [ball_lower, ball_upper]).
glm::dquat clampToBallRange(const Link& link, const glm::dquat& q);

}  // namespace sinew::physics
