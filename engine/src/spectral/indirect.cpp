#include "sinew/spectral/indirect.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numeric>
#include <sstream>

namespace sinew::spectral {
namespace {

constexpr glm::dvec3 kUp(0.0, 1.0, 0.0);

// A chain end lies "on the ground" in the first frame when it is within this fraction of the
// figure's height of the lowest chain end: a standing dog's four paws, not a biped's hands.
constexpr double kGroundBand = 0.1;
// Chain ends closer than this fraction of the figure's height (along the bones) to the joint
// where they branch are one foot (toes of one paw), not two.
constexpr double kOneFootReach = 0.15;
// Below this horizontal speed of the centre of mass the clip runs in place, and the figure's
// facing replaces the travel direction, m/s.
constexpr double kInPlaceSpeed = 0.1;

// ---------------------------------------------------------------- names

// Lower-case words of a joint name: split at '_', '.', '-', ':', spaces, digits and camelCase
// boundaries, so "LeftUpLeg" -> left up leg, "CC_Base_L_Foot" -> cc base l foot, "LThumb" ->
// l thumb.
std::vector<std::string> words(const std::string& name) {
  std::vector<std::string> out;
  std::string word;
  const auto flush = [&] {
    if (!word.empty()) out.push_back(word);
    word.clear();
  };
  for (size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    if (!std::isalpha(c)) {
      flush();
      continue;
    }
    const bool upper = std::isupper(c) != 0;
    const bool prev_lower = i > 0 && std::islower(static_cast<unsigned char>(name[i - 1])) != 0;
    const bool prev_upper = i > 0 && std::isupper(static_cast<unsigned char>(name[i - 1])) != 0;
    const bool next_lower =
        i + 1 < name.size() && std::islower(static_cast<unsigned char>(name[i + 1])) != 0;
    if (upper && (prev_lower || (prev_upper && next_lower))) flush();
    word.push_back(static_cast<char>(std::tolower(c)));
  }
  flush();
  return out;
}

bool nameHas(const std::string& name, std::initializer_list<const char*> parts) {
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return std::any_of(parts.begin(), parts.end(),
                     [&](const char* part) { return lower.find(part) != std::string::npos; });
}

bool isFootName(const std::string& name) {
  return nameHas(name, {"foot", "ankle", "toe", "paw", "hoof"});
}
bool isHandName(const std::string& name) {
  return nameHas(name, {"hand", "wrist"});
}
bool isHeadName(const std::string& name) {
  return nameHas(name, {"head", "skull"});
}
bool isNeckName(const std::string& name) {
  return nameHas(name, {"neck"});
}
bool isTrunkName(const std::string& name) {
  return nameHas(name, {"spine", "chest", "torso", "waist", "abdomen", "belly", "pelvis", "hip",
                        "back", "rib", "breast", "clavicle", "collar", "shoulder"});
}

Side sideFromName(const std::string& name) {
  for (const std::string& word : words(name)) {
    if (word == "l" || word == "left") return Side::kLeft;
    if (word == "r" || word == "right") return Side::kRight;
  }
  return Side::kUnknown;
}

// ---------------------------------------------------------------- skeleton

bool isAncestor(const motion::Skeleton& skeleton, int ancestor, int joint) {
  for (int j = skeleton.parents[joint]; j != motion::kNoParent; j = skeleton.parents[j]) {
    if (j == ancestor) return true;
  }
  return false;
}

bool inSubtree(const motion::Skeleton& skeleton, int root, int joint) {
  return joint == root || isAncestor(skeleton, root, joint);
}

std::vector<int> childCounts(const motion::Skeleton& skeleton) {
  std::vector<int> counts(skeleton.jointCount(), 0);
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    if (skeleton.parents[j] != motion::kNoParent) ++counts[skeleton.parents[j]];
  }
  return counts;
}

int lowestCommonAncestor(const motion::Skeleton& skeleton, int a, int b) {
  for (int j = a; j != motion::kNoParent; j = skeleton.parents[j]) {
    if (inSubtree(skeleton, j, b)) return j;
  }
  return motion::kNoParent;
}

// Length along the bones from `ancestor` down to `joint`, metres.
double boneLength(const motion::Skeleton& skeleton, int ancestor, int joint) {
  double length = 0.0;
  for (int j = joint; j != ancestor && j != motion::kNoParent; j = skeleton.parents[j]) {
    length += glm::length(skeleton.offsets[j]);
  }
  return length;
}

// World positions of every joint and End Site, frame by frame.
struct Poses {
  int joints = 0;
  std::vector<glm::dvec3> joint;  // (frames x joints) metres
  std::vector<glm::dvec3> site;   // (frames x joints) End Site, or the joint when it has none

