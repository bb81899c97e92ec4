// A simulation run: a character built from a skeleton tracks a TargetMotion on a terrain, with
// scheduled pushes, for a fixed time; what it did is recorded on the original skeleton (merged
// joints follow the target) and summarised (fell, distance, tracking error, energy, contacts).
// The same inputs give bit-identical results: every run builds a fresh World.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "sinew/core/status.h"
#include "sinew/motion/clip.h"
#include "sinew/motion/skeleton.h"
#include "sinew/physics/body_plan.h"
#include "sinew/physics/tracking.h"
#include "sinew/physics/world.h"
#include "sinew/spectral/target_motion.h"

namespace sinew::physics {

inline constexpr double kMaxPushImpulse_ns = 1e4;  // |impulse| of one push, N s

struct Push {
  double time_s = 1.0;           // when, seconds from the start, >= 0
  glm::dvec3 impulse_ns{0.0};    // world, N s, |impulse| <= kMaxPushImpulse_ns
  std::string link;              // the link (its skeleton joint's name); empty: the base
};

// Runs with SimulationSettings::trace record every step, so at most this long.
inline constexpr double kMaxTracedSeconds = 120.0;

struct SimulationSettings {
  double seconds = 10.0;      // simulated time, (0, 3600]
  WorldSettings world;
  TrackingSettings tracking;
  bool start_moving = true;   // start in the target's pose at t = 0 with its velocities (the
                              // character enters walking); false: from the standing pose at
                              // rest, blending into the motion over tracking.ramp_s
  std::vector<Push> pushes;
  double record_fps = 30.0;   // frames of the recording per second, > 0
  double fall_height_ratio = 0.5;  // fallen when the centre of mass drops below this share of
                                   // its starting height above the ground, (0, 1)
  bool stop_at_fall = true;   // end the run when the character falls
  bool trace = false;         // record SimulationReport::trace, one TraceStep per step (seconds
                              // <= kMaxTracedSeconds)
  // When set, track_err_rad_rms is measured against this motion (the style the search must
  // keep), not the one the controller tracks, at the same time: a target that changed the tempo
  // drifts out of phase with it, which reads as error (the tempo is part of the style; measuring
  // at the target's phase instead was tried and kept the shape worse, docs/search.md). Same
  // skeleton, not owned.
  const spectral::TargetMotion* reference = nullptr;
  const std::atomic<bool>* cancel = nullptr;  // when set and true, the run ends at the next step
                                              // (SimulationReport::cancelled): how a search stops
                                              // within its latency budget mid-evaluation

  Status validate() const;  // the message names the offending field
};

struct Footfall {
  int foot = 0;             // index into SimulationReport::feet
  double time_s = 0.0;      // touchdown
  glm::dvec3 position{0.0};  // the foot's pivot at touchdown, world metres
};

// One step of a traced run, at the step's end: what the body did against what its servos were
// aiming at, so a fall can be read step by step (which foot was down, which joint gave out).
struct TraceStep {
  double time_s = 0.0;
  glm::dvec3 com{0.0};              // centre of mass, world metres
  glm::dvec3 com_velocity{0.0};     // m/s
  glm::dvec3 target_com{0.0};       // the centre of mass of the motion's pose the servos aimed at
                                    // in the step (before balance feedback), world metres
  glm::dvec3 target_velocity{0.0};  // its change over the step, m/s (the first step: the start's)
  int stance_foot = -1;             // the first leg pair's stance foot in the step
                                    // (SimulationReport::feet), chosen from the contacts before
                                    // it; -1: none was down
  std::vector<std::uint8_t> foot_contacts;  // (feet) contact points with the ground
  std::vector<glm::dvec3> foot_positions;   // (feet) the foot's pivot (ankle), world metres
  std::vector<glm::dvec3> target_foot_positions;  // (feet) the same in the motion's pose the
                                                  // servos aimed at (the frame of target_com):
                                                  // where the target lifts and lands each foot
  std::vector<double> foot_forces_n;        // (feet) the ground's normal force
  std::vector<double> torques_nm;           // (links; 0 for the base) largest |servo torque| of
                                            // the joint's axes
  std::vector<std::uint8_t> at_limit;       // (links) 1: at its torque limit on an axis
  std::vector<double> errors_rad;           // (links; 0 for the base) the joint's angle to its
                                            // target, the one track_err_rad_rms sums
};

struct SimulationReport {
  bool fell = false;
  bool cancelled = false;     // ended early by SimulationSettings::cancel: the figures are partial
  bool diverged = false;      // physics/divergence.h: also counts as fallen; every figure comes
                              // from the states before it
  std::string diverged_reason;  // "a joint at 100 rad/s, Bullet's velocity clamp", or empty
  double fall_time_s = -1.0;  // -1: did not fall
  std::string fall_reason;    // e.g. "LeftHand touched the ground", "backwards: centre of mass
                              // 0.41 m above the ground (started at 0.9 m)"
  double seconds = 0.0;       // simulated (less than asked when it stopped at a fall)
  double distance_m = 0.0;    // horizontal travel of the centre of mass, start to end
  double speed_m_s = 0.0;     // distance / seconds
  double track_err_rad_rms = 0.0;  // RMS over steps and actuated joints of the angle between each
                                   // joint's rotation and the motion's target (before balance
                                   // feedback; or SimulationSettings::reference's), radians
  // (links; 0 for the base and for welded joints) each joint's RMS of the same angle over the
  // steps, radians: where the tracking error lies (the mean of their squares over the turning
  // joints is track_err_rad_rms's square).
  std::vector<double> track_err_by_link_rad;
  double energy_j = 0.0;           // mechanical work of the joint torques, integral of sum |tau w|
  double torque_sq_per_kg = 0.0;   // integral of sum tau^2 dt / mass, N^2 m^2 s / kg
  double min_uprightness = 1.0;    // lowest cosine between the pelvis's up (the direction the
                                   // target's first pose holds up) and the world's up
  double mass_kg = 0.0;
  glm::dvec3 pushed_impulse_ns{0.0};  // the pushes delivered
  std::vector<std::string> feet;      // foot link names
  std::vector<double> contact_share;  // (feet) share of steps with the foot on the ground
  std::vector<Footfall> footfalls;
  // (links; 0 for the base) share of steps in which a joint's servo torque reached its limit on
  // any axis (World::servoTorqueLimits): a joint pinned there is too weak for what it is asked.
  std::vector<double> torque_limited_share;
  std::vector<std::string> links;   // (links) link names, for the share above
  motion::Clip motion;              // what the character did, on the original skeleton, at
                                    // record_fps
  std::vector<glm::dvec3> com;      // (recorded frames) centre of mass, world metres
  std::vector<TraceStep> trace;     // (steps) with SimulationSettings::trace, else empty
};

// Runs the simulation. The skeleton must be the one `plan` and `target` were made from. Fails on
// invalid settings, a push naming no link, or a target that does not match the skeleton.
Result<SimulationReport> simulate(const BodyPlan& plan, const motion::Skeleton& skeleton,
                                  const spectral::TargetMotion& target,
                                  const SimulationSettings& settings = {});

// A skeleton pose (local rotations and translations, joints) for the world's present state:
// each link's simulated rotation on its pivot joint, the joints merged into it at `reference`
// (the target's pose), the base on the root.
void skeletonPoseFromWorld(const World& world, const motion::Skeleton& skeleton,
                           std::span<const glm::dquat> reference_rotations,
                           std::span<const glm::dvec3> reference_translations,
                           std::span<glm::dquat> rotations, std::span<glm::dvec3> translations);

}  // namespace sinew::physics
