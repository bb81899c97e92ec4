#include "sinew/spectral/bands.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace sinew::spectral {
namespace {

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

bool contains(const std::string& text, std::initializer_list<const char*> words) {
  for (const char* word : words) {
    if (text.find(word) != std::string::npos) return true;
  }
  return false;
}

// The group a name says, or -1 when it says none. "Hips" is the pelvis (spine); "LeftHip" a leg.
int groupByName(const std::string& raw) {
  const std::string name = lower(raw);
  if (contains(name, {"head", "neck", "jaw", "eye", "nose", "skull"})) return static_cast<int>(JointGroup::kHead);
  if (contains(name, {"spine", "chest", "torso", "pelvis", "abdomen", "waist", "root"}) ||
      name == "hips" || name.ends_with(":hips") || name.ends_with("_hips")) {
    return static_cast<int>(JointGroup::kSpine);
  }
  if (contains(name, {"shoulder", "clavicle", "collar", "arm", "elbow", "hand", "wrist", "finger",
                      "thumb", "index", "middle", "ring", "pinky"})) {
    return static_cast<int>(JointGroup::kArms);
  }
  if (contains(name, {"leg", "thigh", "knee", "shin", "calf", "foot", "ankle", "toe", "hip", "heel"})) {
    return static_cast<int>(JointGroup::kLegs);
  }
  return -1;
}

}  // namespace

const char* jointGroupName(JointGroup group) {
  switch (group) {
    case JointGroup::kLegs: return "legs";
    case JointGroup::kArms: return "arms";
    case JointGroup::kSpine: return "spine";
    case JointGroup::kHead: return "head";
  }
  return "?";
}

std::vector<JointGroup> jointGroups(const motion::Skeleton& skeleton) {
  std::vector<JointGroup> groups(skeleton.jointCount(), JointGroup::kSpine);
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    const int named = groupByName(skeleton.names[j]);
    const int parent = skeleton.parents[j];
    groups[j] = named >= 0 ? static_cast<JointGroup>(named)
                           : (parent == motion::kNoParent ? JointGroup::kSpine : groups[parent]);
  }
  return groups;
}

Status BandGains::validate() const {
  if (bands.empty()) return Status::error("band gains: no bands");
  if (gains.size() != bands.size()) {
    return Status::error("band gains: " + std::to_string(gains.size()) + " gain rows for " +
                         std::to_string(bands.size()) + " bands");
  }
  for (size_t b = 0; b < bands.size(); ++b) {
    const Band& band = bands[b];
    const std::string label = "band '" + band.name + "'";
    if (band.name.empty()) return Status::error("band " + std::to_string(b) + " has no name");
    if (band.first < 1) return Status::error(label + ": first harmonic must be >= 1");
    if (band.last != 0 && band.last < band.first) return Status::error(label + ": last < first");
    if (band.last == 0 && b + 1 != bands.size()) {
      return Status::error(label + ": only the last band may be open-ended (last = 0)");
    }
    if (b > 0 && (bands[b - 1].last == 0 || band.first <= bands[b - 1].last)) {
      return Status::error(label + ": overlaps band '" + bands[b - 1].name + "'");
    }
    for (int g = 0; g < kJointGroupCount; ++g) {
      if (!std::isfinite(gains[b][g]) || gains[b][g] < 0.0) {
        return Status::error(label + ", " + jointGroupName(static_cast<JointGroup>(g)) +
                             ": gain must be a finite number >= 0");
      }
    }
  }
  return {};
}

double BandGains::gain(int n, JointGroup group) const {
  for (size_t b = 0; b < bands.size(); ++b) {
    if (n >= bands[b].first && (bands[b].last == 0 || n <= bands[b].last)) {
      return gains[b][static_cast<int>(group)];
    }
  }
  return 1.0;
}

Status BandGains::set(const std::string& band, const std::string& group, double value) {
  for (size_t b = 0; b < bands.size(); ++b) {
    if (bands[b].name != band) continue;
    bool matched = group.empty();
    for (int g = 0; g < kJointGroupCount; ++g) {
      if (group.empty() || group == jointGroupName(static_cast<JointGroup>(g))) {
        gains[b][g] = value;
        matched = true;
      }
    }
    if (!matched) {
      return Status::error("unknown joint group '" + group + "' (legs, arms, spine, head)");
    }
    return validate();
  }
  std::string names;
  for (const Band& known : bands) {
    if (!names.empty()) names += ", ";
    names += known.name;
  }
  return Status::error("unknown band '" + band + "' (" + names + ")");
}

TargetMotion applyBandGains(const TargetMotion& target, const motion::Skeleton& skeleton,
                            const BandGains& gains) {
  const std::vector<JointGroup> groups = jointGroups(skeleton);
  TargetMotion out = target;
  for (ChannelModel& channel : out.channels) {
    for (Harmonic& h : channel.terms) h.amplitude *= gains.gain(h.n, groups[channel.joint]);
  }
  return out;
}

}  // namespace sinew::spectral
