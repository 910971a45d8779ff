// Bullet backend (libbullet 3.24, double precision) of PhysicsEngine.
//
// Mapping:
// - Every body is one btRigidBody placed at its centre of mass with principal axes; its shapes
//   sit in a btCompoundShape at inverse(inertial_frame) * pose_in_link. The root of a model
//   fixed to the world is a static body (mass 0), so it cannot move at all.
// - Revolute and continuous joints are btHingeConstraint with the child as body A: the hinge
//   angle, limits and motor then all read "child relative to parent" about +axis. Prismatic
//   joints are btGeneric6DofSpring2Constraint with everything but the x translation locked.
//   Joint positions are measured by us after every step (unwrapped for any number of turns).
// - Friction and contact stiffness are set per contact point in gContactAddedCallback (a
//   Bullet global; we set it to a stateless function), from the SurfaceParams hung on every
//   collision shape: min(mu) as in ODE/Gazebo, kp in series, kd in parallel; two friction
//   directions fixed by the contact normal.
// - Wheels (cylinders spinning about their own axis on a joint, tyre.h) become tyres: rounded
//   tread and slightly compliant friction; see makeShape() and kTyreFrictionCfm.
// - Bodies of one model never collide: a broadphase pair filter on the model id kept in each
//   collision object's user index (-1 = static world).
// - One step() is exactly one Bullet step: stepSimulation(step_s, 0) runs a single internal
//   step of step_s (no substeps, no interpolation), then clears the applied forces. No heap
//   allocation once the contacts exist.
//
// Simplifications: meshes of moving bodies collide as their convex hull (grown by the 1 mm
// margin); box and cylinder edges are rounded by that margin; a manifold holds at most 4 points
// per pair of shapes, so max_contacts is not used; max_contact_correcting_vel_mps has no Bullet
// counterpart. Rigid contacts' correcting velocity is capped as in Gazebo (contact_correction.h).
#include "bullet/bullet_engine.h"

#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>
#include <BulletDynamics/ConstraintSolver/btGeneric6DofSpring2Constraint.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "conde_physics/tyre.h"
#include "contact_correction.h"

