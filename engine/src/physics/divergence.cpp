#include "sinew/physics/divergence.h"

#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "sinew/physics/world.h"

namespace sinew::physics {

std::string divergence(const World& world, double pushed_impulse_ns,
                       const DivergenceLimits& limits) {
  if (!world.finite()) return "a non-finite state (position or velocity)";
  char reason[160];
  const double joint_speed = world.maxJointSpeed();
  if (joint_speed >= limits.joint_speed_rad_s) {
    std::snprintf(reason, sizeof reason, "a joint at %.0f rad/s, Bullet's velocity clamp",
                  joint_speed);
    return reason;
  }
  const double mass = world.totalMass();
  const double speed = mass > 0.0 ? glm::length(world.linearMomentum()) / mass : 0.0;
  const double allowed = limits.energy_margin *
                         (limits.free_speed_m_s + (mass > 0.0 ? pushed_impulse_ns / mass : 0.0));
  if (!(speed <= allowed)) {
    std::snprintf(reason, sizeof reason,
                  "energy blow-up: the centre of mass at %.3g m/s, more than gravity and the "
                  "pushes can give (%.3g m/s)",
                  speed, allowed);
    return reason;
  }
  return {};
}

}  // namespace sinew::physics
