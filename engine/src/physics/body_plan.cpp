#include "sinew/physics/body_plan.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include "sinew/core/rotation.h"

namespace sinew::physics {
namespace {

constexpr glm::dvec3 kUp(0.0, 1.0, 0.0);
constexpr glm::dquat kIdentity(1.0, 0.0, 0.0, 0.0);

bool nameHasAny(const std::string& name, const std::vector<std::string>& parts) {
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const std::string& part : parts) {
    std::string p(part);
    std::transform(p.begin(), p.end(), p.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (!p.empty() && lower.find(p) != std::string::npos) return true;
  }
  return false;
}

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Per-axis extremes of the rotation vectors of `qs` about `center` (log(center^-1 q)).
void rangeAbout(const glm::dquat& center, std::span<const glm::dquat> qs, glm::dvec3& lo,
                glm::dvec3& hi) {
  lo = glm::dvec3(std::numeric_limits<double>::max());
  hi = glm::dvec3(-std::numeric_limits<double>::max());
  const glm::dquat inverse = glm::inverse(center);
  for (const glm::dquat& q : qs) {
    const glm::dvec3 v = shortRotationVector(glm::normalize(inverse * q));
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
}

// Hinge angle of q about a unit axis, radians in (-pi, pi].
double hingeAngle(glm::dquat q, const glm::dvec3& axis) {
  q = positiveW(glm::normalize(q));
  return 2.0 * std::atan2(glm::dot(glm::dvec3(q.x, q.y, q.z), axis), q.w);
}

glm::dvec3 transformPoint(const glm::dmat4& m, const glm::dvec3& p) {
  return glm::dvec3(m * glm::dvec4(p, 1.0));
}

// Shortest rotation taking +Y onto the unit direction d.
glm::dquat rotationFromY(const glm::dvec3& d) {
  const double c = glm::dot(kUp, d);
  if (c < -0.999999) return glm::angleAxis(std::numbers::pi, glm::dvec3(1.0, 0.0, 0.0));
  const glm::dvec3 axis = glm::cross(kUp, d);
  const double s = glm::length(axis);
  if (s < 1e-12) return kIdentity;
  return glm::angleAxis(std::atan2(s, c), axis / s);
}

// The rig's rest pose stood upright: the rest world transforms turned so that the mean direction
// from the feet to the pelvis points up (+Y). Rest poses are the natural standing posture (legs
// straight, feet flat) but some are stored lying down (iClone's is Z-up under a Y-up motion).
// `upright` receives the turn.
std::vector<glm::dmat4> uprightRest(const motion::Skeleton& skeleton, std::span<const int> feet,
                                    glm::dquat& upright) {
  std::vector<glm::dmat4> rest = motion::restWorldTransforms(skeleton);
  upright = kIdentity;
  if (feet.empty()) return rest;
  const glm::dvec3 pelvis(rest[static_cast<size_t>(motion::pelvisJoint(skeleton))][3]);
  glm::dvec3 up(0.0);
  for (int f : feet) up += pelvis - glm::dvec3(rest[static_cast<size_t>(f)][3]);
  if (glm::length(up) < 1e-9) return rest;
  upright = glm::inverse(rotationFromY(glm::normalize(up)));
  const glm::dmat4 turn = glm::mat4_cast(upright);
  for (glm::dmat4& m : rest) m = turn * m;
  return rest;
}

// Principal eigenvector (by power iteration, deterministic) and its share of the trace.
void principalAxis(const glm::dmat3& m, glm::dvec3& axis, double& share) {
  const double trace = m[0][0] + m[1][1] + m[2][2];
  axis = glm::dvec3(1.0, 0.0, 0.0);
  share = 0.0;
  if (!(trace > 1e-15)) return;
  // Start from the column with the largest diagonal to avoid an orthogonal start.
  int best = 0;
  for (int i = 1; i < 3; ++i)
    if (m[i][i] > m[best][best]) best = i;
  glm::dvec3 v = m[best];
  if (glm::length(v) < 1e-300) return;
  v = glm::normalize(v);
  for (int it = 0; it < 200; ++it) {
    const glm::dvec3 next = m * v;
    const double len = glm::length(next);
    if (len < 1e-300) break;
    v = next / len;
  }
  axis = v;
  share = glm::dot(v, m * v) / trace;
}

double segmentRadius(const BodyPlanSettings& s, motion::Segment segment) {
  using motion::Segment;
  switch (segment) {
    case Segment::kHead:
      return s.radius_head;
    case Segment::kTrunk:
      return s.radius_trunk;
    case Segment::kUpperArm:
      return s.radius_upper_arm;
    case Segment::kForearm:
      return s.radius_forearm;
    case Segment::kHand:
      return s.radius_hand;
    case Segment::kThigh:
      return s.radius_thigh;
    case Segment::kShank:
      return s.radius_shank;
    case Segment::kFoot:
      return s.radius_foot;
    default:
      return s.radius_other;
  }
}

double shapeVolume(const Shape& shape) {
  const double pi = std::numbers::pi;
  switch (shape.type) {
    case ShapeType::kCapsule:
      return pi * shape.radius * shape.radius * 2.0 * shape.half_length +
             4.0 / 3.0 * pi * shape.radius * shape.radius * shape.radius;
    case ShapeType::kBox:
      return 8.0 * shape.half_extents.x * shape.half_extents.y * shape.half_extents.z;
    case ShapeType::kSphere:
      return 4.0 / 3.0 * pi * shape.radius * shape.radius * shape.radius;
  }
  return 0.0;
}

// Principal inertia of a uniform shape of `mass` in its own frame, kg m^2.
glm::dvec3 shapeInertia(const Shape& shape, double mass) {
  const double r = shape.radius;
  switch (shape.type) {
    case ShapeType::kCapsule: {
      const double h = 2.0 * shape.half_length;
      const double vc = h;  // proportional volumes: cylinder pi r^2 h, caps 4/3 pi r^3
      const double vs = 4.0 / 3.0 * r;
      const double mc = mass * vc / (vc + vs);
      const double ms = mass - mc;
      const double axial = mc * r * r / 2.0 + ms * 2.0 * r * r / 5.0;
      const double perp = mc * (h * h / 12.0 + r * r / 4.0) +
                          ms * (2.0 * r * r / 5.0 + h * h / 4.0 + 3.0 * h * r / 8.0);
      return {perp, axial, perp};
    }
    case ShapeType::kBox: {
      const glm::dvec3 e = shape.half_extents;
      return {mass / 3.0 * (e.y * e.y + e.z * e.z), mass / 3.0 * (e.x * e.x + e.z * e.z),
              mass / 3.0 * (e.x * e.x + e.y * e.y)};
    }
    case ShapeType::kSphere: {
      const double i = 0.4 * mass * r * r;
      return {i, i, i};
    }
  }
  return glm::dvec3(0.0);
}

// Whether the rig's rest pose stands: in the upright rest pose every foot hangs below the pelvis
// by at least 70% of its leg's length (the bones from the pelvis down to it). Bandai's rest pose
// has every bone along its parent's X axis, legs sideways: no standing pose at all.
bool restPoseStands(const motion::Skeleton& skeleton, std::span<const int> feet) {
  if (feet.empty()) return true;
  glm::dquat upright;
  const std::vector<glm::dmat4> rest = uprightRest(skeleton, feet, upright);
  const int pelvis = motion::pelvisJoint(skeleton);
  for (int f : feet) {
    double length = 0.0;
    for (int j = f; j != pelvis && j != motion::kNoParent; j = skeleton.parents[j])
      length += glm::length(skeleton.offsets[j]);
    const double drop = rest[static_cast<size_t>(pelvis)][3].y - rest[static_cast<size_t>(f)][3].y;
    if (drop < 0.7 * length) return false;
  }
  return true;
}

// The clip's mean pose: per joint, the normalised mean of its local rotations made continuous
// (each on the first frame's side). For a walk or a run it stands: legs together, feet flat.
std::vector<glm::dquat> meanPose(const motion::Clip& clip) {
  std::vector<glm::dquat> mean(static_cast<size_t>(clip.joint_count), glm::dquat(0.0, 0.0, 0.0, 0.0));
  for (int f = 0; f < clip.frame_count; ++f)
    for (int j = 0; j < clip.joint_count; ++j) {
      const glm::dquat q = clip.rotation(f, j);
      glm::dquat& m = mean[static_cast<size_t>(j)];
      const double sign = glm::dot(q, clip.rotation(0, j)) < 0.0 ? -1.0 : 1.0;
      m = glm::dquat(m.w + sign * q.w, m.x + sign * q.x, m.y + sign * q.y, m.z + sign * q.z);
    }
  for (glm::dquat& m : mean) m = glm::normalize(m);
  return mean;
}

// How a foot meets the ground in the clip, in the foot link's frame: the sole's normal (the
// world's up as the foot sees it while it stands flat) and the ankle's height above the ground
// then. The ground: the median over the frames of the lowest point of any foot (one foot is down
// in nearly every frame of a walk; a toe that dips through the floor at toe-off moves a median
// little). Flat: the frames where the ankle is lowest (its lowest 15%, mid-stance, after the heel
// strike and before the toe-off).
struct SoleFit {
  bool ok = false;
  glm::dvec3 up{0.0, 1.0, 0.0};  // unit, foot link frame
  double depth = 0.0;            // ankle above the ground while flat, metres
  int frames = 0;                // flat frames the fit used
};

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * static_cast<double>(values.size())));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

std::vector<SoleFit> fitSoles(const motion::Skeleton& skeleton, const motion::Clip& clip,
                              std::span<const int> feet,
                              const std::vector<std::vector<glm::dvec3>>& local_points) {
  const int n = skeleton.jointCount();
  const int samples = std::min(clip.frame_count, 600);
  std::vector<glm::dmat4> world(static_cast<size_t>(n));
  // (feet x samples) the foot's transform; (samples) the lowest point of any foot.
  std::vector<std::vector<glm::dmat4>> foot(feet.size(), std::vector<glm::dmat4>(samples));
  std::vector<double> lowest(samples, std::numeric_limits<double>::max());
  for (int s = 0; s < samples; ++s) {
    const int f = samples > 1 ? static_cast<int>(static_cast<long long>(s) * (clip.frame_count - 1) /
                                                 (samples - 1))
                              : 0;
    motion::worldTransforms(skeleton, clip, f, world);
    for (size_t k = 0; k < feet.size(); ++k) {
      const glm::dmat4& m = world[static_cast<size_t>(feet[k])];
      foot[k][s] = m;
      lowest[s] = std::min(lowest[s], m[3].y);
      for (const glm::dvec3& p : local_points[k]) lowest[s] = std::min(lowest[s], (m * glm::dvec4(p, 1.0)).y);
    }
  }
  const double ground = quantile(lowest, 0.5);
  std::vector<SoleFit> fits(feet.size());
  for (size_t k = 0; k < feet.size(); ++k) {
    std::vector<double> ankle(samples);
    for (int s = 0; s < samples; ++s) ankle[s] = foot[k][s][3].y;
    const double flat = quantile(ankle, 0.15);
    glm::dvec3 up(0.0);
    std::vector<double> depths;
    for (int s = 0; s < samples; ++s) {
      if (ankle[s] > flat) continue;
      up += glm::inverse(glm::dmat3(foot[k][s])) * kUp;
      depths.push_back(ankle[s] - ground);
    }
    if (depths.empty() || glm::length(up) < 1e-9) continue;
    fits[k] = {true, glm::normalize(up), quantile(depths, 0.5), static_cast<int>(depths.size())};
  }
  return fits;
}

// A foot's box in its link frame, its sole on the plane `depth` below the pivot across `up`:
// forward to the foot's farthest point (a toe joint without an End Site of any length is the
// ball of the foot: the toes reach 40% further), back to a heel of 1.5 radii behind the ankle.
Shape soleBox(const SoleFit& fit, std::span<const glm::dvec3> points, bool bare_tip, double radius) {
  const glm::dvec3 up = fit.up;
  glm::dvec3 forward(0.0);
  double far = 0.0;
  for (const glm::dvec3& p : points) {
    const glm::dvec3 flat = p - glm::dot(p, up) * up;
    if (glm::length(flat) > far) far = glm::length(flat), forward = flat;
  }
  if (far < 1e-6) {  // no toe to say where forward is: across the foot's first local axis
    forward = glm::dvec3(0.0, 0.0, 1.0) - up.z * up;
    if (glm::length(forward) < 1e-6) forward = glm::dvec3(1.0, 0.0, 0.0) - up.x * up;
    far = 4.0 * radius;
  }
  forward = glm::normalize(forward);
  if (bare_tip) far *= 1.4;
  const double heel = 1.5 * radius;
  const double depth = std::max(fit.depth, 0.5 * radius);  // the box spans sole to ankle
  Shape shape;
  shape.type = ShapeType::kBox;
  shape.radius = radius;
  shape.half_extents = glm::dvec3(radius, 0.5 * depth, 0.5 * (far + heel));
  shape.center = forward * (0.5 * (far - heel)) - up * (0.5 * depth);
  const glm::dvec3 side = glm::normalize(glm::cross(up, forward));
  shape.rotation = glm::normalize(glm::quat_cast(glm::dmat3(side, up, forward)));
  return shape;
}

}  // namespace