namespace conde_physics {
namespace {

// Bullet's default 0.04 m margin rounds off anything small (our wheels have 0.032 m radius).
// Boxes and cylinders keep their exact size (the margin is taken from inside); convex hulls
// grow by it.
constexpr double kShapeMargin_m = 0.001;
// Contact points closer than this are reported by lastContacts() even without an impulse.
constexpr double kTouching_m = 0.001;
// Stand-ins for massless bodies of moving models [kg, kg m^2].
constexpr double kTinyMass_kg = 1e-3;
constexpr double kTinyInertia_kgm2 = 1e-6;
// User index of tyre shapes (btCollisionShape's default is -1).
constexpr int kTyreShape = 1;
// Softness of tyre friction: the solver lets each friction impulse leak by this fraction per
// iteration, i.e. a tyre creeps at cfm * impulse / effective mass. Without it, two wheels on
// one chassis with high friction form a closed loop whose internal (squeeze) impulse is
// undetermined; joint drift feeds it and it grows until the wheels are bent off their axles.
// 1e-2 removes that at 50 iterations; 1e-3 does not.
constexpr double kTyreFrictionCfm = 1e-2;
// Half width [rad] of the sliding limit window for revolute ranges Bullet cannot hold (>= pi).
constexpr double kLimitWindow_rad = 1.5;

btVector3 toBt(const Vec3& v) { return btVector3(v.x, v.y, v.z); }
Vec3 fromBt(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }
btTransform toBt(const Pose& p) {
  const Quat& q = p.orientation;
  return btTransform(btQuaternion(q.x, q.y, q.z, q.w), toBt(p.position));
}
Pose fromBt(const btTransform& t) {
  btQuaternion q = t.getRotation();
  if (q.w() < 0.0) q = -q;  // one sign for the same rotation
  return Pose(fromBt(t.getOrigin()), Quat(q.w(), q.x(), q.y(), q.z()));
}

// Rotation whose column `column` (0 = x, 2 = z) is the unit `axis`, completed right-handed.
btMatrix3x3 basisWithAxis(const btVector3& axis, int column) {
  btVector3 p, q;
  btPlaneSpace1(axis, p, q);  // q = axis x p, so (p, q, axis) and (axis, p, q) are right-handed
  const btVector3& c0 = column == 2 ? p : axis;
  const btVector3& c1 = column == 2 ? q : p;
  const btVector3& c2 = column == 2 ? axis : q;
  return btMatrix3x3(c0.x(), c1.x(), c2.x(), c0.y(), c1.y(), c2.y(), c0.z(), c1.z(), c2.z());
}

// ---- contact material ----------------------------------------------------------------------

// The surface of the shape in contact: children of compounds and standalone shapes carry their
// own; triangles of a static mesh fall back to the object's.
const SurfaceParams* surfaceOf(const btCollisionObjectWrapper* wrap) {
  if (const void* s = wrap->getCollisionShape()->getUserPointer()) return static_cast<const SurfaceParams*>(s);
  return static_cast<const SurfaceParams*>(wrap->getCollisionObject()->getUserPointer());
}

bool combineSurfaces(btManifoldPoint& cp, const btCollisionObjectWrapper* wrap0, int, int,
                     const btCollisionObjectWrapper* wrap1, int, int) {
  const SurfaceParams* a = surfaceOf(wrap0);
  const SurfaceParams* b = surfaceOf(wrap1);
  if (a == nullptr || b == nullptr) return false;
  // Isotropic Coulomb friction with the smaller coefficient of the two surfaces.
  cp.m_combinedFriction = std::min(std::min(a->mu, a->mu2), std::min(b->mu, b->mu2));
  cp.m_combinedRestitution = 0.0;
  cp.m_combinedRollingFriction = 0.0;
  cp.m_combinedSpinningFriction = 0.0;
  // Friction rows in fixed directions, with compliance for tyres (see kTyreFrictionCfm).
  btPlaneSpace1(cp.m_normalWorldOnB, cp.m_lateralFrictionDir1, cp.m_lateralFrictionDir2);
  cp.m_contactMotion1 = cp.m_contactMotion2 = 0.0;
  const bool tyre = wrap0->getCollisionShape()->getUserIndex() == kTyreShape ||
                    wrap1->getCollisionShape()->getUserIndex() == kTyreShape;
  cp.m_frictionCFM = tyre ? kTyreFrictionCfm : 0.0;
  cp.m_contactPointFlags |= BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED;
  const double ka_npm = a->stiffness_npm, kb_npm = b->stiffness_npm;
  if (ka_npm > 0.0 || kb_npm > 0.0) {
    // Springs in series (a rigid side adds no compliance), dampers in parallel, as Gazebo does.
    cp.m_combinedContactStiffness1 =
        ka_npm > 0.0 && kb_npm > 0.0 ? 1.0 / (1.0 / ka_npm + 1.0 / kb_npm) : std::max(ka_npm, kb_npm);
    cp.m_combinedContactDamping1 = a->damping_nspm + b->damping_nspm;
    cp.m_contactPointFlags |= BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING;
  } else {
    cp.m_contactPointFlags &= ~BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING;
  }
  return true;
}

// Broadphase filter: the usual group/mask test, and no pairs within one model.
struct ModelPairFilter : public btOverlapFilterCallback {
  bool needBroadphaseCollision(btBroadphaseProxy* p0, btBroadphaseProxy* p1) const override {
    if ((p0->m_collisionFilterGroup & p1->m_collisionFilterMask) == 0 ||
        (p1->m_collisionFilterGroup & p0->m_collisionFilterMask) == 0)
      return false;
    const int model0 = static_cast<const btCollisionObject*>(p0->m_clientObject)->getUserIndex();
    const int model1 = static_cast<const btCollisionObject*>(p1->m_clientObject)->getUserIndex();
    return model0 < 0 || model0 != model1;
  }
};

// ---- engine ----------------------------------------------------------------------------------

struct Body {
  btRigidBody* rb = nullptr;
  btTransform link_in_com;  // link frame in the body's COM frame: inverse(inertial_frame)
};

struct Joint {
  btRigidBody* parent = nullptr;
  btRigidBody* child = nullptr;
  // Joint frame in each body's COM frame; the joint axis is its z (hinge) or x (prismatic).
  btTransform frame_in_parent, frame_in_child;
  btHingeConstraint* hinge = nullptr;
  btGeneric6DofSpring2Constraint* slider = nullptr;
  double position = 0.0;        // [rad] unwrapped, or [m]
  double last_angle_rad = 0.0;  // wrapped angle at the last update, for unwrapping
  double damping = 0.0, friction = 0.0, effort_limit = 0.0, velocity_limit = 0.0;
  bool has_limits = false;
  double lower = 0.0, upper = 0.0;
  bool limit_window = false;  // range too wide for btAngularLimit: slide a window along
  double window_center_rad = 0.0;
  bool motor_on = false;
  double motor_velocity = 0.0, motor_max_effort = 0.0;
  bool motor_at_stop = false;   // hinge resting on a limit: motor applied by us, not by Bullet
  double pending_effort = 0.0;  // [N m] or [N], for the next step only
  // Constraint forces of the last step; the solver writes them through the pointer (hence the heap).
  std::unique_ptr<btJointFeedback> feedback = std::make_unique<btJointFeedback>();
};

struct Model {
  std::vector<Body> bodies;
  std::vector<Joint> joints;
};

// The stock world without continuous collision detection, which no body here uses (none has a
// CCD motion threshold). For it the stock world integrates every body twice more per step: a
// predicted pose whose bounding box is merged into the body's, and predictive contacts. Bounding
// boxes keep Bullet's contact margin (gContactBreakingThreshold, 2 cm), so a body moving less than
// that per step still meets everything it can touch within the step.
class WorldWithoutCcd final : public btDiscreteDynamicsWorld {
 public:
  using btDiscreteDynamicsWorld::btDiscreteDynamicsWorld;