  const glm::dvec3& at(int frame, const FootPoint& p) const {
    const size_t n = static_cast<size_t>(frame) * joints + p.joint;
    return p.end_site ? site[n] : joint[n];
  }
};

Poses computePoses(const motion::Skeleton& skeleton, const motion::Clip& clip, int frames) {
  Poses poses;
  poses.joints = skeleton.jointCount();
  std::vector<glm::dmat4> world(poses.joints);
  for (int f = 0; f < frames; ++f) {
    motion::worldTransforms(skeleton, clip, f, world);
    for (int j = 0; j < poses.joints; ++j) {
      poses.joint.emplace_back(world[j][3]);
      poses.site.push_back(skeleton.end_sites[j]
                               ? glm::dvec3(world[j] * glm::dvec4(*skeleton.end_sites[j], 1.0))
                               : glm::dvec3(world[j][3]));
    }
  }
  return poses;
}

glm::dvec3 horizontal(const glm::dvec3& v) {
  return {v.x, 0.0, v.z};
}

// The figure's left for a travel direction (Y up): up x forward.
glm::dvec3 leftOf(const glm::dvec3& forward) {
  return glm::cross(kUp, forward);
}

// ---------------------------------------------------------------- feet

std::vector<FootPoint> footPoints(const motion::Skeleton& skeleton, int foot) {
  std::vector<FootPoint> points;
  for (int j = foot; j < skeleton.jointCount(); ++j) {
    if (!inSubtree(skeleton, foot, j)) continue;
    points.push_back({j, false});
    if (skeleton.end_sites[j]) points.push_back({j, true});
  }
  return points;
}

// Uppermost joints named like feet, one per chain, below the root.
std::vector<int> namedFeet(const motion::Skeleton& skeleton) {
  std::vector<int> feet;
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    if (skeleton.parents[j] == motion::kNoParent || !isFootName(skeleton.names[j])) continue;
    bool below_another = false;
    for (int a = skeleton.parents[j]; a != motion::kNoParent; a = skeleton.parents[a]) {
      below_another = below_another || isFootName(skeleton.names[a]);
    }
    if (!below_another) feet.push_back(j);
  }
  return feet;
}

// Chain ends on the ground in the first frame that no named foot covers, grouped into feet:
// the joint owning each such End Site (a leaf joint's parent), merged with neighbours that
// branch within a foot's reach.
std::vector<int> groundedFeet(const motion::Skeleton& skeleton, const Poses& first,
                              const std::vector<int>& named) {
  const int joints = skeleton.jointCount();
  const std::vector<int> counts = childCounts(skeleton);
  const int pelvis = motion::pelvisJoint(skeleton);
  if (counts[pelvis] < 2) return {};  // a single chain has no legs
  double low = 1e300;
  double high = -1e300;
  struct End {
    int owner;
    double height;
  };
  std::vector<End> ends;
  for (int j = 0; j < joints; ++j) {
    high = std::max({high, first.joint[j].y, first.site[j].y});
    const bool leaf = counts[j] == 0;
    if (!skeleton.end_sites[j] && !leaf) continue;
    const int owner = skeleton.end_sites[j] ? j : skeleton.parents[j];
    if (owner == motion::kNoParent || !isAncestor(skeleton, pelvis, owner)) continue;
    const double height = skeleton.end_sites[j] ? first.site[j].y : first.joint[j].y;
    low = std::min(low, height);
    ends.push_back({owner, height});
  }
  const double figure = high - low;
  std::vector<int> feet;
  for (const End& end : ends) {
    if (end.height - low > kGroundBand * figure) continue;
    if (std::any_of(named.begin(), named.end(),
                    [&](int foot) { return inSubtree(skeleton, foot, end.owner); })) {
      continue;
    }
    int foot = end.owner;
    for (int& other : feet) {
      const int common = lowestCommonAncestor(skeleton, foot, other);
      if (common == motion::kNoParent || common == pelvis || isAncestor(skeleton, common, pelvis)) {
        continue;
      }
      const double reach = kOneFootReach * figure;
      if (boneLength(skeleton, common, foot) < reach &&
          boneLength(skeleton, common, other) < reach) {
        other = common;
        foot = -1;
        break;
      }
    }
    if (foot >= 0) feet.push_back(foot);
  }
  std::sort(feet.begin(), feet.end());
  feet.erase(std::unique(feet.begin(), feet.end()), feet.end());
  return feet;
}

