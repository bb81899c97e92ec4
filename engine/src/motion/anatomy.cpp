#include "sinew/motion/anatomy.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

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

int commonAncestor(const Skeleton& skeleton, int a, int b) {
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
          commonAncestor(skeleton, points[grounded[a]].joint, points[grounded[b]].joint);
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

FrameDetection detectFrame(const Skeleton& skeleton, const Clip& clip,
                           const FigureSizeRanges& ranges) {
  FrameDetection result;
  const FigureMeasure figure = measureFigure(skeleton, clip);
  result.frame.up = figure.up_axis == 2 ? UpAxis::kZ : UpAxis::kY;
  result.height_in_file_units = figure.height;
  if (!(figure.height > 0.0)) {
    result.reason = "the figure has no height; assuming metres, Y-up";
    return result;
  }
  // What is measured, and the range it should fall in, by family.
  double size = figure.height, lo = 0.0, hi = 0.0;
  const char* what = "tall";
  const char* family = figure.human ? "human" : familyName(figure.family);
  if (!figure.human && figure.family != BodyFamily::kQuadruped) {
    // No body to compare with: the size alone, >= 1000 units as mm, >= 10 as cm, else metres.
    result.frame.unit = figure.height >= 1000.0 ? LengthUnit::kMillimetres
                        : figure.height >= 10.0 ? LengthUnit::kCentimetres
                                                : LengthUnit::kMetres;
    result.height_m = figure.height * metresPerUnit(result.frame.unit);
    std::ostringstream reason;
    reason.precision(3);
    reason << family << " (" << figure.legs << " legs reach the ground), " << figure.height
           << " file units tall along " << upAxisName(result.frame.up) << " reads as "
           << unitName(result.frame.unit) << " (override with --units and --up)";
    result.reason = reason.str();
    return result;
  }
  if (figure.human) {
    lo = ranges.human_height_min_m;
    hi = ranges.human_height_max_m;
  } else if (figure.family == BodyFamily::kQuadruped) {
    size = figure.hip_height;
    lo = ranges.quadruped_hip_min_m;
    hi = ranges.quadruped_hip_max_m;
    what = "at the hips";
  }
  // Commonest first: a tie (both inside the range) goes to the earlier.
  const LengthUnit order[] = {LengthUnit::kCentimetres, LengthUnit::kMetres,
                              LengthUnit::kMillimetres, LengthUnit::kInches,
                              LengthUnit::kCmu,         LengthUnit::kFeet};
  LengthUnit best = order[0];
  double best_distance = 1e300;
  for (LengthUnit unit : order) {
    const double metres = size * metresPerUnit(unit);
    const double distance = metres < lo   ? std::log(lo / metres)
                            : metres > hi ? std::log(metres / hi)
                                          : 0.0;
    if (distance < best_distance - 1e-12) {
      best_distance = distance;
      best = unit;
    }
  }
  result.frame.unit = best;
  result.height_m = figure.height * metresPerUnit(best);
  std::ostringstream reason;
  reason.precision(3);
  reason << family << " (" << figure.legs << " legs reach the ground), " << size << " file units "
         << what << " along " << upAxisName(result.frame.up) << ": " << size * metresPerUnit(best)
         << " m in " << unitName(best) << (best_distance == 0.0 ? ", inside " : ", the nearest to ")
         << lo << "-" << hi << " m (override with --units and --up)";
  result.reason = reason.str();
  return result;
}

}  // namespace sinew::motion