 protected:
  void predictUnconstraintMotion(btScalar step_s) override {
    for (int i = 0; i < m_nonStaticRigidBodies.size(); ++i) {
      btRigidBody* body = m_nonStaticRigidBodies[i];
      if (!body->isStaticOrKinematicObject()) body->applyDamping(step_s);  // what remains of it
    }
  }
  void createPredictiveContacts(btScalar) override { releasePredictiveContacts(); }

  // Rigid contacts (no stiffness) present at most rigidContactSolverDepthM() to the solver, so
  // that a deep penetration is corrected at Gazebo's 0.01 m/s, not thrown apart; their true
  // depth is put back for the contact reports.
  void solveConstraints(btContactSolverInfo& info) override {
    const btScalar deepest_m =
        static_cast<btScalar>(rigidContactSolverDepthM(info.m_linearSlop, info.m_erp, info.m_timeStep));
    clamped_.clear();
    for (int m = 0; m < m_dispatcher1->getNumManifolds(); ++m) {
      btPersistentManifold* manifold = m_dispatcher1->getManifoldByIndexInternal(m);
      for (int p = 0; p < manifold->getNumContacts(); ++p) {
        btManifoldPoint& pt = manifold->getContactPoint(p);
        if ((pt.m_contactPointFlags & BT_CONTACT_FLAG_CONTACT_STIFFNESS_DAMPING) != 0 || pt.m_distance1 >= -deepest_m)
          continue;
        clamped_.push_back({&pt, pt.m_distance1});
        pt.m_distance1 = -deepest_m;
      }
    }
    btDiscreteDynamicsWorld::solveConstraints(info);
    for (const auto& [point, distance_m] : clamped_) point->m_distance1 = distance_m;
  }

 private:
  std::vector<std::pair<btManifoldPoint*, btScalar>> clamped_;
};

class BulletEngine : public PhysicsEngine {
 public:
  explicit BulletEngine(const PhysicsSettings& settings) : PhysicsEngine(settings) {
    gContactAddedCallback = &combineSurfaces;  // stateless; every object opts in by flag
    config_ = std::make_unique<btDefaultCollisionConfiguration>();
    dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
    broadphase_ = std::make_unique<btDbvtBroadphase>();
    broadphase_->getOverlappingPairCache()->setOverlapFilterCallback(&pair_filter_);
    solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
    world_ = std::make_unique<WorldWithoutCcd>(dispatcher_.get(), broadphase_.get(), solver_.get(), config_.get());
    world_->getDispatchInfo().m_useContinuous = false;
    world_->setGravity(toBt(settings.gravity_mps2));
    world_->setForceUpdateAllAabbs(false);  // static objects never move
    btContactSolverInfo& info = world_->getSolverInfo();
    info.m_numIterations = std::max(1, settings.solver_iterations);
    // Bullet uses m_erp for contacts shallower than the split-impulse threshold and for joints,
    // m_erp2 for the split (position-only) correction of deep contacts.
    info.m_erp = settings.contact_erp;
    info.m_erp2 = settings.contact_erp;
    info.m_globalCfm = settings.contact_cfm;
    info.m_linearSlop = settings.contact_surface_layer_m;  // allowed penetration, like ODE's layer
    // One friction direction per point (the default) lets wheels slide sideways.
    info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS | SOLVER_ENABLE_FRICTION_DIRECTION_CACHING;
  }

  ~BulletEngine() override {
    // The world must forget everything before the objects go away.
    for (int i = world_->getNumConstraints() - 1; i >= 0; --i) world_->removeConstraint(world_->getConstraint(i));
    for (int i = world_->getNumCollisionObjects() - 1; i >= 0; --i)
      world_->removeCollisionObject(world_->getCollisionObjectArray()[i]);
  }

  std::string name() const override { return "bullet"; }

  void addGroundPlane(const SurfaceParams& surface) override {
    const SurfaceParams* s = keepSurface(surface);
    btCollisionShape* shape = keepShape(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0.0));
    shape->setUserPointer(const_cast<SurfaceParams*>(s));
    sides_[addRigidBody(0.0, btVector3(0, 0, 0), shape, btTransform::getIdentity(), -1, s, true)] = ContactSide{};
    ray_scene_.addGroundPlane();
  }

  void addStaticShape(const Shape& shape, const Pose& world_pose, const SurfaceParams& surface) override {
    const SurfaceParams* s = keepSurface(surface);
    btCollisionShape* bt_shape = makeShape(shape, /*dynamic=*/false);
    const int index = static_shape_count_++;  // counted even when nothing collides, as in ODE
    if (bt_shape == nullptr) return;
    bt_shape->setUserPointer(const_cast<SurfaceParams*>(s));
    sides_[addRigidBody(0.0, btVector3(0, 0, 0), bt_shape, toBt(world_pose), -1, s, true)] = ContactSide{-1, -1, index};
    ray_scene_.addStatic(shape, world_pose);
  }