// The horizontal travel of the pelvis over the clip, or +Z when it stays in place.
glm::dvec3 clipForward(const motion::Skeleton& skeleton, const motion::Clip& clip) {
  const int pelvis = motion::pelvisJoint(skeleton);
  const glm::dvec3 travel =
      horizontal(motion::worldPositions(skeleton, clip, clip.frame_count - 1)[pelvis] -
                 motion::worldPositions(skeleton, clip, 0)[pelvis]);
  return glm::length(travel) > 0.1 ? glm::normalize(travel) : glm::dvec3(0.0, 0.0, 1.0);
}

}  // namespace

const char* sideName(Side side) {
  switch (side) {
    case Side::kLeft:
      return "left";
    case Side::kRight:
      return "right";
    case Side::kUnknown:
      break;
  }
  return "unknown";
}

const char* segmentName(Segment segment) {
  switch (segment) {
    case Segment::kNone:
      return "none";
    case Segment::kHead:
      return "head";
    case Segment::kTrunk:
      return "trunk";
    case Segment::kUpperArm:
      return "upper arm";
    case Segment::kForearm:
      return "forearm";
    case Segment::kHand:
      return "hand";
    case Segment::kThigh:
      return "thigh";
    case Segment::kShank:
      return "shank";
    case Segment::kFoot:
      return "foot";
    case Segment::kOther:
      return "other";
  }
  return "none";
}

Result<std::vector<Foot>> findFeet(const motion::Skeleton& skeleton, const motion::Clip& clip) {
  if (Status status = clip.validate(skeleton); !status.ok()) return status;
  const Poses first = computePoses(skeleton, clip, 1);
  const std::vector<int> named = namedFeet(skeleton);
  const std::vector<int> grounded = groundedFeet(skeleton, first, named);
  std::vector<Foot> feet;
  for (int joint : named) feet.push_back({joint, Side::kUnknown, true, -1, {}});
  for (int joint : grounded) feet.push_back({joint, Side::kUnknown, false, -1, {}});
  if (feet.empty()) {
    return Status::error(
        "no feet found: no joint is named foot, ankle, toe, paw or hoof, and no "
        "chain end below the pelvis is on the ground in the first frame");
  }
  std::sort(feet.begin(), feet.end(),
            [](const Foot& a, const Foot& b) { return a.joint < b.joint; });

  // Sides from the names of the foot and the joints above it, else from where it stands.
  const glm::dvec3 left = leftOf(clipForward(skeleton, clip));
  const glm::dvec3 pelvis = first.joint[motion::pelvisJoint(skeleton)];
  for (Foot& foot : feet) {
    foot.points = footPoints(skeleton, foot.joint);
    for (int j = foot.joint; j != motion::kNoParent && foot.side == Side::kUnknown;
         j = skeleton.parents[j]) {
      foot.side = sideFromName(skeleton.names[j]);
    }
    if (foot.side == Side::kUnknown) {
      const double across = glm::dot(first.joint[foot.joint] - pelvis, left);
      if (std::abs(across) > 0.01) foot.side = across > 0.0 ? Side::kLeft : Side::kRight;
    }
  }
  // Pairs: each left foot with the right foot nearest along the travel direction (front with
  // front, hind with hind).
  const glm::dvec3 forward = glm::cross(left, kUp);
  for (size_t a = 0; a < feet.size(); ++a) {
    if (feet[a].side != Side::kLeft) continue;
    int best = -1;
    double best_gap = 1e300;
    for (size_t b = 0; b < feet.size(); ++b) {
      if (feet[b].side != Side::kRight || feet[b].pair >= 0) continue;
      const double gap =
          std::abs(glm::dot(first.joint[feet[a].joint] - first.joint[feet[b].joint], forward));
      if (gap < best_gap) {
        best_gap = gap;
        best = static_cast<int>(b);
      }
    }
    if (best >= 0) {
      feet[a].pair = best;
      feet[best].pair = static_cast<int>(a);
    }
  }
  return feet;
}

