#include "sinew/physics/tracking.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>

#include "sinew/core/rotation.h"
#include "sinew/physics/controller.h"
#include "sinew/physics/world.h"
#include "sinew/spectral/signals.h"

namespace sinew::physics {
namespace {

constexpr glm::dvec3 kUp(0.0, 1.0, 0.0);

// Heading angle about +Y of a rotation applied to a horizontal forward vector.
double headingOf(const glm::dquat& rotation, const glm::dvec3& forward_local) {
  const glm::dvec3 f = rotation * forward_local;
  return std::atan2(f.x, f.z);
}

glm::dquat yaw(double angle) { return glm::angleAxis(angle, kUp); }

// The ball-joint coordinate that gives `link` the world rotation `child_world` under a parent at
// `parent_world`.
glm::dquat coordinateFor(const Link& link, const glm::dquat& parent_world,
                         const glm::dquat& child_world) {
  glm::dquat q = glm::normalize(glm::inverse(link.zero_rotation) * glm::inverse(parent_world) *
                                child_world);
  if (q.w < 0.0) q = -q;
  return q;
}

// World transforms of every link for a pose (links), by forward kinematics from the base.
void linkTransformsOf(const BodyPlan& plan, const LinkPose& pose, std::vector<glm::dmat4>& out) {
  const std::vector<glm::dquat> rotations = linkWorldRotations(plan, pose);
  out.resize(plan.links.size());
  std::vector<glm::dvec3> origins(plan.links.size(), pose.base_position);
  for (size_t li = 0; li < plan.links.size(); ++li) {
    const Link& link = plan.links[li];
    if (li > 0) {
      const size_t parent = static_cast<size_t>(link.parent);
      origins[li] = origins[parent] + rotations[parent] * link.pivot;
    }
    out[li] = glm::mat4_cast(rotations[li]);
    out[li][3] = glm::dvec4(origins[li], 1.0);
  }
}

// The samples (of the cyclic series h) at which h rises above and comes back within `eps` of
// `ground` either side of its maximum; {-1, -1} if it never rises above that.
std::pair<int, int> swingOf(const std::vector<double>& h, double ground, double eps) {
  const size_t n = h.size();
  const size_t top = static_cast<size_t>(std::max_element(h.begin(), h.end()) - h.begin());
  if (h[top] - ground <= eps) return {-1, -1};
  int down = -1, up = -1;
  for (size_t k = 1; k <= n && down < 0; ++k)
    if (h[(top + k) % n] <= ground + eps) down = static_cast<int>((top + k) % n);
  for (size_t k = 1; k <= n && up < 0; ++k)
    if (h[(top + n - k) % n] <= ground + eps) up = static_cast<int>((top + n - k + 1) % n);
  return {up, down};
}

// One damped least-squares step of moveFoot.
void moveFootStep(const BodyPlan& plan, LinkPose& pose, const std::vector<int>& leg, int foot,
                  const glm::dvec3& displacement) {
  std::vector<glm::dmat4> frames;
  linkTransformsOf(plan, pose, frames);
  const glm::dvec3 ankle(frames[static_cast<size_t>(foot)][3]);
  struct Column {
    size_t link;
    glm::dvec3 axis;  // world
    glm::dvec3 moves;  // the pivot's velocity per unit turn about axis
  };
  std::vector<Column> columns;
  for (int li : leg) {
    const Link& link = plan.links[static_cast<size_t>(li)];
    const glm::dmat4& frame = frames[static_cast<size_t>(li)];
    const glm::dvec3 arm = ankle - glm::dvec3(frame[3]);
    if (link.type == JointType::kBall) {
      for (int a = 0; a < 3; ++a) {
        glm::dvec3 axis(0.0);
        axis[a] = 1.0;
        columns.push_back({static_cast<size_t>(li), axis, glm::cross(axis, arm)});
      }
    } else if (link.type == JointType::kHinge) {
      const glm::dvec3 axis = glm::normalize(glm::dmat3(frame) * link.hinge_axis);
      columns.push_back({static_cast<size_t>(li), axis, glm::cross(axis, arm)});
    }
  }
  glm::dmat3 jjt(0.0);
  for (const Column& c : columns) jjt += glm::outerProduct(c.moves, c.moves);
  const double damping = 0.02 * plan.size_m;
  const glm::dvec3 y =
      glm::inverse(jjt + glm::dmat3(damping * damping)) * displacement;
  // Each leg link turns by its columns' share, its children with it; the foot stays as it was.
  const std::vector<glm::dquat> world = linkWorldRotations(plan, pose);
  glm::dquat turned(1.0, 0.0, 0.0, 0.0);  // what the links above have turned by, world
  glm::dquat parent_new = world[static_cast<size_t>(plan.links[static_cast<size_t>(leg.front())].parent)];
  for (int li : leg) {
    const size_t l = static_cast<size_t>(li);
    glm::dvec3 turn(0.0);
    double hinge = 0.0;
    for (const Column& c : columns)
      if (c.link == l) {
        turn += glm::dot(c.moves, y) * c.axis;
        hinge += glm::dot(c.moves, y);
      }
    turned = glm::normalize(turned * fromRotationVector(turn));
    const Link& link = plan.links[l];
    const glm::dquat link_new = glm::normalize(turned * world[l]);
    if (link.type == JointType::kBall) pose.rotations[l] = coordinateFor(link, parent_new, link_new);
    else if (link.type == JointType::kHinge) pose.angles[l] += hinge;
    parent_new = link_new;
  }
  const Link& foot_link = plan.links[static_cast<size_t>(foot)];
  if (foot_link.type == JointType::kBall)
    pose.rotations[static_cast<size_t>(foot)] =
        coordinateFor(foot_link, parent_new, world[static_cast<size_t>(foot)]);
}

// Moves `foot`'s pivot by `displacement` (world, metres) in `pose` by two damped least-squares
// steps over the links of `leg` (top to bottom, the foot's parent last); the foot keeps its
// attitude.
void moveFoot(const BodyPlan& plan, LinkPose& pose, const std::vector<int>& leg, int foot,
              const glm::dvec3& displacement) {
  const auto pivot = [&] {
    std::vector<glm::dmat4> frames;
    linkTransformsOf(plan, pose, frames);
    return glm::dvec3(frames[static_cast<size_t>(foot)][3]);
  };
  const glm::dvec3 goal = pivot() + displacement;
  moveFootStep(plan, pose, leg, foot, displacement);
  moveFootStep(plan, pose, leg, foot, goal - pivot());
}

}  // namespace

// Legs in pairs that balance together: each pair's feet meet at a link (the pelvis; a
// quadruped's chest for its forelegs) below which each has its own ball-jointed top link, the
// hip. Feet pair with the partner they share the deepest link with (the forelegs meet at the
// chest before either meets a hind leg at the pelvis); a foot left over, or a pair whose hips are
// not both ball joints, balances with no partner (no feedback).
std::vector<LegPair> findLegPairs(const BodyPlan& plan) {
  std::vector<int> feet;
  for (size_t li = 0; li < plan.links.size(); ++li)
    if (plan.links[li].foot) feet.push_back(static_cast<int>(li));
  auto depth = [&](int li) {
    int d = 0;
    for (; li > 0; li = plan.links[static_cast<size_t>(li)].parent) ++d;
    return d;
  };
  auto common = [&](int a, int b) {
    while (a > 0 && !isAncestorLink(plan, a, b)) a = plan.links[static_cast<size_t>(a)].parent;
    return a;
  };
  struct Candidate {
    int depth, a, b, base;
  };
  std::vector<Candidate> candidates;
  for (size_t a = 0; a < feet.size(); ++a)
    for (size_t b = a + 1; b < feet.size(); ++b) {
      const int base = common(feet[a], feet[b]);
      candidates.push_back({depth(base), static_cast<int>(a), static_cast<int>(b), base});
    }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.depth > y.depth; });
  std::vector<char> taken(feet.size(), 0);
  std::vector<LegPair> pairs;
  for (const Candidate& c : candidates) {
    if (taken[static_cast<size_t>(c.a)] || taken[static_cast<size_t>(c.b)]) continue;
    taken[static_cast<size_t>(c.a)] = taken[static_cast<size_t>(c.b)] = 1;
    LegPair pair{{c.a, c.b}, {0, 0}, c.base, glm::dvec3(0.0, 0.0, 1.0)};
    bool ball = true;
    for (int side = 0; side < 2; ++side) {
      int hip = feet[static_cast<size_t>(pair.feet[side])];
      while (plan.links[static_cast<size_t>(hip)].parent != c.base)
        hip = plan.links[static_cast<size_t>(hip)].parent;
      pair.hips[side] = hip;
      ball = ball && plan.links[static_cast<size_t>(hip)].type == JointType::kBall;
    }
    if (ball && pair.hips[0] != pair.hips[1]) pairs.push_back(pair);
  }
  // A foot no other foot pairs with (a hopper's one leg) balances alone about the link its leg
  // hangs from, if that leg has a ball-jointed hip of its own above the foot.
  for (size_t a = 0; a < feet.size(); ++a) {
    if (taken[a]) continue;
    auto carriesAnother = [&](int li) {
      for (int other : feet)
        if (other != feet[a] && isAncestorLink(plan, li, other)) return true;
      return false;
    };
    int hip = feet[a];
    while (plan.links[static_cast<size_t>(hip)].parent > 0 &&
           !carriesAnother(plan.links[static_cast<size_t>(hip)].parent))
      hip = plan.links[static_cast<size_t>(hip)].parent;
    const int base = plan.links[static_cast<size_t>(hip)].parent;
    if (hip != feet[a] && base >= 0 && plan.links[static_cast<size_t>(hip)].type == JointType::kBall)
      pairs.push_back(LegPair{{static_cast<int>(a), static_cast<int>(a)}, {hip, hip}, base,
                              glm::dvec3(0.0, 0.0, 1.0)});
  }
  return pairs;
}

