#include "sinew/physics/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodySphericalJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include "ball_joint_limit.h"

namespace sinew::physics {
namespace {

// Collision groups: the ground collides with the character; the character's links do not collide
// with each other (self-collision off in this slice).
constexpr int kGroundGroup = 1;
constexpr int kCharacterGroup = 2;

btVector3 toBt(const glm::dvec3& v) {
  return btVector3(v.x, v.y, v.z);
}
glm::dvec3 toGlm(const btVector3& v) {
  return {v.x(), v.y(), v.z()};
}
btQuaternion toBt(const glm::dquat& q) {
  return btQuaternion(q.x, q.y, q.z, q.w);
}
glm::dquat toGlm(const btQuaternion& q) {
  return glm::dquat(q.w(), q.x(), q.y(), q.z());
}

double radians(double deg) { return deg * std::numbers::pi / 180.0; }

// Rough terrain: one height per grid node, uniform in [0, amplitude] from the seed (the top 53
// bits of the engine's output: the same on every platform).
constexpr double kRoughExtentM = 40.0;

std::vector<double> roughHeights(const TerrainSettings& t, int& nodes) {
  nodes = static_cast<int>(std::ceil(kRoughExtentM / t.cell_m)) + 1;
  std::mt19937_64 engine(t.seed);
  std::vector<double> heights(static_cast<size_t>(nodes) * static_cast<size_t>(nodes));
  for (double& h : heights) h = t.amplitude_m * static_cast<double>(engine() >> 11) * 0x1.0p-53;
  return heights;
}

}  // namespace

const char* terrainKindName(TerrainSettings::Kind kind) {
  switch (kind) {
    case TerrainSettings::Kind::kFlat:
      return "flat";
    case TerrainSettings::Kind::kSlope:
      return "slope";
    case TerrainSettings::Kind::kSteps:
      return "steps";
    case TerrainSettings::Kind::kRough:
      return "rough";
  }
  return "flat";
}

Status TerrainSettings::validate() const {
  if (!(std::isfinite(slope_deg) && std::abs(slope_deg) < 45.0))
    return Status::error("terrain.slope_deg must be in (-45, 45)");
  if (!(std::isfinite(step_height_m) && step_height_m > 0.0 && step_height_m <= 1.0))
    return Status::error("terrain.step_height_m must be in (0, 1]");
  if (!(std::isfinite(step_depth_m) && step_depth_m >= 0.1))
    return Status::error("terrain.step_depth_m must be >= 0.1");
  if (step_count < 1 || step_count > 1000) return Status::error("terrain.step_count must be in 1..1000");
  if (!std::isfinite(step_start_m)) return Status::error("terrain.step_start_m must be finite");
  if (!(std::isfinite(amplitude_m) && amplitude_m > 0.0 && amplitude_m <= 1.0))
    return Status::error("terrain.amplitude_m must be in (0, 1]");
  if (!(std::isfinite(cell_m) && cell_m >= 0.02 && cell_m <= 2.0))
    return Status::error("terrain.cell_m must be in [0.02, 2]");
  return Status();
}

Status WorldSettings::validate() const {
  if (!(std::isfinite(step_hz) && step_hz >= 30.0 && step_hz <= 10000.0))
    return Status::error("step_hz must be in 30..10000");
  if (!(std::isfinite(gravity_m_s2) && gravity_m_s2 >= 0.0))
    return Status::error("gravity_m_s2 must be >= 0");
  if (!(std::isfinite(ground_friction) && ground_friction >= 0.0))
    return Status::error("ground_friction must be >= 0");
  if (!std::isfinite(ground_height_m)) return Status::error("ground_height_m must be finite");
  if (Status t = terrain.validate(); !t.ok()) return t;
  if (solver_iterations < 1 || solver_iterations > 1000)
    return Status::error("solver_iterations must be in 1..1000");
  if (!(std::isfinite(ground_clearance_m) && ground_clearance_m >= 0.0))
    return Status::error("ground_clearance_m must be >= 0");
  return Status();
}

// Members are declared in construction order, so they are destroyed in reverse; the destructor
// first removes every object from the Bullet world, which must outlive them while they are in it.
struct World::Impl {
  BodyPlan plan;
  WorldSettings settings;
  double dt = 0.0;
  long long steps = 0;
  std::vector<int> dof_offsets;
  int dofs = 0;

  std::unique_ptr<btDefaultCollisionConfiguration> config;
  std::unique_ptr<btCollisionDispatcher> dispatcher;
  std::unique_ptr<btDbvtBroadphase> broadphase;
  std::unique_ptr<btMultiBodyConstraintSolver> solver;
  std::unique_ptr<btMultiBodyDynamicsWorld> world;
  std::vector<std::unique_ptr<btCollisionShape>> ground_shapes;
  std::vector<std::unique_ptr<btCollisionObject>> grounds;  // plane first, then steps
  std::vector<double> heights;                              // rough terrain grid (x fastest)
  int height_nodes = 0;
  std::vector<std::unique_ptr<btCollisionShape>> child_shapes;
  std::vector<std::unique_ptr<btCompoundShape>> shapes;
  std::unique_ptr<btMultiBody> body;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;  // (links), base first
  std::vector<std::unique_ptr<btMultiBodyConstraint>> limits;       // hinge and ball ranges
  std::vector<std::unique_ptr<btMultiBodyConstraint>> servos;  // (links), null: no servo
  double servo_rate = 0.0;
  std::vector<double> servo_limits;  // (links) N m, as enableServos was given them