  ModelId addModel(const ArticulatedModel& model, const Pose& root_pose) override {
    const ModelId id = static_cast<ModelId>(models_.size());
    auto m = std::make_unique<Model>();
    m->bodies.resize(model.bodies.size());
    for (size_t i = 0; i < model.bodies.size(); ++i) {
      const BodySpec& spec = model.bodies[i];
      const bool is_static = model.fixed_to_world && i == 0;
      double mass_kg = spec.mass_kg;
      btVector3 inertia_kgm2 = toBt(spec.principal_inertia_kgm2);
      if (is_static) {
        mass_kg = 0.0;
        inertia_kgm2.setZero();
      } else if (mass_kg <= 0.0) {
        mass_kg = kTinyMass_kg;
        inertia_kgm2.setValue(kTinyInertia_kgm2, kTinyInertia_kgm2, kTinyInertia_kgm2);
      }
      Body& body = m->bodies[i];
      body.link_in_com = toBt(spec.inertial_frame.inverse());

      btCollisionShape* shape = nullptr;
      const SurfaceParams* fallback = nullptr;
      if (!spec.collisions.empty()) {
        auto compound = std::make_unique<btCompoundShape>(/*enableDynamicAabbTree=*/false,
                                                          static_cast<int>(spec.collisions.size()));
        for (const CollisionSpec& c : spec.collisions) {
          const bool tyre = !is_static && isWheelCollision(model, static_cast<int>(i), c);
          btCollisionShape* child = makeShape(c.shape, !is_static, tyre);
          if (child == nullptr) continue;
          const SurfaceParams* s = keepSurface(c.surface);
          if (fallback == nullptr) fallback = s;
          child->setUserPointer(const_cast<SurfaceParams*>(s));
          if (tyre) child->setUserIndex(kTyreShape);
          compound->addChildShape(body.link_in_com * toBt(c.pose_in_link), child);
        }
        if (compound->getNumChildShapes() > 0) shape = keepShape(std::move(compound));
      }
      const bool collides = shape != nullptr;
      if (!collides) shape = keepShape(std::make_unique<btEmptyShape>());
      const btTransform com_world = toBt(root_pose * spec.initial_pose_in_model * spec.inertial_frame);
      body.rb = addRigidBody(mass_kg, inertia_kgm2, shape, com_world, id, fallback, collides);
      sides_[body.rb] = ContactSide{id, static_cast<int>(i), -1};
    }

    m->joints.resize(model.joints.size());
    for (size_t j = 0; j < model.joints.size(); ++j) {
      const JointSpec& spec = model.joints[j];
      if (spec.parent_body < 0 || spec.child_body < 0 || spec.parent_body >= static_cast<int>(model.bodies.size()) ||
          spec.child_body >= static_cast<int>(model.bodies.size()))
        throw std::invalid_argument("joint '" + spec.name + "' refers to a missing body");
      Joint& joint = m->joints[j];
      joint.parent = m->bodies[spec.parent_body].rb;
      joint.child = m->bodies[spec.child_body].rb;
      joint.damping = spec.damping;
      joint.friction = spec.friction;
      joint.effort_limit = spec.effort_limit;
      joint.velocity_limit = spec.velocity_limit;
      joint.has_limits = spec.has_position_limits && spec.lower <= spec.upper;
      joint.lower = spec.lower;
      joint.upper = spec.upper;

      btVector3 axis = toBt(spec.axis);
      axis = axis.length2() > 0.0 ? axis.normalized() : btVector3(1, 0, 0);
      const bool prismatic = spec.type == JointType::kPrismatic;
      const btTransform joint_world =
          toBt(root_pose * model.bodies[spec.parent_body].initial_pose_in_model * spec.pose_in_parent) *
          btTransform(basisWithAxis(axis, prismatic ? 0 : 2), btVector3(0, 0, 0));
      joint.frame_in_parent = joint.parent->getCenterOfMassTransform().inverse() * joint_world;
      joint.frame_in_child = joint.child->getCenterOfMassTransform().inverse() * joint_world;

      btTypedConstraint* constraint = nullptr;
      if (prismatic) {
        auto slider = std::make_unique<btGeneric6DofSpring2Constraint>(
            *joint.parent, *joint.child, joint.frame_in_parent, joint.frame_in_child, RO_XYZ);
        // Lower > upper leaves an axis free; equal values lock it.
        slider->setLinearLowerLimit(btVector3(joint.has_limits ? joint.lower : 1.0, 0, 0));
        slider->setLinearUpperLimit(btVector3(joint.has_limits ? joint.upper : -1.0, 0, 0));
        slider->setAngularLowerLimit(btVector3(0, 0, 0));
        slider->setAngularUpperLimit(btVector3(0, 0, 0));
        joint.slider = slider.get();
        constraint = keepConstraint(std::move(slider));
      } else {
        auto hinge = std::make_unique<btHingeConstraint>(*joint.child, *joint.parent, joint.frame_in_child,
                                                         joint.frame_in_parent, /*useReferenceFrameA=*/false);
        joint.hinge = hinge.get();
        constraint = keepConstraint(std::move(hinge));
        if (spec.type == JointType::kContinuous) joint.has_limits = false;
        joint.limit_window = joint.has_limits && joint.upper - joint.lower >= M_PI - 0.1;
        updateHingeLimit(joint, /*force=*/true);
      }
      constraint->setJointFeedback(joint.feedback.get());
      constraint->enableFeedback(true);
      world_->addConstraint(constraint, /*disableCollisionsBetweenLinkedBodies=*/false);  // the pair filter does it
      updateMotor(joint);
    }
    models_.push_back(std::move(m));
    ray_scene_.addModel(id, model);
    return id;
  }