constexpr double kSwingShare = 0.15;  // of a swing's height: where it starts and ends

std::vector<FootCycle> targetFootCycles(const BodyPlan& plan, const motion::Skeleton& skeleton,
                                        const spectral::TargetMotion& target,
                                        const std::vector<int>& feet) {
  constexpr int kSamples = 128;
  const double period = target.period();
  const size_t joints = static_cast<size_t>(skeleton.jointCount());
  std::vector<glm::dquat> rotations(joints);
  std::vector<glm::dvec3> translations(joints);
  std::vector<glm::dmat4> transforms;
  std::vector<std::vector<double>> lowest(feet.size(), std::vector<double>(kSamples));
  for (int k = 0; k < kSamples; ++k) {
    target.pose(period * k / kSamples, rotations, translations);
    linkTransformsOf(plan, linkPoseFromSkeleton(plan, skeleton, rotations, translations), transforms);
    for (size_t f = 0; f < feet.size(); ++f) {
      const size_t li = static_cast<size_t>(feet[f]);
      lowest[f][static_cast<size_t>(k)] = lowestPoint(plan.links[li].shape, transforms[li]);
    }
  }
  std::vector<FootCycle> cycles(feet.size());
  for (size_t f = 0; f < feet.size(); ++f) {
    // The ground: the lowest quarter's top, a standing foot (a rigid sole's toe dips below it
    // for a moment at toe-off: 4 cm on the bundled walk, so not the lowest). A swing starts and
    // ends 15% of its height above it (a third keeps only its middle, and the lift then misses
    // the early swing, where a Bandai walk's toe scuffs).
    std::vector<double> sorted = lowest[f];
    std::nth_element(sorted.begin(), sorted.begin() + kSamples / 4, sorted.end());
    const double ground = sorted[kSamples / 4];
    const double top = *std::max_element(lowest[f].begin(), lowest[f].end());
    if (top - ground < 0.01 * plan.size_m) continue;
    const auto [up, down] = swingOf(lowest[f], ground, kSwingShare * (top - ground));
    if (up < 0 || down < 0) continue;
    cycles[f] = {period * up / kSamples, period * down / kSamples};
  }
  return cycles;
}