const char* jointTypeName(JointType type) {
  switch (type) {
    case JointType::kBase:
      return "base";
    case JointType::kFixed:
      return "fixed";
    case JointType::kHinge:
      return "hinge";
    case JointType::kBall:
      return "ball";
  }
  return "?";
}

int dofCount(JointType type) {
  switch (type) {
    case JointType::kHinge:
      return 1;
    case JointType::kBall:
      return 3;
    default:
      return 0;
  }
}

double lowestPoint(const Shape& shape, const glm::dmat4& link_to_world) {
  const glm::dvec3 c(link_to_world * glm::dvec4(shape.center, 1.0));
  const glm::dmat3 r = glm::dmat3(link_to_world) * glm::mat3_cast(shape.rotation);
  switch (shape.type) {
    case ShapeType::kSphere:
      return c.y - shape.radius;
    case ShapeType::kCapsule: {
      const glm::dvec3 axis = r[1] * shape.half_length;
      return std::min(c.y + axis.y, c.y - axis.y) - shape.radius;
    }
    case ShapeType::kBox: {
      double y = 0.0;
      for (int k = 0; k < 3; ++k) y += std::abs(r[k].y) * shape.half_extents[k];
      return c.y - y;
    }
  }
  return c.y;
}

bool isAncestorLink(const BodyPlan& plan, int ancestor, int link) {
  while (link > ancestor) link = plan.links[static_cast<size_t>(link)].parent;
  return link == ancestor;
}