  std::vector<std::pair<int, glm::dvec3>> pending_pushes;  // (link, impulse N s) for the next step
  glm::dvec3 pushed_impulse{0.0};                         // every push so far, N s
  std::vector<std::uint8_t> contacts;
  std::vector<double> normal_forces;
  glm::dvec3 contact_impulse{0.0};
  ExternalLoads loads;

  ~Impl() {
    if (!world) return;
    for (auto& limit : limits) world->removeMultiBodyConstraint(limit.get());
    for (auto& servo : servos)
      if (servo) world->removeMultiBodyConstraint(servo.get());
    if (body) world->removeMultiBody(body.get());
    for (auto& collider : colliders) world->removeCollisionObject(collider.get());
    for (auto& ground : grounds) world->removeCollisionObject(ground.get());
  }

  void addGround(std::unique_ptr<btCollisionShape> shape, const btTransform& transform) {
    auto object = std::make_unique<btCollisionObject>();
    object->setCollisionShape(shape.get());
    object->setWorldTransform(transform);
    object->setFriction(settings.ground_friction);
    object->setRestitution(0.0);
    world->addCollisionObject(object.get(), kGroundGroup, kCharacterGroup);
    ground_shapes.push_back(std::move(shape));
    grounds.push_back(std::move(object));
  }

