// A ball joint's range as a constraint Bullet's solver resolves with the contacts and the servos
// (private to the physics module: Bullet types stay out of the public headers).
//
// The range is a box on the rotation vector v = log(center^-1 q) of the joint coordinate q about
// the middle of its range (Link::ball_center): lower_k <= v_k <= upper_k per axis. Each side of
// each axis is a unilateral row: an impulse that only pushes the joint back in, acting between
// the link and its parent (an internal joint torque, like the hinges' Bullet limits), never on
// the base. Rows exist only near a side, so a joint inside its range costs the solver nothing.
//
// Why not Bullet's btMultiBodySphericalJointLimit: it is symmetric about the joint's zero pose
// and its rows push along the link's axes while it measures Euler angles of a swing/twist split;
// the two disagree away from the zero pose. Measured on one free link under sustained joint
// torques in 30 random directions: worst overshoot 0.09 rad at +-0.7 rad limits, and at +-1.1 rad
// the link escapes its range altogether (0.85 rad over) and spins. Here each row's direction is
// the exact derivative of the measured coordinate: d v / dt = Jr^-1(v) w, w the joint's angular
// velocity in the link frame (Bullet's spherical joint velocity).
#pragma once

#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>

namespace sinew::physics {

class BallJointLimit final : public btMultiBodyConstraint {
 public:
  // `link`: a Bullet link index (>= 0) with a spherical joint. `center`: the range's middle in
  // joint coordinates; `lower` < `upper`: radians per axis of log(center^-1 q).
  // `max_impulse`: the largest impulse a row applies in one step, N m s.
  BallJointLimit(btMultiBody* body, int link, const btQuaternion& center, const btVector3& lower,
                 const btVector3& upper, btScalar max_impulse);

  void finalizeMultiDof() override;
  int getIslandIdA() const override;
  int getIslandIdB() const override;
  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override;
  void debugDraw(btIDebugDraw*) override {}

  // The coordinates the range bounds (log(center^-1 q), radians) at the joint's present pose.
  btVector3 coordinates() const;

 private:
  btQuaternion center_inverse_;
  btVector3 lower_;
  btVector3 upper_;
};

}  // namespace sinew::physics
