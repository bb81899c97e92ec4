#include "sinew/motion/anatomy.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numeric>
#include <sstream>
#include <string>

namespace sinew::motion {
namespace {

// A point of the pelvis's subtree: a joint, or a joint's End Site.
struct FigurePoint {
  int joint = 0;
  bool end_site = false;
  bool chain_end = false;  // an End Site, or a joint without children or End Site
};

std::vector<FigurePoint> figurePoints(const Skeleton& skeleton, int pelvis) {
  const int joints = skeleton.jointCount();
  std::vector<int> children(joints, 0);
  for (int j = 0; j < joints; ++j)
    if (skeleton.parents[j] != kNoParent) ++children[skeleton.parents[j]];
  std::vector<char> below(joints, 0);
  std::vector<FigurePoint> points;
  for (int j = pelvis; j < joints; ++j) {
    const int parent = skeleton.parents[j];
    below[j] = j == pelvis || (parent != kNoParent && below[parent]);
    if (!below[j]) continue;
    points.push_back({j, false, children[j] == 0 && !skeleton.end_sites[j]});
    if (skeleton.end_sites[j]) points.push_back({j, true, true});
  }
  return points;
}

void posePoints(const Skeleton& skeleton, const Clip& clip, int frame,
                const std::vector<FigurePoint>& points, std::vector<glm::dmat4>& world,
                std::vector<glm::dvec3>& out) {
  worldTransforms(skeleton, clip, frame, world);
  out.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::dmat4& m = world[static_cast<size_t>(points[i].joint)];
    out[i] = points[i].end_site
                 ? glm::dvec3(m * glm::dvec4(*skeleton.end_sites[points[i].joint], 1.0))
                 : glm::dvec3(m[3]);
  }
}

// The up axis (1 Y, 2 Z) along which most chain ends share the lowest level, the pelvis (point 0)
// clearly above them.
int upAxisOf(const std::vector<FigurePoint>& points, const std::vector<glm::dvec3>& at) {
  glm::dvec3 lo = at[0], hi = at[0];
  for (const glm::dvec3& p : at) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const double size = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  int best_axis = 1;
  int best_score = -1;
  for (int axis : {1, 2}) {
    double low = hi[axis];
    for (size_t i = 0; i < points.size(); ++i)
      if (points[i].chain_end) low = std::min(low, at[i][axis]);
    int on_ground = 0;
    for (size_t i = 0; i < points.size(); ++i)
      if (points[i].chain_end && at[i][axis] - low < 0.1 * size) ++on_ground;
    const bool upright = size > 0.0 && at[0][axis] - low > 0.2 * size;
    const int score = upright ? on_ground : 0;
    if (score > best_score) {
      best_score = score;
      best_axis = axis;
    }
  }
  return best_axis;
}

// The deepest joint whose subtree holds both a and b (a itself when b is below it), or kNoParent
// when they are in different trees.
int lowestCommonAncestor(const Skeleton& skeleton, int a, int b) {
  while (a != b) {
    if (a > b)
      a = skeleton.parents[a];  // parents come first: step the deeper index up
    else
      b = skeleton.parents[b];
    if (a == kNoParent || b == kNoParent) return kNoParent;
  }
  return a;
}

int findRoot(std::vector<int>& group, int i) {
  while (group[i] != i) i = group[i] = group[group[i]];
  return i;
}

}  // namespace

const char* familyName(BodyFamily family) {
  switch (family) {
    case BodyFamily::kBiped:
      return "biped";
    case BodyFamily::kQuadruped:
      return "quadruped";
    case BodyFamily::kOther:
      return "other";
  }
  return "other";
}