namespace {

// The series of a target's channels, in its order, for FourierEvaluator.
std::vector<spectral::FourierEvaluator::Channel> seriesOf(const spectral::TargetMotion& target) {
  std::vector<spectral::FourierEvaluator::Channel> series;
  for (const spectral::ChannelModel& model : target.channels) {
    spectral::FourierEvaluator::Channel channel;
    channel.mean = model.mean;
    for (const spectral::Harmonic& h : model.terms) channel.terms.push_back(spectral::cartesian(h));
    series.push_back(std::move(channel));
  }
  return series;
}

}  // namespace

FourierTargets::FourierTargets(const spectral::TargetMotion& target)
    : omega0_(target.omega0),
      base_(target.base_rotations),
      base_translations_(target.base_translations),
      series_(target.omega0, seriesOf(target)),
      secondary_(target.secondary),
      vectors_(target.base_rotations.size()),
      rotates_(target.base_rotations.size(), 0) {
  for (const spectral::ChannelModel& model : target.channels) {
    const bool rotation = model.kind == spectral::SignalKind::kRotation;
    slots_.push_back({model.joint, model.axis, rotation, model.trend});
    if (rotation) rotates_[static_cast<size_t>(model.joint)] = 1;
    for (const spectral::Harmonic& h : model.terms) max_n_ = std::max(max_n_, h.n);
  }
  for (const spectral::SecondaryTerm& term : secondary_) rotates_[static_cast<size_t>(term.joint)] = 1;
}

void FourierTargets::evaluate(double t, std::span<glm::dquat> rotations,
                              std::span<glm::dvec3> translations) {
  series_.setTime(t);
  std::fill(vectors_.begin(), vectors_.end(), glm::dvec3(0.0));
  const bool translate = !translations.empty();
  if (translate) std::copy(base_translations_.begin(), base_translations_.end(), translations.begin());
  for (size_t c = 0; c < slots_.size(); ++c) {
    const Slot& slot = slots_[c];
    const size_t joint = static_cast<size_t>(slot.joint);
    if (slot.rotation) vectors_[joint][slot.axis] = series_.value(c);
    else if (translate) translations[joint][slot.axis] += series_.value(c) + slot.trend * t;
  }
  for (const spectral::SecondaryTerm& term : secondary_)
    vectors_[static_cast<size_t>(term.joint)][term.axis] +=
        term.amplitude * std::sin(term.omega * t + term.phase);
  for (size_t j = 0; j < base_.size(); ++j)
    rotations[j] = rotates_[j] != 0
                       ? glm::normalize(base_[j] * fromRotationVector(vectors_[j]))
                       : base_[j];
}

const char* balanceGainName(int i) {
  static const char* const kNames[kBalanceGainCount] = {
      "cd_sagittal", "cv_sagittal",   "cd_coronal",    "cv_coronal",
      "torso",       "ankle_sagittal", "ankle_coronal", "swing_lift",
      "heading",     "stance_sagittal", "stance_coronal", "stance_vertical",
      "stance_yaw",  "stance_yield"};
  return kNames[std::clamp(i, 0, kBalanceGainCount - 1)];
}

