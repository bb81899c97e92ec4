// Explicit PD torques at the joints towards target joint coordinates. Torques act only at joints
// (between a link and its parent), never on the base: the character stays honest.
//
// Gains. Each joint degree of freedom gets a nominal stiffness from the load it carries,
//   kp_nominal = stiffness_per_load * m_carried * g * rig size
// (m_carried: the whole body for joints whose subtree holds a foot, the subtree's mass otherwise),
// capped by the joint's effective inertia I so that the explicit step stays stable:
//   kp <= I * (2 pi f_max)^2,  f_max = max_frequency_ratio * step rate,
//   kd  = 2 * damping_ratio * sqrt(kp * I).
// I is 1 / (M^-1)_ii, M the joint-space inertia of the floating character at its initial pose
// (World::jointInverseInertia) with the planted feet held: the inertia a torque at that degree of
// freedom actually meets, its neighbours, the free base and the ground included. Estimates from a
// link's own shape are not enough: a head on a chest pulled by four joints turns about its own
// centre, not about the neck, and gains from the larger figure diverge in a dozen steps (measured).
// Uncapped gains on light links (a foot, a forearm's twist) diverge; the cap is what keeps them
// stable. For a single degree of freedom, semi-implicit Euler is stable while (w h)^2 + 4 zeta (w
// h) < 4 (h the step, w the natural frequency): the default 0.1 and zeta 1 use 73% of that bound.
// Joints act together, so the gains are then lowered until every row of M^-1 meets a shared budget
// (Gershgorin):
//   sum_j |M^-1_ij| (kp_j h^2 + 2 kd_j h) <= 4 * stability_budget.
// Torque limits: torque_scale * m_carried * g * rig size, per joint (vector norm for ball joints).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sinew/core/status.h"
#include "sinew/physics/body_plan.h"

namespace sinew::physics {

struct ControllerSettings {
  double stiffness_per_load = 4.0;     // nominal kp per (carried weight x rig size), 1/rad, > 0
  double damping_ratio = 1.0;          // of the capped PD loop, > 0
  double max_frequency_ratio = 0.1;    // f_max / step rate, in (0, 0.25]
  double support_torque_scale = 0.15;  // torque limit per (body weight x size), joints that carry
                                       // the body (their subtree holds a foot), > 0
  double limb_torque_scale = 1.0;      // torque limit per (subtree weight x size), others, > 0
  double gravity_m_s2 = 9.81;          // for the loads above, m/s^2, > 0
  int planted_contact_points = 3;      // a foot is planted (held by the ground: its gain set)
                                       // while it has at least this many contact points, >= 1
  double tipping_margin = 0.8;         // share of the tipping torque a planted foot's joint may
                                       // apply, in (0, 1]
  double stability_budget = 0.5;       // share of the explicit stability bound the coupled gains
                                       // may use (see PdController), in (0, 1)

  Status validate() const;  // the message names the offending field
};

// Gains of one degree of freedom.
struct DofGains {
  double inertia = 0.0;  // effective inertia 1 / (M^-1)_ii, kg m^2
  double kp = 0.0;       // N m / rad
  double kd = 0.0;       // N m s / rad
};

class World;

class PdController {
 public:
  static constexpr size_t kMaxFeetStates = 4;  // feet up to which every planted/lifted
                                               // combination gets its own gain set

  // Gains for the world's character at its initial pose, measured from the world's joint-space
  // inertia (World::jointInverseInertia) once per state of the feet: a planted foot is held by
  // the ground, so the joints above it meet the body's inertia, not the foot's. Fails on invalid
  // settings or a world that has already stepped.
  static Result<PdController> create(World& world, const ControllerSettings& settings = {});

  // Joint torques (dofs, N m, each joint's frame) towards `target` for the world's current state:
  // PD on the error (ball: the rotation vector of current^-1 * target, in the joint's frame;
  // hinge: the angle error; target velocities zero in this slice). The planted feet
  // (World::linkContacts) choose the gain set; a planted foot's joint torque is limited to what
  // its ground force holds without tipping the foot over its sole's edge (force x half the sole
  // x tipping_margin), so the stiff planted gains never lift the foot they assume planted.
  // Precondition: the world is the one this controller was created for.
  void computeTorques(const World& world, const LinkPose& target, std::span<double> torques) const;

  // The gain set for a state of the feet (bit f set: foot f planted; 0: all in the air).
  const std::vector<DofGains>& gains(unsigned state = 0) const { return gain_sets_[state]; }
  unsigned stateCount() const { return static_cast<unsigned>(gain_sets_.size()); }
  unsigned contactState(std::span<const std::uint8_t> link_contacts) const;
  const std::vector<int>& feet() const { return feet_; }               // foot link indices
  const std::vector<double>& torqueLimits() const { return limits_; }  // (links), N m; 0 base
  int dofCount() const { return gain_sets_.empty() ? 0 : static_cast<int>(gain_sets_[0].size()); }

 private:
  PdController() = default;
  std::vector<JointType> types_;                  // (links)
  std::vector<int> offsets_;                      // (links) first dof
  std::vector<int> feet_;                         // foot links
  std::vector<std::vector<DofGains>> gain_sets_;  // (states x dofs)
  std::vector<double> limits_;                    // (links)
  int planted_points_ = 3;
  double tipping_margin_ = 0.8;
  std::vector<Shape> foot_shapes_;  // (feet) the sole boxes
};

// The rotation vector (log map) of a unit quaternion, radians, shortest arc: core's
// shortRotationVector of q normalised (rotation.h owns the maths; this name stays for callers).
glm::dvec3 rotationVectorOf(const glm::dquat& q);

}  // namespace sinew::physics