glm::dquat linkRelativeRotation(const Link& link, const glm::dquat& q, double angle) {
  switch (link.type) {
    case JointType::kBall:
      return link.zero_rotation * q;
    case JointType::kHinge:
      return link.zero_rotation * glm::angleAxis(angle, link.hinge_axis);
    default:
      return link.zero_rotation;
  }
}

glm::dvec3 ballRangeCoordinates(const Link& link, const glm::dquat& q) {
  return shortRotationVector(glm::normalize(glm::inverse(link.ball_center) * q));
}

glm::dquat clampToBallRange(const Link& link, const glm::dquat& q) {
  const glm::dvec3 v = ballRangeCoordinates(link, q);
  const glm::dvec3 inside = glm::clamp(v, link.ball_lower, link.ball_upper);
  if (inside == v) return q;
  return glm::normalize(link.ball_center * fromRotationVector(inside));
}

Status BodyPlanSettings::validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  auto nonNegative = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!positive(reference_size_m)) return Status::error("reference_size_m must be > 0");
  if (!nonNegative(min_segment_length_m)) return Status::error("min_segment_length_m must be >= 0");
  if (!nonNegative(max_lost_displacement)) return Status::error("max_lost_displacement must be >= 0");
  if (!(hinge_dominance >= 0.0 && hinge_dominance <= 1.0))
    return Status::error("hinge_dominance must be in 0..1");
  if (!nonNegative(fixed_range_rad)) return Status::error("fixed_range_rad must be >= 0");
  if (!nonNegative(limit_margin_rad)) return Status::error("limit_margin_rad must be >= 0");
  if (!positive(human_mass_kg)) return Status::error("human_mass_kg must be > 0");
  if (!positive(density_kg_m3)) return Status::error("density_kg_m3 must be > 0");
  if (!(std::isfinite(min_link_mass_fraction) && min_link_mass_fraction >= 0.0 &&
        min_link_mass_fraction < 0.1))
    return Status::error("min_link_mass_fraction must be in [0, 0.1)");
  const std::pair<const char*, double> radii[] = {
      {"radius_head", radius_head},           {"radius_trunk", radius_trunk},
      {"radius_upper_arm", radius_upper_arm}, {"radius_forearm", radius_forearm},
      {"radius_hand", radius_hand},           {"radius_thigh", radius_thigh},
      {"radius_shank", radius_shank},         {"radius_foot", radius_foot},
      {"radius_other", radius_other}};
  for (const auto& [name, value] : radii)
    if (!positive(value)) return Status::error(std::string(name) + " must be > 0");
  if (Status s = mass_table.validate(); !s.ok()) return Status::error("mass_table: " + s.message());
  for (const auto& [name, kg] : mass_overrides)
    if (!positive(kg)) return Status::error("mass_overrides: " + name + " must be > 0 kg");
  for (const auto& [name, type] : type_overrides)
    if (type != JointType::kFixed && type != JointType::kBall)
      return Status::error("type_overrides: " + name +
                           " can be made fixed or ball (hinges come from hinge_names)");
  for (const auto& [name, range] : hinge_limit_overrides)
    if (!(std::isfinite(range.first) && std::isfinite(range.second) && range.first < range.second))
      return Status::error("hinge_limit_overrides: " + name + " needs lower < upper");
  return Status();
}

int BodyPlan::dofCount() const {
  int n = 0;
  for (const Link& link : links) n += physics::dofCount(link.type);
  return n;
}

std::vector<int> BodyPlan::dofOffsets() const {
  std::vector<int> offsets(links.size(), 0);
  int n = 0;
  for (size_t i = 0; i < links.size(); ++i) {
    offsets[i] = n;
    n += physics::dofCount(links[i].type);
  }
  return offsets;
}

