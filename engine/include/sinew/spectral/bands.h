// Band gains: named bands of harmonics (gait 1-2, style 3-5, detail 6+ by default) with a gain
// per band and per joint group. 0 filters a band out, 1 leaves it, > 1 amplifies it.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/motion/skeleton.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::spectral {

enum class JointGroup { kLegs, kArms, kSpine, kHead };
inline constexpr int kJointGroupCount = 4;
const char* jointGroupName(JointGroup group);  // "legs", "arms", "spine", "head"

// Groups by name (case-insensitive: leg/thigh/knee/shin/foot/ankle/toe/hip -> legs;
// shoulder/clavicle/arm/elbow/hand/wrist/finger/thumb -> arms; head/neck/jaw/eye -> head;
// spine/chest/pelvis/hips/root -> spine); a joint no rule names inherits its parent's group, a
// root is spine. (joints) entries.
std::vector<JointGroup> jointGroups(const motion::Skeleton& skeleton);

struct Band {
  std::string name;
  int first = 1;  // lowest harmonic number in the band, >= 1
  int last = 0;   // highest, >= first; 0 means no upper limit (only for the last band)
};

struct BandGains {
  std::vector<Band> bands = {{"gait", 1, 2}, {"style", 3, 5}, {"detail", 6, 0}};
  // (bands) gain per joint group, indexed by JointGroup; 1 = unchanged, 0 = removed; >= 0.
  std::vector<std::array<double, kJointGroupCount>> gains =
      std::vector<std::array<double, kJointGroupCount>>(3, {1.0, 1.0, 1.0, 1.0});

  // Bands ascending and disjoint, one gain row per band, gains finite and >= 0.
  Status validate() const;
  // Gain of harmonic n for a joint group (1 outside every band).
  double gain(int n, JointGroup group) const;
  // Sets a band's gain for one group, or for all groups when `group` is empty. The message
  // names an unknown band or group.
  Status set(const std::string& band, const std::string& group, double value);
};

// Every harmonic amplitude scaled by its band's gain for the joint's group; means, phases,
// tempo and travel unchanged. Precondition: gains validated.
TargetMotion applyBandGains(const TargetMotion& target, const motion::Skeleton& skeleton,
                            const BandGains& gains);

}  // namespace sinew::spectral