double& balanceGain(BalanceGains& g, int i) {
  double* const fields[kBalanceGainCount] = {&g.cd_sagittal, &g.cv_sagittal,   &g.cd_coronal,
                                             &g.cv_coronal,  &g.torso,         &g.ankle_sagittal,
                                             &g.ankle_coronal, &g.swing_lift,  &g.heading,
                                             &g.stance_sagittal, &g.stance_coronal,
                                             &g.stance_vertical, &g.stance_yaw,
                                             &g.stance_yield};
  return *fields[std::clamp(i, 0, kBalanceGainCount - 1)];
}

bool balanceGainIsShare(int i) { return i == 4 || i == 7 || i == 8 || i == 13; }

double balanceGainLimit(int i, double signed_limit) {
  switch (i) {
    case 4: case 8: return 1.0;  // torso, heading
    case 7: return 0.1;          // swing_lift, per rig size
    case 13: return 0.9;         // stance_yield: a planted leg's servos keep a tenth of their rate
    default: return signed_limit;
  }
}

std::string balanceGainRule(int i, double signed_limit) {
  char text[64];
  std::snprintf(text, sizeof(text), balanceGainIsShare(i) ? "from 0 to %g" : "within +-%g",
                balanceGainLimit(i, signed_limit));
  return text;
}

Status TrackingSettings::validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!(positive(servo_rate) && servo_rate <= 1.0)) return Status::error("servo_rate must be in (0, 1]");
  if (!positive(support_torque_scale)) return Status::error("support_torque_scale must be > 0");
  if (!positive(limb_torque_scale)) return Status::error("limb_torque_scale must be > 0");
  if (!positive(gravity_m_s2)) return Status::error("gravity_m_s2 must be > 0");
  if (!(std::isfinite(ramp_s) && ramp_s >= 0.0)) return Status::error("ramp_s must be >= 0");
  if (!validServoLead(servo_lead_s))
    return Status::error("servo_lead_s must be seconds in [0, 1]");
  BalanceGains b = balance;
  for (int i = 0; i < kBalanceGainCount; ++i) {
    const double g = balanceGain(b, i);
    const double limit = balanceGainLimit(i, std::numeric_limits<double>::max());
    if (!(std::isfinite(g) && std::abs(g) <= limit && (g >= 0.0 || !balanceGainIsShare(i))))
      return Status::error(std::string("balance.") + balanceGainName(i) + " must be " +
                           (balanceGainIsShare(i) ? balanceGainRule(i, limit) : "finite"));
  }
  return Status();
}

double servoLag(double step_hz, double rate) { return 1.0 / (step_hz * rate); }

bool validServoLead(double seconds) { return seconds >= 0.0 && seconds <= 1.0; }  // NaN fails

std::vector<double> jointTorqueLimits(const BodyPlan& plan, double support_scale,
                                      double limb_scale, double gravity_m_s2) {
  const size_t n = plan.links.size();
  std::vector<double> subtree(n, 0.0);
  for (size_t li = n; li-- > 0;) {
    subtree[li] += plan.links[li].mass_kg;
    if (plan.links[li].parent >= 0) subtree[static_cast<size_t>(plan.links[li].parent)] += subtree[li];
  }
  std::vector<double> limits(n, 0.0);
  for (size_t li = 1; li < n; ++li) {
    const Link& link = plan.links[li];
    limits[li] = link.supports ? support_scale * plan.total_mass_kg * gravity_m_s2 * plan.size_m
                               : limb_scale * subtree[li] * gravity_m_s2 * plan.size_m;
  }
  return limits;
}

PoseKinematics poseKinematics(const BodyPlan& plan, const LinkPose& pose) {
  const size_t n = plan.links.size();
  const std::vector<glm::dquat> rotations = linkWorldRotations(plan, pose);
  PoseKinematics out;
  out.pivots.assign(n, pose.base_position);
  for (size_t li = 0; li < n; ++li) {
    const Link& link = plan.links[li];
    if (li > 0) {
      const size_t parent = static_cast<size_t>(link.parent);
      out.pivots[li] = out.pivots[parent] + rotations[parent] * link.pivot;
    }
    out.com += (out.pivots[li] + rotations[li] * link.com) * link.mass_kg;
  }
  out.com /= plan.total_mass_kg;
  return out;
}

std::vector<glm::dquat> linkWorldRotations(const BodyPlan& plan, const LinkPose& pose) {
  std::vector<glm::dquat> world(plan.links.size(), pose.base_rotation);
  for (size_t li = 1; li < plan.links.size(); ++li) {
    const Link& link = plan.links[li];
    world[li] = glm::normalize(world[static_cast<size_t>(link.parent)] *
                               linkRelativeRotation(link, pose.rotations[li], pose.angles[li]));
  }
  return world;
}