  void buildGround() {
    const TerrainSettings& t = settings.terrain;
    const double h0 = settings.ground_height_m;
    btTransform identity;
    identity.setIdentity();
    switch (t.kind) {
      case TerrainSettings::Kind::kFlat:
        addGround(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), h0), identity);
        break;
      case TerrainSettings::Kind::kSlope: {
        const double a = radians(t.slope_deg);
        // Normal tilted back: height rises by tan(a) per metre of +Z.
        addGround(std::make_unique<btStaticPlaneShape>(btVector3(0, std::cos(a), -std::sin(a)),
                                                       h0 * std::cos(a)),
                  identity);
        break;
      }
      case TerrainSettings::Kind::kSteps: {
        addGround(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), h0), identity);
        for (int k = 0; k < t.step_count; ++k) {
          // Step k: a block from the ground to its top, from its riser to the far end (each block
          // runs under the ones above it, so no gaps open between them).
          const double top = h0 + (k + 1) * t.step_height_m;
          const double z0 = t.step_start_m + k * t.step_depth_m;
          const double z1 = t.step_start_m + t.step_count * t.step_depth_m + 5.0;
          const double half_y = 0.5 * (top - h0 + 1.0);
          btTransform at;
          at.setIdentity();
          at.setOrigin(btVector3(0.0, top - half_y, 0.5 * (z0 + z1)));
          addGround(std::make_unique<btBoxShape>(btVector3(50.0, half_y, 0.5 * (z1 - z0))), at);
        }
        break;
      }
      case TerrainSettings::Kind::kRough: {
        heights = roughHeights(t, height_nodes);
        // The heightfield's local origin is the middle of its height range: shift it up.
        auto shape = std::make_unique<btHeightfieldTerrainShape>(
            height_nodes, height_nodes, heights.data(), 0.0, t.amplitude_m, 1, false);
        shape->setLocalScaling(btVector3(t.cell_m, 1.0, t.cell_m));
        btTransform at;
        at.setIdentity();
        at.setOrigin(btVector3(0.0, h0 + 0.5 * t.amplitude_m, 0.0));
        addGround(std::move(shape), at);
        break;
      }
    }
  }

  double groundHeight(double x, double z) const {
    const TerrainSettings& t = settings.terrain;
    const double h0 = settings.ground_height_m;
    switch (t.kind) {
      case TerrainSettings::Kind::kFlat:
        return h0;
      case TerrainSettings::Kind::kSlope:
        return h0 + z * std::tan(radians(t.slope_deg));
      case TerrainSettings::Kind::kSteps: {
        const double k = std::floor((z - t.step_start_m) / t.step_depth_m) + 1.0;
        return h0 + std::clamp(k, 0.0, static_cast<double>(t.step_count)) * t.step_height_m;
      }
      case TerrainSettings::Kind::kRough: {
        // Bilinear over the grid, centred on the origin, as Bullet triangulates it (close enough
        // for placing the character: its lowest point clears the highest of the four nodes).
        const double half = 0.5 * (height_nodes - 1) * t.cell_m;
        const double gx = std::clamp((x + half) / t.cell_m, 0.0, height_nodes - 1.0);
        const double gz = std::clamp((z + half) / t.cell_m, 0.0, height_nodes - 1.0);
        const int ix = std::min(static_cast<int>(gx), height_nodes - 2);
        const int iz = std::min(static_cast<int>(gz), height_nodes - 2);
        double top = 0.0;
        for (int dz = 0; dz < 2; ++dz)
          for (int dx = 0; dx < 2; ++dx)
            top = std::max(top, heights[static_cast<size_t>((iz + dz) * height_nodes + ix + dx)]);
        return h0 + top;
      }
    }
    return h0;
  }

  // The multibody: the base and one Bullet link per plan link, jointed as the plan says.
  void buildBody() {
    const size_t n = plan.links.size();
    const Link& base = plan.links[0];
    body = std::make_unique<btMultiBody>(static_cast<int>(n) - 1, base.mass_kg, toBt(base.inertia),
                                         /*fixedBase=*/false, /*canSleep=*/false);
    btMultiBody& mb = *body;
    for (size_t li = 1; li < n; ++li) {
      const Link& link = plan.links[li];
      const Link& parent = plan.links[static_cast<size_t>(link.parent)];
      const int i = bulletLink(static_cast<int>(li));
      const btQuaternion parent_to_this = toBt(glm::inverse(link.zero_rotation));
      const btVector3 parent_com_to_pivot = toBt(link.pivot - parent.com);
      const btVector3 pivot_to_com = toBt(link.com);
      const int parent_index = bulletLink(link.parent);
      switch (link.type) {
        case JointType::kBall:
          mb.setupSpherical(i, link.mass_kg, toBt(link.inertia), parent_index, parent_to_this,
                            parent_com_to_pivot, pivot_to_com, true);
          break;
        case JointType::kHinge:
          mb.setupRevolute(i, link.mass_kg, toBt(link.inertia), parent_index, parent_to_this,
                           toBt(link.hinge_axis), parent_com_to_pivot, pivot_to_com, true);
          break;
        default:
          mb.setupFixed(i, link.mass_kg, toBt(link.inertia), parent_index, parent_to_this,
                        parent_com_to_pivot, pivot_to_com, true);
          break;
      }
    }
    mb.finalizeMultiDof();
    // Bullet damps multibody velocities by default (0.04): an external effect. Off.
    mb.setLinearDamping(0.0);
    mb.setAngularDamping(0.0);
    mb.setHasSelfCollision(false);
    mb.setUseGyroTerm(true);
  }

  // `initial`'s rotations and angles with the base at `base_position`, every velocity zero.
  void setPose(const LinkPose& initial, const glm::dvec3& base_position) {
    btMultiBody& mb = *body;
    const glm::dquat r = glm::normalize(initial.base_rotation);
    mb.setBasePos(toBt(base_position + r * plan.links[0].com));
    mb.setWorldToBaseRot(toBt(glm::inverse(r)));
    mb.setBaseVel(btVector3(0, 0, 0));
    mb.setBaseOmega(btVector3(0, 0, 0));
    for (size_t li = 1; li < plan.links.size(); ++li) {
      const int i = bulletLink(static_cast<int>(li));
      const Link& link = plan.links[li];
      if (link.type == JointType::kBall) {
        const glm::dquat q = glm::normalize(initial.rotations[li]);
        const double pos[4] = {q.x, q.y, q.z, q.w};
        const double zero[3] = {0.0, 0.0, 0.0};
        mb.setJointPosMultiDof(i, pos);
        mb.setJointVelMultiDof(i, zero);
      } else if (link.type == JointType::kHinge) {
        mb.setJointPos(i, initial.angles[li]);
        mb.setJointVel(i, 0.0);
      }
    }
  }

  // Colliders: one compound per link (the shape offset from the centre of mass frame).
  void buildColliders() {
    btMultiBody& mb = *body;
    for (size_t li = 0; li < plan.links.size(); ++li) {
      const Link& link = plan.links[li];
      std::unique_ptr<btCollisionShape> child;
      switch (link.shape.type) {
        case ShapeType::kCapsule:
          child = std::make_unique<btCapsuleShape>(link.shape.radius, 2.0 * link.shape.half_length);
          break;
        case ShapeType::kBox:
          child = std::make_unique<btBoxShape>(toBt(link.shape.half_extents));
          break;
        case ShapeType::kSphere:
          child = std::make_unique<btSphereShape>(link.shape.radius);
          break;
      }
      auto compound = std::make_unique<btCompoundShape>(false, 1);
      compound->addChildShape(
          btTransform(toBt(link.shape.rotation), toBt(link.shape.center - link.com)), child.get());
      const int i = bulletLink(static_cast<int>(li));
      auto collider = std::make_unique<btMultiBodyLinkCollider>(&mb, i);
      collider->setCollisionShape(compound.get());
      collider->setFriction(settings.ground_friction);
      collider->setRestitution(0.0);
      world->addCollisionObject(collider.get(), kCharacterGroup, kGroundGroup);
      if (i < 0)
        mb.setBaseCollider(collider.get());
      else
        mb.getLink(i).m_collider = collider.get();
      child_shapes.push_back(std::move(child));
      shapes.push_back(std::move(compound));
      colliders.push_back(std::move(collider));
    }
  }

  // Joint ranges: Bullet-solved constraints between each link and its parent (internal, like
  // the servos). Both keep Bullet's default largest impulse per step (100 N m s).
  void buildLimits() {
    for (size_t li = 1; li < plan.links.size(); ++li) {
      const Link& link = plan.links[li];
      const int i = bulletLink(static_cast<int>(li));
      std::unique_ptr<btMultiBodyConstraint> limit;
      if (link.type == JointType::kHinge) {
        limit = std::make_unique<btMultiBodyJointLimitConstraint>(body.get(), i, link.hinge_lower,
                                                                  link.hinge_upper);
      } else if (link.type == JointType::kBall) {
        limit = std::make_unique<BallJointLimit>(body.get(), i, toBt(link.ball_center),
                                                 toBt(link.ball_lower), toBt(link.ball_upper),
                                                 btScalar(100.0));
      } else {
        continue;
      }
      world->addMultiBodyConstraint(limit.get());
      limits.push_back(std::move(limit));
    }
  }

  // Lowers or raises the character so its lowest point is ground_clearance_m above the highest
  // ground within half its size of the base.
  void placeOnGround(const LinkPose& initial) {
    double lowest = std::numeric_limits<double>::max();
    for (size_t li = 0; li < plan.links.size(); ++li)
      lowest =
          std::min(lowest, lowestPoint(plan.links[li].shape, linkTransform(static_cast<int>(li))));
    glm::dvec3 base_position = initial.base_position;
    double ground = -std::numeric_limits<double>::max();
    const double reach = 0.5 * std::max(plan.size_m, 0.1);
    for (double dx : {-reach, 0.0, reach})
      for (double dz : {-reach, 0.0, reach})
        ground = std::max(ground, groundHeight(base_position.x + dx, base_position.z + dz));
    base_position.y += ground + settings.ground_clearance_m - lowest;
    setPose(initial, base_position);
    refreshTransforms();
  }

  // Link index in Bullet (-1 base) for plan link li.
  static int bulletLink(int li) { return li - 1; }

  void refreshTransforms() {
    btAlignedObjectArray<btQuaternion> scratch_q;
    btAlignedObjectArray<btVector3> scratch_m;
    body->forwardKinematics(scratch_q, scratch_m);
    body->updateCollisionObjectWorldTransforms(scratch_q, scratch_m);
  }

  glm::dmat4 linkTransform(int li) const {
    const btTransform& t = colliders[li]->getWorldTransform();
    const glm::dquat r = toGlm(t.getRotation());
    const glm::dvec3 origin = toGlm(t.getOrigin()) - r * plan.links[li].com;
    glm::dmat4 m = glm::mat4_cast(r);
    m[3] = glm::dvec4(origin, 1.0);
    return m;
  }

  void readContacts() {
    std::fill(contacts.begin(), contacts.end(), std::uint8_t{0});
    std::fill(normal_forces.begin(), normal_forces.end(), 0.0);
    contact_impulse = glm::dvec3(0.0);
    const int manifolds = dispatcher->getNumManifolds();
    for (int m = 0; m < manifolds; ++m) {
      const btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(m);
      const auto* a = btMultiBodyLinkCollider::upcast(manifold->getBody0());
      const auto* b = btMultiBodyLinkCollider::upcast(manifold->getBody1());
      const btMultiBodyLinkCollider* character = a != nullptr ? a : b;
      if (character == nullptr) continue;
      const double sign = a != nullptr ? 1.0 : -1.0;  // the normal points from B to A
      for (int p = 0; p < manifold->getNumContacts(); ++p) {
        const btManifoldPoint& pt = manifold->getContactPoint(p);
        std::uint8_t& count = contacts[static_cast<size_t>(character->m_link + 1)];
        if ((pt.getAppliedImpulse() > 0.0 || pt.getDistance() <= 0.0) && count < 255) ++count;
        normal_forces[static_cast<size_t>(character->m_link + 1)] += pt.getAppliedImpulse() / dt;
        contact_impulse += sign * (toGlm(pt.m_normalWorldOnB) * pt.getAppliedImpulse() +
                                   toGlm(pt.m_lateralFrictionDir1) * pt.m_appliedImpulseLateral1 +
                                   toGlm(pt.m_lateralFrictionDir2) * pt.m_appliedImpulseLateral2);
      }
    }
  }

  void recordExternalLoads() {
    loads.max_base_force_n =
        std::max(loads.max_base_force_n, double(body->getBaseForce().length()));
    loads.max_base_torque_nm =
        std::max(loads.max_base_torque_nm, double(body->getBaseTorque().length()));
    for (int i = 0; i < body->getNumLinks(); ++i) {
      loads.max_link_force_n =
          std::max(loads.max_link_force_n, double(body->getLinkForce(i).length()));
      loads.max_link_torque_nm =
          std::max(loads.max_link_torque_nm, double(body->getLinkTorque(i).length()));
    }
  }
};

