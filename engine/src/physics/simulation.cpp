#include "sinew/physics/simulation.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <sstream>

#include "sinew/core/rotation.h"
#include "sinew/physics/controller.h"
#include "sinew/physics/divergence.h"

namespace sinew::physics {
namespace {

// Links that may touch the ground without a fall: the feet and the links below them, and for a
// creature on four feet or more also the segment above each foot (a dog's pastern and carpus: the
// MANN dog's ForeArm ends a paw's length above the ground, and its capsule meets the ground when
// the wrist folds at touchdown).
std::vector<char> groundLinks(const BodyPlan& plan) {
  std::vector<char> allowed(plan.links.size(), 0);
  int feet = 0;
  for (size_t li = 0; li < plan.links.size(); ++li) {
    const int parent = plan.links[li].parent;
    allowed[li] = plan.links[li].foot || (parent >= 0 && allowed[static_cast<size_t>(parent)]);
    feet += plan.links[li].foot ? 1 : 0;
  }
  if (feet >= 4)
    for (const Link& link : plan.links)
      if (link.foot && link.parent > 0) allowed[static_cast<size_t>(link.parent)] = 1;
  return allowed;
}

glm::dmat4 localTransform(const glm::dvec3& translation, const glm::dquat& rotation) {
  glm::dmat4 m = glm::mat4_cast(glm::normalize(rotation));
  m[3] = glm::dvec4(translation, 1.0);
  return m;
}

}  // namespace

Status SimulationSettings::validate() const {
  if (!(std::isfinite(seconds) && seconds > 0.0 && seconds <= 3600.0))
    return Status::error("seconds must be in (0, 3600]");
  if (Status s = world.validate(); !s.ok()) return Status::error("world: " + s.message());
  if (Status s = tracking.validate(); !s.ok()) return Status::error("tracking: " + s.message());
  if (!(std::isfinite(record_fps) && record_fps > 0.0 && record_fps <= world.step_hz))
    return Status::error("record_fps must be in (0, step_hz]");
  if (!(std::isfinite(fall_height_ratio) && fall_height_ratio > 0.0 && fall_height_ratio < 1.0))
    return Status::error("fall_height_ratio must be in (0, 1)");
  if (trace && seconds > kMaxTracedSeconds)
    return Status::error("trace: a traced run records every step, so at most " +
                         std::to_string(static_cast<int>(kMaxTracedSeconds)) + " s");
  for (size_t i = 0; i < pushes.size(); ++i) {
    const Push& p = pushes[i];
    if (!(std::isfinite(p.time_s) && p.time_s >= 0.0) ||
        !(glm::length(p.impulse_ns) <= kMaxPushImpulse_ns))
      return Status::error("pushes[" + std::to_string(i) +
                           "]: time must be >= 0 s, impulse at most 10000 N s");
  }
  return Status();
}

void skeletonPoseFromWorld(const World& world, const motion::Skeleton& skeleton,
                           std::span<const glm::dquat> reference_rotations,
                           std::span<const glm::dvec3> reference_translations,
                           std::span<glm::dquat> rotations, std::span<glm::dvec3> translations) {
  const BodyPlan& plan = world.plan();
  const size_t joints = static_cast<size_t>(skeleton.jointCount());
  std::copy(reference_rotations.begin(), reference_rotations.begin() + joints, rotations.begin());
  std::copy(reference_translations.begin(), reference_translations.begin() + joints,
            translations.begin());
  const LinkPose pose = world.jointPositions();
  for (size_t li = 1; li < plan.links.size(); ++li) {
    const Link& link = plan.links[li];
    // The chain's product is the link's relative rotation: solve for its last joint.
    glm::dquat above(1.0, 0.0, 0.0, 0.0);
    for (size_t k = 0; k + 1 < link.chain.size(); ++k)
      above = above * rotations[static_cast<size_t>(link.chain[k])];
    const glm::dquat relative = linkRelativeRotation(link, pose.rotations[li], pose.angles[li]);
    rotations[static_cast<size_t>(link.joint)] = glm::normalize(glm::inverse(above) * relative);
  }
  // The base: its world transform is the product of the base chain's local transforms; the
  // joints below the root keep the reference's, the root takes the rest.
  if (!plan.base_chain.empty()) {
    glm::dmat4 below(1.0);
    for (size_t k = 1; k < plan.base_chain.size(); ++k) {
      const size_t j = static_cast<size_t>(plan.base_chain[k]);
      below = below * localTransform(translations[j], rotations[j]);
    }
    const glm::dmat4 base = localTransform(pose.base_position, pose.base_rotation);
    const glm::dmat4 root = base * glm::inverse(below);
    const size_t r = static_cast<size_t>(plan.base_chain[0]);
    translations[r] = glm::dvec3(root[3]);
    rotations[r] = glm::normalize(glm::quat_cast(glm::dmat3(root)));
  }
}

namespace {

// The link each push lands on: the named joint's own body, else the base.
Result<std::vector<int>> pushLinks(const BodyPlan& plan, const motion::Skeleton& skeleton,
                                   const std::vector<Push>& pushes) {
  std::vector<int> links;
  for (const Push& p : pushes) {
    int link = 0;
    if (!p.link.empty()) {
      const int joint = skeleton.findJoint(p.link);
      if (joint < 0 || plan.links[static_cast<size_t>(plan.link_of_joint[static_cast<size_t>(joint)])].joint != joint)
        return Status::error("push: no link named \"" + p.link + "\" (a joint of the skeleton with a body of its own)");
      link = plan.link_of_joint[static_cast<size_t>(joint)];
    }
    links.push_back(link);
  }
  return links;
}

// The world, started in the motion's first pose and velocities (or standing), and the
// controller that tracks `target` in it.
struct Character {
  std::unique_ptr<World> world;
  std::unique_ptr<TrackingController> controller;
};

Result<Character> makeCharacter(const BodyPlan& plan, const motion::Skeleton& skeleton,
                                const spectral::TargetMotion& target,
                                const SimulationSettings& settings, const MotionState& state,
                                const LinkPose& standing) {
  Result<std::unique_ptr<World>> created =
      World::create(plan, settings.start_moving ? state.pose : standing, settings.world);
  if (!created.ok()) return created.status();
  Character character;
  character.world = std::move(created).value();
  TrackingSettings tracking = settings.tracking;
  if (settings.start_moving) {
    if (Status s = character.world->setVelocities(state.base_linear, state.base_angular,
                                                  state.joint_velocities);
        !s.ok())
      return s;
    tracking.ramp_s = 0.0;
  }
  Result<std::unique_ptr<TrackingController>> made =
      TrackingController::create(*character.world, skeleton, target, standing, tracking);
  if (!made.ok()) return made.status();
  character.controller = std::move(made).value();
  return character;
}

// The run as a clip on the skeleton: the world's pose, the joints merged into links at the
// target's pose of the same time.
struct Recorder {
  const motion::Skeleton& skeleton;
  const spectral::TargetMotion& target;
  std::vector<glm::dquat> reference_rotations, rotations;        // (joints)
  std::vector<glm::dvec3> reference_translations, translations;  // (joints) metres

