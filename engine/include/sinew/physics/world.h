// The simulated world: one character (a Bullet btMultiBody built from a BodyPlan) on a static
// ground plane with friction, stepped at a fixed rate. The character moves only by the joint
// torques passed to step(), gravity and ground contact: nothing in this module applies a force or
// torque to any body. Every evaluation builds a fresh World, so the same inputs give bit-identical
// results. Bullet is an implementation detail: no Bullet type appears here.
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

struct WorldSettings {
  double step_hz = 240.0;             // fixed simulation rate, steps per second, 30..10000; the
                                      // step never follows the display's frame rate
  double gravity_m_s2 = 9.81;         // downwards along -Y, m/s^2, >= 0
  double ground_friction = 0.9;       // Coulomb friction coefficient of the ground, >= 0
  double ground_height_m = 0.0;       // the ground plane's height, metres
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
  bool finite() const;

 private:
  struct Impl;
  explicit World(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace sinew::physics
