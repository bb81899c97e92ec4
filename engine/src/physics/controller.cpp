#include "sinew/physics/controller.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "sinew/core/rotation.h"
#include "sinew/physics/world.h"

namespace sinew::physics {
namespace {

// Gains for one joint-space inverse inertia (see the header): the per-dof cap, then the coupled
// budget.
std::vector<DofGains> gainsFor(const std::vector<double>& kp_nominal,
                               const std::vector<double>& minv, const ControllerSettings& settings,
                               double step_hz) {
  const size_t n = kp_nominal.size();
  const double h = 1.0 / step_hz;
  const double w_max = 2.0 * std::numbers::pi * settings.max_frequency_ratio * step_hz;
  const double zeta = settings.damping_ratio;
  std::vector<DofGains> gains(n);
  std::vector<double> budget(n);
  for (size_t i = 0; i < n; ++i) {
    DofGains& g = gains[i];
    g.inertia = 1.0 / std::max(minv[i * n + i], 1e-12);
    g.kp = std::min(kp_nominal[i], g.inertia * w_max * w_max);
    g.kd = 2.0 * zeta * std::sqrt(g.kp * g.inertia);
    budget[i] = g.kp * h * h + 2.0 * g.kd * h;
  }
  // Coupled step: the largest eigenvalue of B^1/2 M^-1 B^1/2 must stay below the bound; shrink
  // the budgets of the degrees of freedom in the offending mode, by their share of it.
  const double bound = 4.0 * settings.stability_budget;
  std::vector<double> root(n), u(n), next(n);
  for (int round = 0; round < 500 && n > 0; ++round) {
    for (size_t i = 0; i < n; ++i) root[i] = std::sqrt(budget[i]);
    std::fill(u.begin(), u.end(), 1.0 / std::sqrt(static_cast<double>(n)));
    double lambda = 0.0;
    for (int it = 0; it < 200; ++it) {
      for (size_t i = 0; i < n; ++i) {
        double sum = 0.0;
        for (size_t j = 0; j < n; ++j) sum += minv[i * n + j] * root[j] * u[j];
        next[i] = root[i] * sum;
      }
      double norm = 0.0;
      for (double x : next) norm += x * x;
      norm = std::sqrt(norm);
      if (!(norm > 0.0)) break;
      lambda = 0.0;
      for (size_t i = 0; i < n; ++i) lambda += u[i] * next[i];  // Rayleigh quotient
      for (size_t i = 0; i < n; ++i) u[i] = next[i] / norm;
    }
    if (lambda <= bound) break;
    double peak = 0.0;
    for (double x : u) peak = std::max(peak, x * x);
    const double cut = 1.0 - std::max(bound / lambda, 0.5);
    for (size_t i = 0; i < n; ++i) budget[i] *= 1.0 - cut * (u[i] * u[i] / peak);
  }
  for (size_t i = 0; i < n; ++i) {
    DofGains& g = gains[i];
    const double x = -2.0 * zeta + std::sqrt(4.0 * zeta * zeta + budget[i] / g.inertia);  // w h
    const double kp = g.inertia * x * x / (h * h);
    if (kp < g.kp) {
      g.kp = kp;
      g.kd = 2.0 * zeta * g.inertia * x / h;
    }
  }
  return gains;
}

}  // namespace

glm::dvec3 rotationVectorOf(const glm::dquat& q) {
  return shortRotationVector(glm::normalize(q));
}

Status ControllerSettings::validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(stiffness_per_load)) return Status::error("stiffness_per_load must be > 0");
  if (!positive(damping_ratio)) return Status::error("damping_ratio must be > 0");
  if (!(positive(max_frequency_ratio) && max_frequency_ratio <= 0.25))
    return Status::error("max_frequency_ratio must be in (0, 0.25]");
  if (!positive(support_torque_scale)) return Status::error("support_torque_scale must be > 0");
  if (!positive(limb_torque_scale)) return Status::error("limb_torque_scale must be > 0");
  if (!positive(gravity_m_s2)) return Status::error("gravity_m_s2 must be > 0");
  if (!(positive(tipping_margin) && tipping_margin <= 1.0))
    return Status::error("tipping_margin must be in (0, 1]");
  if (planted_contact_points < 1) return Status::error("planted_contact_points must be >= 1");
  if (!(positive(stability_budget) && stability_budget < 1.0))
    return Status::error("stability_budget must be in (0, 1)");
  return Status();
}

