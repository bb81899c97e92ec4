#include "ball_joint_limit.h"

#include <algorithm>
#include <cmath>

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include "sinew/core/rotation.h"

namespace sinew::physics {
namespace {

// A row is made when its side is this close (radians), or would be reached within the step at
// the joint's present speed: inside that band it lets the joint close exactly the gap in one
// step (a speculative contact), so a fast joint stops on its side instead of past it.
constexpr btScalar kActivationRad = 0.05;

// Rotation vectors longer than this are near the log map's fold at pi, where a small turn flips
// v to the far side of the range: no rows there (a plan's ranges stay well inside it).
constexpr btScalar kFoldRad = 0.9 * SIMD_PI;

// Jr^-1(v): the rotation vector's rate per body angular velocity, d v / dt = Jr^-1(v) w, for
// q(t + dt) = q(t) exp(w dt) (Bullet's spherical joints integrate their velocity in the link
// frame so). Jr^-1 = I + [v]/2 + (1/t^2 - (1 + cos t) / (2 t sin t)) [v]^2, t = |v|.
btMatrix3x3 inverseRightJacobian(const btVector3& v) {
  const btScalar t = v.length();
  // The [v]^2 coefficient; its series below 1e-4 rad (1/12 + t^2/720) avoids 0/0.
  const btScalar c = t < 1e-4 ? 1.0 / 12.0 + t * t / 720.0
                              : 1.0 / (t * t) - (1.0 + std::cos(t)) / (2.0 * t * std::sin(t));
  const btMatrix3x3 k(0.0, -v.z(), v.y(),  //
                      v.z(), 0.0, -v.x(),  //
                      -v.y(), v.x(), 0.0);
  btMatrix3x3 j = k * k;
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col)
      j[r][col] = (r == col ? 1.0 : 0.0) + 0.5 * k[r][col] + c * j[r][col];
  return j;
}

int islandOf(const btMultiBody* body) {
  if (const btMultiBodyLinkCollider* base = body->getBaseCollider()) return base->getIslandTag();
  for (int i = 0; i < body->getNumLinks(); ++i)
    if (const btMultiBodyLinkCollider* c = body->getLink(i).m_collider) return c->getIslandTag();
  return -1;
}

}  // namespace

BallJointLimit::BallJointLimit(btMultiBody* body, int link, const btQuaternion& center,
                               const btVector3& lower, const btVector3& upper, btScalar max_impulse)
    // Six rows: row k keeps axis k above its lower side, row 3 + k below its upper side.
    : btMultiBodyConstraint(body, body, link, body->getLink(link).m_parent, 6, true,
                            MULTIBODY_CONSTRAINT_SPHERICAL_LIMIT),
      center_inverse_(center.inverse()),
      lower_(lower),
      upper_(upper) {
  m_maxAppliedImpulse = max_impulse;
}

void BallJointLimit::finalizeMultiDof() {
  // The jacobians (zero but for the joint's own three entries, written per step) live in m_data.
  allocateJacobiansMultiDof();
  m_numDofsFinalized = m_jacSizeBoth;
}

int BallJointLimit::getIslandIdA() const {
  return islandOf(m_bodyA);
}
int BallJointLimit::getIslandIdB() const {
  return islandOf(m_bodyB);
}

btVector3 BallJointLimit::coordinates() const {
  const btScalar* p = m_bodyA->getJointPosMultiDof(m_linkA);
  btQuaternion q = center_inverse_ * btQuaternion(p[0], p[1], p[2], p[3]);
  q.normalize();
  const glm::dvec3 v = shortRotationVector(glm::dquat(q.w(), q.x(), q.y(), q.z()));
  return btVector3(v.x, v.y, v.z);
}

void BallJointLimit::createConstraintRows(btMultiBodyConstraintArray& rows,
                                          btMultiBodyJacobianData& data,
                                          const btContactSolverInfo& info) {
  if (m_numDofsFinalized != m_jacSizeBoth) finalizeMultiDof();
  const btVector3 v = coordinates();
  if (v.length() > kFoldRad) return;
  const btMatrix3x3 rate = inverseRightJacobian(v);
  const btScalar* w = m_bodyA->getJointVelMultiDof(m_linkA);
  const btVector3 v_dot = rate * btVector3(w[0], w[1], w[2]);
  const btScalar dt = info.m_timeStep;
  const int offset = 6 + m_bodyA->getLink(m_linkA).m_dofOffset;
  const btVector3 zero(0.0, 0.0, 0.0);
  for (int row = 0; row < 6; ++row) {
    const int axis = row % 3;
    const btScalar sign = row < 3 ? 1.0 : -1.0;  // the gap grows with +v on the lower side
    const btScalar gap = row < 3 ? v[axis] - lower_[axis] : upper_[axis] - v[axis];
    const btScalar closing = std::min(sign * v_dot[axis], btScalar(0.0));
    if (gap + closing * dt > kActivationRad) continue;
    // The gap's rate per unit joint velocity: row `axis` of Jr^-1, signed by the side.
    btScalar* jacobian = jacobianA(row);
    for (int d = 0; d < 3; ++d) jacobian[offset + d] = sign * rate[axis][d];
    btMultiBodySolverConstraint& constraint = rows.expandNonInitializing();
    constraint.m_orgConstraint = this;
    constraint.m_orgDofIndex = row;
    const btScalar gap_rate =
        fillMultiBodyConstraint(constraint, data, jacobian, jacobianB(row), zero, zero, zero, zero,
                                0.0, info, 0.0, m_maxAppliedImpulse);
    constraint.m_contactNormal1.setZero();
    constraint.m_contactNormal2.setZero();
    constraint.m_relpos1CrossNormal.setZero();
    constraint.m_relpos2CrossNormal.setZero();
    // Inside: close at most the gap in this step. Past the side: come back by the solver's error
    // reduction share of the overshoot per step, as Bullet's hinge limits do.
    const btScalar wanted = gap >= 0.0 ? -gap / dt : -gap * info.m_erp / dt;
    constraint.m_rhs = (wanted - gap_rate) * constraint.m_jacDiagABInv;
    constraint.m_rhsPenetration = 0.0;
  }
}

}  // namespace sinew::physics