Status ContactSettings::validate() const {
  if (!(height_tolerance_m > 0.0) || !std::isfinite(height_tolerance_m)) {
    return Status::error("contacts.height_tolerance_m must be > 0 metres");
  }
  if (!(speed_tolerance_m_s > 0.0) || !std::isfinite(speed_tolerance_m_s)) {
    return Status::error("contacts.speed_tolerance_m_s must be > 0 m/s");
  }
  if (!(ground_quantile >= 0.0 && ground_quantile <= 1.0)) {
    return Status::error("contacts.ground_quantile must be in [0, 1]");
  }
  if (!(max_gap_s >= 0.0) || !std::isfinite(max_gap_s)) {
    return Status::error("contacts.max_gap_s must be >= 0 seconds");
  }
  if (!(min_contact_s >= 0.0) || !std::isfinite(min_contact_s)) {
    return Status::error("contacts.min_contact_s must be >= 0 seconds");
  }
  return {};
}

Status SegmentMassTable::validate() const {
  const std::pair<const char*, double> fields[] = {
      {"head", head}, {"trunk", trunk}, {"upper_arm", upper_arm}, {"forearm", forearm},
      {"hand", hand}, {"thigh", thigh}, {"shank", shank},         {"foot", foot}};
  double sum = 0.0;
  for (const auto& [name, value] : fields) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      return Status::error(std::string("masses.") + name + " must be a finite fraction >= 0");
    }
    sum += value;
  }
  if (!(sum > 0.0)) return Status::error("masses: the segment fractions sum to 0");
  return {};
}

Status IndirectSettings::validate() const {
  if (Status status = contacts.validate(); !status.ok()) return status;
  return masses.validate();
}

// ---------------------------------------------------------------- masses

