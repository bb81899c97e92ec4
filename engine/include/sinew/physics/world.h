// The simulated world: one character (a Bullet btMultiBody built from a BodyPlan) on a static
// ground plane with friction, stepped at a fixed rate. The character moves only by the joint
// torques passed to step(), gravity and ground contact: nothing in this module applies a force or
// torque to any body. Every evaluation builds a fresh World, so the same inputs give bit-identical
// results. Bullet is an implementation detail: no Bullet type appears here.
//
// Joint ranges (BodyPlan: hinge_lower/upper, the ball_* range) are constraints the solver resolves
// with the contacts: impulses between a link and its parent, like the servos, never on the base.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "sinew/core/status.h"
#include "sinew/physics/body_plan.h"

namespace sinew::physics {

// The ground. The character starts near x = z = 0 facing any way; terrain features lie along +Z
// (where the bundled characters walk) and are level across X.
struct TerrainSettings {
  enum class Kind : std::uint8_t {
    kFlat,   // a plane at ground_height_m
    kSlope,  // a plane through (0, ground_height_m, 0) rising along +Z by slope_deg
    kSteps,  // flat, then a staircase up along +Z from z = step_start_m
    kRough,  // a heightfield of random heights in [0, amplitude_m] (seeded), 40 m square
  };
  Kind kind = Kind::kFlat;
  double slope_deg = 5.0;       // kSlope: degrees, in (-45, 45)
  double step_height_m = 0.05;  // kSteps: riser height, metres, (0, 1]
  double step_depth_m = 0.6;    // kSteps: tread depth, metres, >= 0.1
  int step_count = 10;          // kSteps: how many steps, 1..1000
  double step_start_m = 1.0;    // kSteps: z of the first riser, metres
  double amplitude_m = 0.02;    // kRough: largest height above ground_height_m, metres, (0, 1]
  double cell_m = 0.2;          // kRough: heightfield spacing, metres, [0.02, 2]
  std::uint64_t seed = 1;       // kRough: same seed, same ground

  Status validate() const;  // the message names the offending field
};
const char* terrainKindName(TerrainSettings::Kind kind);  // "flat", "slope", "steps", "rough"

struct WorldSettings {
  double step_hz = 240.0;             // fixed simulation rate, steps per second, 30..10000; the
                                      // step never follows the display's frame rate
  double gravity_m_s2 = 9.81;         // downwards along -Y, m/s^2, >= 0
  double ground_friction = 0.9;       // Coulomb friction coefficient of the ground, >= 0
  double ground_height_m = 0.0;       // the ground plane's height, metres
  TerrainSettings terrain;
  int solver_iterations = 10;         // constraint solver iterations per step, 1..1000
  bool place_on_ground = true;        // lift or lower the initial pose so its lowest shape point is
                                      // `ground_clearance_m` above the ground
  double ground_clearance_m = 0.002;  // metres, >= 0

  Status validate() const;  // the message names the offending field
};

// Loads on the multibody that did not come from our joint torques, read before each step.
struct ExternalLoads {
  double max_base_force_n = 0.0;    // largest |force| accumulated on the base, N
  double max_base_torque_nm = 0.0;  // largest |torque| accumulated on the base, N m
  double max_link_force_n = 0.0;    // largest |force| accumulated on any link, N
  double max_link_torque_nm = 0.0;  // largest |Cartesian torque| accumulated on any link, N m
};

class World {
 public:
  // Builds the ground and the character at `initial` (joint velocities zero). Fails, saying why,
  // on invalid settings, an invalid plan or a pose whose sizes do not match the plan.
  static Result<std::unique_ptr<World>> create(const BodyPlan& plan, const LinkPose& initial,
                                               const WorldSettings& settings = {});
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // Applies `joint_torques` (dofs, N m, in each joint's own frame; order: links in plan order, ball
  // joints 3, hinges 1) for one fixed step, then advances the simulation by dt().
  // Precondition: joint_torques.size() == dofCount().
  void step(std::span<const double> joint_torques);

  // A scheduled push: `impulse_ns` (world, N s) delivered to the link's centre of mass during the
  // next step, as a force of impulse / dt for that one step. The only load besides gravity and
  // the ground that ever acts on the character (externalLoads() is read before it is applied).
  Status push(int link, const glm::dvec3& impulse_ns);
  glm::dvec3 pushedImpulse() const;  // sum of the pushes delivered so far, N s