  // The model's constraints and bodies leave the world; the objects themselves stay owned by
  // the engine (a few per model) until it is destroyed.
  void removeModel(ModelId model) override {
    const Model& m = modelAt(model);
    for (const Joint& joint : m.joints) {
      if (joint.hinge) world_->removeConstraint(joint.hinge);
      if (joint.slider) world_->removeConstraint(joint.slider);
    }
    for (const Body& body : m.bodies) {
      world_->removeRigidBody(body.rb);
      sides_.erase(body.rb);
    }
    last_contacts_.clear();
    models_[model].reset();
    ray_scene_.removeModel(model);
  }

  void step() override {
    const double dt_s = settings_.step_s;
    for (auto& m : models_)
      if (m)
        for (Joint& joint : m->joints) applyJointEfforts(joint, dt_s);
    world_->stepSimulation(dt_s, 0, dt_s);  // exactly one internal step; clears applied forces
    collectContacts(dt_s);
    for (auto& m : models_)
      if (m)
        for (Joint& joint : m->joints) updatePosition(joint);
  }

  void setBodyState(ModelId model, int body, const Pose& link_pose, const Twist& twist) override {
    const Body& b = bodyAt(model, body);
    if (b.rb->isStaticObject()) return;  // the root of a model welded to the world
    const btTransform com = toBt(link_pose) * b.link_in_com.inverse();
    b.rb->setCenterOfMassTransform(com);
    const btVector3 w = toBt(twist.angular_radps);
    const btVector3 v_com = toBt(twist.linear_mps) + w.cross(com.getOrigin() - toBt(link_pose.position));
    b.rb->setLinearVelocity(v_com);
    b.rb->setAngularVelocity(w);
    b.rb->setInterpolationLinearVelocity(v_com);
    b.rb->setInterpolationAngularVelocity(w);
  }

  void addBodyWrench(ModelId model, int body, const Vec3& force_N, const Vec3& torque_Nm,
                     const Vec3& point_world) override {
    const Body& b = bodyAt(model, body);  // stepSimulation clears the applied forces
    b.rb->applyForce(toBt(force_N), toBt(point_world) - b.rb->getCenterOfMassPosition());
    b.rb->applyTorque(toBt(torque_Nm));
  }

  Pose bodyPose(ModelId model, int body) const override {
    const Body& b = bodyAt(model, body);
    return fromBt(b.rb->getCenterOfMassTransform() * b.link_in_com);
  }

  Twist bodyTwist(ModelId model, int body) const override {
    const Body& b = bodyAt(model, body);
    const btTransform& com = b.rb->getCenterOfMassTransform();
    const btVector3 link_origin_from_com = com.getBasis() * b.link_in_com.getOrigin();
    Twist t;
    t.linear_mps = fromBt(b.rb->getVelocityInLocalPoint(link_origin_from_com));
    t.angular_radps = fromBt(b.rb->getAngularVelocity());
    return t;
  }

  double jointPosition(ModelId model, int joint) const override { return jointAt(model, joint).position; }
  // The child is body A of a hinge and body B of a slider; torques are about the centre of mass.
  JointWrench jointWrench(ModelId model, int joint) const override {
    const Joint& j = jointAt(model, joint);
    const btJointFeedback& f = *j.feedback;
    return j.hinge ? JointWrench{fromBt(f.m_appliedForceBodyA), fromBt(f.m_appliedTorqueBodyA)}
                   : JointWrench{fromBt(f.m_appliedForceBodyB), fromBt(f.m_appliedTorqueBodyB)};
  }

  double jointVelocity(ModelId model, int joint) const override { return velocityOf(jointAt(model, joint)); }

  void setJointVelocityMotor(ModelId model, int joint, double velocity, double max_effort) override {
    Joint& j = jointAt(model, joint);
    if (j.velocity_limit > 0.0) velocity = std::clamp(velocity, -j.velocity_limit, j.velocity_limit);
    if (j.effort_limit > 0.0) max_effort = std::min(max_effort, j.effort_limit);
    j.motor_on = max_effort > 0.0;
    j.motor_velocity = velocity;
    j.motor_max_effort = std::max(0.0, max_effort);
    updateMotor(j);
  }

  void addJointEffort(ModelId model, int joint, double effort) override {
    jointAt(model, joint).pending_effort += effort;
  }