Status BodyPlan::validate() const {
  if (links.empty()) return Status::error("body plan has no links");
  double sum = 0.0;
  for (size_t i = 0; i < links.size(); ++i) {
    const Link& link = links[i];
    const std::string where = "link " + std::to_string(i) + " (" + link.name + "): ";
    if (i == 0 && (link.parent != -1 || link.type != JointType::kBase))
      return Status::error(where + "link 0 must be the base with parent -1");
    if (i > 0 && (link.parent < 0 || link.parent >= static_cast<int>(i)))
      return Status::error(where + "parent must be an earlier link");
    if (i > 0 && link.type == JointType::kBase)
      return Status::error(where + "type base is only for link 0");
    if (!(std::isfinite(link.mass_kg) && link.mass_kg > 0.0))
      return Status::error(where + "mass_kg must be > 0");
    if (!finite(link.inertia) || link.inertia.x <= 0.0 || link.inertia.y <= 0.0 ||
        link.inertia.z <= 0.0)
      return Status::error(where + "inertia must be > 0 on every axis");
    if (!finite(link.pivot)) return Status::error(where + "pivot must be finite");
    if (!finite(link.com)) return Status::error(where + "com must be finite");
    if (std::abs(glm::length(link.zero_rotation) - 1.0) > 1e-6)
      return Status::error(where + "zero_rotation must be a unit quaternion");
    if (link.type == JointType::kBall) {
      if (std::abs(glm::length(link.ball_center) - 1.0) > 1e-6)
        return Status::error(where + "ball_center must be a unit quaternion");
      for (int k = 0; k < 3; ++k)
        if (!(link.ball_lower[k] < link.ball_upper[k]))
          return Status::error(where + "ball_lower must be < ball_upper on every axis");
    }
    if (link.type == JointType::kHinge) {
      if (std::abs(glm::length(link.hinge_axis) - 1.0) > 1e-6)
        return Status::error(where + "hinge_axis must be a unit vector");
      if (!(link.hinge_lower < link.hinge_upper))
        return Status::error(where + "hinge_lower must be < hinge_upper");
    }
    const Shape& s = link.shape;
    if (!(s.radius > 0.0) || !(s.half_length >= 0.0) || !(s.half_extents.x > 0.0) ||
        !(s.half_extents.y > 0.0) || !(s.half_extents.z > 0.0) || !finite(s.center))
      return Status::error(where + "shape sizes must be > 0 and finite");
    sum += link.mass_kg;
  }
  if (std::abs(sum - total_mass_kg) > 1e-6 * std::max(1.0, sum))
    return Status::error("total_mass_kg " + std::to_string(total_mass_kg) +
                         " differs from the sum of link masses " + std::to_string(sum));
  for (size_t j = 0; j < link_of_joint.size(); ++j)
    if (link_of_joint[j] < 0 || link_of_joint[j] >= static_cast<int>(links.size()))
      return Status::error("link_of_joint[" + std::to_string(j) + "] is not a link");
  return Status();
}

namespace {

// The points link li holds, in the world of the joint transforms `world`: the joints merged into
// it, its children's pivots and its End Sites.
std::vector<glm::dvec3> linkPoints(const motion::Skeleton& skeleton, const BodyPlan& plan, int li,
                                   const std::vector<glm::dmat4>& world) {
  const Link& link = plan.links[static_cast<size_t>(li)];
  std::vector<glm::dvec3> points;
  for (int j = link.joint; j < skeleton.jointCount(); ++j) {
    const int owner = plan.link_of_joint[j];
    const bool own = owner == li && j != link.joint;
    const bool child_pivot =
        owner != li && plan.links[owner].joint == j && plan.links[owner].parent == li;
    if (own || child_pivot) points.emplace_back(world[j][3]);
    if (owner == li && skeleton.end_sites[j])
      points.push_back(transformPoint(world[j], *skeleton.end_sites[j]));
  }
  return points;
}

// Without a clip, foot link li's sole: level when the foot stands at rest, a box measured in the
// upright rest pose (`rest_up`; both feet alike), then carried into the first pose's link frame.
Shape restSoleBox(const motion::Skeleton& skeleton, const BodyPlan& plan, int li,
                  const std::vector<glm::dmat4>& rest_up, const glm::dvec3& lateral_world,
                  double radius) {
  const Link& link = plan.links[static_cast<size_t>(li)];
  Shape shape;
  shape.radius = radius;
  const std::vector<glm::dvec3> sole_points = linkPoints(skeleton, plan, li, rest_up);
  const glm::dvec3 ankle(rest_up[link.joint][3]);
  glm::dvec3 forward(0.0);
  double far = 0.0, bottom = ankle.y;
  for (const glm::dvec3& p : sole_points) {
    glm::dvec3 d = p - ankle;
    d.y = 0.0;
    if (glm::length(d) > far) far = glm::length(d), forward = d;
    bottom = std::min(bottom, p.y);
  }
  if (far < 1e-6) {
    forward = glm::normalize(glm::cross(lateral_world, kUp));
    far = 4.0 * radius;
  } else {
    forward /= far;
  }
  const glm::dvec3 side = glm::normalize(glm::cross(kUp, forward));
  const double heel = 1.5 * radius;
  if (ankle.y - bottom < 1.5 * radius) bottom = ankle.y - 1.5 * radius;
  const double top = ankle.y;
  const glm::dvec3 center_world =
      ankle + forward * (0.5 * (far - heel)) + kUp * (0.5 * (top + bottom) - ankle.y);
  shape.type = ShapeType::kBox;
  shape.half_extents = glm::dvec3(radius, 0.5 * (top - bottom), 0.5 * (far + heel));
  const glm::dquat world_rotation = glm::quat_cast(glm::dmat3(side, kUp, forward));
  shape.center = transformPoint(glm::inverse(rest_up[link.joint]), center_world);
  shape.rotation = glm::normalize(
      glm::inverse(glm::quat_cast(glm::dmat3(rest_up[link.joint]))) * world_rotation);
  return shape;
}

// Masses by the figure's family (motion::estimateBody): a human's total from its stature, shared
// by the de Leva fractions; a quadruped's total from its trunk, shared by shape volume; other
// creatures by shape volume at settings.density_kg_m3. No link below a share of the body; the
// user's overrides after the rules; inertia from the shapes.
Status assignMasses(BodyPlan& plan, const motion::Skeleton& skeleton, const motion::Clip& clip,
                    const motion::MassDistribution& masses, const std::vector<motion::Foot>& feet,
                    const BodyPlanSettings& settings) {
  const int link_count = static_cast<int>(plan.links.size());
  const int n = static_cast<int>(masses.fractions.size());
  motion::BodyMassModel model;
  model.human_mass_kg = settings.human_mass_kg;
  model.human_stature_m = settings.reference_size_m;
  const motion::BodyEstimate body = motion::estimateBody(skeleton, clip, feet, model);
  plan.human = body.figure.human && body.mass_kg > 0.0;
  plan.notes.push_back("mass: " + body.basis);
  std::vector<double> fraction(link_count, 0.0);
  if (plan.human)
    for (int j = 0; j < n; ++j) fraction[plan.link_of_joint[j]] += masses.fractions[j];
  double total = 0.0;
  for (int li = 0; li < link_count; ++li) {
    Link& link = plan.links[li];
    const double by_volume = shapeVolume(link.shape) * settings.density_kg_m3;
    link.mass_kg = fraction[li] > 0.0 ? fraction[li] * body.mass_kg : by_volume;
    total += link.mass_kg;
  }
  // Light links (a tail tip, a paw) against a heavy body make the articulated solve and the
  // contacts stiff; no link is lighter than this share of the body.
  const double floor_mass = settings.min_link_mass_fraction * total;
  for (Link& link : plan.links) {
    if (link.mass_kg >= floor_mass) continue;
    total += floor_mass - link.mass_kg;
    link.mass_kg = floor_mass;
  }
  if (body.mass_kg > 0.0) {
    const double k = body.mass_kg / total;
    total = 0.0;
    for (Link& link : plan.links) total += (link.mass_kg *= k);
  }
  // The user's overrides, after the rules.
  auto findLink = [&](const std::string& name) {
    for (int li = 0; li < link_count; ++li)
      if (plan.links[li].name == name) return li;
    return -1;
  };
  for (const auto& [name, kg] : settings.mass_overrides) {
    const int li = findLink(name);
    if (li < 0) return Status::error("mass_overrides: no link named '" + name + "'");
    total += kg - plan.links[li].mass_kg;
    plan.links[li].mass_kg = kg;
  }
  for (const auto& [name, type] : settings.type_overrides) {
    const int li = findLink(name);
    if (li <= 0) return Status::error("type_overrides: no jointed link named '" + name + "'");
    plan.links[li].type = type;
  }
  for (const auto& [name, range] : settings.hinge_limit_overrides) {
    const int li = findLink(name);
    if (li < 0 || plan.links[li].type != JointType::kHinge)
      return Status::error("hinge_limit_overrides: no hinge named '" + name + "'");
    plan.links[li].hinge_lower = range.first;
    plan.links[li].hinge_upper = range.second;
  }
  plan.total_mass_kg = total;

  // Inertia from the shapes, rotated into the link frame (diagonal kept).
  for (Link& link : plan.links) {
    const glm::dvec3 principal = shapeInertia(link.shape, link.mass_kg);
    const glm::dmat3 r = glm::mat3_cast(link.shape.rotation);
    const glm::dmat3 tensor =
        r * glm::dmat3(principal.x, 0, 0, 0, principal.y, 0, 0, 0, principal.z) * glm::transpose(r);
    const double floor = 1e-7;
    link.inertia = glm::dvec3(std::max(tensor[0][0], floor), std::max(tensor[1][1], floor),
                              std::max(tensor[2][2], floor));
  }
  return {};
}

// The first pose's bounding size of the joints from the base down (joints above it, a root at the
// origin, do not count) and their End Sites: the body's size in metres.
double bodySize(const motion::Skeleton& skeleton, const std::vector<glm::dmat4>& world, int base) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (int j = base; j < skeleton.jointCount(); ++j) {
    const glm::dvec3 p(world[j][3]);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
    if (skeleton.end_sites[j]) {
      const glm::dvec3 e = transformPoint(world[j], *skeleton.end_sites[j]);
      lo = glm::min(lo, e);
      hi = glm::max(hi, e);
    }
  }
  const glm::dvec3 extent = hi - lo;
  return std::max({extent.x, extent.y, extent.z});
}