  Recorder(const motion::Skeleton& s, const spectral::TargetMotion& t)
      : skeleton(s),
        target(t),
        reference_rotations(static_cast<size_t>(s.jointCount())),
        rotations(static_cast<size_t>(s.jointCount())),
        reference_translations(static_cast<size_t>(s.jointCount())),
        translations(static_cast<size_t>(s.jointCount())) {}

  void record(const World& world, SimulationReport& report) {
    target.pose(world.time(), reference_rotations, reference_translations);
    skeletonPoseFromWorld(world, skeleton, reference_rotations, reference_translations, rotations,
                          translations);
    report.motion.rotations.insert(report.motion.rotations.end(), rotations.begin(),
                                   rotations.end());
    report.motion.translations.insert(report.motion.translations.end(), translations.begin(),
                                      translations.end());
    ++report.motion.frame_count;
    report.com.push_back(world.centreOfMass());
  }
};

// The pushes due by the coming step, delivered once each; `pushed_ns` sums their magnitudes.
Status deliverPushes(World& world, const std::vector<Push>& pushes,
                     const std::vector<int>& push_links, std::vector<char>& pushed,
                     double& pushed_ns) {
  for (size_t p = 0; p < pushes.size(); ++p)
    if (!pushed[p] && world.time() + 0.5 * world.dt() >= pushes[p].time_s) {
      pushed[p] = 1;
      if (Status s = world.push(push_links[p], pushes[p].impulse_ns); !s.ok()) return s;
      pushed_ns += glm::length(pushes[p].impulse_ns);
    }
  return {};
}

bool turns(const Link& link) {
  return link.type == JointType::kBall || link.type == JointType::kHinge;
}

// Each joint's angle to its target in `wanted` this step (`angles`, links; 0 for the base and
// fixed joints), its square added to `link_sums` (links).
void addTrackingError(const BodyPlan& plan, const LinkPose& now, const LinkPose& wanted,
                      std::vector<double>& angles, std::vector<double>& link_sums) {
  angles.assign(plan.links.size(), 0.0);
  for (size_t li = 1; li < plan.links.size(); ++li) {
    const JointType type = plan.links[li].type;
    if (type == JointType::kBall)
      angles[li] = glm::length(
          shortRotationVector(glm::normalize(glm::inverse(now.rotations[li]) * wanted.rotations[li])));
    else if (type == JointType::kHinge)
      angles[li] = std::abs(std::remainder(now.angles[li] - wanted.angles[li], 2.0 * std::numbers::pi));
    link_sums[li] += angles[li] * angles[li];
  }
}

// track_err_rad_rms (over the joints that turn) and track_err_by_link_rad from the sums over
// `steps` steps.
void finishTrackingError(const BodyPlan& plan, const std::vector<double>& link_sums,
                         long long steps, SimulationReport& report) {
  report.track_err_by_link_rad.assign(link_sums.size(), 0.0);
  const auto turning = std::count_if(plan.links.begin() + 1, plan.links.end(), turns);
  if (steps <= 0 || turning <= 0) return;
  double sum = 0.0;
  for (size_t li = 0; li < link_sums.size(); ++li) {
    sum += link_sums[li];
    report.track_err_by_link_rad[li] = std::sqrt(link_sums[li] / static_cast<double>(steps));
  }
  report.track_err_rad_rms = std::sqrt(sum / static_cast<double>(steps * turning));
}

// The step's mechanical work and torque^2 / mass.
void addEffort(const World& world, std::span<const double> torques,
               std::span<const double> velocities, SimulationReport& report) {
  for (size_t d = 0; d < torques.size(); ++d) {
    report.energy_j += std::abs(torques[d] * velocities[d]) * world.dt();
    report.torque_sq_per_kg += torques[d] * torques[d] * world.dt() / report.mass_kg;
  }
}

// Per link (links), whether its servo torque (`torques`, the last step's) is at its limit (within
// 0.1%) on any axis.
void torqueLimitFlags(const World& world, std::span<const double> torques,
                      const std::vector<int>& offsets, std::vector<std::uint8_t>& at_limit) {
  const BodyPlan& plan = world.plan();
  const std::vector<double>& limits = world.servoTorqueLimits();
  at_limit.assign(plan.links.size(), 0);
  for (size_t li = 1; li < limits.size(); ++li) {
    const int dofs = dofCount(plan.links[li].type);
    for (int d = 0; d < dofs; ++d)
      if (limits[li] > 0.0 &&
          std::abs(torques[static_cast<size_t>(offsets[li] + d)]) >= 0.999 * limits[li])
        at_limit[li] = 1;
  }
}

// The step as a TraceStep (SimulationSettings::trace); `previous_target` (the last step's
// target_com) is updated.
TraceStep traceStep(const World& world, const TrackingController& controller,
                    const std::vector<glm::dmat4>& transforms, std::span<const double> torques,
                    const std::vector<int>& offsets, const std::vector<std::uint8_t>& at_limit,
                    const std::vector<double>& errors, glm::dvec3& previous_target) {
  const BodyPlan& plan = world.plan();
  TraceStep row;
  row.time_s = world.time();
  row.com = world.centreOfMass();
  row.com_velocity = world.linearMomentum() / world.totalMass();
  const PoseKinematics target = poseKinematics(plan, controller.motionTarget());
  row.target_com = target.com;
  row.target_velocity = (row.target_com - previous_target) / world.dt();
  previous_target = row.target_com;
  row.stance_foot = controller.stanceFoot();
  for (int f : controller.feet()) {
    const size_t li = static_cast<size_t>(f);
    row.foot_contacts.push_back(world.linkContacts()[li]);
    row.foot_positions.push_back(glm::dvec3(transforms[li][3]));
    row.target_foot_positions.push_back(target.pivots[li]);
    row.foot_forces_n.push_back(world.linkNormalForces()[li]);
  }
  row.torques_nm.assign(plan.links.size(), 0.0);
  for (size_t li = 1; li < plan.links.size(); ++li)
    for (int d = 0; d < dofCount(plan.links[li].type); ++d)
      row.torques_nm[li] = std::max(row.torques_nm[li],
                                    std::abs(torques[static_cast<size_t>(offsets[li] + d)]));
  row.at_limit = at_limit;
  row.errors_rad = errors;
  return row;
}

// How many steps a foot must be off the ground before its touchdown is a footfall: a quarter of
// its swing in the target (a tenth of the period for a foot the target never lifts). A planted
// sole chatters (a corner lifts for a step or a few: 40 of the bundled walk's 53 touchdowns
// unevolved came after gaps of 20 ms or less); a real step is off the ground for most of a swing.
std::vector<int> footfallGaps(const World& world, const TrackingController& controller,
                              double period_s) {
  std::vector<int> gaps;
  for (const FootCycle& cycle : controller.footCycles()) {
    const double swing = cycle.liftoff_s >= 0.0
                             ? std::fmod(cycle.touchdown_s - cycle.liftoff_s + period_s, period_s)
                             : 0.4 * period_s;
    gaps.push_back(std::max(1, static_cast<int>(std::lround(0.25 * swing / world.dt()))));
  }
  return gaps;
}

// Footfalls: a foot that touches the ground after at least `gaps` steps off it (one in the air at
// the first step counts as swinging, one down then is not stepping); the steps each foot is down.
// `off` (feet): steps off the ground so far, -1 before the first step.
void countFootfalls(const World& world, const std::vector<int>& feet,
                    const std::vector<std::uint8_t>& contacts,
                    const std::vector<glm::dmat4>& transforms, const std::vector<int>& gaps,
                    std::vector<int>& off, SimulationReport& report) {
  for (size_t f = 0; f < feet.size(); ++f) {
    const bool down = contacts[static_cast<size_t>(feet[f])] > 0;
    if (off[f] < 0) off[f] = down ? 0 : gaps[f];
    if (!down) {
      ++off[f];
      continue;
    }
    report.contact_share[f] += 1.0;
    if (off[f] >= gaps[f])
      report.footfalls.push_back({static_cast<int>(f), world.time(),
                                  glm::dvec3(transforms[static_cast<size_t>(feet[f])][3])});
    off[f] = 0;
  }
}

// The horizontal direction the target faces: the first leg pair's base's forward in the
// target's pose, else the base's +Z.
glm::dvec3 targetForward(const BodyPlan& plan, const TrackingController& controller) {
  const std::vector<glm::dquat> rotations = linkWorldRotations(plan, controller.motionTarget());
  const std::vector<LegPair>& pairs = controller.legPairs();
  const glm::dvec3 f = pairs.empty() ? rotations[0] * glm::dvec3(0.0, 0.0, 1.0)
                                     : rotations[static_cast<size_t>(pairs[0].base)] *
                                           pairs[0].forward_local;
  const glm::dvec3 flat(f.x, 0.0, f.z);
  return glm::length(flat) > 1e-9 ? glm::normalize(flat) : glm::dvec3(0.0, 0.0, 1.0);
}

// Which way a falling body went: the centre of mass against the middle of its feet, in
// the frame of the heading the target faces (targetForward): "backwards", "forwards",
// "to the left" or "to the right" by the larger component, or "folded over its feet" within 15%
// of the rig's size (the legs gave way under it).
std::string fallDirection(const BodyPlan& plan, const World& world,
                          const TrackingController& controller,
                          const std::vector<glm::dmat4>& transforms) {
  const std::vector<int>& feet = controller.feet();
  if (feet.empty()) return "";
  const glm::dvec3 forward = targetForward(plan, controller);
  glm::dvec3 middle(0.0);
  for (int f : feet) middle += glm::dvec3(transforms[static_cast<size_t>(f)][3]);
  middle /= static_cast<double>(feet.size());
  glm::dvec3 offset = world.centreOfMass() - middle;
  offset.y = 0.0;
  if (glm::length(offset) < 0.15 * plan.size_m) return "folded over its feet";
  const glm::dvec3 left = glm::cross(glm::dvec3(0.0, 1.0, 0.0), forward);
  const double ahead = glm::dot(offset, forward), aside = glm::dot(offset, left);
  if (std::abs(ahead) >= std::abs(aside)) return ahead > 0.0 ? "forwards" : "backwards";
  return aside > 0.0 ? "to the left" : "to the right";
}

// What a fall check needs of the present step besides the world.
struct FallContext {
  const std::vector<std::uint8_t>& contacts;  // (links) the world's
  const std::vector<glm::dmat4>& transforms;  // (links) the world's
  const TrackingController& controller;
  double up_y;                                // the pelvis's up, its world y
};

// A fall, first of: a link that may not touch the ground on it, the pelvis upside down, the
// centre of mass below a share of its starting height; each says which way the body went
// (fallDirection).
void checkFall(const BodyPlan& plan, const World& world, const FallContext& now,
               const std::vector<char>& may_touch, double start_height, double fall_height_ratio,
               SimulationReport& report) {
  std::ostringstream reason;
  reason.precision(3);
  for (size_t li = 0; li < plan.links.size() && reason.tellp() == 0; ++li)
    if (now.contacts[li] > 0 && !may_touch[li]) reason << plan.links[li].name << " touched the ground";
  if (reason.tellp() == 0 && now.up_y < 0.0) reason << "turned over (the pelvis upside down)";
  const glm::dvec3 com = world.centreOfMass();
  const double height = com.y - world.groundHeight(com.x, com.z);
  if (reason.tellp() == 0 && height < fall_height_ratio * start_height)
    reason << "centre of mass " << height << " m above the ground (started at " << start_height
           << " m)";
  if (reason.tellp() == 0) return;
  const std::string way = fallDirection(plan, world, now.controller, now.transforms);
  report.fell = true;
  report.fall_reason = (way.empty() ? "" : way + ": ") + reason.str();
  report.fall_time_s = world.time();
}

// The report before the first step: the body's mass, its feet and links by name, the recording's
// header, the shares at zero.
SimulationReport startReport(const BodyPlan& plan, const World& world,
                             const TrackingController& controller, const motion::Skeleton& skeleton,
                             const spectral::TargetMotion& target,
                             const SimulationSettings& settings) {
  SimulationReport report;
  report.mass_kg = world.totalMass();
  for (int f : controller.feet()) report.feet.push_back(plan.links[static_cast<size_t>(f)].name);
  report.contact_share.assign(controller.feet().size(), 0.0);
  report.torque_limited_share.assign(plan.links.size(), 0.0);
  for (const Link& link : plan.links) report.links.push_back(link.name);
  report.motion.name = target.name + "_simulated";
  report.motion.frame_time = 1.0 / settings.record_fps;
  report.motion.joint_count = skeleton.jointCount();
  if (settings.trace)
    report.trace.reserve(static_cast<size_t>(settings.seconds * settings.world.step_hz) + 1);
  return report;
}

// What each step adds to the report from the servos and the ground: effort, steps at the torque
// limit, contacts and footfalls, and (SimulationSettings::trace) the step's TraceStep.
struct StepMeter {
  std::vector<int> dof_offsets;
  std::vector<double> torques, velocities;     // (dofs) the last step's
  std::vector<glm::dmat4> transforms;          // (links) after the last step
  std::vector<std::uint8_t> at_limit;          // (links)
  std::vector<double> errors;                  // (links) the step's angles to the target, rad
  std::vector<int> footfall_gaps, off_ground;  // (feet) countFootfalls
  glm::dvec3 target_com{0.0};                  // the last step's (trace)
  glm::dvec3 start_velocity{0.0};              // the first step's target velocity (trace)