 private:
  // The manifolds' points that touch or carried an impulse this step. Bullet's normal on B
  // points from B towards A, and the solver's impulses act on A along the normal and friction
  // directions, as Contact wants for a = body 0, b = body 1.
  void collectContacts(double dt_s) {
    last_contacts_.clear();
    for (int m = 0; m < dispatcher_->getNumManifolds(); ++m) {
      const btPersistentManifold* manifold = dispatcher_->getManifoldByIndexInternal(m);
      const auto side0 = sides_.find(manifold->getBody0());
      const auto side1 = sides_.find(manifold->getBody1());
      if (side0 == sides_.end() || side1 == sides_.end()) continue;
      for (int p = 0; p < manifold->getNumContacts(); ++p) {
        const btManifoldPoint& pt = manifold->getContactPoint(p);
        // Manifolds keep points up to 2 cm apart; a body resting against another without pushing
        // stays a hair apart (no impulse), so points within kTouching_m count as touching.
        if (pt.getDistance() > kTouching_m && pt.getAppliedImpulse() <= 0.0) continue;  // apart
        Contact c;
        c.a = side0->second;
        c.b = side1->second;
        c.position_m = fromBt((pt.getPositionWorldOnA() + pt.getPositionWorldOnB()) * 0.5);
        c.normal = fromBt(pt.m_normalWorldOnB);
        c.depth_m = std::max(0.0, -static_cast<double>(pt.getDistance()));
        const btVector3 impulse = pt.m_normalWorldOnB * pt.getAppliedImpulse() +
                                  pt.m_lateralFrictionDir1 * pt.m_appliedImpulseLateral1 +
                                  pt.m_lateralFrictionDir2 * pt.m_appliedImpulseLateral2;
        c.force_on_a_N = fromBt(impulse / dt_s);
        c.has_force = true;
        last_contacts_.push_back(c);
      }
    }
  }

  // ---- construction helpers ----

  const SurfaceParams* keepSurface(const SurfaceParams& s) {
    surfaces_.push_back(s);
    return &surfaces_.back();
  }
  template <class T>
  T* keepShape(std::unique_ptr<T> shape) {
    T* raw = shape.get();
    shapes_.push_back(std::move(shape));
    return raw;
  }
  template <class T>
  T* keepConstraint(std::unique_ptr<T> c) {
    T* raw = c.get();
    constraints_.push_back(std::move(c));
    return raw;
  }

  // Shape of one collision; nullptr for an empty mesh. A tyre is a cylinder whose edges are
  // rounded with half its width: a flat tread touches flat ground at one of its edges, which
  // moves the wheel's contact sideways (by half the width, changing the track of a
  // differential drive); the rounded tread touches in its mid-plane at the full radius.
  btCollisionShape* makeShape(const Shape& shape, bool dynamic, bool tyre = false) {
    switch (shape.type) {
      case ShapeType::kBox: {
        const btVector3 half_m = toBt(shape.box_size_m) * 0.5;
        auto box = std::make_unique<btBoxShape>(half_m);
        box->setMargin(std::min(kShapeMargin_m, 0.5 * half_m[half_m.minAxis()]));
        return keepShape(std::move(box));
      }
      case ShapeType::kCylinder: {
        const double half_length_m = 0.5 * shape.length_m;
        auto cylinder = std::make_unique<btCylinderShapeZ>(btVector3(shape.radius_m, shape.radius_m, half_length_m));
        if (tyre && canBeTyre(shape.radius_m, shape.length_m)) {
          cylinder->setMargin(half_length_m);  // core: a flat disk of radius r - width/2
        } else {
          cylinder->setMargin(std::min(kShapeMargin_m, 0.5 * std::min(shape.radius_m, half_length_m)));
        }
        return keepShape(std::move(cylinder));
      }
      case ShapeType::kSphere:
        return keepShape(std::make_unique<btSphereShape>(shape.radius_m));  // margin = radius
      case ShapeType::kMesh: {
        if (shape.mesh_vertices_m.empty()) return nullptr;
        if (dynamic) {
          auto hull = std::make_unique<btConvexHullShape>();
          for (const Vec3& v : shape.mesh_vertices_m) hull->addPoint(toBt(v), false);
          hull->setMargin(kShapeMargin_m);
          hull->recalcLocalAabb();
          return keepShape(std::move(hull));
        }
        auto mesh = std::make_unique<btTriangleMesh>(/*use32bitIndices=*/true, /*use4componentVertices=*/false);
        const int n = static_cast<int>(shape.mesh_vertices_m.size());
        for (size_t t = 0; t + 2 < shape.mesh_triangles.size(); t += 3) {
          const int a = shape.mesh_triangles[t], b = shape.mesh_triangles[t + 1], c = shape.mesh_triangles[t + 2];
          if (a < 0 || b < 0 || c < 0 || a >= n || b >= n || c >= n) continue;
          mesh->addTriangle(toBt(shape.mesh_vertices_m[a]), toBt(shape.mesh_vertices_m[b]),
                            toBt(shape.mesh_vertices_m[c]));
        }
        if (mesh->getNumTriangles() == 0) return nullptr;
        auto bvh = std::make_unique<btBvhTriangleMeshShape>(mesh.get(), /*useQuantizedAabbCompression=*/true);
        bvh->setMargin(kShapeMargin_m);
        meshes_.push_back(std::move(mesh));
        return keepShape(std::move(bvh));
      }
    }
    return nullptr;
  }