// What buildBodyPlan's stages share: the skeleton's first pose and what was found in it.
struct FirstPose {
  const motion::Skeleton& skeleton;
  const std::vector<glm::dmat4>& world;  // (joints) joint to world at the first frame
  const motion::MassDistribution& masses;
  const std::vector<char>& is_foot;               // (joints)
  const std::vector<std::vector<int>>& children;  // (joints)
  int base = 0;                                   // the base link's joint
};

// How far joint j's turning in the clip moves the pivots of its children, metres: the largest
// distance over the frames of a child's pivot, turned by j's rotation, from where j's mean
// rotation puts it (a twist about the child's own direction moves it nowhere). A joint merged
// into its parent's link turns its children's links about their own pivots, not about its own,
// so this much of the motion is lost (the MANN dog's Spine, at the hips with Spine1 19 cm ahead:
// merged, the chest and both forelegs rode 3-5 cm too low in the target, into the ground).
// `mean`: meanPose of the clip. 0 without a clip or children.
double childDisplacement(const FirstPose& pose, const motion::Clip* clip,
                         std::span<const glm::dquat> mean, int j) {
  if (clip == nullptr || pose.children[j].empty()) return 0.0;
  double farthest = 0.0;
  for (int c : pose.children[j]) {
    const glm::dvec3 offset = pose.skeleton.offsets[c];
    const glm::dvec3 at_mean = mean[static_cast<size_t>(j)] * offset;
    for (int f = 0; f < clip->frame_count; ++f)
      farthest = std::max(farthest, glm::length(clip->rotation(f, j) * offset - at_mean));
  }
  return farthest;
}

// Merging, parents first: whole subtrees by name (fingers, hands), single joints by length.
// (joints) 1 where the joint merges into its parent's link.
std::vector<char> mergedJoints(const FirstPose& pose, const motion::Clip* clip,
                               const BodyPlanSettings& settings, double size_m) {
  const motion::Skeleton& skeleton = pose.skeleton;
  const int n = skeleton.jointCount();
  const int base = pose.base;
  const double min_length = settings.min_segment_length_m * (size_m / settings.reference_size_m);
  std::vector<char> merged(n, 0), subtree_merged(n, 0);
  const std::vector<glm::dquat> mean = clip != nullptr ? meanPose(*clip) : std::vector<glm::dquat>();
  for (int j = base + 1; j < n; ++j) {
    const int p = skeleton.parents[j];
    if (p < base) continue;  // cannot happen for a single-child base chain
    const bool keep = nameHasAny(skeleton.names[j], settings.keep_names);
    if (pose.is_foot[j] || keep) continue;
    bool m = subtree_merged[p] != 0;
    if (!m && (nameHasAny(skeleton.names[j], settings.merge_names) ||
               pose.masses.segments[j] == motion::Segment::kHand)) {
      subtree_merged[j] = 1;
      m = true;
    }
    if (subtree_merged[p]) subtree_merged[j] = 1;
    // Short, but its turning carries its children too far to be lost: a link of its own (asked
    // only of a joint a length rule would merge).
    const auto carries = [&] {
      const double carried = childDisplacement(pose, clip, mean, j);
      return carried > 0.0 && carried >= settings.max_lost_displacement * size_m;
    };
    if (!m && glm::length(skeleton.offsets[j]) < min_length && !carries()) m = true;
    if (!m && pose.children[j].empty()) {
      const double leaf = skeleton.end_sites[j] ? glm::length(*skeleton.end_sites[j]) : 0.0;
      if (leaf < min_length) m = true;
    }
    if (!m && settings.merge_short_trunk &&
        (pose.masses.segments[j] == motion::Segment::kTrunk ||
         pose.masses.segments[j] == motion::Segment::kHead)) {
      // Distance from the pivot of the link the parent belongs to, at the first pose.
      int owner = p;
      while (owner > base && merged[owner]) owner = skeleton.parents[owner];
      const double distance =
          glm::length(glm::dvec3(pose.world[j][3]) - glm::dvec3(pose.world[owner][3]));
      const double diameter = 2.0 * segmentRadius(settings, pose.masses.segments[owner]) * size_m;
      if (distance < diameter && !carries()) m = true;
    }
    merged[j] = m ? 1 : 0;
  }
  return merged;
}