MassDistribution massDistribution(const motion::Skeleton& skeleton, const std::vector<Foot>& feet,
                                  const SegmentMassTable& table) {
  const int joints = skeleton.jointCount();
  const int pelvis = motion::pelvisJoint(skeleton);
  std::vector<Segment> segment(joints, Segment::kNone);
  std::vector<int> group(joints, -1);  // joints sharing one segment's mass
  std::vector<bool> massless(joints, false);
  for (int j = skeleton.parents[pelvis]; j != motion::kNoParent; j = skeleton.parents[j]) {
    massless[j] = true;
  }
  const auto unassigned = [&](int j) {
    return j != motion::kNoParent && j != pelvis && !massless[j] && segment[j] == Segment::kNone;
  };
  const auto assign = [&](int j, Segment s, int g) {
    if (unassigned(j)) {
      segment[j] = s;
      group[j] = g;
    }
  };
  const auto assignSubtree = [&](int root, Segment s) {
    for (int j = root; j < joints; ++j) {
      if (inSubtree(skeleton, root, j)) assign(j, s, root);
    }
  };
  // A limb: its end's subtree, the bone above it, the one above that.
  const auto assignLimb = [&](int end, Segment tip, Segment middle, Segment top) {
    assignSubtree(end, tip);
    const int p = skeleton.parents[end];
    if (p == motion::kNoParent) return;
    assign(p, middle, p);
    assign(skeleton.parents[p], top, skeleton.parents[p]);
  };
  for (const Foot& foot : feet)
    assignLimb(foot.joint, Segment::kFoot, Segment::kShank, Segment::kThigh);
  for (int j = 0; j < joints; ++j) {
    if (!unassigned(j) || !isHandName(skeleton.names[j])) continue;
    bool below_hand = false;
    for (int a = skeleton.parents[j]; a != motion::kNoParent; a = skeleton.parents[a]) {
      below_hand = below_hand || isHandName(skeleton.names[a]);
    }
    if (!below_hand) assignLimb(j, Segment::kHand, Segment::kForearm, Segment::kUpperArm);
  }
  constexpr int kHeadGroup = -2;
  constexpr int kTrunkGroup = -3;
  for (int j = 0; j < joints; ++j) {
    if (unassigned(j) && isHeadName(skeleton.names[j])) {
      for (int k = j; k < joints; ++k) {
        if (inSubtree(skeleton, j, k)) assign(k, Segment::kHead, kHeadGroup);
      }
      break;
    }
  }
  for (int j = 0; j < joints; ++j) {
    if (isNeckName(skeleton.names[j])) assign(j, Segment::kHead, kHeadGroup);
  }
  // Everything above a limb or the head is trunk (the pelvis included).
  for (int j = joints - 1; j >= 0; --j) {
    if (segment[j] == Segment::kNone || segment[j] == Segment::kOther) continue;
    for (int a = skeleton.parents[j]; a != motion::kNoParent && !massless[a];
         a = skeleton.parents[a]) {
      if (segment[a] == Segment::kNone) {
        segment[a] = Segment::kTrunk;
        group[a] = kTrunkGroup;
      }
    }
  }
  if (segment[pelvis] == Segment::kNone) {
    segment[pelvis] = Segment::kTrunk;
    group[pelvis] = kTrunkGroup;
  }
  // The rest: twist and helper joints share their limb segment; trunk-named joints are trunk;
  // anything else (a tail) is "other".
  for (int j = 0; j < joints; ++j) {
    if (!unassigned(j)) continue;
    const int p = skeleton.parents[j];
    const Segment parent = segment[p];
    if (parent == Segment::kThigh || parent == Segment::kShank || parent == Segment::kUpperArm ||
        parent == Segment::kForearm) {
      assign(j, parent, group[p]);
    } else if (isTrunkName(skeleton.names[j]) && parent == Segment::kTrunk) {
      assign(j, Segment::kTrunk, kTrunkGroup);
    } else {
      assign(j, Segment::kOther, j);
    }
  }

  // Body lengths: the bones to the children and End Site.
  std::vector<double> length(joints, 0.0);
  for (int j = 0; j < joints; ++j) {
    const int p = skeleton.parents[j];
    if (p != motion::kNoParent) length[p] += glm::length(skeleton.offsets[j]);
    if (skeleton.end_sites[j]) length[j] += glm::length(*skeleton.end_sites[j]);
  }
  const auto tableFraction = [&](Segment s) {
    switch (s) {
      case Segment::kHead:
        return table.head;
      case Segment::kTrunk:
        return table.trunk;
      case Segment::kUpperArm:
        return table.upper_arm;
      case Segment::kForearm:
        return table.forearm;
      case Segment::kHand:
        return table.hand;
      case Segment::kThigh:
        return table.thigh;
      case Segment::kShank:
        return table.shank;
      case Segment::kFoot:
        return table.foot;
      case Segment::kNone:
      case Segment::kOther:
        break;
    }
    return 0.0;
  };
  // Each group's fraction, split among its joints by body length (evenly when they have none).
  std::vector<double> fraction(joints, 0.0);
  double matched_mass = 0.0;
  double matched_length = 0.0;
  for (int j = 0; j < joints; ++j) {
    if (segment[j] == Segment::kNone || segment[j] == Segment::kOther) continue;
    double group_length = 0.0;
    int members = 0;
    bool first_member = true;
    for (int k = 0; k < joints; ++k) {
      if (group[k] != group[j] || segment[k] != segment[j]) continue;
      group_length += length[k];
      ++members;
      first_member = first_member && k >= j;
    }
    const double share = group_length > 0.0 ? length[j] / group_length : 1.0 / members;
    fraction[j] = tableFraction(segment[j]) * share;
    matched_mass += fraction[j];
    if (first_member) matched_length += group_length;
  }
  const double density = matched_length > 0.0 ? matched_mass / matched_length : 0.0;
  for (int j = 0; j < joints; ++j) {
    if (segment[j] == Segment::kOther) fraction[j] = density * length[j];
  }
  const double total = std::accumulate(fraction.begin(), fraction.end(), 0.0);
  if (total > 0.0) {
    for (double& f : fraction) f /= total;
  } else {
    fraction.assign(joints, 1.0 / joints);  // nothing matched and nothing has length
  }
  return {segment, fraction};
}

std::vector<glm::dvec3> centreOfMass(const motion::Skeleton& skeleton, const motion::Clip& clip,
                                     const MassDistribution& masses) {
  const int joints = skeleton.jointCount();
  std::vector<glm::dmat4> world(joints);
  std::vector<glm::dvec3> com(clip.frame_count, glm::dvec3(0.0));
  std::vector<glm::dvec3> weighted(joints);
  std::vector<double> weight(joints);
  for (int f = 0; f < clip.frame_count; ++f) {
    motion::worldTransforms(skeleton, clip, f, world);
    std::fill(weighted.begin(), weighted.end(), glm::dvec3(0.0));
    std::fill(weight.begin(), weight.end(), 0.0);
    // Each bone's midpoint, weighted by its rest length, into the body of the joint it hangs on.
    for (int j = 0; j < joints; ++j) {
      const glm::dvec3 here(world[j][3]);
      const int p = skeleton.parents[j];
      if (p != motion::kNoParent) {
        const double l = glm::length(skeleton.offsets[j]);
        weighted[p] += l * 0.5 * (glm::dvec3(world[p][3]) + here);
        weight[p] += l;
      }
      if (skeleton.end_sites[j]) {
        const double l = glm::length(*skeleton.end_sites[j]);
        weighted[j] +=
            l * 0.5 * (here + glm::dvec3(world[j] * glm::dvec4(*skeleton.end_sites[j], 1.0)));
        weight[j] += l;
      }
    }
    for (int j = 0; j < joints; ++j) {
      const glm::dvec3 body = weight[j] > 0.0 ? weighted[j] / weight[j] : glm::dvec3(world[j][3]);
      com[f] += masses.fractions[j] * body;
    }
  }
  return com;
}

