// Anatomy: the one place that says what a skeleton's joints are. From geometry alone, what kind
// of figure it is (how many legs reach the ground), how tall it stands, and so in what length unit
// and up axis its file was written; from names where they say it and geometry where they do not,
// its feet (and their sides and pairs) and each joint's anthropometric segment and mass share.
// Analysis, physics and the editor all ask here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "sinew/core/status.h"

#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/motion/units.h"

namespace sinew::motion {

enum class BodyFamily : std::uint8_t {
  kBiped,      // two legs reach the ground (a human, a bird)
  kQuadruped,  // four
  kOther,      // one (a hopper), three, more than four, or none found
};
const char* familyName(BodyFamily family);  // "biped", "quadruped", "other"

// A figure measured in one clip, along one up axis, in the clip's own units.
struct FigureMeasure {
  int up_axis = 1;  // 1: Y, 2: Z (of the clip's numbers)
  BodyFamily family = BodyFamily::kOther;
  bool human = false;       // a biped with arms and a head above its legs (three chain ends or
                            // more that never reach the ground, height >= 1.3 hip heights)
  int legs = 0;             // limbs whose lowest point reaches the ground in the sampled frames
  double height = 0.0;      // extent along up of the pelvis and everything below it, first frame
  double hip_height = 0.0;  // the pelvis above the lowest point, first frame
};

// Measures the figure: the pelvis (the first joint that branches) and its subtree, End Sites
// included, posed by `clip` (any units). A leg is a group of chain ends that come within a quarter
// of the hip height of the lowest point in some sampled frame (up to 64 frames), grouped while they
// meet below half the hip height (a foot's toes meet at the ankle; two feet only at the pelvis).
// The up axis, when not given (up_axis 0), is the one along which several chain ends share the
// lowest level with the pelvis clearly above them.
// Precondition: clip validated against the skeleton.
FigureMeasure measureFigure(const Skeleton& skeleton, const Clip& clip, int up_axis = 0);

// Plausible sizes, metres. For a human or a quadruped the unit is the one that puts the figure's
// size inside its family's range (nearest to the range, on a log scale, when none does); among
// several, the commoner unit in the order cm, m, mm, in, CMU, ft. Other creatures have no size to
// expect: >= 1000 file units reads as mm, >= 10 as cm, else metres.
struct FigureSizeRanges {
  // The extent of the joints in the first frame: an adult of 1.4-2.1 m stature, less the head
  // above its last joint (Bandai's head End Site has no length) and a lean or a crouch.
  double human_height_min_m = 1.1;
  double human_height_max_m = 2.1;
  double quadruped_hip_min_m = 0.15;  // hip height: a cat to a horse
  double quadruped_hip_max_m = 1.8;
  // Other creatures have no range; a file that states its unit (glTF: metres) is believed for a
  // figure under this height (the size rule above reads 10 units and more as centimetres).
  double other_height_max_m = 10.0;
};

// Up axis and unit of a file's skeleton and clip (still in the file's numbers), by anatomy; the
// reason names the family, the measured size and the unit's choice.
FrameDetection detectFrame(const Skeleton& skeleton, const Clip& clip,
                           const FigureSizeRanges& ranges = {});

// For a file whose format states its frame (glTF: metres, Y-up by specification) but whose
// exporters do not always keep it (the Khronos Fox is in centimetres): the figure is measured
// along the stated up axis, and the stated unit is kept when it makes the figure plausible (a
// human or a quadruped inside its range, another creature under other_height_max_m); otherwise
// the unit is chosen as detectFrame chooses it, and the reason says both.
FrameDetection detectStatedFrame(const Skeleton& skeleton, const Clip& clip,
                                 const SourceFrame& stated, const FigureSizeRanges& ranges = {});

enum class Side : std::uint8_t { kUnknown, kLeft, kRight };
const char* sideName(Side side);  // "left", "right", "unknown"

// A point that can touch the ground: a joint, or a joint's End Site.
struct FootPoint {
  int joint = 0;          // skeleton joint index
  bool end_site = false;  // the joint's End Site rather than the joint itself
};

struct Foot {
  int joint = 0;                  // the foot joint (ankle, or paw): its subtree is the foot
  Side side = Side::kUnknown;     // from the joint names, else from the first frame's pose
  bool by_name = true;            // found by its name; false: by geometry (lowest chain end)
  int pair = -1;                  // the opposite foot of the same pair (left <-> right; front or
                                  // hind for quadrupeds), index into the feet, or -1
  std::vector<FootPoint> points;  // the foot joint, its descendants and their End Sites; each
                                  // frame the lowest of them is the contact point (heel or ankle
                                  // first, then the toe as a flat foot rolls over)
};

// World positions of every joint and End Site over a clip's first frames: what finding feet and
// their contacts reads.
struct Poses {
  int joints = 0;
  std::vector<glm::dvec3> joint;  // (frames x joints) metres
  std::vector<glm::dvec3> site;   // (frames x joints) End Site, or the joint when it has none

