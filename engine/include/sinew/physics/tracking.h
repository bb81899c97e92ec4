// Tracking a TargetMotion with joint servos, and SIMBICON-style balance feedback.
//
// Each step the controller evaluates the target's harmonic series (FourierTargets), maps the
// skeleton pose into joint coordinates, corrects the hips for balance and hands the result to the
// world's joint servos (World::enableServos: implicit PD solved with the contacts, torques
// bounded per joint). Nothing acts on the base: the character moves by its joint torques, gravity
// and the ground only.
//
// Balance feedback (Yin, Loken and van de Panne 2007), per pair of legs that meet at a common
// link (a biped's pelvis; a quadruped's forelegs at the chest and hind legs at the pelvis, like
// the leg frames of Coros, Karpathy, Jones, Reveret and van de Panne 2011): with one foot of the
// pair down (the stance foot), the swing hip's target
// is turned, in the world, by
//   delta = c_d * d + c_v * v
// per horizontal direction (sagittal: the character's forward; coronal: its side), d the centre
// of mass's offset from the stance foot and v its velocity, each less the target motion's own at
// that moment (the target already swings the leg for its nominal gait), so that the swing foot
// lands where it catches the body; and the stance hip's target is replaced, by the share `torso`, with the
// rotation that brings the pelvis to the target's attitude (its tilt, at the pelvis's present
// heading turned back towards the target's by the share `heading`). Both hips' targets are set
// relative to the desired pelvis, not the present one.
//
// Swing clearance: while the target swings a foot (from its lift-off to its touchdown), the
// foot's target is raised by swing_lift x rig size x sin^2(pi u), u the share of the swing
// done: one damped least-squares step over the leg's joints moves the foot's pivot straight up,
// the foot keeps its attitude. A real capture's foot passes a centimetre or two above the ground
// at mid-swing, within what tracking misses by; a rigid sole that scuffs there trips the body.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/skeleton.h"
#include "sinew/physics/body_plan.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::physics {

class World;

// A TargetMotion's pose evaluated by spectral's FourierEvaluator (the angle-addition recurrence:
// one sin/cos pair per step for every channel, plus one per secondary term, not one sin() per
// harmonic).
class FourierTargets {
 public:
  // Precondition: target validated against its skeleton.
  explicit FourierTargets(const spectral::TargetMotion& target);

  // Local rotations (joints) at time t, as TargetMotion::pose gives them (to 1e-12), and, when
  // `translations` is not empty (joints), the translations with the travel.
  void evaluate(double t, std::span<glm::dquat> rotations,
                std::span<glm::dvec3> translations = {});
  int maxHarmonic() const { return max_n_; }
  double omega0() const { return omega0_; }

 private:
  struct Slot {
    int joint = 0;
    int axis = 0;
    bool rotation = true;  // a rotation vector's component, or a translation's
    double trend = 0.0;    // translations: metres per second
  };
  double omega0_ = 0.0;
  int max_n_ = 0;
  std::vector<glm::dquat> base_;
  std::vector<glm::dvec3> base_translations_;
  spectral::FourierEvaluator series_;
  std::vector<Slot> slots_;  // (series_ channels) where each value goes
  std::vector<spectral::SecondaryTerm> secondary_;
  std::vector<glm::dvec3> vectors_;
  std::vector<char> rotates_;
};