// ---------------------------------------------------------------- contacts and spectra

namespace {

// The signal over the spectrum's window, resampled like the joint channels (minus its linear
// trend when `detrend`), and its harmonics.
IndirectSeries fitOverWindow(std::string name, std::string unit, const std::vector<double>& values,
                             const MotionSpectrum& spectrum, bool detrend) {
  const double dt = spectrum.signals.frame_time;
  const int samples = spectrum.window.strides * spectrum.samples_per_stride;
  const double length = spectrum.window.strides * spectrum.period_s;
  const double start = spectrum.window.start_s / dt;
  const double slope =
      detrend ? (catmullRomAt(values, start + length / dt) - catmullRomAt(values, start)) / length : 0.0;
  std::vector<double> sampled(samples);
  for (int i = 0; i < samples; ++i) {
    const double t = i * length / samples;
    sampled[i] = catmullRomAt(values, start + t / dt) - slope * t;
  }
  IndirectSeries out{std::move(name), std::move(unit), {}, 0.0};
  out.series = fitHarmonics(sampled, spectrum.window.strides, &out.aperiodic_energy);
  return out;
}

// Fills breaks up to `max_gap` frames inside contacts, then drops contacts shorter than
// `min_length` frames.
void cleanContacts(std::vector<std::uint8_t>& down, int max_gap, int min_length) {
  const int n = static_cast<int>(down.size());
  const auto runs = [&](std::uint8_t value, auto&& visit) {
    for (int i = 0; i < n;) {
      int end = i;
      while (end < n && down[end] == down[i]) ++end;
      if (down[i] == value) visit(i, end);
      i = end;
    }
  };
  runs(0, [&](int begin, int end) {
    if (begin > 0 && end < n && end - begin <= max_gap) {
      std::fill(down.begin() + begin, down.begin() + end, std::uint8_t{1});
    }
  });
  runs(1, [&](int begin, int end) {
    if (end - begin < min_length)
      std::fill(down.begin() + begin, down.begin() + end, std::uint8_t{0});
  });
}

}  // namespace