MotionState targetState(const BodyPlan& plan, const motion::Skeleton& skeleton,
                        const spectral::TargetMotion& target, double t) {
  const size_t joints = static_cast<size_t>(skeleton.jointCount());
  std::vector<glm::dquat> rotations(joints);
  std::vector<glm::dvec3> translations(joints);
  auto poseAt = [&](double time) {
    target.pose(time, rotations, translations);
    return linkPoseFromSkeleton(plan, skeleton, rotations, translations);
  };
  constexpr double h = 5e-4;
  MotionState state;
  state.pose = poseAt(t);
  const LinkPose before = poseAt(t - h), after = poseAt(t + h);
  state.base_linear = (after.base_position - before.base_position) / (2.0 * h);
  state.base_angular =
      rotationVectorOf(after.base_rotation * glm::inverse(before.base_rotation)) / (2.0 * h);
  const std::vector<int> offsets = plan.dofOffsets();
  state.joint_velocities.assign(static_cast<size_t>(plan.dofCount()), 0.0);
  for (size_t li = 1; li < plan.links.size(); ++li) {
    const size_t o = static_cast<size_t>(offsets[li]);
    if (plan.links[li].type == JointType::kBall) {
      const glm::dvec3 w =
          rotationVectorOf(glm::inverse(before.rotations[li]) * after.rotations[li]) / (2.0 * h);
      for (int d = 0; d < 3; ++d) state.joint_velocities[o + static_cast<size_t>(d)] = w[d];
    } else if (plan.links[li].type == JointType::kHinge) {
      state.joint_velocities[o] = (after.angles[li] - before.angles[li]) / (2.0 * h);
    }
  }
  return state;
}

Result<std::unique_ptr<TrackingController>> TrackingController::create(
    World& world, const motion::Skeleton& skeleton, const spectral::TargetMotion& target,
    const LinkPose& standing, const TrackingSettings& settings) {
  if (Status s = settings.validate(); !s.ok()) return Status::error("tracking settings: " + s.message());
  if (Status s = target.validate(skeleton); !s.ok()) return Status::error("target motion: " + s.message());
  const BodyPlan& plan = world.plan();
  if (standing.rotations.size() != plan.links.size() || standing.angles.size() != plan.links.size())
    return Status::error("tracking: the standing pose needs one entry per link");
  const std::vector<double> limits = jointTorqueLimits(plan, settings.support_torque_scale,
                                                       settings.limb_torque_scale,
                                                       settings.gravity_m_s2);
  if (Status s = world.enableServos(limits, settings.servo_rate); !s.ok()) return s;

  std::unique_ptr<TrackingController> c(new TrackingController());
  c->plan_ = &world.plan();
  c->skeleton_ = &skeleton;
  c->settings_ = settings;
  c->fourier_ = std::make_unique<FourierTargets>(target);
  c->standing_ = standing;
  c->rotations_.resize(static_cast<size_t>(skeleton.jointCount()));
  c->translations_ = target.base_translations;
  for (size_t li = 0; li < plan.links.size(); ++li)
    if (plan.links[li].foot) c->feet_.push_back(static_cast<int>(li));

  c->pairs_ = findLegPairs(plan);
  c->last_down_.assign(c->pairs_.size(), -1);
  c->balance_ = !c->pairs_.empty();
  c->setForward(target);
  c->target_ = standing;
  c->motion_ = standing;
  c->cycles_ = targetFootCycles(plan, skeleton, target, c->feet_);
  // Each foot's leg: its ancestors below the first link that also carries another foot.
  for (int foot : c->feet_) {
    std::vector<int> leg;
    for (int li = plan.links[static_cast<size_t>(foot)].parent; li > 0;
         li = plan.links[static_cast<size_t>(li)].parent) {
      bool shared = false;
      for (int other : c->feet_) shared = shared || (other != foot && isAncestorLink(plan, li, other));
      if (shared) break;
      leg.insert(leg.begin(), li);
    }
    c->legs_.push_back(std::move(leg));
  }
  return c;
}

// Forward, in each pair's base frame: the way the motion travels over a period, where it travels
// (at least 5% of the rig's size), else the way its feet's soles point (their boxes' +Z), both
// in the motion's own first pose. Not the standing pose: a rig whose rest pose lies on its side
// (the MANN dog's) would hold a forward that turns vertical once the motion's attitude is on.
void TrackingController::setForward(const spectral::TargetMotion& target) {
  const BodyPlan& plan = *plan_;
  const double period = target.period();
  fourier_->evaluate(0.0, rotations_, translations_);
  const LinkPose first = linkPoseFromSkeleton(plan, *skeleton_, rotations_, translations_);
  fourier_->evaluate(period, rotations_, translations_);
  const LinkPose later = linkPoseFromSkeleton(plan, *skeleton_, rotations_, translations_);
  glm::dvec3 forward = poseKinematics(plan, later).com - poseKinematics(plan, first).com;
  forward.y = 0.0;
  const std::vector<glm::dquat> first_world = linkWorldRotations(plan, first);
  if (!(period > 0.0) || glm::length(forward) < 0.05 * plan.size_m) {
    forward = glm::dvec3(0.0);
    for (int foot : feet_) {
      const Link& link = plan.links[static_cast<size_t>(foot)];
      forward += first_world[static_cast<size_t>(foot)] * (link.shape.rotation * glm::dvec3(0, 0, 1));
    }
    forward.y = 0.0;
  }
  if (glm::length(forward) < 1e-9) forward = glm::dvec3(0.0, 0.0, 1.0);
  for (LegPair& pair : pairs_)
    pair.forward_local =
        glm::inverse(first_world[static_cast<size_t>(pair.base)]) * glm::normalize(forward);
}