FigureMeasure measureFigure(const Skeleton& skeleton, const Clip& clip, int up_axis) {
  FigureMeasure measure;
  if (skeleton.jointCount() == 0 || clip.frame_count < 1) return measure;
  const int pelvis = pelvisJoint(skeleton);
  const std::vector<FigurePoint> points = figurePoints(skeleton, pelvis);
  std::vector<glm::dmat4> world(static_cast<size_t>(skeleton.jointCount()));
  std::vector<glm::dvec3> first, at;
  posePoints(skeleton, clip, 0, points, world, first);
  const int axis = up_axis == 1 || up_axis == 2 ? up_axis : upAxisOf(points, first);
  measure.up_axis = axis;
  double low = first[0][axis], high = first[0][axis];
  for (const glm::dvec3& p : first) {
    low = std::min(low, p[axis]);
    high = std::max(high, p[axis]);
  }
  measure.height = high - low;
  measure.hip_height = first[0][axis] - low;
  if (!(measure.hip_height > 0.0)) return measure;
  std::vector<double> joint_height(world.size());  // first frame, above the lowest point
  for (size_t j = 0; j < world.size(); ++j) joint_height[j] = world[j][3][axis] - low;

  // Each chain end's lowest height above the figure's lowest point over the sampled frames.
  std::vector<double> reach(points.size(), 1e300);
  const int samples = std::min(clip.frame_count, 64);
  for (int s = 0; s < samples; ++s) {
    const int frame =
        samples > 1
            ? static_cast<int>(static_cast<long long>(s) * (clip.frame_count - 1) / (samples - 1))
            : 0;
    posePoints(skeleton, clip, frame, points, world, at);
    double frame_low = at[0][axis];
    for (const glm::dvec3& p : at) frame_low = std::min(frame_low, p[axis]);
    for (size_t i = 0; i < points.size(); ++i)
      reach[i] = std::min(reach[i], at[i][axis] - frame_low);
  }
  // Grounded chain ends, grouped while they meet low (one foot's toes) but not at the pelvis.
  std::vector<int> grounded;
  for (size_t i = 0; i < points.size(); ++i)
    if (points[i].chain_end && reach[i] < 0.25 * measure.hip_height)
      grounded.push_back(static_cast<int>(i));
  std::vector<int> group(grounded.size());
  std::iota(group.begin(), group.end(), 0);
  for (size_t a = 0; a < grounded.size(); ++a)
    for (size_t b = a + 1; b < grounded.size(); ++b) {
      const int meet =
          lowestCommonAncestor(skeleton, points[grounded[a]].joint, points[grounded[b]].joint);
      if (meet != kNoParent && joint_height[static_cast<size_t>(meet)] < 0.5 * measure.hip_height)
        group[findRoot(group, static_cast<int>(a))] = findRoot(group, static_cast<int>(b));
    }
  for (size_t a = 0; a < grounded.size(); ++a)
    if (findRoot(group, static_cast<int>(a)) == static_cast<int>(a)) ++measure.legs;
  measure.family = measure.legs == 2   ? BodyFamily::kBiped
                   : measure.legs == 4 ? BodyFamily::kQuadruped
                                       : BodyFamily::kOther;
  // A human: a biped whose trunk stands on its legs and carries arms and a head (three chain
  // ends or more that never reach the ground), not a bird or a stepping machine.
  int upper_ends = 0;
  for (size_t i = 0; i < points.size(); ++i)
    if (points[i].chain_end && reach[i] >= 0.25 * measure.hip_height) ++upper_ends;
  measure.human = measure.family == BodyFamily::kBiped && upper_ends >= 3 &&
                  measure.height >= 1.3 * measure.hip_height;
  return measure;
}