  btRigidBody* addRigidBody(double mass_kg, const btVector3& inertia_kgm2, btCollisionShape* shape,
                            const btTransform& com_world, int model_id, const SurfaceParams* fallback, bool collides) {
    btRigidBody::btRigidBodyConstructionInfo info(mass_kg, nullptr, shape, inertia_kgm2);
    info.m_startWorldTransform = com_world;
    info.m_restitution = 0.0;
    info.m_rollingFriction = 0.0;
    info.m_spinningFriction = 0.0;
    auto rb = std::make_unique<btRigidBody>(info);
    rb->setCollisionFlags(rb->getCollisionFlags() | btCollisionObject::CF_CUSTOM_MATERIAL_CALLBACK);
    if (mass_kg > 0.0) rb->setActivationState(DISABLE_DEACTIVATION);  // sleeping would change results
    rb->setUserIndex(model_id);
    rb->setUserPointer(const_cast<SurfaceParams*>(fallback));
    btRigidBody* raw = rb.get();
    bodies_.push_back(std::move(rb));
    if (collides) {
      world_->addRigidBody(raw);
    } else {
      world_->addRigidBody(raw, btBroadphaseProxy::DefaultFilter, 0);  // mask 0: no pairs, no rays
    }
    return raw;
  }

  // ---- joint helpers ----

  // Joint frames in the world: parent side and child side.
  void jointFrames(const Joint& j, btTransform& parent_frame, btTransform& child_frame) const {
    parent_frame = j.parent->getCenterOfMassTransform() * j.frame_in_parent;
    child_frame = j.child->getCenterOfMassTransform() * j.frame_in_child;
  }

  btVector3 axisWorld(const Joint& j) const {
    return j.parent->getCenterOfMassTransform().getBasis() * j.frame_in_parent.getBasis().getColumn(j.hinge ? 2 : 0);
  }

  double velocityOf(const Joint& j) const {
    if (j.hinge) return axisWorld(j).dot(j.child->getAngularVelocity() - j.parent->getAngularVelocity());
    btTransform pf, cf;
    jointFrames(j, pf, cf);
    const btVector3& point = cf.getOrigin();
    const btVector3 v_child = j.child->getVelocityInLocalPoint(point - j.child->getCenterOfMassPosition());
    const btVector3 v_parent = j.parent->getVelocityInLocalPoint(point - j.parent->getCenterOfMassPosition());
    return pf.getBasis().getColumn(0).dot(v_child - v_parent);
  }

  void updatePosition(Joint& j) {
    btTransform pf, cf;
    jointFrames(j, pf, cf);
    if (j.slider) {
      j.position = pf.getBasis().getColumn(0).dot(cf.getOrigin() - pf.getOrigin());
      return;
    }
    // Rotation of the child's joint frame about the parent's z: angle of the child's x axis.
    const btVector3 child_x = cf.getBasis().getColumn(0);
    const double angle_rad =
        std::atan2(child_x.dot(pf.getBasis().getColumn(1)), child_x.dot(pf.getBasis().getColumn(0)));
    j.position += wrapAngle(angle_rad - j.last_angle_rad);
    j.last_angle_rad = angle_rad;
    if (j.limit_window) updateHingeLimit(j, false);
  }

  // Stops of a hinge: relaxation 0 (no bounce off the stop), bias 1 (the full ERP corrects an
  // overshoot). btAngularLimit holds ranges below pi only; wider ranges get a window of the
  // range around the current position, moved long before the joint could reach a false edge.
  void updateHingeLimit(Joint& j, bool force) {
    if (!j.has_limits) {
      if (force) j.hinge->setLimit(1.0, -1.0);  // lower > upper: free
      return;
    }
    if (!j.limit_window) {
      j.hinge->setLimit(j.lower, j.upper, 0.9, 1.0, 0.0);
      return;
    }
    if (!force && std::abs(j.position - j.window_center_rad) < 0.25 * kLimitWindow_rad) return;
    j.window_center_rad = j.position;
    const double lo = std::max(j.lower, j.position - kLimitWindow_rad);
    const double hi = std::min(j.upper, j.position + kLimitWindow_rad);
    j.hinge->setLimit(lo, hi, 0.9, 1.0, 0.0);  // Bullet reads both modulo 2 pi, as its angle is
  }

  // The velocity motor, or when none is set a zero-velocity motor holding the Coulomb friction.
  // False when neither acts.
  static bool motorCommand(const Joint& j, double& velocity, double& max_effort) {
    velocity = j.motor_on ? j.motor_velocity : 0.0;
    max_effort = j.motor_on ? j.motor_max_effort : j.friction;
    return max_effort > 0.0;
  }