// Balance gains: what the evolutionary search tunes besides the harmonics.
struct BalanceGains {
  // Defaults: the swing terms off and the torso half held, the best of a grid on the bundled walk
  // (docs/physics.md): the target already places the feet for its gait, and the swing terms
  // shortened that walk at every value tried; the search tunes them per motion. The ankle gains
  // start off (0.3 kept unevolved Bandai walks up 30-60% longer but slowed them, and searches from
  // it did worse) and the lift at 2% (docs/physics.md).
  double cd_sagittal = 0.0;  // swing-hip turn per metre of centre-of-mass offset, rad/m
  double cv_sagittal = 0.0;  // per m/s of centre-of-mass velocity, rad/(m/s)
  double cd_coronal = 0.0;
  double cv_coronal = 0.0;
  double torso = 0.5;        // share of the stance hip that holds the pelvis's attitude, 0..1
  double ankle_sagittal = 0.0;  // stance-foot turn per m/s of centre-of-mass velocity error
  double ankle_coronal = 0.0;   // forward and to the side, rad/(m/s)
  double swing_lift = 0.02;     // mid-swing lift of a swing foot per rig size, [0, 0.1]
  // Share of the base's heading error (the target's heading less the present one) by which the
  // stance hips turn the base back, [0, 1]. Off (0) the stance hip holds the present heading, so
  // nothing steers a turned body back; the search tunes it for characters with two or more leg
  // pairs only (bipeds were worse with it: docs/physics.md).
  double heading = 0.0;
  // Stance legs (every foot of a pair that is down): the foot's target moved, relative to the
  // base, by gain x the centre of mass's velocity error (the body's less the target's; forward,
  // to the side, up), so the servos move the body back towards the target's velocity while a
  // foot is down: the kinematic form of Coros et al. 2010's stance-leg virtual force, and a
  // yielding leg vertically. Seconds (metres per m/s); positive gains oppose the error; off (0)
  // by default, genes of the search.
  double stance_sagittal = 0.0;
  double stance_coronal = 0.0;
  double stance_vertical = 0.0;
  // Stance legs against the heading error (the target's heading less the base's): every planted
  // foot's target turned about the vertical through the target's centre of mass by -gain x the
  // error, so the ground, holding the feet, turns the body towards the target's heading. Where
  // feet stand ahead of and behind the centre of mass (a quadruped's two pairs) this is the yaw
  // moment a body with small feet has no other way to make. Radians per radian; the search tunes
  // it for characters with two or more leg pairs only, like `heading`.
  double stance_yaw = 0.0;
  // Share by which the servos of every leg whose foot is down (its links and the foot) run slower
  // than `servo_rate` (x (1 - share)), [0, 0.9]: a landing leg gives and extends with its target
  // instead of being driven straight back to it at up to its torque limit (a strut that turns a
  // run's forward speed into flight: docs/physics.md "The stance yield").
  // Off (0) here and at the search's first start; 0.5 is its second start, tried when the first
  // has not walked in time (search::GenomeLayout::startPoints; docs/physics.md "The stance yield").
  double stance_yield = 0.0;
};

// The gains by index, in the order files and the genome hold them.
inline constexpr int kBalanceGainCount = 14;
const char* balanceGainName(int i);  // "cd_sagittal", ..., "heading", ..., "stance_yield"
double& balanceGain(BalanceGains& gains, int i);
// The largest value gain i may take, and whether it is a share from 0 (torso, swing_lift,
// heading, stance_yield) rather than signed.
double balanceGainLimit(int i, double signed_limit);
bool balanceGainIsShare(int i);
// What gain i must be, for messages: "from 0 to 0.9" for a share, "within +-100" otherwise.
std::string balanceGainRule(int i, double signed_limit);

struct TrackingSettings {
  double servo_rate = 0.2;             // World::enableServos rate, (0, 1]
  double support_torque_scale = 0.25;  // torque limit per (body weight x rig size) for joints that
                                       // carry the body (their subtree holds a foot), > 0
  double limb_torque_scale = 1.0;      // per (subtree weight x rig size) for the others, > 0
  double gravity_m_s2 = 9.81;          // for the limits above, > 0
  double ramp_s = 1.0;                 // the targets blend from the standing pose into the motion
                                       // over this time, seconds, >= 0
  bool feedback = true;                // balance feedback (for legs in pairs: legPairs())
  // The servos are given the motion this far ahead of the present, seconds in [0, 1]: a servo
  // that closes `servo_rate` of its error a step trails a moving target by servoLag(), and
  // leading it by as much takes that lag out. The feedback's references and the tracking error
  // stay at the present time. 0 here (and in a best.json that predates it); the search's
  // problems lead by servoLag() (pipeline::simulationSettings).
  double servo_lead_s = 0.0;
  // A planted leg that yields (balance.stance_yield) closes (1 - yield) of what the others do a
  // step and trails by servo_lead_s / (1 - yield): when set, its servos (hip to foot) are led by
  // that instead. Off here (and in a best.json or checkpoint that predates it); the search's
  // problems set it (pipeline::simulationSettings).
  bool lead_yielding_legs = false;
  BalanceGains balance;