// Links in joint order (parents first): the base, then every joint not merged, each with the
// chain of joints from its parent link's joint down to its own.
void makeLinks(const FirstPose& pose, const std::vector<char>& merged, BodyPlan& plan) {
  const motion::Skeleton& skeleton = pose.skeleton;
  const int n = skeleton.jointCount();
  plan.link_of_joint.assign(n, 0);
  Link b;
  b.name = skeleton.names[pose.base];
  b.joint = pose.base;
  b.parent = -1;
  b.type = JointType::kBase;
  b.segment = pose.masses.segments[pose.base];
  plan.links.push_back(b);
  for (int j = pose.base + 1; j < n; ++j) {
    if (merged[j]) {
      plan.link_of_joint[j] = plan.link_of_joint[skeleton.parents[j]];
      continue;
    }
    Link link;
    link.name = skeleton.names[j];
    link.joint = j;
    link.segment = pose.masses.segments[j];
    link.foot = pose.is_foot[j] != 0;
    int a = skeleton.parents[j];
    link.chain.push_back(j);
    while (a != plan.links[plan.link_of_joint[a]].joint) {
      link.chain.insert(link.chain.begin(), a);
      a = skeleton.parents[a];
    }
    link.parent = plan.link_of_joint[a];
    plan.link_of_joint[j] = static_cast<int>(plan.links.size());
    plan.links.push_back(std::move(link));
  }
}

// Left-to-right direction for hinge axes without a clip: from the feet's sides, else X.
glm::dvec3 lateralDirection(const std::vector<motion::Foot>& feet,
                            const std::vector<glm::dmat4>& world) {
  glm::dvec3 lateral_world(1.0, 0.0, 0.0);
  glm::dvec3 left(0.0), right(0.0);
  int nl = 0, nr = 0;
  for (const motion::Foot& f : feet) {
    const glm::dvec3 p(world[f.joint][3]);
    if (f.side == motion::Side::kLeft) left += p, ++nl;
    if (f.side == motion::Side::kRight) right += p, ++nr;
  }
  if (nl > 0 && nr > 0) {
    glm::dvec3 d = left / double(nl) - right / double(nr);
    d.y = 0.0;
    if (glm::length(d) > 1e-6) lateral_world = glm::normalize(d);
  }
  return lateral_world;
}

// The link's pivot and zero rotation: its chain's offsets, the joints above its own frozen at
// the first pose, its own at rest.
void setPivot(const motion::Skeleton& skeleton, const BodyPlan& plan, Link& link) {
  glm::dmat4 t(1.0);
  for (size_t k = 0; k < link.chain.size(); ++k) {
    const int a = link.chain[k];
    const bool last = k + 1 == link.chain.size();
    const glm::dquat r = last ? skeleton.rest_rotations[a] : plan.frozen_rotations[a];
    t = t * glm::translate(glm::dmat4(1.0), skeleton.offsets[a]) * glm::mat4_cast(r);
  }
  link.pivot = glm::dvec3(t[3]);
  link.zero_rotation = glm::normalize(glm::quat_cast(glm::dmat3(t)));
}

// The link's observed coordinates over the clip, q_f = zero^-1 * (product of the chain's local
// rotations at frame f), kept in one hemisphere frame to frame.
struct ObservedRotations {
  std::vector<glm::dquat> qs;   // (frames)
  double max_from_first = 0.0;  // largest angle from the first frame's, radians
  glm::dmat3 moment{0.0};       // sum of the rotation vectors' outer products
};

ObservedRotations observedRotations(const Link& link, const motion::Clip& clip) {
  const glm::dquat zero_inv = glm::inverse(link.zero_rotation);
  ObservedRotations out;
  out.qs.resize(clip.frame_count);
  glm::dquat previous = kIdentity;
  for (int f = 0; f < clip.frame_count; ++f) {
    glm::dquat rel = kIdentity;
    for (int a : link.chain) rel = rel * clip.rotation(f, a);
    glm::dquat q = glm::normalize(zero_inv * rel);
    if (glm::dot(q, previous) < 0.0) q = -q;
    previous = q;
    out.qs[f] = q;
    out.max_from_first = std::max(out.max_from_first, angleBetween(out.qs[0], q));
    const glm::dvec3 v = shortRotationVector(glm::normalize(q));
    out.moment += glm::outerProduct(v, v);
  }
  return out;
}

// The ball range: what the clip does and the standing pose (the rest pose, where a run from
// standing starts and what the standing tests hold; a T-pose's arms lie outside a walk's). About
// the middle of those poses rather than the zero pose: the rotation vectors stay short there (the
// log map folds at pi), and the bounds are the observed extremes.
void setBallRange(const motion::Skeleton& skeleton, const std::vector<glm::dquat>& qs,
                  const BodyPlanSettings& settings, Link& link) {
  glm::dquat rest_rel = kIdentity;
  for (int a : link.chain) rest_rel = rest_rel * skeleton.rest_rotations[a];
  std::vector<glm::dquat> poses = qs;
  poses.push_back(glm::normalize(glm::inverse(link.zero_rotation) * rest_rel));
  glm::dquat center = kIdentity;
  glm::dvec3 vlo, vhi;
  for (int pass = 0; pass < 3; ++pass) {  // the middle moves the extremes: settle it
    rangeAbout(center, poses, vlo, vhi);
    center = glm::normalize(center * fromRotationVector(0.5 * (vlo + vhi)));
  }
  rangeAbout(center, poses, vlo, vhi);
  link.ball_center = positiveW(center);
  link.ball_lower = vlo - settings.limit_margin_rad;
  link.ball_upper = vhi + settings.limit_margin_rad;
}

// A hinge candidate becomes a hinge when one axis carries most of its observed rotation, with the
// observed range; otherwise it stays a ball and a note says why.
void hingeIfDominant(const ObservedRotations& observed, const glm::dvec3& lateral_link,
                     const BodyPlanSettings& settings, Link& link,
                     std::vector<std::string>& notes) {
  glm::dvec3 axis;
  double share = 0.0;
  principalAxis(observed.moment, axis, share);
  if (share < settings.hinge_dominance) {
    std::ostringstream note;
    note.precision(2);
    note << link.name << ": ball joint, not a hinge (main axis carries " << share
         << " of the observed rotation, below " << settings.hinge_dominance << ")";
    notes.push_back(note.str());
    return;
  }
  if (glm::dot(axis, lateral_link) < 0.0) axis = -axis;
  link.type = JointType::kHinge;
  link.hinge_axis = glm::normalize(axis);
  double alo = std::numbers::pi, ahi = -std::numbers::pi;
  for (const glm::dquat& q : observed.qs) {
    const double angle = hingeAngle(q, link.hinge_axis);
    alo = std::min(alo, angle);
    ahi = std::max(ahi, angle);
  }
  link.hinge_lower = std::max(-std::numbers::pi, alo - settings.limit_margin_rad);
  link.hinge_upper = std::min(std::numbers::pi, ahi + settings.limit_margin_rad);
}

