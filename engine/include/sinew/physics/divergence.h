// Divergence: a simulation whose state is no longer a motion of the character (numbers that
// are not finite, joints held at Bullet's speed clamp, kinetic energy from nowhere). Detected
// where it happens, after each step, so that no figure of a run is computed from a state past it:
// the run is marked diverged with the reason, and a search scores it as a failure.
#pragma once

#include <string>

#include <glm/vec3.hpp>

namespace sinew::physics {

class World;

// btMultiBody clamps every joint velocity component to +-m_maxCoordinateVelocity, 100 rad/s by
// default (World leaves it there). A joint at the clamp is not moving as physics says it should.
inline constexpr double kBulletMaxCoordinateVelocity_rad_s = 100.0;

struct DivergenceLimits {
  double joint_speed_rad_s = 0.99 * kBulletMaxCoordinateVelocity_rad_s;  // at the clamp
  // The centre of mass may move no faster than a fall from the highest height gives plus what
  // the pushes delivered can give (|impulse| / mass), times `energy_margin`: beyond, energy came
  // from nowhere.
  double free_speed_m_s = 20.0;  // a fall from 20 m, m/s
  double energy_margin = 2.0;    // > 1
};

// Why the world's present state has diverged, or empty when it has not. `pushed_impulse_ns` is
// the magnitude of all impulses delivered so far (World::pushedImpulse sums them as vectors,
// which can cancel; the caller adds magnitudes).
std::string divergence(const World& world, double pushed_impulse_ns,
                       const DivergenceLimits& limits = {});

}  // namespace sinew::physics