  StepMeter(const World& world, const TrackingController& controller, double period_s)
      : dof_offsets(world.plan().dofOffsets()),
        torques(static_cast<size_t>(world.dofCount()), 0.0),
        velocities(static_cast<size_t>(world.dofCount()), 0.0),
        transforms(world.plan().links.size()),
        footfall_gaps(footfallGaps(world, controller, period_s)),
        off_ground(controller.feet().size(), -1),
        target_com(poseKinematics(world.plan(), controller.motionTarget()).com),
        start_velocity(world.linearMomentum() / world.totalMass()) {}

  void measure(const World& world, const TrackingController& controller, bool trace,
               SimulationReport& report) {
    world.servoTorques(torques);
    world.jointVelocities(velocities);
    addEffort(world, torques, velocities, report);
    torqueLimitFlags(world, torques, dof_offsets, at_limit);
    for (size_t li = 0; li < at_limit.size(); ++li) report.torque_limited_share[li] += at_limit[li];
    world.linkTransforms(transforms);
    countFootfalls(world, controller.feet(), world.linkContacts(), transforms, footfall_gaps,
                   off_ground, report);
    if (!trace) return;
    const bool first = report.trace.empty();
    report.trace.push_back(
        traceStep(world, controller, transforms, torques, dof_offsets, at_limit, errors, target_com));
    if (first) report.trace.back().target_velocity = start_velocity;
  }
};

}  // namespace

Result<SimulationReport> simulate(const BodyPlan& plan, const motion::Skeleton& skeleton,
                                  const spectral::TargetMotion& target,
                                  const SimulationSettings& settings) {
  if (Status s = settings.validate(); !s.ok()) return Status::error("simulation: " + s.message());
  if (Status s = target.validate(skeleton); !s.ok())
    return Status::error("target motion: " + s.message());
  Result<std::vector<int>> push_links = pushLinks(plan, skeleton, settings.pushes);
  if (!push_links.ok()) return push_links.status();

  const LinkPose standing = standingPose(plan, skeleton);
  const MotionState state = targetState(plan, skeleton, target, 0.0);
  Result<Character> made = makeCharacter(plan, skeleton, target, settings, state, standing);
  if (!made.ok()) return made.status();
  World& world = *made.value().world;
  TrackingController& controller = *made.value().controller;

  SimulationReport report = startReport(plan, world, controller, skeleton, target, settings);
  const std::vector<char> may_touch = groundLinks(plan);
  const std::vector<double> zero(static_cast<size_t>(world.dofCount()), 0.0);
  StepMeter meter(world, controller, target.period());
  Recorder recorder(skeleton, target);

  // Uprightness is the pelvis's up against the world's, "up" being what the motion itself holds
  // up at its start (a rig's pelvis axes are its own: Bandai's local Y lies 92 degrees off).
  const glm::dvec3 pelvis_up =
      glm::normalize(glm::inverse(state.pose.base_rotation) * glm::dvec3(0.0, 1.0, 0.0));
  const glm::dvec3 start = world.centreOfMass();
  const double start_height = start.y - world.groundHeight(start.x, start.z);
  const long long steps = std::llround(settings.seconds / world.dt());
  const double record_every = world.dt() > 0.0 ? 1.0 / (settings.record_fps * world.dt()) : 1.0;
  double next_record = 0.0;
  std::vector<double> error_sums(plan.links.size(), 0.0);  // (links) squared angles to the target
  long long error_steps = 0;
  std::vector<char> pushed(settings.pushes.size(), 0);
  double pushed_ns = 0.0;       // magnitudes of the impulses delivered, N s
  glm::dvec3 last_com = start;  // of the last state that did not diverge
  // SimulationSettings::reference: the error is measured against it instead of the target.
  std::unique_ptr<FourierTargets> reference;
  std::vector<glm::dquat> reference_pose(static_cast<size_t>(skeleton.jointCount()));
  LinkPose reference_links;
  if (settings.reference != nullptr) {
    if (Status s = settings.reference->validate(skeleton); !s.ok())
      return Status::error("reference motion: " + s.message());
    reference = std::make_unique<FourierTargets>(*settings.reference);
  }
  recorder.record(world, report);
  next_record += record_every;
  long long step = 0;
  for (; step < steps; ++step) {
    if (settings.cancel != nullptr && settings.cancel->load(std::memory_order_relaxed)) {
      report.cancelled = true;
      break;
    }
    if (Status s = deliverPushes(world, settings.pushes, push_links.value(), pushed, pushed_ns);
        !s.ok())
      return s;
    controller.update(world);
    world.step(zero);
    if (std::string why = divergence(world, pushed_ns); !why.empty()) {
      report.diverged = true;  // no figure below comes from this state or later
      report.diverged_reason = std::move(why);
      report.fell = true;
      report.fall_time_s = world.time();
      report.fall_reason = "the simulation diverged: " + report.diverged_reason;
      break;
    }
    last_com = world.centreOfMass();

    // Tracking error against the motion's target (the reference's translations: the target's
    // at the last recorded frame), energy and torques.
    const LinkPose* wanted = &controller.motionTarget();
    if (reference) {
      reference->evaluate(world.time(), reference_pose);
      reference_links =
          linkPoseFromSkeleton(plan, skeleton, reference_pose, recorder.reference_translations);
      wanted = &reference_links;
    }
    addTrackingError(plan, world.jointPositions(), *wanted, meter.errors, error_sums);
    ++error_steps;
    meter.measure(world, controller, settings.trace, report);

    // Any link on the ground but a foot is a fall.
    const std::vector<glm::dmat4>& transforms = meter.transforms;
    const glm::dvec3 up = glm::dmat3(transforms[0]) * pelvis_up;
    report.min_uprightness = std::min(report.min_uprightness, up.y);
    if (!report.fell)
      checkFall(plan, world, {world.linkContacts(), transforms, controller, up.y},
                may_touch, start_height, settings.fall_height_ratio, report);
    if (static_cast<double>(step + 1) + 1e-9 >= next_record) {
      recorder.record(world, report);
      next_record += record_every;
    }
    if (report.fell && settings.stop_at_fall) {
      ++step;
      break;
    }
  }
  report.seconds = world.time();
  const glm::dvec3 end = report.diverged ? last_com : world.centreOfMass();
  report.distance_m = glm::length(glm::dvec2(end.x - start.x, end.z - start.z));
  report.speed_m_s = report.seconds > 0.0 ? report.distance_m / report.seconds : 0.0;
  finishTrackingError(plan, error_sums, error_steps, report);
  for (double& share : report.contact_share) share /= std::max<long long>(1, step);
  for (double& share : report.torque_limited_share) share /= std::max<long long>(1, step);
  report.pushed_impulse_ns = world.pushedImpulse();
  return report;
}

}  // namespace sinew::physics