Result<IndirectSignals> analyzeIndirect(const motion::Skeleton& skeleton, const motion::Clip& clip,
                                        const MotionSpectrum& spectrum,
                                        const IndirectSettings& settings) {
  if (Status status = settings.validate(); !status.ok()) return status;
  if (Status status = clip.validate(skeleton); !status.ok()) return status;
  if (clip.frame_count < 2)
    return Status::error("clip '" + clip.name + "' has one frame: no contacts");
  if (spectrum.signals.frame_count != clip.frame_count || spectrum.samples_per_stride < 4) {
    return Status::error("the spectrum is not this clip's analysis (" +
                         std::to_string(spectrum.signals.frame_count) + " frames against " +
                         std::to_string(clip.frame_count) + ")");
  }
  Result<std::vector<Foot>> feet = findFeet(skeleton, clip);
  if (!feet.ok()) return feet.status();
  IndirectSignals out;
  out.frame_time = clip.frame_time;
  out.feet = std::move(feet).value();
  const int frames = clip.frame_count;
  const double dt = clip.frame_time;
  const Poses poses = computePoses(skeleton, clip, frames);
  const ContactSettings& cs = settings.contacts;

  // Each foot's contact point (its lowest point) per frame, its height above the foot's own
  // ground level, and its horizontal speed. The speed follows the same point across the
  // neighbouring frames, so a change of lowest point (heel to toe) is not a jump.
  const auto footCount = out.feet.size();
  out.ground_levels_m.resize(footCount);
  out.foot_heights_m.assign(footCount, std::vector<double>(frames));
  out.foot_speeds_m_s.assign(footCount, std::vector<double>(frames));
  out.contacts.assign(footCount, std::vector<std::uint8_t>(frames, 0));
  std::vector<std::vector<FootPoint>> lowest(footCount, std::vector<FootPoint>(frames));
  for (size_t i = 0; i < footCount; ++i) {
    const Foot& foot = out.feet[i];
    std::vector<double>& height = out.foot_heights_m[i];
    for (int f = 0; f < frames; ++f) {
      FootPoint best = foot.points.front();
      for (const FootPoint& p : foot.points) {
        if (poses.at(f, p).y < poses.at(f, best).y) best = p;
      }
      lowest[i][f] = best;
      height[f] = poses.at(f, best).y;
      const int a = std::max(f - 1, 0);
      const int b = std::min(f + 1, frames - 1);
      out.foot_speeds_m_s[i][f] =
          b > a ? glm::length(horizontal(poses.at(b, best) - poses.at(a, best))) / ((b - a) * dt)
                : 0.0;
    }
    // The ground level is where the foot rests, not the lowest it ever goes: retargeted rigs
    // (the iClone run) dip a toe tip below the stance level at toe-off, at speed.
    std::vector<double> resting;
    for (int f = 0; f < frames; ++f) {
      if (out.foot_speeds_m_s[i][f] <= cs.speed_tolerance_m_s) resting.push_back(height[f]);
    }
    if (resting.empty()) resting = height;
    const auto q = static_cast<long>(cs.ground_quantile * static_cast<double>(resting.size() - 1));
    std::nth_element(resting.begin(), resting.begin() + q, resting.end());
    out.ground_levels_m[i] = resting[static_cast<size_t>(q)];
    for (int f = 0; f < frames; ++f) {
      height[f] -= out.ground_levels_m[i];
      out.contacts[i][f] =
          height[f] <= cs.height_tolerance_m && out.foot_speeds_m_s[i][f] <= cs.speed_tolerance_m_s;
    }
    cleanContacts(out.contacts[i], static_cast<int>(std::floor(cs.max_gap_s / dt + 1e-9)),
                  static_cast<int>(std::ceil(cs.min_contact_s / dt - 1e-9)));
  }

  // Footfalls: contact starts after the first frame.
  for (size_t i = 0; i < footCount; ++i) {
    const std::vector<std::uint8_t>& down = out.contacts[i];
    for (int f = 1; f < frames; ++f) {
      if (!down[f] || down[f - 1]) continue;
      int end = f;
      while (end < frames && down[end]) ++end;
      out.footfalls.push_back(
          {static_cast<int>(i), f, f * dt, (end - f) * dt, poses.at(f, lowest[i][f])});
    }
  }
  std::sort(out.footfalls.begin(), out.footfalls.end(), [](const Footfall& a, const Footfall& b) {
    return a.frame != b.frame ? a.frame < b.frame : a.foot < b.foot;
  });

  // The centre of mass, and the travel direction over the analysed window.
  out.masses = massDistribution(skeleton, out.feet, settings.masses);
  out.com = centreOfMass(skeleton, clip, out.masses);
  const double window_s = spectrum.window.strides * spectrum.period_s;
  const double first = spectrum.window.start_s / dt;
  const double last = std::min(first + window_s / dt, frames - 1.0);
  const auto comAt = [&](double frame) {
    const int i = std::min(static_cast<int>(frame), frames - 2);
    const double u = frame - i;
    return (1.0 - u) * out.com[i] + u * out.com[i + 1];
  };
  const glm::dvec3 travel = horizontal(comAt(last) - comAt(first));
  const double travel_s = (last - first) * dt;
  out.gait.speed_m_s = travel_s > 0.0 ? glm::length(travel) / travel_s : 0.0;
  if (out.gait.speed_m_s > kInPlaceSpeed) {
    out.forward = glm::normalize(travel);
  } else {
    // In place: the figure faces across the line from its right feet to its left feet.
    glm::dvec3 across(0.0);
    for (const Foot& foot : out.feet) {
      const double sign = foot.side == Side::kLeft ? 1.0 : foot.side == Side::kRight ? -1.0 : 0.0;
      for (int f = 0; f < frames; ++f) {
        across +=
            sign * horizontal(poses.joint[static_cast<size_t>(f) * poses.joints + foot.joint]);
      }
    }
    if (glm::length(across) > 1e-9) out.forward = glm::normalize(glm::cross(across, kUp));
    out.notes.push_back("the clip runs in place: forward is the figure's facing");
  }
  out.left = leftOf(out.forward);

  // Strides (same foot) and steps (to the pair's other foot).
  GaitFigures& gait = out.gait;
  double interval_sum = 0.0;
  double stride_length_sum = 0.0;
  for (size_t a = 0; a < out.footfalls.size(); ++a) {
    const Footfall& from = out.footfalls[a];
    const int pair = out.feet[from.foot].pair;
    bool found_pair = pair < 0;
    for (size_t b = a + 1; b < out.footfalls.size(); ++b) {
      const Footfall& to = out.footfalls[b];
      if (to.foot == from.foot) {
        interval_sum += to.time_s - from.time_s;
        stride_length_sum += glm::length(horizontal(to.position - from.position));
        ++gait.stride_intervals;
        break;
      }
      if (to.foot == pair && !found_pair) {
        const glm::dvec3 d = to.position - from.position;
        out.steps.push_back({static_cast<int>(a), static_cast<int>(b), glm::dot(d, out.forward),
                             std::abs(glm::dot(d, out.left)), to.time_s - from.time_s});
        found_pair = true;
      }
    }
  }
  if (gait.stride_intervals > 0) {
    gait.stride_period_s = interval_sum / gait.stride_intervals;
    gait.stride_length_m = stride_length_sum / gait.stride_intervals;
    gait.contact_speed_m_s = gait.stride_length_m / gait.stride_period_s;
  }
  for (const Step& step : out.steps) {
    gait.step_length_m += step.length_m / static_cast<double>(out.steps.size());
    gait.step_width_m += step.width_m / static_cast<double>(out.steps.size());
    gait.step_duration_s += step.duration_s / static_cast<double>(out.steps.size());
  }
  gait.analysis_period_s = spectrum.stride.found ? spectrum.stride.period_s : 0.0;
  if (gait.stride_period_s > 0.0 && gait.analysis_period_s > 0.0) {
    gait.period_difference = gait.stride_period_s / gait.analysis_period_s - 1.0;
  }
  // Duty factor over the analysed window's frames.
  const int f0 = static_cast<int>(std::ceil(first - 1e-9));
  const int f1 = static_cast<int>(std::floor(last + 1e-9));
  for (size_t i = 0; i < footCount && f1 > f0; ++i) {
    const long down = std::count(out.contacts[i].begin() + f0, out.contacts[i].begin() + f1, 1);
    gait.duty_factor += static_cast<double>(down) / (f1 - f0) / static_cast<double>(footCount);
  }
  if (gait.stride_intervals == 0)
    out.notes.push_back("no foot lands twice: no stride from contacts");
  if (gait.stride_period_s > 0.0 && gait.analysis_period_s > 0.0 &&
      std::abs(gait.period_difference) > 0.05) {
    std::ostringstream note;
    note << "the stride from foot contacts (" << gait.stride_period_s
         << " s) differs from the analysed stride (" << gait.analysis_period_s << " s) by "
         << 100.0 * gait.period_difference << "%";
    out.notes.push_back(note.str());
  }

  // Spectra over the analysed window: the centre of mass's bob, sway and surge (the latter two
  // without the travel), each foot's contact indicator and height.
  std::vector<double> height(frames), lateral(frames), surge(frames);
  for (int f = 0; f < frames; ++f) {
    height[f] = out.com[f].y;
    lateral[f] = glm::dot(out.com[f], out.left);
    surge[f] = glm::dot(out.com[f], out.forward);
  }
  out.spectra.push_back(fitOverWindow("com height", "m", height, spectrum, false));
  out.spectra.push_back(fitOverWindow("com lateral", "m", lateral, spectrum, true));
  out.spectra.push_back(fitOverWindow("com forward", "m", surge, spectrum, true));
  for (size_t i = 0; i < footCount; ++i) {
    const std::string& name = skeleton.names[out.feet[i].joint];
    const std::vector<double> indicator(out.contacts[i].begin(), out.contacts[i].end());
    out.spectra.push_back(fitOverWindow(name + " contact", "", indicator, spectrum, false));
    out.spectra.push_back(
        fitOverWindow(name + " height", "m", out.foot_heights_m[i], spectrum, false));
  }
  return out;
}

}  // namespace sinew::spectral