World::World(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
World::~World() = default;

namespace {

// One rotation and angle per link, finite, rotations of unit length.
Status checkInitialPose(const BodyPlan& plan, const LinkPose& initial) {
  const size_t n = plan.links.size();
  if (initial.rotations.size() != n || initial.angles.size() != n)
    return Status::error("initial pose: rotations and angles need one entry per link (" +
                         std::to_string(n) + ")");
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(initial.angles[i]) ||
        !(std::abs(glm::length(initial.rotations[i]) - 1.0) < 1e-6))
      return Status::error("initial pose: link " + std::to_string(i) + " (" + plan.links[i].name +
                           ") has a non-finite angle or a non-unit rotation");
  if (!std::isfinite(initial.base_position.x) || !std::isfinite(initial.base_position.y) ||
      !std::isfinite(initial.base_position.z) ||
      !(std::abs(glm::length(initial.base_rotation) - 1.0) < 1e-6))
    return Status::error("initial pose: base position must be finite, base rotation unit");
  return {};
}

}  // namespace

Result<std::unique_ptr<World>> World::create(const BodyPlan& plan, const LinkPose& initial,
                                             const WorldSettings& settings) {
  if (Status s = settings.validate(); !s.ok())
    return Status::error("world settings: " + s.message());
  if (Status s = plan.validate(); !s.ok()) return Status::error("body plan: " + s.message());
  if (Status s = checkInitialPose(plan, initial); !s.ok()) return s;

  auto impl = std::make_unique<Impl>();
  Impl& w = *impl;
  const size_t n = plan.links.size();
  w.plan = plan;
  w.settings = settings;
  w.dt = 1.0 / settings.step_hz;
  w.dof_offsets = plan.dofOffsets();
  w.dofs = plan.dofCount();
  w.contacts.assign(n, 0);
  w.normal_forces.assign(n, 0.0);

  w.config = std::make_unique<btDefaultCollisionConfiguration>();
  w.dispatcher = std::make_unique<btCollisionDispatcher>(w.config.get());
  w.broadphase = std::make_unique<btDbvtBroadphase>();
  w.solver = std::make_unique<btMultiBodyConstraintSolver>();
  w.world = std::make_unique<btMultiBodyDynamicsWorld>(w.dispatcher.get(), w.broadphase.get(),
                                                       w.solver.get(), w.config.get());
  w.world->setGravity(btVector3(0.0, -settings.gravity_m_s2, 0.0));
  w.world->getSolverInfo().m_numIterations = settings.solver_iterations;

  w.buildGround();
  w.buildBody();
  w.setPose(initial, initial.base_position);
  w.buildColliders();
  w.world->addMultiBody(w.body.get());
  w.buildLimits();
  w.refreshTransforms();
  if (settings.place_on_ground) w.placeOnGround(initial);
  return std::unique_ptr<World>(new World(std::move(impl)));
}