// Joint type and limits of link li: without a clip by its segment (a shank or forearm hinges
// about the lateral axis); with one, fixed when it hardly moves, else a ball over the observed
// range or a hinge when one axis dominates.
void setJointType(const FirstPose& pose, const motion::Clip* observed_motion,
                  const glm::dvec3& lateral_world, const BodyPlanSettings& settings, Link& link,
                  std::vector<std::string>& notes) {
  const bool hinge_candidate = link.segment == motion::Segment::kShank ||
                               link.segment == motion::Segment::kForearm ||
                               nameHasAny(link.name, settings.hinge_names);
  const glm::dvec3 lateral_link = glm::normalize(
      glm::inverse(glm::quat_cast(glm::dmat3(pose.world[link.joint]))) * lateral_world);
  if (observed_motion == nullptr) {
    link.type = hinge_candidate ? JointType::kHinge : JointType::kBall;
    link.hinge_axis = lateral_link;
    return;
  }
  const ObservedRotations observed = observedRotations(link, *observed_motion);
  if (observed.max_from_first < settings.fixed_range_rad) {
    link.type = JointType::kFixed;
    link.zero_rotation = glm::normalize(link.zero_rotation * observed.qs[0]);
    return;
  }
  setBallRange(pose.skeleton, observed.qs, settings, link);
  link.type = JointType::kBall;
  if (hinge_candidate) hingeIfDominant(observed, lateral_link, settings, link, notes);
}

// The soles fitted to the clip's own feet, where it stands flat: per foot link in link order, its
// points in its own frame at the first pose, whether no End Site gives its toes a length, and the
// fit (not ok without a clip, or where the clip never stands the foot flat).
struct FootSoles {
  std::vector<std::vector<glm::dvec3>> points;  // (feet) in the foot link's frame
  std::vector<char> bare_tip;                   // (feet) no End Site gives the toes a length
  std::vector<SoleFit> fits;                    // (feet)
};

FootSoles fitFootSoles(const FirstPose& pose, const BodyPlan& plan,
                       const motion::Clip* observed_motion, std::span<const int> foot_joints) {
  const motion::Skeleton& skeleton = pose.skeleton;
  FootSoles soles;
  for (int li = 0; li < static_cast<int>(plan.links.size()); ++li) {
    const Link& link = plan.links[static_cast<size_t>(li)];
    if (!link.foot) continue;
    const glm::dmat4 to_link = glm::inverse(pose.world[link.joint]);
    std::vector<glm::dvec3> points = linkPoints(skeleton, plan, li, pose.world);
    for (glm::dvec3& p : points) p = transformPoint(to_link, p);
    bool bare = true;
    for (int j = link.joint; j < skeleton.jointCount(); ++j)
      if (plan.link_of_joint[j] == li && skeleton.end_sites[j])
        bare = bare && glm::length(*skeleton.end_sites[j]) < 1e-6;
    soles.points.push_back(std::move(points));
    soles.bare_tip.push_back(bare ? 1 : 0);
  }
  soles.fits = observed_motion != nullptr
                   ? fitSoles(skeleton, *observed_motion, foot_joints, soles.points)
                   : std::vector<SoleFit>(foot_joints.size());
  return soles;
}

// A link's shape that is not a foot, from the points it holds (`points_world`) in its own frame:
// a sphere for none, a padded box for the trunk, else a capsule (or a sphere when short) from
// the pivot to the points' centroid.
Shape limbShape(const Link& link, bool is_base, const glm::dmat4& to_link,
                const std::vector<glm::dvec3>& points_world, double radius) {
  Shape shape;
  shape.radius = radius;
  if (points_world.empty()) {
    shape.type = ShapeType::kSphere;
  } else if (points_world.size() >= 2 && (link.segment == motion::Segment::kTrunk || is_base)) {
    // A trunk link spans its points (hips, spine, shoulders, neck): a box around them padded
    // by the trunk radius. A sphere at their centroid would make a light, tiny-inertia torso
    // that explicit PD cannot hold stiffly against the legs.
    glm::dvec3 plo(0.0), phi(0.0);
    for (const glm::dvec3& p : points_world) {
      const glm::dvec3 q = transformPoint(to_link, p);
      plo = glm::min(plo, q);
      phi = glm::max(phi, q);
    }
    shape.type = ShapeType::kBox;
    shape.center = 0.5 * (plo + phi);
    shape.half_extents = 0.5 * (phi - plo) + glm::dvec3(radius);
  } else {
    glm::dvec3 end(0.0);
    for (const glm::dvec3& p : points_world) end += transformPoint(to_link, p);
    end /= double(points_world.size());
    const double length = glm::length(end);
    shape.center = 0.5 * end;
    if (length <= 2.0 * radius) {
      shape.type = ShapeType::kSphere;
    } else {
      shape.type = ShapeType::kCapsule;
      shape.half_length = 0.5 * length - radius;
      shape.rotation = rotationFromY(end / length);
    }
  }
  return shape;
}

// Shapes from the points each link holds, in its own frame at the first pose: feet get a sole
// box (fitted to the clip, else measured at rest), the others limbShape.
void assignShapes(const FirstPose& pose, const motion::Clip* observed_motion,
                  std::span<const int> foot_joints, const glm::dvec3& lateral_world,
                  const BodyPlanSettings& settings, BodyPlan& plan) {
  const motion::Skeleton& skeleton = pose.skeleton;
  glm::dquat upright;
  const std::vector<glm::dmat4> rest_up = uprightRest(skeleton, foot_joints, upright);
  const FootSoles soles = fitFootSoles(pose, plan, observed_motion, foot_joints);
  size_t foot_index = 0;
  for (int li = 0; li < static_cast<int>(plan.links.size()); ++li) {
    Link& link = plan.links[static_cast<size_t>(li)];
    const double radius = segmentRadius(settings, link.segment) * plan.size_m;
    Shape shape;
    if (link.foot && soles.fits[foot_index].ok) {
      shape = soleBox(soles.fits[foot_index], soles.points[foot_index],
                      soles.bare_tip[foot_index] != 0, radius);
    } else if (link.foot) {
      shape = restSoleBox(skeleton, plan, li, rest_up, lateral_world, radius);
    } else {
      shape = limbShape(link, li == 0, glm::inverse(pose.world[link.joint]),
                        linkPoints(skeleton, plan, li, pose.world), radius);
    }
    if (link.foot) ++foot_index;
    link.shape = shape;
    link.com = shape.center;
  }
}

}  // namespace