namespace {

// What a family's plausible size is measured on, and its range in metres (lo = hi = 0: none).
struct SizeRange {
  double size = 0.0;  // file units
  double lo = 0.0, hi = 0.0;
  const char* what = "tall";
};

SizeRange sizeRange(const FigureMeasure& figure, const FigureSizeRanges& ranges) {
  if (figure.human) return {figure.height, ranges.human_height_min_m, ranges.human_height_max_m};
  if (figure.family == BodyFamily::kQuadruped)
    return {figure.hip_height, ranges.quadruped_hip_min_m, ranges.quadruped_hip_max_m,
            "at the hips"};
  return {figure.height};
}

const char* familyLabel(const FigureMeasure& figure) {
  return figure.human ? "human" : familyName(figure.family);
}

// The flags that override a detection, for its reason: a format that states its up axis (glTF)
// takes only --units.
const char* overrideNote(bool up_stated) {
  return up_stated ? " (override with --units)" : " (override with --units and --up)";
}

// The unit by the size alone, for figures without a family's range: >= 1000 units as mm, >= 10
// as cm, else metres.
FrameDetection unitBySize(const FigureMeasure& figure, UpAxis up, bool up_stated) {
  FrameDetection result;
  result.frame.up = up;
  result.height_in_file_units = figure.height;
  result.frame.unit = figure.height >= 1000.0 ? LengthUnit::kMillimetres
                      : figure.height >= 10.0 ? LengthUnit::kCentimetres
                                              : LengthUnit::kMetres;
  result.height_m = figure.height * metresPerUnit(result.frame.unit);
  std::ostringstream reason;
  reason.precision(3);
  reason << familyLabel(figure) << " (" << figure.legs << " legs reach the ground), "
         << figure.height << " file units tall along " << upAxisName(up) << " reads as "
         << unitName(result.frame.unit) << overrideNote(up_stated);
  result.reason = reason.str();
  return result;
}

// The unit that puts the family's size inside its range, else the nearest on a log scale; the
// commonest first, so a tie (both inside the range) goes to the earlier.
FrameDetection unitByFamily(const FigureMeasure& figure, UpAxis up, const SizeRange& range,
                            bool up_stated) {
  const LengthUnit order[] = {LengthUnit::kCentimetres, LengthUnit::kMetres,
                              LengthUnit::kMillimetres, LengthUnit::kInches,
                              LengthUnit::kCmu,         LengthUnit::kFeet};
  LengthUnit best = order[0];
  double best_distance = 1e300;
  for (LengthUnit unit : order) {
    const double metres = range.size * metresPerUnit(unit);
    const double distance = metres < range.lo   ? std::log(range.lo / metres)
                            : metres > range.hi ? std::log(metres / range.hi)
                                                : 0.0;
    if (distance < best_distance - 1e-12) {
      best_distance = distance;
      best = unit;
    }
  }
  FrameDetection result;
  result.frame = {best, up};
  result.height_in_file_units = figure.height;
  result.height_m = figure.height * metresPerUnit(best);
  std::ostringstream reason;
  reason.precision(3);
  reason << familyLabel(figure) << " (" << figure.legs << " legs reach the ground), " << range.size
         << " file units " << range.what << " along " << upAxisName(up) << ": "
         << range.size * metresPerUnit(best) << " m in " << unitName(best)
         << (best_distance == 0.0 ? ", inside " : ", the nearest to ") << range.lo << "-"
         << range.hi << " m" << overrideNote(up_stated);
  result.reason = reason.str();
  return result;
}

// `up_stated`: the figure was measured along the format's stated up axis, which no flag changes.
FrameDetection chooseUnit(const FigureMeasure& figure, const FigureSizeRanges& ranges,
                          bool up_stated) {
  const UpAxis up = figure.up_axis == 2 ? UpAxis::kZ : UpAxis::kY;
  if (!(figure.height > 0.0)) {
    FrameDetection result;
    result.frame.up = up;
    result.reason = "the figure has no height; assuming metres, Y-up";
    return result;
  }
  const SizeRange range = sizeRange(figure, ranges);
  return range.hi > 0.0 ? unitByFamily(figure, up, range, up_stated)
                        : unitBySize(figure, up, up_stated);
}

}  // namespace

FrameDetection detectFrame(const Skeleton& skeleton, const Clip& clip,
                           const FigureSizeRanges& ranges) {
  return chooseUnit(measureFigure(skeleton, clip), ranges, false);
}