void World::step(std::span<const double> joint_torques) {
  Impl& w = *impl_;
  btMultiBody& mb = *w.body;
  // Nothing but joint torques may be applied: the accumulators must be empty here.
  w.recordExternalLoads();
  for (size_t li = 1; li < w.plan.links.size(); ++li) {
    const int i = Impl::bulletLink(static_cast<int>(li));
    const size_t o = static_cast<size_t>(w.dof_offsets[li]);
    switch (w.plan.links[li].type) {
      case JointType::kBall:
        for (int d = 0; d < 3; ++d) mb.addJointTorqueMultiDof(i, d, joint_torques[o + d]);
        break;
      case JointType::kHinge:
        mb.addJointTorque(i, joint_torques[o]);
        break;
      default:
        break;
    }
  }
  // Scheduled pushes, after the check: a force of impulse / dt at the link's centre of mass for
  // this one step.
  for (const auto& [li, impulse] : w.pending_pushes) {
    const btVector3 force = toBt(impulse / w.dt);
    if (li == 0)
      mb.addBaseForce(force);
    else
      mb.addLinkForce(Impl::bulletLink(li), force);
    w.pushed_impulse += impulse;
  }
  w.pending_pushes.clear();
  // maxSubSteps 0: exactly one step of dt, no interpolation, no accumulated remainder.
  w.world->stepSimulation(w.dt, 0, w.dt);
  ++w.steps;
  w.readContacts();
}

Status World::push(int link, const glm::dvec3& impulse_ns) {
  Impl& w = *impl_;
  if (link < 0 || link >= static_cast<int>(w.plan.links.size()))
    return Status::error("push: link " + std::to_string(link) + " is not a link of the character (0.." +
                         std::to_string(w.plan.links.size() - 1) + ")");
  if (!std::isfinite(impulse_ns.x) || !std::isfinite(impulse_ns.y) || !std::isfinite(impulse_ns.z))
    return Status::error("push: the impulse must be finite");
  w.pending_pushes.emplace_back(link, impulse_ns);
  return Status();
}

glm::dvec3 World::pushedImpulse() const {
  return impl_->pushed_impulse;
}