Result<BodyPlan> buildBodyPlan(const motion::Skeleton& skeleton,
                               const motion::Clip* observed_motion,
                               const BodyPlanSettings& settings) {
  if (Status s = settings.validate(); !s.ok())
    return Status::error("body plan settings: " + s.message());
  if (Status s = skeleton.validate(); !s.ok()) return Status::error("skeleton: " + s.message());
  const int n = skeleton.jointCount();
  if (n == 0) return Status::error("skeleton: no joints");
  for (int j = 1; j < n; ++j)
    if (skeleton.parents[j] == motion::kNoParent)
      return Status::error("skeleton: joint " + skeleton.names[j] +
                           " is a second root; a simulated character needs one root");
  if (observed_motion != nullptr) {
    if (Status s = observed_motion->validate(skeleton); !s.ok())
      return Status::error("observed motion: " + s.message());
  }
  const motion::Clip rest = motion::restClip(skeleton, 1, 1.0 / 30.0);
  const motion::Clip& clip = observed_motion != nullptr ? *observed_motion : rest;

  BodyPlan plan;
  plan.frozen_rotations.resize(n);
  for (int j = 0; j < n; ++j) plan.frozen_rotations[j] = glm::normalize(clip.rotation(0, j));

  std::vector<glm::dmat4> world(n);
  motion::worldTransforms(skeleton, clip, 0, world);
  std::vector<motion::Foot> feet;
  if (auto found = motion::findFeet(skeleton, clip); found.ok()) feet = found.value();
  const motion::MassDistribution masses =
      motion::massDistribution(skeleton, feet, settings.mass_table);
  std::vector<char> is_foot(n, 0);
  for (const motion::Foot& f : feet) is_foot[f.joint] = 1;
  std::vector<std::vector<int>> children(n);
  for (int j = 1; j < n; ++j) children[skeleton.parents[j]].push_back(j);
  FirstPose pose{skeleton, world, masses, is_foot, children};

  // The base: skip a massless root chain (a root at the origin above the pelvis).
  plan.base_chain.push_back(0);
  while (masses.segments[pose.base] == motion::Segment::kNone && children[pose.base].size() == 1) {
    pose.base = children[pose.base][0];
    plan.base_chain.push_back(pose.base);
  }
  plan.size_m = bodySize(skeleton, world, pose.base);
  if (!(plan.size_m > 1e-6)) return Status::error("skeleton: all joints at one point; no size");

  const std::vector<char> merged = mergedJoints(pose, observed_motion, settings, plan.size_m);
  if (const long count = std::count(merged.begin(), merged.end(), 1); count > 0)
    plan.notes.push_back(std::to_string(count) + " joints merged into their parents");
  makeLinks(pose, merged, plan);

  // Pivots, zero rotations, joint types and limits.
  const glm::dvec3 lateral_world = lateralDirection(feet, world);
  for (size_t li = 1; li < plan.links.size(); ++li) {
    setPivot(skeleton, plan, plan.links[li]);
    setJointType(pose, observed_motion, lateral_world, settings, plan.links[li], plan.notes);
  }

  std::vector<int> foot_joints;
  for (const Link& link : plan.links)
    if (link.foot) foot_joints.push_back(link.joint);
  if (observed_motion != nullptr && !restPoseStands(skeleton, foot_joints)) {
    plan.standing_rotations = meanPose(clip);
    plan.notes.push_back(
        "the rest pose does not stand (feet not below the pelvis); standing is "
        "the clip's mean pose");
  }
  assignShapes(pose, observed_motion, foot_joints, lateral_world, settings, plan);
  if (Status s = assignMasses(plan, skeleton, clip, masses, feet, settings); !s.ok()) return s;

  // Which links carry the body: their subtree holds a foot.
  for (int li = static_cast<int>(plan.links.size()) - 1; li >= 0; --li) {
    Link& link = plan.links[li];
    link.supports = link.supports || link.foot;
    if (link.parent >= 0 && link.supports) plan.links[link.parent].supports = true;
  }

  if (Status s = plan.validate(); !s.ok()) return Status::error("body plan: " + s.message());
  return plan;
}

LinkPose linkPoseFromSkeleton(const BodyPlan& plan,
                              [[maybe_unused]] const motion::Skeleton& skeleton,
                              std::span<const glm::dquat> rotations,
                              std::span<const glm::dvec3> translations) {
  LinkPose pose;
  glm::dmat4 base(1.0);
  for (int j : plan.base_chain) {
    base = base * glm::translate(glm::dmat4(1.0), translations[j]) *
           glm::mat4_cast(glm::normalize(rotations[j]));
  }
  pose.base_position = glm::dvec3(base[3]);
  pose.base_rotation = glm::normalize(glm::quat_cast(glm::dmat3(base)));
  pose.rotations.assign(plan.links.size(), kIdentity);
  pose.angles.assign(plan.links.size(), 0.0);
  for (size_t li = 1; li < plan.links.size(); ++li) {
    const Link& link = plan.links[li];
    if (link.type == JointType::kFixed) continue;
    glm::dquat rel = kIdentity;
    for (int a : link.chain) rel = rel * rotations[a];
    const glm::dquat q = positiveW(glm::normalize(glm::inverse(link.zero_rotation) * rel));
    if (link.type == JointType::kBall)
      pose.rotations[li] = q;
    else
      pose.angles[li] = hingeAngle(q, link.hinge_axis);
  }
  return pose;
}

}  // namespace sinew::physics

namespace sinew::physics {

LinkPose standingPose(const BodyPlan& plan, const motion::Skeleton& skeleton) {
  std::vector<int> feet;
  for (const Link& link : plan.links)
    if (link.foot) feet.push_back(link.joint);
  if (!plan.standing_rotations.empty())  // already upright: the clip's own attitudes
    return linkPoseFromSkeleton(plan, skeleton, plan.standing_rotations, skeleton.offsets);
  glm::dquat upright;
  uprightRest(skeleton, feet, upright);
  LinkPose pose = linkPoseFromSkeleton(plan, skeleton, skeleton.rest_rotations, skeleton.offsets);
  pose.base_position = upright * pose.base_position;
  pose.base_rotation = glm::normalize(upright * pose.base_rotation);
  return pose;
}

}  // namespace sinew::physics