  const glm::dvec3& at(int frame, const FootPoint& p) const {
    const size_t n = static_cast<size_t>(frame) * joints + p.joint;
    return p.end_site ? site[n] : joint[n];
  }
};

// Precondition: clip validated against the skeleton, frames <= clip.frame_count.
Poses computePoses(const Skeleton& skeleton, const Clip& clip, int frames);

// A vector's horizontal part (Y up), and the figure's left for a travel direction: up x forward.
glm::dvec3 horizontal(const glm::dvec3& v);
glm::dvec3 leftOf(const glm::dvec3& forward);

// Chain ends of the leg chains: joints named foot, ankle, toe, paw or hoof (the uppermost such
// joint of each chain); and, for legs those names miss (a dog's front legs end in "Hand"),
// chain ends lying on the ground in the first frame in branches of their own below the pelvis.
// Feet are in joint order. Fails, saying why, when the skeleton has none.
Result<std::vector<Foot>> findFeet(const Skeleton& skeleton, const Clip& clip);

// Segment mass fractions of the whole body (de Leva 1996, adult male: Adjustments to
// Zatsiorsky-Seluyanov's segment inertia parameters, J. Biomech. 29(9)). Fractions, 0..1, for one
// segment (each limb segment counts once per limb); renormalised over the segments a skeleton has.
struct SegmentMassTable {
  double head = 0.0694;       // head and neck
  double trunk = 0.4346;      // pelvis to shoulders, clavicles included
  double upper_arm = 0.0271;  // per arm
  double forearm = 0.0162;
  double hand = 0.0061;
  double thigh = 0.1416;  // per leg (a quadruped's front legs count as legs)
  double shank = 0.0433;
  double foot = 0.0137;  // toes included

  Status validate() const;  // every fraction finite and >= 0, their sum > 0
};

enum class Segment : std::uint8_t {
  kNone,  // carries no mass: joints above the pelvis (a root at the origin), or zero length
  kHead,
  kTrunk,
  kUpperArm,
  kForearm,
  kHand,
  kThigh,
  kShank,
  kFoot,
  kOther,  // no anthropometric match (a tail): mass by bone length at the body's mean density
};
const char* segmentName(Segment segment);

// Each joint's body is the bones from the joint to its children and End Site; its centre of mass
// is the length-weighted mean of the bones' midpoints (the joint itself when they have no
// length).
struct MassDistribution {
  std::vector<Segment> segments;  // (joints) what each joint's body is
  std::vector<double> fractions;  // (joints) share of the total mass, summing to 1
};

// Segments are matched structurally where names are ambiguous ("Shoulder" is a clavicle in some
// rigs and an upper arm in others): from each foot up, foot / shank / thigh; from each hand
// (the uppermost joint named hand or wrist outside the legs) up, hand / forearm / upper arm; the
// uppermost head joint's subtree and neck joints, head; the joints above those, trunk. Twist and
// helper joints inside a limb segment share its mass.
MassDistribution massDistribution(const Skeleton& skeleton, const std::vector<Foot>& feet,
                                  const SegmentMassTable& table = {});

// What a figure's skeleton says of its body: its family, its size in the terms of that family and
// what it weighs. Sources: stature from the legs by Winter's segment lengths (Biomechanics and
// Motor Control of Human Movement, 4th ed., fig. 4.1: hip joint 0.530 and ankle 0.039 of the
// stature, so thigh plus shank is 0.491) or from the joints' extent when that is taller (a
// short-legged figure; the topmost joint is taken at the chin's level, 0.870); a human's mass
// from the stature at a constant body-mass index; a quadruped's from the trunk between its limb
// girdles, cubed (canids: red fox, coyote and grey wolf all weigh about 19 kg per cubed metre of
// head-body length, and the trunk from hip to shoulder joint is about 0.45 of that length).
struct BodyMassModel {
  double human_mass_kg = 70.0;     // a human of human_stature_m, kg, > 0 (body-mass index 22.9)
  double human_stature_m = 1.75;   // > 0; a human of stature H weighs human_mass_kg (H / this)^2
  double quadruped_kg_m3 = 208.0;  // a quadruped weighs this times its trunk length cubed, > 0
                                   // (19 kg/m^3 / 0.45^3)
};

struct BodyEstimate {
  FigureMeasure figure;         // family, legs and human, measured along Y (metres)
  double extent_m = 0.0;        // the joints' extent along Y in the first frame: to the topmost
                                // joint or End Site (often the head joint, not the head top)
  double leg_length_m = 0.0;    // mean over the legs of thigh plus shank bone length (each foot
                                // joint's bone and the one above it), metres
  double stature_m = 0.0;       // a human's standing height to the top of the head, else 0
  double trunk_length_m = 0.0;  // a quadruped's: between the mid-points of its two pairs of leg
                                // tops (hip and shoulder) in the first frame, else 0
  double mass_kg = 0.0;         // by the model for a human or a quadruped; 0: no model (other
                                // creatures), the caller weighs them by volume
  std::string basis;            // one line: the family and what the size and mass come from
};

// Precondition: skeleton in metres, Y up (as imported); clip validated; `feet` from findFeet.
BodyEstimate estimateBody(const Skeleton& skeleton, const Clip& clip, const std::vector<Foot>& feet,
                          const BodyMassModel& model = {});

// Centre of mass per frame, world metres.
std::vector<glm::dvec3> centreOfMass(const Skeleton& skeleton, const Clip& clip,
                                     const MassDistribution& masses);

}  // namespace sinew::motion