void TrackingController::liftSwingFeet(double time) {
  const double period = 2.0 * std::numbers::pi / fourier_->omega0();
  for (size_t f = 0; f < feet_.size(); ++f) {
    const FootCycle& cycle = cycles_[f];
    if (cycle.liftoff_s < 0.0 || legs_[f].empty()) continue;
    const double swing = std::fmod(cycle.touchdown_s - cycle.liftoff_s + period, period);
    const double into = std::fmod(std::fmod(time - cycle.liftoff_s, period) + period, period);
    if (swing <= 0.0 || into >= swing) continue;
    const double bump = std::pow(std::sin(std::numbers::pi * into / swing), 2.0);
    moveFoot(*plan_, target_, legs_[f], feet_[f],
             glm::dvec3(0.0, settings_.balance.swing_lift * plan_->size_m * bump, 0.0));
  }
}

LinkPose TrackingController::motionAt(double time) {
  const BodyPlan& plan = *plan_;
  // The whole pose, the root's travel included: the reference centre of mass moves with the
  // motion, so its velocity is the motion's, not only what the joints' turning gives.
  fourier_->evaluate(time, rotations_, translations_);
  LinkPose pose = linkPoseFromSkeleton(plan, *skeleton_, rotations_, translations_);
  // Ramp from the standing pose into the motion.
  const double ramp =
      settings_.ramp_s > 0.0 ? std::clamp(time / settings_.ramp_s, 0.0, 1.0) : 1.0;
  if (ramp < 1.0) {
    const double w = ramp * ramp * (3.0 - 2.0 * ramp);  // smoothstep
    for (size_t li = 1; li < plan.links.size(); ++li) {
      pose.rotations[li] = glm::slerp(standing_.rotations[li], pose.rotations[li], w);
      pose.angles[li] = standing_.angles[li] + w * (pose.angles[li] - standing_.angles[li]);
    }
    pose.base_rotation = glm::slerp(standing_.base_rotation, pose.base_rotation, w);
  }
  return pose;
}

void TrackingController::update(World& world) {
  const double t = world.time();
  const double lead = settings_.servo_lead_s;
  // The servos' pose ahead by the lead (the planted legs that yield further), then the present
  // one (last: translations_ stay the present's), which the feedback and the tracking error are
  // measured against.
  if (lead > 0.0) target_ = motionAt(t + lead);
  leadYieldingLegs(world, t);
  motion_ = motionAt(t);
  if (lead <= 0.0) target_ = motion_;
  if (settings_.balance.swing_lift > 0.0) liftSwingFeet(t + lead);
  stance_ = -1;
  if (settings_.feedback && balance_) {
    // The target's own centre of mass and ankles (forward kinematics of the motion's pose).
    const glm::dvec3 previous = reference_com_;
    referenceKinematics();
    reference_velocity_ = have_reference_ ? (reference_com_ - previous) / world.dt()
                                          : world.linearMomentum() / world.totalMass();
    have_reference_ = true;
  }
  if (settings_.feedback && balance_) applyFeedback(world);
  setServoRates(world);
  world.setServoTargets(target_, servo_rates_);
}

// A leg whose foot is down yields (setServoRates): its servos close (1 - stance_yield) of what
// the others do each step, so they trail their target by servoLag at that slower rate, the
// lead / (1 - stance_yield). Those legs get the motion's pose that much ahead.
void TrackingController::leadYieldingLegs(const World& world, double t) {
  if (!settings_.lead_yielding_legs || settings_.servo_lead_s <= 0.0) return;
  const std::vector<int> yielding = yieldingLinks(world);
  if (yielding.empty()) return;
  const LinkPose ahead =
      motionAt(t + settings_.servo_lead_s / (1.0 - settings_.balance.stance_yield));
  for (int li : yielding) {
    target_.rotations[static_cast<size_t>(li)] = ahead.rotations[static_cast<size_t>(li)];
    target_.angles[static_cast<size_t>(li)] = ahead.angles[static_cast<size_t>(li)];
  }
}

std::vector<int> TrackingController::yieldingLinks(const World& world) const {
  std::vector<int> links;
  if (!(settings_.feedback && balance_) || settings_.balance.stance_yield <= 0.0) return links;
  const std::vector<std::uint8_t>& contacts = world.linkContacts();
  for (size_t f = 0; f < feet_.size(); ++f) {
    if (contacts[static_cast<size_t>(feet_[f])] == 0) continue;
    links.push_back(feet_[f]);
    links.insert(links.end(), legs_[f].begin(), legs_[f].end());
  }
  return links;
}

void TrackingController::setServoRates(const World& world) {
  servo_rates_.clear();
  if (!(settings_.feedback && balance_) || settings_.balance.stance_yield <= 0.0) return;
  servo_rates_.assign(plan_->links.size(), settings_.servo_rate);
  for (int li : yieldingLinks(world))
    servo_rates_[static_cast<size_t>(li)] =
        settings_.servo_rate * (1.0 - settings_.balance.stance_yield);
}

void TrackingController::referenceKinematics() {
  const PoseKinematics kinematics = poseKinematics(*plan_, motion_);
  reference_com_ = kinematics.com;
  reference_ankles_.resize(feet_.size());
  for (size_t f = 0; f < feet_.size(); ++f)
    reference_ankles_[f] = kinematics.pivots[static_cast<size_t>(feet_[f])];
}