FrameDetection detectStatedFrame(const Skeleton& skeleton, const Clip& clip,
                                 const SourceFrame& stated, const FigureSizeRanges& ranges) {
  const FigureMeasure figure = measureFigure(skeleton, clip, stated.up == UpAxis::kZ ? 2 : 1);
  const SizeRange range = sizeRange(figure, ranges);
  const double per_unit = metresPerUnit(stated.unit);
  const double metres = range.size * per_unit;
  const bool plausible = range.hi > 0.0 ? metres >= range.lo && metres <= range.hi
                                        : metres < ranges.other_height_max_m;
  if (!(figure.height > 0.0) || !plausible) {
    FrameDetection chosen = chooseUnit(figure, ranges, true);
    chosen.reason = std::string("implausible in the file's ") + std::string(unitName(stated.unit)) +
                    "; " + chosen.reason;
    return chosen;
  }
  FrameDetection result;
  result.frame = stated;
  result.height_in_file_units = figure.height;
  result.height_m = figure.height * per_unit;
  std::ostringstream reason;
  reason.precision(3);
  reason << familyLabel(figure) << " (" << figure.legs << " legs reach the ground), " << metres
         << " m " << range.what << " along " << upAxisName(stated.up) << " in the file's "
         << unitName(stated.unit);
  if (range.hi > 0.0)
    reason << ", inside " << range.lo << "-" << range.hi << " m";
  else
    reason << ", under " << ranges.other_height_max_m << " m";
  reason << overrideNote(true);
  result.reason = reason.str();
  return result;
}

}  // namespace sinew::motion

// ---------------------------------------------------------------- feet and segments, by names
// and by geometry (moved here from spectral/indirect.cpp: anatomy has one owner)

namespace sinew::motion {
namespace {

constexpr glm::dvec3 kUp(0.0, 1.0, 0.0);

// A chain end lies "on the ground" in the first frame when it is within this fraction of the
// figure's height of the lowest chain end: a standing dog's four paws, not a biped's hands.
constexpr double kGroundBand = 0.1;
// Chain ends closer than this fraction of the figure's height (along the bones) to the joint
// where they branch are one foot (toes of one paw), not two.
constexpr double kOneFootReach = 0.15;

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

bool isAncestor(const Skeleton& skeleton, int ancestor, int joint) {
  for (int j = skeleton.parents[joint]; j != kNoParent; j = skeleton.parents[j]) {
    if (j == ancestor) return true;
  }
  return false;
}

bool inSubtree(const Skeleton& skeleton, int root, int joint) {
  return joint == root || isAncestor(skeleton, root, joint);
}

std::vector<int> childCounts(const Skeleton& skeleton) {
  std::vector<int> counts(skeleton.jointCount(), 0);
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    if (skeleton.parents[j] != kNoParent) ++counts[skeleton.parents[j]];
  }
  return counts;
}

// Length along the bones from `ancestor` down to `joint`, metres.
double boneLength(const Skeleton& skeleton, int ancestor, int joint) {
  double length = 0.0;
  for (int j = joint; j != ancestor && j != kNoParent; j = skeleton.parents[j]) {
    length += glm::length(skeleton.offsets[j]);
  }
  return length;
}

}  // namespace