Status World::setVelocities(const glm::dvec3& base_linear, const glm::dvec3& base_angular,
                            std::span<const double> joint_velocities) {
  Impl& w = *impl_;
  if (w.steps != 0) return Status::error("initial velocities: set them before the first step");
  if (joint_velocities.size() != static_cast<size_t>(w.dofs))
    return Status::error("initial velocities: need one joint velocity per degree of freedom (" +
                         std::to_string(w.dofs) + ")");
  for (double v : joint_velocities)
    if (!std::isfinite(v)) return Status::error("initial velocities: not finite");
  btMultiBody& mb = *w.body;
  // The base's linear velocity is that of its centre of mass, not of the base frame's origin.
  const glm::dmat4 base = w.linkTransform(0);
  const glm::dvec3 com_offset = glm::dmat3(base) * w.plan.links[0].com;
  mb.setBaseVel(toBt(base_linear + glm::cross(base_angular, com_offset)));
  mb.setBaseOmega(toBt(base_angular));
  for (size_t li = 1; li < w.plan.links.size(); ++li) {
    const int dofs = physics::dofCount(w.plan.links[li].type);
    if (dofs == 0) continue;
    double v[3] = {0.0, 0.0, 0.0};
    for (int d = 0; d < dofs; ++d) v[d] = joint_velocities[static_cast<size_t>(w.dof_offsets[li] + d)];
    mb.setJointVelMultiDof(Impl::bulletLink(static_cast<int>(li)), v);
  }
  return Status();
}

Status World::enableServos(std::span<const double> max_torque_nm, double rate) {
  Impl& w = *impl_;
  const size_t n = w.plan.links.size();
  if (w.steps != 0) return Status::error("servos: enable them before the first step");
  if (!w.servos.empty()) return Status::error("servos: already enabled");
  if (max_torque_nm.size() != n)
    return Status::error("servos: max_torque_nm needs one entry per link (" + std::to_string(n) +
                         ")");
  if (!(std::isfinite(rate) && rate > 0.0 && rate <= 1.0))
    return Status::error("servos: rate must be in (0, 1]");
  w.servo_rate = rate;
  w.servos.resize(n);
  w.servo_limits.assign(n, 0.0);
  btMultiBody& mb = *w.body;
  for (size_t li = 1; li < n; ++li) {
    const double limit = max_torque_nm[li];
    if (!(std::isfinite(limit) && limit >= 0.0))
      return Status::error("servos: max_torque_nm of link " + std::to_string(li) + " (" +
                           w.plan.links[li].name + ") must be finite and >= 0");
    const int i = Impl::bulletLink(static_cast<int>(li));
    const double impulse = limit * w.dt;
    if (limit == 0.0) continue;
    w.servo_limits[li] = limit;
    if (w.plan.links[li].type == JointType::kBall) {
      auto motor = std::make_unique<btMultiBodySphericalJointMotor>(&mb, i, impulse);
      motor->setMaxAppliedImpulseMultiDof(btVector3(impulse, impulse, impulse));
      w.servos[li] = std::move(motor);
    } else if (w.plan.links[li].type == JointType::kHinge) {
      auto motor = std::make_unique<btMultiBodyJointMotor>(&mb, i, 0.0, impulse);
      w.servos[li] = std::move(motor);
    } else {
      continue;
    }
    w.world->addMultiBodyConstraint(w.servos[li].get());
  }
  setServoTargets(jointPositions());
  return Status();
}

void World::setServoTargets(const LinkPose& target, std::span<const double> rates) {
  Impl& w = *impl_;
  const bool per_link = rates.size() == w.servos.size();
  const double erp = w.world->getSolverInfo().m_erp;
  for (size_t li = 1; li < w.servos.size(); ++li) {
    btMultiBodyConstraint* servo = w.servos[li].get();
    if (servo == nullptr) continue;
    const Link& link = w.plan.links[li];
    const double rate =
        per_link && rates[li] > 0.0 && rates[li] <= 1.0 ? rates[li] : w.servo_rate;
    // A target outside the joint's range is unreachable: the servo aims at the range's nearest
    // point instead of pushing into the limit with all its torque (a fight the solver's few
    // iterations settle past the limit).
    if (link.type == JointType::kBall) {
      auto* motor = static_cast<btMultiBodySphericalJointMotor*>(servo);
      const glm::dquat q = clampToBallRange(link, glm::normalize(target.rotations[li]));
      motor->setPositionTarget(toBt(q), rate / erp);
    } else {
      auto* motor = static_cast<btMultiBodyJointMotor*>(servo);
      motor->setPositionTarget(std::clamp(target.angles[li], link.hinge_lower, link.hinge_upper),
                               rate);
      motor->setVelocityTarget(0.0, 1.0);
    }
  }
}

const std::vector<double>& World::servoTorqueLimits() const {
  return impl_->servo_limits;
}

void World::servoTorques(std::span<double> out) const {
  const Impl& w = *impl_;
  std::fill(out.begin(), out.end(), 0.0);
  for (size_t li = 1; li < w.servos.size(); ++li) {
    btMultiBodyConstraint* servo = w.servos[li].get();
    if (servo == nullptr) continue;
    const int dofs = physics::dofCount(w.plan.links[li].type);
    for (int d = 0; d < dofs; ++d)
      out[static_cast<size_t>(w.dof_offsets[li] + d)] = servo->getAppliedImpulse(d) / w.dt;
  }
}