Result<PdController> PdController::create(World& world, const ControllerSettings& settings) {
  if (Status s = settings.validate(); !s.ok())
    return Status::error("controller settings: " + s.message());
  if (world.stepCount() != 0)
    return Status::error(
        "controller: create it from a world that has not stepped yet (gains are "
        "measured at the initial pose, at rest)");
  const BodyPlan& plan = world.plan();
  const size_t n = plan.links.size();
  const size_t dof_count = static_cast<size_t>(plan.dofCount());

  PdController c;
  c.offsets_ = plan.dofOffsets();
  c.planted_points_ = settings.planted_contact_points;
  c.tipping_margin_ = settings.tipping_margin;
  c.types_.resize(n);
  c.limits_.assign(n, 0.0);
  std::vector<double> kp_nominal(dof_count, 0.0);
  for (size_t li = 0; li < n; ++li) {
    const Link& link = plan.links[li];
    c.types_[li] = link.type;
    if (link.foot) {
      c.feet_.push_back(static_cast<int>(li));
      c.foot_shapes_.push_back(link.shape);
    }
    if (li == 0) continue;
    double subtree_mass = 0.0;
    for (size_t k = li; k < n; ++k)
      if (isAncestorLink(plan, static_cast<int>(li), static_cast<int>(k)))
        subtree_mass += plan.links[k].mass_kg;
    const double carried = link.supports ? plan.total_mass_kg : subtree_mass;
    const double load = carried * settings.gravity_m_s2 * plan.size_m;
    c.limits_[li] =
        (link.supports ? settings.support_torque_scale : settings.limb_torque_scale) * load;
    for (int d = 0; d < physics::dofCount(link.type); ++d)
      kp_nominal[static_cast<size_t>(c.offsets_[li] + d)] = settings.stiffness_per_load * load;
  }

  // One gain set per state of the feet (which are planted), up to 4 feet; more feet: none / all.
  const size_t feet = c.feet_.size();
  const unsigned states = feet <= kMaxFeetStates ? 1u << feet : 2u;
  for (unsigned state = 0; state < states; ++state) {
    std::vector<int> welded;
    for (size_t f = 0; f < feet; ++f)
      if (feet <= kMaxFeetStates ? (state >> f) & 1u : state == 1u) welded.push_back(c.feet_[f]);
    const std::vector<double> minv = world.jointInverseInertia(welded);
    for (size_t i = 0; i < dof_count; ++i)
      if (!std::isfinite(minv[i * dof_count + i]))
        return Status::error("controller: the joint-space inertia is not finite (degenerate plan)");
    c.gain_sets_.push_back(gainsFor(kp_nominal, minv, settings, 1.0 / world.dt()));
    // A foot's own joint keeps its free gains even when planted: a foot that rocks onto an edge
    // is light again at once, and one step of planted gains on it diverges (measured).
    if (state > 0)
      for (int li : welded)
        for (int d = 0; d < physics::dofCount(plan.links[static_cast<size_t>(li)].type); ++d) {
          const size_t i = static_cast<size_t>(c.offsets_[static_cast<size_t>(li)] + d);
          c.gain_sets_.back()[i] = c.gain_sets_[0][i];
        }
  }
  return c;
}

unsigned PdController::contactState(std::span<const std::uint8_t> link_contacts) const {
  const size_t feet = feet_.size();
  unsigned state = 0;
  bool all = feet > 0;
  for (size_t f = 0; f < feet; ++f) {
    const bool down = link_contacts[static_cast<size_t>(feet_[f])] >= planted_points_;
    if (down) state |= 1u << std::min<size_t>(f, 31);
    all = all && down;
  }
  if (feet > kMaxFeetStates) return all ? 1u : 0u;
  return state;
}

void PdController::computeTorques(const World& world, const LinkPose& target,
                                  std::span<double> torques) const {
  const size_t n = types_.size();
  const LinkPose current = world.jointPositions();
  std::vector<double> velocities(static_cast<size_t>(world.dofCount()));
  world.jointVelocities(velocities);
  const std::vector<std::uint8_t>& link_contacts = world.linkContacts();
  const std::vector<double>& normal_forces = world.linkNormalForces();
  const unsigned state = contactState(link_contacts);
  const std::vector<DofGains>& gains = gain_sets_[state];

  for (size_t li = 1; li < n; ++li) {
    const size_t o = static_cast<size_t>(offsets_[li]);
    if (types_[li] == JointType::kBall) {
      const glm::dvec3 error = shortRotationVector(
          glm::normalize(glm::inverse(current.rotations[li]) * target.rotations[li]));
      glm::dvec3 tau;
      for (int d = 0; d < 3; ++d) {
        const DofGains& g = gains[o + static_cast<size_t>(d)];
        tau[d] = g.kp * error[d] - g.kd * velocities[o + static_cast<size_t>(d)];
      }
      const double norm = glm::length(tau);
      if (norm > limits_[li]) tau *= limits_[li] / norm;
      // A planted foot: no more torque than its ground force holds without tipping it.
      for (size_t f = 0; f < feet_.size(); ++f) {
        if (feet_[f] != static_cast<int>(li) || link_contacts[li] < planted_points_) continue;
        const Shape& sole = foot_shapes_[f];
        const double force = std::max(0.0, normal_forces[li]) * tipping_margin_;
        glm::dvec3 t = glm::inverse(sole.rotation) * tau;  // sole frame: x side, y up, z forward
        const glm::dvec3 e = sole.half_extents;
        t.x = std::clamp(t.x, -force * e.z, force * e.z);              // pitch over toe or heel
        t.z = std::clamp(t.z, -force * e.x, force * e.x);              // roll over the sole's side
        t.y = std::clamp(t.y, -0.5 * force * e.z, 0.5 * force * e.z);  // yaw against friction
        tau = sole.rotation * t;
      }
      for (int d = 0; d < 3; ++d) torques[o + static_cast<size_t>(d)] = tau[d];
    } else if (types_[li] == JointType::kHinge) {
      const DofGains& g = gains[o];
      const double error =
          std::remainder(target.angles[li] - current.angles[li], 2.0 * std::numbers::pi);
      const double tau = g.kp * error - g.kd * velocities[o];
      torques[o] = std::clamp(tau, -limits_[li], limits_[li]);
    }
  }
}

}  // namespace sinew::physics