  Status validate() const;  // the message names the offending field
};

// How far a servo closing `rate` of its error each step of a world stepping at `step_hz` trails a
// target moving at a steady speed, seconds: 1 / (step_hz x rate) (20.8 ms at 240 Hz and 0.2).
double servoLag(double step_hz, double rate);
// Whether `seconds` is a servo lead TrackingSettings, best.json and checkpoints accept: [0, 1].
bool validServoLead(double seconds);

// Joint torque limits (links, N m; 0 for the base): support_scale x body weight x size for
// joints whose subtree holds a foot, limb_scale x subtree weight x size for the others.
std::vector<double> jointTorqueLimits(const BodyPlan& plan, double support_scale,
                                      double limb_scale, double gravity_m_s2);

// A foot's swing in a periodic target: seconds within the period, -1 when it never lifts.
struct FootCycle {
  double liftoff_s = -1.0;
  double touchdown_s = -1.0;
};

// Two legs that balance together (the biped's; a quadruped's forelegs, and its hind legs).
struct LegPair {
  int feet[2] = {0, 0};  // indices into the controller's feet
  int hips[2] = {0, 0};  // links: each leg's top link below `base`
  int base = 0;          // the link the two legs meet at: the pelvis, a quadruped's chest
  glm::dvec3 forward_local{0.0, 0.0, 1.0};  // the character's forward in the base link's frame
  // A leg alone (a hopper's): both sides are the one foot and hip. Down, its hip holds the base;
  // in the air, it is placed to catch the body (Raibert 1984).
  bool alone() const { return feet[0] == feet[1]; }
};

// The plan's legs in pairs that balance together (LegPair::feet index the plan's foot links in
// link order; forward_local is left at +Z): each pair's feet meet at a link below which each has
// its own ball-jointed hip. Feet pair with the partner they share the deepest link with; a foot
// left without one balances alone (LegPair::alone) if its leg has a ball-jointed hip.
std::vector<LegPair> findLegPairs(const BodyPlan& plan);

class TrackingController {
 public:
  // Enables the world's servos and prepares the targets. `standing`: the pose the ramp starts
  // from (the world's initial pose, usually). Fails on invalid settings, a target that does not
  // match the skeleton, or a world that has stepped.
  static Result<std::unique_ptr<TrackingController>> create(
      World& world, const motion::Skeleton& skeleton, const spectral::TargetMotion& target,
      const LinkPose& standing, const TrackingSettings& settings = {});

  // Sets the servo targets for the world's present time and state; call before every step.
  void update(World& world);

  const LinkPose& target() const { return target_; }        // the last targets given the servos
  const LinkPose& motionTarget() const { return motion_; }  // the same before balance feedback
  // The first leg pair's stance foot: index into the plan's feet (link order), -1: none.
  int stanceFoot() const { return stance_; }
  bool balancing() const { return balance_; }  // a leg pair under a common link: feedback applies
  const std::vector<LegPair>& legPairs() const { return pairs_; }
  const std::vector<int>& feet() const { return feet_; }  // foot links
  // (feet) when the target lifts and lands each foot within its period
  const std::vector<FootCycle>& footCycles() const { return cycles_; }
  // (links) each servo's rate in the last update: `servo_rate`, times (1 - stance_yield) on the
  // legs whose foot is down; empty (every servo at the world's rate) with no yield or feedback.
  const std::vector<double>& servoRates() const { return servo_rates_; }