double World::dt() const {
  return impl_->dt;
}
double World::time() const {
  return static_cast<double>(impl_->steps) * impl_->dt;
}
long long World::stepCount() const {
  return impl_->steps;
}
int World::linkCount() const {
  return static_cast<int>(impl_->plan.links.size());
}
int World::dofCount() const {
  return impl_->dofs;
}
const BodyPlan& World::plan() const {
  return impl_->plan;
}

void World::linkTransforms(std::span<glm::dmat4> out) const {
  for (size_t li = 0; li < out.size() && li < impl_->plan.links.size(); ++li)
    out[li] = impl_->linkTransform(static_cast<int>(li));
}

void World::linkCentres(std::span<glm::dvec3> out) const {
  for (size_t li = 0; li < out.size() && li < impl_->colliders.size(); ++li)
    out[li] = toGlm(impl_->colliders[li]->getWorldTransform().getOrigin());
}

LinkPose World::jointPositions() const {
  const Impl& w = *impl_;
  const btMultiBody& mb = *w.body;
  LinkPose pose;
  const glm::dmat4 base = w.linkTransform(0);
  pose.base_position = glm::dvec3(base[3]);
  pose.base_rotation = glm::normalize(glm::quat_cast(glm::dmat3(base)));
  const size_t n = w.plan.links.size();
  pose.rotations.assign(n, glm::dquat(1.0, 0.0, 0.0, 0.0));
  pose.angles.assign(n, 0.0);
  for (size_t li = 1; li < n; ++li) {
    const int i = Impl::bulletLink(static_cast<int>(li));
    if (w.plan.links[li].type == JointType::kBall) {
      const btScalar* q = mb.getJointPosMultiDof(i);
      pose.rotations[li] = glm::normalize(glm::dquat(q[3], q[0], q[1], q[2]));
    } else if (w.plan.links[li].type == JointType::kHinge) {
      pose.angles[li] = mb.getJointPos(i);
    }
  }
  return pose;
}

void World::jointVelocities(std::span<double> out) const {
  const Impl& w = *impl_;
  for (size_t li = 1; li < w.plan.links.size(); ++li) {
    const int dofs = physics::dofCount(w.plan.links[li].type);
    const btScalar* v = w.body->getJointVelMultiDof(Impl::bulletLink(static_cast<int>(li)));
    for (int d = 0; d < dofs; ++d) out[static_cast<size_t>(w.dof_offsets[li] + d)] = v[d];
  }
}