  void updateMotor(Joint& j) {
    double velocity = 0.0, max_effort = 0.0;
    const bool on = motorCommand(j, velocity, max_effort) && !j.motor_at_stop;
    if (j.hinge) {
      j.hinge->enableAngularMotor(on, velocity, max_effort * settings_.step_s);  // [N m s] per step
    } else {
      j.slider->enableMotor(0, on);
      j.slider->setTargetVelocity(0, -velocity);  // its linear motor drives parent (A) relative to child (B)
      j.slider->setMaxMotorForce(0, max_effort);  // [N]
    }
  }

  // Commanded effort, viscous damping and (on a stop) the motor, applied as equal and opposite
  // torques or forces for the coming step.
  void applyJointEfforts(Joint& j, double dt_s) {
    double effort = j.pending_effort;
    j.pending_effort = 0.0;
    if (j.effort_limit > 0.0) effort = std::clamp(effort, -j.effort_limit, j.effort_limit);

    // Bullet's hinge shares one row between limit and motor; on a stop the row takes the limit's
    // bounds, so a motor pulling away from the stop would get unlimited torque. There we apply
    // the motor ourselves, explicitly, as ODE does.
    if (j.hinge && j.has_limits) {
      const bool at_stop = j.position >= j.upper || j.position <= j.lower;
      if (at_stop != j.motor_at_stop) {
        j.motor_at_stop = at_stop;
        updateMotor(j);
      }
    }
    double motor_velocity = 0.0, motor_max_effort = 0.0;
    const bool explicit_motor = j.motor_at_stop && motorCommand(j, motor_velocity, motor_max_effort);
    if (j.damping > 0.0 || explicit_motor) {
      const btVector3 axis = axisWorld(j);
      const double v = velocityOf(j);
      const double inv_inertia =
          j.hinge ? j.child->computeAngularImpulseDenominator(axis) + j.parent->computeAngularImpulseDenominator(axis)
                  : j.child->getInvMass() + j.parent->getInvMass();
      // Effort that would bring the joint to `target` in this step by itself [N m or N]: caps
      // the explicit terms so they cannot overshoot (stable for any damping on light wheels).
      auto reaching = [&](double target) { return inv_inertia > 0.0 ? (target - v) / (inv_inertia * dt_s) : 0.0; };
      if (j.damping > 0.0) {
        const double cap = std::abs(reaching(0.0));
        effort += std::clamp(-j.damping * v, -cap, cap);
      }
      if (explicit_motor) effort += std::clamp(reaching(motor_velocity), -motor_max_effort, motor_max_effort);
    }
    if (effort == 0.0) return;
    const btVector3 axis = axisWorld(j);
    if (j.hinge) {
      const btVector3 torque = axis * effort;
      j.child->applyTorque(torque);
      if (!j.parent->isStaticObject()) j.parent->applyTorque(-torque);
    } else {
      btTransform pf, cf;
      jointFrames(j, pf, cf);
      const btVector3 force = axis * effort;
      const btVector3& point = cf.getOrigin();
      j.child->applyForce(force, point - j.child->getCenterOfMassPosition());
      if (!j.parent->isStaticObject()) j.parent->applyForce(-force, point - j.parent->getCenterOfMassPosition());
    }
  }

  // ---- lookup ----

  const Model& modelAt(ModelId model) const {
    if (model < 0 || model >= static_cast<ModelId>(models_.size()) || !models_[model])
      throw std::out_of_range("bullet: no model " + std::to_string(model));
    return *models_[model];
  }
  const Body& bodyAt(ModelId model, int body) const {
    const Model& m = modelAt(model);
    if (body < 0 || body >= static_cast<int>(m.bodies.size()))
      throw std::out_of_range("bullet: model " + std::to_string(model) + " has no body " + std::to_string(body));
    return m.bodies[body];
  }
  const Joint& jointAt(ModelId model, int joint) const {
    const Model& m = modelAt(model);
    if (joint < 0 || joint >= static_cast<int>(m.joints.size()))
      throw std::out_of_range("bullet: model " + std::to_string(model) + " has no joint " + std::to_string(joint));
    return m.joints[joint];
  }
  Joint& jointAt(ModelId model, int joint) {
    return const_cast<Joint&>(static_cast<const BulletEngine*>(this)->jointAt(model, joint));
  }

  // Declaration order is destruction order reversed: the world goes before what it uses, and
  // the objects (removed from the world in the destructor) after it.
  ModelPairFilter pair_filter_;
  std::deque<SurfaceParams> surfaces_;  // stable addresses, pointed to by shapes and objects
  std::vector<std::unique_ptr<btTriangleMesh>> meshes_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::vector<std::unique_ptr<btTypedConstraint>> constraints_;
  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btDbvtBroadphase> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<WorldWithoutCcd> world_;
  std::vector<std::unique_ptr<Model>> models_;
  std::unordered_map<const btCollisionObject*, ContactSide> sides_;  // who each object is
};

}  // namespace

std::unique_ptr<PhysicsEngine> createBulletEngine(const PhysicsSettings& settings) {
  return std::make_unique<BulletEngine>(settings);
}

}  // namespace conde_physics
