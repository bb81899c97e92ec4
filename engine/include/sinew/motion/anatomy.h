// Anatomy from geometry: what kind of figure a skeleton is (how many legs reach the ground), how
// tall it stands, and so in what length unit and up axis its file was written. Names are never
// needed here: the rules read the posed skeleton only, so they hold for any studio's rig.
#pragma once

#include <cstdint>
#include <vector>

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
};

// Up axis and unit of a file's skeleton and clip (still in the file's numbers), by anatomy; the
// reason names the family, the measured size and the unit's choice.
FrameDetection detectFrame(const Skeleton& skeleton, const Clip& clip,
                           const FigureSizeRanges& ranges = {});

}  // namespace sinew::motion