std::vector<double> World::jointInverseInertia(std::span<const int> welded_links) {
  btMultiBody& mb = *impl_->body;
  const int dofs = mb.getNumDofs();
  const size_t m = static_cast<size_t>(6 + dofs);
  btAlignedObjectArray<btScalar> scratch_r;
  btAlignedObjectArray<btVector3> scratch_v;
  btAlignedObjectArray<btMatrix3x3> scratch_m;
  // The articulated-body pass caches what calcAccelerationDeltasMultiDof needs. With dt = 0 it
  // changes no velocity.
  mb.computeAccelerationsArticulatedBodyAlgorithmMultiDof(0.0, scratch_r, scratch_v, scratch_m,
                                                          false, false, false);
  // Full inverse inertia F (base wrench and joint torques -> accelerations), m x m.
  std::vector<double> full(m * m, 0.0);
  std::vector<btScalar> force(m, 0.0), out(m, 0.0);
  for (size_t j = 0; j < m; ++j) {
    std::fill(force.begin(), force.end(), 0.0);
    force[j] = 1.0;
    mb.calcAccelerationDeltasMultiDof(force.data(), out.data(), scratch_r, scratch_v);
    for (size_t i = 0; i < m; ++i) full[i * m + j] = out[i];
  }
  if (!welded_links.empty()) {
    // Welding: F_c = F - F J^T (J F J^T)^-1 J F, J the welded links' spatial velocity rows.
    const size_t rows = 6 * welded_links.size();
    std::vector<double> jac(rows * m, 0.0);
    std::vector<btScalar> row(m, 0.0);
    size_t r = 0;
    for (int li : welded_links) {
      const btVector3 point =
          impl_->colliders[static_cast<size_t>(li)]->getWorldTransform().getOrigin();
      for (int k = 0; k < 6; ++k, ++r) {
        btVector3 ang(0, 0, 0), lin(0, 0, 0);
        (k < 3 ? ang : lin)[k % 3] = 1.0;
        mb.fillConstraintJacobianMultiDof(Impl::bulletLink(li), point, ang, lin, row.data(),
                                          scratch_r, scratch_v, scratch_m);
        for (size_t c = 0; c < m; ++c) jac[r * m + c] = row[c];
      }
    }
    // JF = J F (rows x m); A = JF J^T (rows x rows).
    std::vector<double> jf(rows * m, 0.0), a(rows * rows, 0.0);
    for (size_t i = 0; i < rows; ++i)
      for (size_t k = 0; k < m; ++k) {
        const double v = jac[i * m + k];
        if (v == 0.0) continue;
        for (size_t c = 0; c < m; ++c) jf[i * m + c] += v * full[k * m + c];
      }
    for (size_t i = 0; i < rows; ++i)
      for (size_t j = 0; j < rows; ++j) {
        double sum = 0.0;
        for (size_t c = 0; c < m; ++c) sum += jf[i * m + c] * jac[j * m + c];
        a[i * rows + j] = sum + (i == j ? 1e-12 : 0.0);
      }
    // X = A^-1 JF by Gaussian elimination with partial pivoting.
    std::vector<double> x = jf;
    for (size_t col = 0; col < rows; ++col) {
      size_t pivot = col;
      for (size_t i = col + 1; i < rows; ++i)
        if (std::abs(a[i * rows + col]) > std::abs(a[pivot * rows + col])) pivot = i;
      if (pivot != col) {
        for (size_t c = 0; c < rows; ++c) std::swap(a[col * rows + c], a[pivot * rows + c]);
        for (size_t c = 0; c < m; ++c) std::swap(x[col * m + c], x[pivot * m + c]);
      }
      const double d = a[col * rows + col];
      if (std::abs(d) < 1e-300) continue;
      for (size_t i = 0; i < rows; ++i) {
        if (i == col) continue;
        const double f = a[i * rows + col] / d;
        if (f == 0.0) continue;
        for (size_t c = 0; c < rows; ++c) a[i * rows + c] -= f * a[col * rows + c];
        for (size_t c = 0; c < m; ++c) x[i * m + c] -= f * x[col * m + c];
      }
    }
    for (size_t i = 0; i < rows; ++i) {
      const double d = a[i * rows + i];
      for (size_t c = 0; c < m; ++c) x[i * m + c] = std::abs(d) < 1e-300 ? 0.0 : x[i * m + c] / d;
    }
    // F -= JF^T X (F symmetric, so F J^T = JF^T).
    for (size_t i = 0; i < m; ++i)
      for (size_t k = 0; k < rows; ++k) {
        const double v = jf[k * m + i];
        if (v == 0.0) continue;
        for (size_t c = 0; c < m; ++c) full[i * m + c] -= v * x[k * m + c];
      }
  }
  std::vector<double> inverse(static_cast<size_t>(dofs * dofs), 0.0);
  for (size_t i = 0; i < static_cast<size_t>(dofs); ++i)
    for (size_t j = 0; j < static_cast<size_t>(dofs); ++j)
      inverse[i * static_cast<size_t>(dofs) + j] = full[(6 + i) * m + 6 + j];
  return inverse;
}

double World::maxJointSpeed() const {
  std::vector<double> v(static_cast<size_t>(impl_->dofs));
  jointVelocities(v);
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

glm::dvec3 World::linearMomentum() const {
  const Impl& w = *impl_;
  const btMultiBody& mb = *w.body;
  const int links = mb.getNumLinks();
  btAlignedObjectArray<btVector3> omega, vel;
  omega.resize(links + 1);
  vel.resize(links + 1);
  mb.compTreeLinkVelocities(&omega[0], &vel[0]);
  glm::dvec3 p = toGlm(mb.getBaseVel()) * double(mb.getBaseMass());
  for (int i = 0; i < links; ++i) {
    const btQuaternion r =
        w.colliders[static_cast<size_t>(i + 1)]->getWorldTransform().getRotation();
    p += toGlm(quatRotate(r, vel[i + 1])) * double(mb.getLinkMass(i));
  }
  return p;
}

glm::dvec3 World::centreOfMass() const {
  glm::dvec3 c(0.0);
  for (size_t li = 0; li < impl_->colliders.size(); ++li)
    c += toGlm(impl_->colliders[li]->getWorldTransform().getOrigin()) *
         impl_->plan.links[li].mass_kg;
  return c / impl_->plan.total_mass_kg;
}

double World::totalMass() const {
  return impl_->plan.total_mass_kg;
}
const std::vector<std::uint8_t>& World::linkContacts() const {
  return impl_->contacts;
}
const std::vector<double>& World::linkNormalForces() const {
  return impl_->normal_forces;
}
glm::dvec3 World::lastContactImpulse() const {
  return impl_->contact_impulse;
}
double World::groundHeight(double x, double z) const {
  return impl_->groundHeight(x, z);
}

const ExternalLoads& World::externalLoads() const {
  return impl_->loads;
}

bool World::finite() const {
  const Impl& w = *impl_;
  for (const auto& c : w.colliders) {
    const btTransform& t = c->getWorldTransform();
    if (!std::isfinite(t.getOrigin().x()) || !std::isfinite(t.getOrigin().y()) ||
        !std::isfinite(t.getOrigin().z()) || !std::isfinite(t.getRotation().w()))
      return false;
  }
  std::vector<double> v(static_cast<size_t>(w.dofs));
  jointVelocities(v);
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

}  // namespace sinew::physics