 private:
  TrackingController() = default;
  LinkPose motionAt(double time);  // the target's pose at `time`, ramped; fills the scratch
  void liftSwingFeet(double time);
  void applyFeedback(const World& world);
  // Pair p's feedback; returns its stance foot (index into feet_), -1 with no foot down.
  int balancePair(const World& world, size_t p, const std::vector<glm::dmat4>& transforms,
                  const std::vector<glm::dquat>& target_world);
  // Where a swing foot should land, from one pair's frame this step (see balancePair).
  struct Placement {
    glm::dquat base_now, base_wanted;  // the base's attitude, and the one its stance hip holds
    glm::dvec3 offset_error, velocity_error;  // the centre of mass's, less the target's (heading
                                              // frame: x left, y up, z forward)
    glm::dvec3 forward;                        // the present heading, in the world
  };
  void placeSwingFoot(int hip, const Placement& placement);
  void turnStanceAnkle(int foot_link, const glm::dvec3& velocity_error, const glm::dvec3& forward,
                       const glm::dvec3& side);
  void driveStanceLegs(const LegPair& pair, const std::vector<std::uint8_t>& contacts,
                       const glm::dvec3& velocity_error, double heading_target,
                       double heading_error);
  void leadYieldingLegs(const World& world, double t);  // the yielding legs' target, further ahead
  // The links that yield this step (stance_yield, with feedback): every foot that is down and the
  // leg above it (legs_); none without a yield.
  std::vector<int> yieldingLinks(const World& world) const;
  void setServoRates(const World& world);  // servo_rates_ for this step
  void referenceKinematics();  // reference_com_ and reference_ankles_ from motion_
  void setForward(const spectral::TargetMotion& target);  // every pair's forward_local

  const BodyPlan* plan_ = nullptr;
  const motion::Skeleton* skeleton_ = nullptr;
  TrackingSettings settings_;
  std::unique_ptr<FourierTargets> fourier_;
  LinkPose standing_;
  LinkPose motion_;
  LinkPose target_;
  std::vector<glm::dquat> rotations_;     // (joints) scratch
  std::vector<glm::dvec3> translations_;  // (joints) the target's translations at the present time
  std::vector<int> feet_;                 // foot links
  std::vector<LegPair> pairs_;            // the legs that balance, in pairs
  std::vector<int> last_down_;            // (pairs) the side (0, 1) last down, -1 before any
  bool balance_ = false;
  int stance_ = -1;
  glm::dvec3 reference_com_{0.0};           // the target pose's centre of mass, world m
  glm::dvec3 reference_velocity_{0.0};      // its velocity, m/s
  std::vector<glm::dvec3> reference_ankles_;  // (feet) the target pose's foot pivots
  bool have_reference_ = false;
  std::vector<FootCycle> cycles_;     // (feet)
  std::vector<std::vector<int>> legs_;  // (feet) the links a foot's lift moves, top to bottom
  std::vector<double> servo_rates_;     // (links) see servoRates()
};

// When each foot of `feet` (links) leaves the ground and comes down again within the target's
// period: its shape's lowest point rising above, and coming back within, 15% of its swing's
// height of the ground, either side of the swing's highest point, from the target's kinematics
// at 128 points a period; the ground is the top of the lowest quarter of that point's heights
// (the foot standing). -1 for a foot that rises less than 1% of the rig's size.
std::vector<FootCycle> targetFootCycles(const BodyPlan& plan, const motion::Skeleton& skeleton,
                                        const spectral::TargetMotion& target,
                                        const std::vector<int>& feet);

// A character's state taken from a target: its pose at time t and its velocities (central
// differences over 1 ms), so a simulation can start in the motion rather than from rest.
struct MotionState {
  LinkPose pose;
  glm::dvec3 base_linear{0.0};           // base frame origin, world m/s
  glm::dvec3 base_angular{0.0};          // world rad/s
  std::vector<double> joint_velocities;  // (dofs) as World::jointVelocities
};
MotionState targetState(const BodyPlan& plan, const motion::Skeleton& skeleton,
                        const spectral::TargetMotion& target, double t);

// World rotations of every link for a pose (links), by forward kinematics from the base.
std::vector<glm::dquat> linkWorldRotations(const BodyPlan& plan, const LinkPose& pose);
// A pose's link pivots (links, world metres) and its centre of mass, by forward kinematics.
struct PoseKinematics {
  std::vector<glm::dvec3> pivots;
  glm::dvec3 com{0.0};
};
PoseKinematics poseKinematics(const BodyPlan& plan, const LinkPose& pose);

}  // namespace sinew::physics