void TrackingController::applyFeedback(const World& world) {
  std::vector<glm::dmat4> transforms(plan_->links.size());
  world.linkTransforms(transforms);
  const std::vector<glm::dquat> target_world = linkWorldRotations(*plan_, motion_);
  for (size_t p = 0; p < pairs_.size(); ++p) {
    const int stance = balancePair(world, p, transforms, target_world);
    if (p == 0) stance_ = stance;
  }
}

int TrackingController::balancePair(const World& world, size_t p,
                                    const std::vector<glm::dmat4>& transforms,
                                    const std::vector<glm::dquat>& target_world) {
  const BodyPlan& plan = *plan_;
  const LegPair& pair = pairs_[p];
  const std::vector<std::uint8_t>& contacts = world.linkContacts();
  const std::vector<double>& forces = world.linkNormalForces();
  const size_t foot0 = static_cast<size_t>(feet_[static_cast<size_t>(pair.feet[0])]);
  const size_t foot1 = static_cast<size_t>(feet_[static_cast<size_t>(pair.feet[1])]);
  const bool down0 = contacts[foot0] > 0;
  const bool down1 = contacts[foot1] > 0;
  // One foot down: it is the stance foot, the other swings. Both down: the one carrying more
  // holds the torso and nothing swings. Both up on a body with one pair (a run's flight, a walk's
  // stance foot leaving before the swing foot lands, a body a push has lifted): the foot last
  // down stands in as the stance foot, and the swing foot goes on being placed to catch the body
  // until it lands (a placement dropped in the air swung back to the target's within the 75 ms a
  // pushed walk spent off the ground, and the foot landed where it could not catch it); nothing
  // holds the base. With two pairs or more, a pair in the air waits for a foot to land (placed
  // there, the unevolved trot fell sooner at every gain tried). A leg alone is placed whenever it
  // is in the air (below).
  const bool flight = !down0 && !down1;
  const bool pair_in_air = flight && !pair.alone();
  if (pair_in_air && (pairs_.size() > 1 || last_down_[p] < 0)) return -1;
  int side_down = pair_in_air ? last_down_[p] : (down0 && !down1 ? 0 : (down1 && !down0 ? 1 : -1));
  const bool swinging = side_down >= 0 && !flight;
  if (side_down < 0) side_down = forces[foot0] >= forces[foot1] ? 0 : 1;
  if (!flight) last_down_[p] = side_down;
  const size_t stance = static_cast<size_t>(pair.feet[static_cast<size_t>(side_down)]);

  auto rotationOf = [&](int li) {
    return glm::normalize(glm::quat_cast(glm::dmat3(transforms[static_cast<size_t>(li)])));
  };
  const BalanceGains& gains = settings_.balance;
  const glm::dquat base_now = rotationOf(pair.base);
  // The desired base (pelvis, or a quadruped's chest): the target's attitude at the present
  // heading turned back towards the target's by the share `heading`.
  const glm::dquat base_target = target_world[static_cast<size_t>(pair.base)];
  const double heading_now = headingOf(base_now, pair.forward_local);
  const double heading_target = headingOf(base_target, pair.forward_local);
  const double heading_error =
      std::remainder(heading_target - heading_now, 2.0 * std::numbers::pi);
  const double heading_held = heading_now + gains.heading * heading_error;
  const glm::dquat base_wanted =
      glm::normalize(yaw(heading_held) * glm::inverse(yaw(heading_target)) * base_target);

  // The centre of mass's offset from the stance foot and its velocity, and the target motion's
  // own at this moment, in each one's heading frame: x to the side (left), z forward.
  const glm::dvec3 com = world.centreOfMass();
  const glm::dvec3 velocity = world.linearMomentum() / world.totalMass();
  const glm::dvec3 ankle(transforms[static_cast<size_t>(feet_[stance])][3]);
  const glm::dvec3 d = glm::inverse(yaw(heading_now)) * (com - ankle);
  const glm::dvec3 v = glm::inverse(yaw(heading_now)) * velocity;
  const glm::dvec3 d_ref =
      glm::inverse(yaw(heading_target)) * (reference_com_ - reference_ankles_[stance]);
  const glm::dvec3 v_ref = glm::inverse(yaw(heading_target)) * reference_velocity_;
  const Placement placement{base_now, base_wanted, d - d_ref, v - v_ref,
                            yaw(heading_now) * glm::dvec3(0.0, 0.0, 1.0)};
  if (flight) {  // Raibert's hopper: the leg in the air lands where it catches the body
    placeSwingFoot(pair.hips[static_cast<size_t>(pair.alone() ? 0 : 1 - side_down)], placement);
    return -1;
  }

  // Stance hip: hold the base.
  const size_t stance_hip = static_cast<size_t>(pair.hips[static_cast<size_t>(side_down)]);
  const glm::dquat held =
      coordinateFor(plan.links[stance_hip], base_wanted, rotationOf(static_cast<int>(stance_hip)));
  target_.rotations[stance_hip] =
      glm::normalize(glm::slerp(target_.rotations[stance_hip], held, gains.torso));

  turnStanceAnkle(feet_[stance], v - v_ref, placement.forward, glm::cross(kUp, placement.forward));
  driveStanceLegs(pair, contacts, v - v_ref, heading_target, heading_error);
  if (swinging && !pair.alone())
    placeSwingFoot(pair.hips[static_cast<size_t>(1 - side_down)], placement);
  return static_cast<int>(stance);
}