  // Initial velocities (before the first step): the base frame origin's linear and angular
  // velocity (world, m/s and rad/s) and the joint velocities (dofs, as jointVelocities gives
  // them). A state, not a force: a character can enter the simulation already walking.
  Status setVelocities(const glm::dvec3& base_linear, const glm::dvec3& base_angular,
                       std::span<const double> joint_velocities);

  // Joint servos: implicit PD. Each actuated joint gets a Bullet joint motor, a constraint the
  // solver resolves together with the ground contacts, that drives the joint towards its target
  // coordinate: the joint's velocity after the step is asked to close `rate` of the position
  // error (and cancel its velocity), with a torque no larger than the link's limit (ball joints:
  // per axis of the joint frame). The motor acts between a link and its parent only: an internal
  // joint torque, like step()'s. Stable for any body mass at any rate in (0, 1], which explicit PD
  // at 240 Hz is not (see docs/physics.md). Call once, before the first step; the targets start
  // at the current pose. `max_torque_nm` (links): 0 leaves a joint unactuated.
  Status enableServos(std::span<const double> max_torque_nm, double rate);
  // A target outside a joint's range is moved to the range's nearest point (hinges: the angle
  // clamped; balls: clampToBallRange), which the servo can reach. `rates` (links, each in
  // (0, 1]): the share of its error each joint's servo closes this step instead of
  // enableServos' rate; empty (or not one per link): that rate for every joint, as for an
  // entry outside (0, 1].
  void setServoTargets(const LinkPose& target, std::span<const double> rates = {});
  // Torques the servos applied in the last step (dofs, N m, each joint's frame).
  void servoTorques(std::span<double> out) const;
  // Each servo's torque limit (links, N m, per axis; 0 for a joint without one), as
  // enableServos set it; empty before.
  const std::vector<double>& servoTorqueLimits() const;

  double dt() const;    // 1 / step_hz, seconds
  double time() const;  // simulated seconds since creation
  long long stepCount() const;
  int linkCount() const;
  int dofCount() const;
  const BodyPlan& plan() const;

  // Link frames (pivot origin, joint frame axes) in world space, (links), metres.
  void linkTransforms(std::span<glm::dmat4> out) const;
  // Centres of mass of the links, world metres, (links).
  void linkCentres(std::span<glm::dvec3> out) const;
  // Current joint coordinates (ball: quaternion, hinge: angle) and the base pose.
  LinkPose jointPositions() const;
  // Joint velocities (dofs): ball: angular velocity in the link frame, rad/s; hinge: rad/s.
  void jointVelocities(std::span<double> out) const;
  double maxJointSpeed() const;  // largest |joint velocity| component, rad/s

  // The joint-space inverse inertia of the floating character at its current pose (dofs x dofs,
  // row-major, 1/(kg m^2)): entry (i, j) is the acceleration of dof i per unit torque at dof j,
  // the base free, and the links in `welded_links` (plan indices) held still as a planted foot
  // is by the ground. Its diagonal's inverse is each joint's effective inertia. Call it before
  // the first step (it runs Bullet's articulated-body pass, which at rest changes nothing).
  std::vector<double> jointInverseInertia(std::span<const int> welded_links = {});

  glm::dvec3 linearMomentum() const;  // of the whole character, kg m/s
  glm::dvec3 centreOfMass() const;    // world metres
  double totalMass() const;           // kg

  // Per link, how many contact points it had with the ground in the last step (links; 0: none,
  // a box sole lying flat has 4).
  const std::vector<std::uint8_t>& linkContacts() const;
  // Per link, the ground's normal force on it in the last step (normal impulse / dt), N (links).
  const std::vector<double>& linkNormalForces() const;
  // Impulse the ground gave the character in the last step (normal and friction), N s, world.
  glm::dvec3 lastContactImpulse() const;
  // The largest external loads seen on the multibody before any step so far (zero when only
  // joint torques were applied), and whether every link state is finite.
  const ExternalLoads& externalLoads() const;
  // Height of the ground at (x, z), world metres (the top of a step, the heightfield's surface).
  double groundHeight(double x, double z) const;
  bool finite() const;

 private:
  struct Impl;
  explicit World(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace sinew::physics