Poses computePoses(const Skeleton& skeleton, const Clip& clip, int frames) {
  Poses poses;
  poses.joints = skeleton.jointCount();
  std::vector<glm::dmat4> world(poses.joints);
  for (int f = 0; f < frames; ++f) {
    worldTransforms(skeleton, clip, f, world);
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

glm::dvec3 leftOf(const glm::dvec3& forward) {
  return glm::cross(kUp, forward);
}

namespace {

// ---------------------------------------------------------------- feet

std::vector<FootPoint> footPoints(const Skeleton& skeleton, int foot) {
  std::vector<FootPoint> points;
  for (int j = foot; j < skeleton.jointCount(); ++j) {
    if (!inSubtree(skeleton, foot, j)) continue;
    points.push_back({j, false});
    if (skeleton.end_sites[j]) points.push_back({j, true});
  }
  return points;
}

// Uppermost joints named like feet, one per chain, below the root.
std::vector<int> namedFeet(const Skeleton& skeleton) {
  std::vector<int> feet;
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    if (skeleton.parents[j] == kNoParent || !isFootName(skeleton.names[j])) continue;
    bool below_another = false;
    for (int a = skeleton.parents[j]; a != kNoParent; a = skeleton.parents[a]) {
      below_another = below_another || isFootName(skeleton.names[a]);
    }
    if (!below_another) feet.push_back(j);
  }
  return feet;
}

// Chain ends on the ground in the first frame that no named foot covers, grouped into feet:
// the joint owning each such End Site (a leaf joint's parent), merged with neighbours that
// branch within a foot's reach.
std::vector<int> groundedFeet(const Skeleton& skeleton, const Poses& first,
                              const std::vector<int>& named) {
  const int joints = skeleton.jointCount();
  const std::vector<int> counts = childCounts(skeleton);
  const int pelvis = pelvisJoint(skeleton);
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
    if (owner == kNoParent || !isAncestor(skeleton, pelvis, owner)) continue;
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
      if (common == kNoParent || common == pelvis || isAncestor(skeleton, common, pelvis)) {
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
glm::dvec3 clipForward(const Skeleton& skeleton, const Clip& clip) {
  const int pelvis = pelvisJoint(skeleton);
  const glm::dvec3 travel =
      horizontal(worldPositions(skeleton, clip, clip.frame_count - 1)[pelvis] -
                 worldPositions(skeleton, clip, 0)[pelvis]);
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

Result<std::vector<Foot>> findFeet(const Skeleton& skeleton, const Clip& clip) {
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
  const glm::dvec3 pelvis = first.joint[pelvisJoint(skeleton)];
  for (Foot& foot : feet) {
    foot.points = footPoints(skeleton, foot.joint);
    for (int j = foot.joint; j != kNoParent && foot.side == Side::kUnknown;
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

// ---------------------------------------------------------------- masses

namespace {

constexpr int kHeadGroup = -2;   // the group of every head and neck joint
constexpr int kTrunkGroup = -3;  // the group of every trunk joint

// Each joint's segment and the group that shares one segment's mass, as massDistribution
// assigns them: a joint keeps the first segment it is given. The joints above the pelvis (a
// root that carries the travel) are massless and never assigned.
struct SegmentAssignment {
  const Skeleton& skeleton;
  int joints = 0;
  int pelvis = 0;
  std::vector<Segment> segment;  // (joints)
  std::vector<int> group;        // (joints) joints sharing one segment's mass, -1 none
  std::vector<bool> massless;    // (joints)

  explicit SegmentAssignment(const Skeleton& s)
      : skeleton(s),
        joints(s.jointCount()),
        pelvis(pelvisJoint(s)),
        segment(joints, Segment::kNone),
        group(joints, -1),
        massless(joints, false) {
    for (int j = s.parents[pelvis]; j != kNoParent; j = s.parents[j]) massless[j] = true;
  }

  bool unassigned(int j) const {
    return j != kNoParent && j != pelvis && !massless[j] && segment[j] == Segment::kNone;
  }
  void assign(int j, Segment s, int g) {
    if (unassigned(j)) {
      segment[j] = s;
      group[j] = g;
    }
  }
  void assignSubtree(int root, Segment s, int g) {
    for (int j = root; j < joints; ++j) {
      if (inSubtree(skeleton, root, j)) assign(j, s, g);
    }
  }
  // A limb: its end's subtree, the bone above it, the one above that.
  void assignLimb(int end, Segment tip, Segment middle, Segment top) {
    assignSubtree(end, tip, end);
    const int p = skeleton.parents[end];
    if (p == kNoParent) return;
    assign(p, middle, p);
    assign(skeleton.parents[p], top, skeleton.parents[p]);
  }
};

// Legs from each foot up; arms from each uppermost hand (or wrist) up; the uppermost head's
// subtree and the neck joints, head.
void assignLimbsAndHead(SegmentAssignment& a, const std::vector<Foot>& feet) {
  const Skeleton& skeleton = a.skeleton;
  for (const Foot& foot : feet)
    a.assignLimb(foot.joint, Segment::kFoot, Segment::kShank, Segment::kThigh);
  for (int j = 0; j < a.joints; ++j) {
    if (!a.unassigned(j) || !isHandName(skeleton.names[j])) continue;
    bool below_hand = false;
    for (int p = skeleton.parents[j]; p != kNoParent; p = skeleton.parents[p]) {
      below_hand = below_hand || isHandName(skeleton.names[p]);
    }
    if (!below_hand) a.assignLimb(j, Segment::kHand, Segment::kForearm, Segment::kUpperArm);
  }
  for (int j = 0; j < a.joints; ++j) {
    if (a.unassigned(j) && isHeadName(skeleton.names[j])) {
      a.assignSubtree(j, Segment::kHead, kHeadGroup);
      break;
    }
  }
  for (int j = 0; j < a.joints; ++j) {
    if (isNeckName(skeleton.names[j])) a.assign(j, Segment::kHead, kHeadGroup);
  }
}

// Everything above a limb or the head is trunk (the pelvis included). The rest: twist and
// helper joints share their limb segment; trunk-named joints are trunk; anything else (a tail)
// is "other".
void assignTrunkAndRest(SegmentAssignment& a) {
  const Skeleton& skeleton = a.skeleton;
  for (int j = a.joints - 1; j >= 0; --j) {
    if (a.segment[j] == Segment::kNone || a.segment[j] == Segment::kOther) continue;
    for (int p = skeleton.parents[j]; p != kNoParent && !a.massless[p]; p = skeleton.parents[p]) {
      if (a.segment[p] == Segment::kNone) {
        a.segment[p] = Segment::kTrunk;
        a.group[p] = kTrunkGroup;
      }
    }
  }
  if (a.segment[a.pelvis] == Segment::kNone) {
    a.segment[a.pelvis] = Segment::kTrunk;
    a.group[a.pelvis] = kTrunkGroup;
  }
  for (int j = 0; j < a.joints; ++j) {
    if (!a.unassigned(j)) continue;
    const int p = skeleton.parents[j];
    const Segment parent = a.segment[p];
    if (parent == Segment::kThigh || parent == Segment::kShank || parent == Segment::kUpperArm ||
        parent == Segment::kForearm) {
      a.assign(j, parent, a.group[p]);
    } else if (isTrunkName(skeleton.names[j]) && parent == Segment::kTrunk) {
      a.assign(j, Segment::kTrunk, kTrunkGroup);
    } else {
      a.assign(j, Segment::kOther, j);
    }
  }
}

// Body lengths: each joint's bones to its children and End Site, metres.
std::vector<double> bodyLengths(const Skeleton& skeleton) {
  std::vector<double> length(skeleton.jointCount(), 0.0);
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    const int p = skeleton.parents[j];
    if (p != kNoParent) length[p] += glm::length(skeleton.offsets[j]);
    if (skeleton.end_sites[j]) length[j] += glm::length(*skeleton.end_sites[j]);
  }
  return length;
}

double tableFraction(const SegmentMassTable& table, Segment s) {
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
}

// Each group's fraction, split among its joints by body length (evenly when they have none);
// "other" joints at the matched segments' mass per length; normalised to 1.
std::vector<double> massFractions(const SegmentAssignment& a, const SegmentMassTable& table) {
  const std::vector<double> length = bodyLengths(a.skeleton);
  const int joints = a.joints;
  std::vector<double> fraction(joints, 0.0);
  double matched_mass = 0.0;
  double matched_length = 0.0;
  for (int j = 0; j < joints; ++j) {
    if (a.segment[j] == Segment::kNone || a.segment[j] == Segment::kOther) continue;
    double group_length = 0.0;
    int members = 0;
    bool first_member = true;
    for (int k = 0; k < joints; ++k) {
      if (a.group[k] != a.group[j] || a.segment[k] != a.segment[j]) continue;
      group_length += length[k];
      ++members;
      first_member = first_member && k >= j;
    }
    const double share = group_length > 0.0 ? length[j] / group_length : 1.0 / members;
    fraction[j] = tableFraction(table, a.segment[j]) * share;
    matched_mass += fraction[j];
    if (first_member) matched_length += group_length;
  }
  const double density = matched_length > 0.0 ? matched_mass / matched_length : 0.0;
  for (int j = 0; j < joints; ++j) {
    if (a.segment[j] == Segment::kOther) fraction[j] = density * length[j];
  }
  const double total = std::accumulate(fraction.begin(), fraction.end(), 0.0);
  if (total > 0.0) {
    for (double& f : fraction) f /= total;
  } else {
    fraction.assign(joints, 1.0 / joints);  // nothing matched and nothing has length
  }
  return fraction;
}

}  // namespace

MassDistribution massDistribution(const Skeleton& skeleton, const std::vector<Foot>& feet,
                                  const SegmentMassTable& table) {
  SegmentAssignment assignment(skeleton);
  assignLimbsAndHead(assignment, feet);
  assignTrunkAndRest(assignment);
  return {assignment.segment, massFractions(assignment, table)};
}

std::vector<glm::dvec3> centreOfMass(const Skeleton& skeleton, const Clip& clip,
                                     const MassDistribution& masses) {
  const int joints = skeleton.jointCount();
  std::vector<glm::dmat4> world(joints);
  std::vector<glm::dvec3> com(clip.frame_count, glm::dvec3(0.0));
  std::vector<glm::dvec3> weighted(joints);
  std::vector<double> weight(joints);
  for (int f = 0; f < clip.frame_count; ++f) {
    worldTransforms(skeleton, clip, f, world);
    std::fill(weighted.begin(), weighted.end(), glm::dvec3(0.0));
    std::fill(weight.begin(), weight.end(), 0.0);
    // Each bone's midpoint, weighted by its rest length, into the body of the joint it hangs on.
    for (int j = 0; j < joints; ++j) {
      const glm::dvec3 here(world[j][3]);
      const int p = skeleton.parents[j];
      if (p != kNoParent) {
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

}  // namespace sinew::motion

// ---------------------------------------------------------------- body size and mass

namespace sinew::motion {
namespace {

constexpr double kLegOfStature = 0.530 - 0.039;  // Winter: hip joint less ankle height
constexpr double kTopJointOfStature = 0.870;     // Winter: the chin

// A leg's top joint, as massDistribution counts it: the joint above the foot joint's parent (the
// thigh's, the hip), or the highest that exists.
int legTop(const Skeleton& skeleton, int foot) {
  int top = foot;
  for (int k = 0; k < 2 && skeleton.parents[top] != kNoParent; ++k) top = skeleton.parents[top];
  return top;
}

// The distance between the mid-points of the two pairs of leg tops, or failing pairs the largest
// distance between two leg tops.
double trunkLength(const Skeleton& skeleton, const std::vector<Foot>& feet,
                   const std::vector<glm::dvec3>& world) {
  std::vector<glm::dvec3> girdles;
  for (size_t a = 0; a < feet.size(); ++a) {
    const int b = feet[a].pair;
    if (b <= static_cast<int>(a)) continue;
    girdles.push_back(
        0.5 * (world[legTop(skeleton, feet[a].joint)] + world[legTop(skeleton, feet[b].joint)]));
  }
  if (girdles.size() == 2) return glm::length(girdles[0] - girdles[1]);
  double longest = 0.0;
  for (const Foot& a : feet)
    for (const Foot& b : feet)
      longest = std::max(longest, glm::length(world[legTop(skeleton, a.joint)] -
                                              world[legTop(skeleton, b.joint)]));
  return longest;
}

// Whether the figure's topmost point in the first frame is an End Site with length (the top of
// the head, as most rigs end their head) rather than a joint (Bandai's head joint, whose End Site
// has none; a neck).
bool topIsHeadTop(const Skeleton& skeleton, const Clip& clip) {
  const int pelvis = pelvisJoint(skeleton);
  const Poses first = computePoses(skeleton, clip, 1);
  double top = -1e300;
  bool end_site = false;
  for (int j = 0; j < skeleton.jointCount(); ++j) {
    if (!inSubtree(skeleton, pelvis, j)) continue;
    if (first.joint[j].y > top) top = first.joint[j].y, end_site = false;
    const bool has_length = skeleton.end_sites[j] && glm::length(*skeleton.end_sites[j]) > 0.0;
    if (has_length && first.site[j].y > top) top = first.site[j].y, end_site = true;
  }
  return end_site;
}

// A quadruped's four feet: as given, or else from the first of up to 16 sampled frames in which
// all four stand (a walk's first frame may have one in the air), or else from the rest pose.
std::vector<Foot> fourFeet(const Skeleton& skeleton, const Clip& clip,
                           const std::vector<Foot>& feet) {
  if (feet.size() == 4) return feet;
  const int samples = std::min(clip.frame_count, 16);
  const size_t n = static_cast<size_t>(clip.joint_count);
  for (int s = 1; s < samples; ++s) {
    const size_t f = static_cast<size_t>(s) * static_cast<size_t>(clip.frame_count - 1) /
                     static_cast<size_t>(samples - 1);
    Clip one = clip;
    one.frame_count = 1;
    one.rotations.assign(clip.rotations.begin() + f * n, clip.rotations.begin() + (f + 1) * n);
    one.translations.assign(clip.translations.begin() + f * n,
                            clip.translations.begin() + (f + 1) * n);
    if (!clip.scales.empty())
      one.scales.assign(clip.scales.begin() + f * n, clip.scales.begin() + (f + 1) * n);
    if (Result<std::vector<Foot>> found = findFeet(skeleton, one);
        found.ok() && found.value().size() == 4)
      return found.value();
  }
  if (Result<std::vector<Foot>> rest = findFeet(skeleton, restClip(skeleton, 1, clip.frame_time));
      rest.ok() && rest.value().size() == 4)
    return rest.value();
  return feet;
}

}  // namespace

BodyEstimate estimateBody(const Skeleton& skeleton, const Clip& clip, const std::vector<Foot>& feet,
                          const BodyMassModel& model) {
  BodyEstimate body;
  body.figure = measureFigure(skeleton, clip, 1);
  body.extent_m = body.figure.height;
  double legs = 0.0;
  for (const Foot& foot : feet) {
    const int knee = skeleton.parents[foot.joint];
    legs += glm::length(skeleton.offsets[foot.joint]) +
            (knee != kNoParent ? glm::length(skeleton.offsets[knee]) : 0.0);
  }
  if (!feet.empty()) body.leg_length_m = legs / static_cast<double>(feet.size());
  std::ostringstream basis;
  basis.precision(3);
  if (body.figure.human) {
    const double by_legs = body.leg_length_m / kLegOfStature;
    const double by_extent =
        topIsHeadTop(skeleton, clip) ? body.extent_m : body.extent_m / kTopJointOfStature;
    body.stature_m = std::max(by_legs, by_extent);
    const double r = body.stature_m / model.human_stature_m;
    body.mass_kg = model.human_mass_kg * r * r;
    basis << "human, stature " << body.stature_m << " m from "
          << (by_legs >= by_extent ? "its legs (thigh and shank " : "its joints' extent (")
          << (by_legs >= by_extent ? body.leg_length_m : body.extent_m) << " m), " << body.mass_kg
          << " kg at " << model.human_mass_kg << " kg for " << model.human_stature_m << " m";
  } else if (const std::vector<Foot> four = body.figure.family == BodyFamily::kQuadruped
                                                ? fourFeet(skeleton, clip, feet)
                                                : std::vector<Foot>{};
             four.size() == 4) {
    const std::vector<glm::dvec3> world = worldPositions(skeleton, clip, 0);
    body.trunk_length_m = trunkLength(skeleton, four, world);
    const double t = body.trunk_length_m;
    body.mass_kg = model.quadruped_kg_m3 * t * t * t;
    basis << "quadruped, " << body.figure.hip_height << " m at the hips, trunk " << t
          << " m from hip to shoulder, legs " << body.leg_length_m << " m, " << body.mass_kg
          << " kg at " << model.quadruped_kg_m3 << " kg per cubed metre of trunk";
  } else {
    basis << familyName(body.figure.family) << " (" << body.figure.legs
          << " legs reach the ground), " << body.extent_m << " m tall: no size model, weighed by "
          << "volume";
  }
  body.basis = basis.str();
  return body;
}

}  // namespace sinew::motion