// Swing hip: its target relative to the desired base, turned so the foot lands where it catches
// the centre of mass: by how far the offset and velocity differ from the target's (the target
// already swings the leg for its nominal gait). Turning the leg about -side by a positive angle
// moves the foot forward; about +forward, to the left.
void TrackingController::placeSwingFoot(int hip, const Placement& p) {
  const BalanceGains& gains = settings_.balance;
  const glm::dvec3 side = glm::cross(kUp, p.forward);  // the character's left
  const double sagittal = gains.cd_sagittal * p.offset_error.z + gains.cv_sagittal * p.velocity_error.z;
  const double coronal = gains.cd_coronal * p.offset_error.x + gains.cv_coronal * p.velocity_error.x;
  const glm::dquat correction = glm::normalize(glm::angleAxis(sagittal, -side) *
                                               glm::angleAxis(coronal, p.forward));
  const size_t swing_hip = static_cast<size_t>(hip);
  const Link& swing_link = plan_->links[swing_hip];
  const glm::dquat thigh_wanted = correction * p.base_wanted *
                                  linkRelativeRotation(swing_link, target_.rotations[swing_hip], 0.0);
  target_.rotations[swing_hip] = coordinateFor(swing_link, p.base_now, thigh_wanted);
}

// The ankle strategy of Lee, Kim and Lee 2010: the planted foot's target turned against the
// centre of mass's velocity error (heading frame: x left, z forward), so the foot tilts the body
// back towards the target's velocity. The ground holds the foot, so the servo turns the shank
// the other way: a foot turned by +a about `side` tips the body back, one turned by -a about
// `forward` tips it to the right; positive gains oppose the error in both planes.
void TrackingController::turnStanceAnkle(int foot_link, const glm::dvec3& velocity_error,
                                         const glm::dvec3& forward, const glm::dvec3& side) {
  const BalanceGains& gains = settings_.balance;
  if (gains.ankle_sagittal == 0.0 && gains.ankle_coronal == 0.0) return;
  const size_t foot = static_cast<size_t>(foot_link);
  const Link& link = plan_->links[foot];
  if (link.type != JointType::kBall) return;
  const std::vector<glm::dquat> wanted = linkWorldRotations(*plan_, target_);
  const glm::dquat turn =
      glm::normalize(glm::angleAxis(gains.ankle_sagittal * velocity_error.z, side) *
                     glm::angleAxis(-gains.ankle_coronal * velocity_error.x, forward));
  target_.rotations[foot] = coordinateFor(link, wanted[static_cast<size_t>(link.parent)],
                                          glm::normalize(turn * wanted[foot]));
}

// The stance legs (Coros et al. 2010's virtual force, kinematically): every foot of the pair
// that is down has its target moved, relative to the base, by the stance gains x the centre of
// mass's velocity error (heading frame: x left, y up, z forward), plus a turn about the vertical
// through the target's centre of mass by -stance_yaw x the heading error, at most a tenth of the
// rig's size in all. The ground holds the foot, so the servos move the body the other way: a foot
// moved forward holds a body that runs ahead of the target back, one moved up lowers a body that
// rises faster than the target's, front feet moved right and hind feet left turn it left.
void TrackingController::driveStanceLegs(const LegPair& pair,
                                         const std::vector<std::uint8_t>& contacts,
                                         const glm::dvec3& velocity_error, double heading_target,
                                         double heading_error) {
  const BalanceGains& gains = settings_.balance;
  if (gains.stance_sagittal == 0.0 && gains.stance_coronal == 0.0 &&
      gains.stance_vertical == 0.0 && gains.stance_yaw == 0.0)
    return;
  const glm::dvec3 pushed(gains.stance_coronal * velocity_error.x,
                          gains.stance_vertical * velocity_error.y,
                          gains.stance_sagittal * velocity_error.z);
  const double turn = -gains.stance_yaw * heading_error;
  const double most = 0.1 * plan_->size_m;
  // The target pose faces the target's heading: the moves are made in its frame, then turned.
  const glm::dquat frame = yaw(heading_target);
  for (int k = 0; k < (pair.alone() ? 1 : 2); ++k) {
    const size_t f = static_cast<size_t>(pair.feet[k]);
    if (contacts[static_cast<size_t>(feet_[f])] == 0 || legs_[f].empty()) continue;
    const glm::dvec3 arm = glm::inverse(frame) * (reference_ankles_[f] - reference_com_);
    glm::dvec3 moved = pushed + turn * glm::dvec3(arm.z, 0.0, -arm.x);  // turn x (up x arm)
    if (glm::length(moved) > most) moved *= most / glm::length(moved);
    moveFoot(*plan_, target_, legs_[f], feet_[f], frame * moved);
  }
}

}  // namespace sinew::physics
