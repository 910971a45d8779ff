// ODE backend (libode 0.16, double precision) of PhysicsEngine.
//
// Each body is an ODE body at its centre of mass with principal axes; geoms hang off it with
// offsets. A model welded to the world gets a kinematic root body, so it is exactly still but
// still carries joints and geoms. Contacts come from the engine's own spaces (dynamic geoms, and
// static ones apart); joints are hinges (revolute, continuous) and sliders (prismatic) attached
// as (child, parent), so ODE's angle, rate, motor and torque signs match the URDF convention
// "child relative to parent about the axis". Wheels (tyre.h) touch planes at one point of a
// rounded tread, computed here, as Bullet's rounded cylinders do; all other pairs use dCollide.
#include "ode/ode_engine.h"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "conde_physics/tyre.h"
#include "contact_correction.h"

namespace conde_physics {
namespace {

// Stand-in for massless bodies (the builder warns about them earlier) [kg, kg m^2].
constexpr double kTinyMassKg = 1e-3;
constexpr double kTinyInertiaKgm2 = 1e-6;
// Floor for principal moments: ODE rejects a mass whose inertia is not positive definite.
constexpr double kMinInertiaKgm2 = 1e-12;

constexpr double kTwoPi = 2.0 * M_PI;

// Library init once per process, ODE's per-thread data once per calling thread.
void ensureOdeThreadData() {
  static const bool initialized = [] { return dInitODE2(0) != 0; }();
  if (!initialized) throw std::runtime_error("ode: dInitODE2 failed");
  thread_local bool allocated = false;
  if (!allocated) {
    dAllocateODEDataForThread(dAllocateMaskAll);
    allocated = true;
  }
}

// This libode is built without thread-local storage: the random seed QuickStep uses to shuffle
// constraint rows and OPCODE's trimesh collider cache are process-wide. Every engine saves and
// restores its own seed (determinism), and holds this lock while it creates or destroys geoms,
// steps or casts rays, so engines in different threads stay correct and deterministic (they
// are serialised; an uncontended lock costs ~20 ns of a ~10 us step).
std::mutex& odeGlobalStateMutex() {
  static std::mutex mutex;
  return mutex;
}

Vec3 toVec3(const dReal* v) { return Vec3(v[0], v[1], v[2]); }
Quat toQuat(const dReal* q) { return Quat(q[0], q[1], q[2], q[3]); }  // ODE is (w, x, y, z) too
void toOde(const Quat& q, dQuaternion out) {
  out[0] = q.w;
  out[1] = q.x;
  out[2] = q.y;
  out[3] = q.z;
}

bool finitePositive(double v) { return std::isfinite(v) && v > 0.0; }

// Owned by the engine; every geom's user data points at one (stable address in a deque).
struct GeomInfo {
  ModelId model = -1;     // -1: static world
  int body = -1;          // body index in the model (model >= 0)
  int static_shape = -1;  // static world: addStaticShape index, -1 for the ground plane
  SurfaceParams surface;
  bool tyre = false;  // a wheel's cylinder (tyre.h): one rounded-tread contact on planes
  double tyre_radius_m = 0.0, tyre_width_m = 0.0;
};

// Vertex and index arrays must outlive the trimesh data that references them.
struct MeshStore {
  std::vector<double> vertices_m;  // x, y, z per vertex
  std::vector<dTriIndex> indices;  // 3 per triangle
  dTriMeshDataID data = nullptr;
};

struct JointState {
  dJointID id = nullptr;
  // Constraint forces of the last step; ODE writes them through the pointer (hence the heap).
  std::unique_ptr<dJointFeedback> feedback = std::make_unique<dJointFeedback>();
  bool hinge = true;            // false: slider
  double damping = 0.0;         // [N m s/rad] or [N s/m]
  double friction = 0.0;        // [N m] or [N]
  double effort_limit = 0.0;    // 0 = unlimited
  double velocity_limit = 0.0;  // 0 = unlimited
  double pending_effort = 0.0;  // applied in the next step only
  // Unwrapped hinge angle = raw - raw_at_attach + 2 pi * turns; ODE's raw angle wraps at ±pi.
  double raw_at_attach_rad = 0.0;
  double last_raw_rad = 0.0;
  long turns = 0;
};

struct ModelState {
  std::vector<dBodyID> bodies;
  std::vector<Pose> link_in_body;  // inverse(inertial_frame): link frame in the ODE body frame
  size_t first_joint = 0;          // index into OdeEngine::joints_
  size_t joint_count = 0;
  dSpaceID space = nullptr;           // the moving geoms
  std::vector<dGeomID> static_geoms;  // geoms of a kinematic root (in the static space)
  bool removed = false;
};

class OdeEngine final : public PhysicsEngine {
 public:
  explicit OdeEngine(const PhysicsSettings& settings);
  ~OdeEngine() override;
  OdeEngine(const OdeEngine&) = delete;
  OdeEngine& operator=(const OdeEngine&) = delete;

  std::string name() const override { return "ode"; }
  void addGroundPlane(const SurfaceParams& surface) override;
  void addStaticShape(const Shape& shape, const Pose& world_pose, const SurfaceParams& surface) override;
  ModelId addModel(const ArticulatedModel& model, const Pose& root_pose) override;
  void removeModel(ModelId model) override;
  void step() override;
  Pose bodyPose(ModelId model, int body) const override;
  Twist bodyTwist(ModelId model, int body) const override;
  void setBodyState(ModelId model, int body, const Pose& link_pose, const Twist& twist) override;
  void addBodyWrench(ModelId model, int body, const Vec3& force_N, const Vec3& torque_Nm,
                     const Vec3& point_world) override;
  double jointPosition(ModelId model, int joint) const override;
  double jointVelocity(ModelId model, int joint) const override;
  void setJointVelocityMotor(ModelId model, int joint, double velocity, double max_effort) override;
  void addJointEffort(ModelId model, int joint, double effort) override;
  JointWrench jointWrench(ModelId model, int joint) const override;

 private:
  static void nearCallback(void* data, dGeomID a, dGeomID b);
  void collidePair(dGeomID a, dGeomID b);
  int tyreOnPlaneContact(dGeomID tyre, const GeomInfo& info, dGeomID plane);
  dGeomID createGeom(const Shape& shape);
  GeomInfo& registerGeom(dGeomID geom, ModelId model, const SurfaceParams& surface, dSpaceID space);
  const ModelState& modelAt(ModelId model) const;
  dBodyID bodyAt(ModelId model, int body) const;
  const JointState& jointAt(ModelId model, int joint) const;
  JointState& jointAt(ModelId model, int joint) {
    return const_cast<JointState&>(static_cast<const OdeEngine*>(this)->jointAt(model, joint));
  }
  void setMotorParams(const JointState& joint, double velocity, double max_effort);

  dWorldID world_ = nullptr;
  // Static geoms (world shapes, kinematic roots of welded models) never collide with each other,
  // so they live apart: a step tests dynamic-dynamic pairs plus dynamic x static, which stays
  // cheap with many static shapes (a simple space's pair sweep would be quadratic in them).
  // The moving geoms of each model sit in a space of their own inside `dynamic_space_`: a step
  // tests models' bounding boxes against each other and looks inside two models only where
  // those overlap, so the pairs grow with the number of models, not of geoms, and pairs within
  // one model (which must not collide) are never even formed.
  dSpaceID dynamic_space_ = nullptr;
  dSpaceID static_space_ = nullptr;
  dJointGroupID contact_group_ = nullptr;
  unsigned long rand_seed_ = 0;  // this engine's QuickStep shuffle seed
  int max_contacts_per_pair_ = 1;
  std::vector<dContact> contacts_;  // dCollide output, max_contacts_per_pair_ long
  // The step's contact joints' feedback (stable addresses), one per entry of last_contacts_.
  std::deque<dJointFeedback> feedback_;
  std::vector<char> feedback_reversed_;  // the joint's first body is b's (a has no body)
  std::deque<GeomInfo> geom_infos_;
  std::vector<std::unique_ptr<MeshStore>> meshes_;
  std::vector<ModelState> models_;
  std::vector<JointState> joints_;  // all models' joints, models_ index into it
};

OdeEngine::OdeEngine(const PhysicsSettings& settings) : PhysicsEngine(settings) {
  if (!finitePositive(settings.step_s)) throw std::invalid_argument("ode: step_s must be > 0");
  ensureOdeThreadData();
  world_ = dWorldCreate();
  const Vec3& g = settings.gravity_mps2;
  dWorldSetGravity(world_, g.x, g.y, g.z);
  // Before any joint is created: joint limits copy the world ERP/CFM as their stop ERP/CFM.
  dWorldSetERP(world_, settings.contact_erp);
  dWorldSetCFM(world_, settings.contact_cfm);
  dWorldSetQuickStepNumIterations(world_, std::max(1, settings.solver_iterations));
  dWorldSetContactSurfaceLayer(world_, settings.contact_surface_layer_m);
  dWorldSetContactMaxCorrectingVel(world_, settings.max_contact_correcting_vel_mps);
  dWorldSetAutoDisableFlag(world_, 0);

  // Few models and few static shapes per world: a simple space's AABB sweep beats hashing at
  // this size, and a hash space's collide2 against a geom is a linear scan anyway.
  dynamic_space_ = dSimpleSpaceCreate(nullptr);
  static_space_ = dSimpleSpaceCreate(nullptr);
  contact_group_ = dJointGroupCreate(0);

  max_contacts_per_pair_ = std::clamp(settings.max_contacts, 1, 0xffff);  // dCollide flags: 16 bits
  contacts_.resize(static_cast<size_t>(max_contacts_per_pair_));
}

OdeEngine::~OdeEngine() {
  std::lock_guard<std::mutex> lock(odeGlobalStateMutex());
  // Geoms first (a space destroys its geoms and spaces), then what they reference, then the world.
  dSpaceDestroy(dynamic_space_);
  dSpaceDestroy(static_space_);
  for (auto& mesh : meshes_) dGeomTriMeshDataDestroy(mesh->data);
  dJointGroupDestroy(contact_group_);
  dWorldDestroy(world_);  // bodies and joints
}

GeomInfo& OdeEngine::registerGeom(dGeomID geom, ModelId model, const SurfaceParams& surface, dSpaceID space) {
  GeomInfo info;
  info.model = model;
  info.surface = surface;
  geom_infos_.push_back(info);
  dGeomSetData(geom, &geom_infos_.back());
  dSpaceAdd(space, geom);
  return geom_infos_.back();
}

// Throws before anything is created, so a rejected model leaves the world untouched.
void validateShape(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::kBox: {
      const Vec3& s = shape.box_size_m;
      if (!finitePositive(s.x) || !finitePositive(s.y) || !finitePositive(s.z))
        throw std::invalid_argument("ode: box sizes must be > 0");
      return;
    }
    case ShapeType::kCylinder:
      if (!finitePositive(shape.radius_m) || !finitePositive(shape.length_m))
        throw std::invalid_argument("ode: cylinder radius and length must be > 0");
      return;
    case ShapeType::kSphere:
      if (!finitePositive(shape.radius_m)) throw std::invalid_argument("ode: sphere radius must be > 0");
      return;
    case ShapeType::kMesh:
      if (shape.mesh_triangles.empty() || shape.mesh_triangles.size() % 3 != 0)
        throw std::invalid_argument("ode: mesh needs 3 indices per triangle");
      for (int index : shape.mesh_triangles) {
        if (index < 0 || static_cast<size_t>(index) >= shape.mesh_vertices_m.size())
          throw std::invalid_argument("ode: mesh triangle index out of range");
      }
      return;
  }
  throw std::invalid_argument("ode: unknown shape type");
}

dGeomID OdeEngine::createGeom(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::kBox:
      return dCreateBox(nullptr, shape.box_size_m.x, shape.box_size_m.y, shape.box_size_m.z);
    case ShapeType::kCylinder:
      return dCreateCylinder(nullptr, shape.radius_m, shape.length_m);  // axis along local z
    case ShapeType::kSphere:
      return dCreateSphere(nullptr, shape.radius_m);
    case ShapeType::kMesh:
      break;
  }
  auto mesh = std::make_unique<MeshStore>();
  mesh->vertices_m.reserve(3 * shape.mesh_vertices_m.size());
  for (const Vec3& v : shape.mesh_vertices_m) mesh->vertices_m.insert(mesh->vertices_m.end(), {v.x, v.y, v.z});
  mesh->indices.assign(shape.mesh_triangles.begin(), shape.mesh_triangles.end());
  mesh->data = dGeomTriMeshDataCreate();
  dGeomTriMeshDataBuildDouble(mesh->data, mesh->vertices_m.data(), 3 * sizeof(double),
                              static_cast<int>(shape.mesh_vertices_m.size()), mesh->indices.data(),
                              static_cast<int>(mesh->indices.size()), 3 * sizeof(dTriIndex));
  dGeomID geom = dCreateTriMesh(nullptr, mesh->data, nullptr, nullptr, nullptr);
  meshes_.push_back(std::move(mesh));
  return geom;
}

void OdeEngine::addGroundPlane(const SurfaceParams& surface) {
  std::lock_guard<std::mutex> lock(odeGlobalStateMutex());
  registerGeom(dCreatePlane(nullptr, 0, 0, 1, 0), -1, surface, static_space_);
  ray_scene_.addGroundPlane();
}

void OdeEngine::addStaticShape(const Shape& shape, const Pose& world_pose, const SurfaceParams& surface) {
  validateShape(shape);
  std::lock_guard<std::mutex> lock(odeGlobalStateMutex());
  dGeomID geom = createGeom(shape);
  dGeomSetPosition(geom, world_pose.position.x, world_pose.position.y, world_pose.position.z);
  dQuaternion q;
  toOde(world_pose.orientation, q);
  dGeomSetQuaternion(geom, q);
  registerGeom(geom, -1, surface, static_space_).static_shape = static_shape_count_++;
  ray_scene_.addStatic(shape, world_pose);
}

ModelId OdeEngine::addModel(const ArticulatedModel& model, const Pose& root_pose) {
  if (model.bodies.empty()) throw std::invalid_argument("ode: model '" + model.name + "' has no bodies");
  const int body_count = static_cast<int>(model.bodies.size());
  for (const JointSpec& j : model.joints) {
    if (j.parent_body < 0 || j.parent_body >= body_count || j.child_body < 0 || j.child_body >= body_count ||
        j.parent_body == j.child_body)
      throw std::invalid_argument("ode: joint '" + j.name + "' has invalid bodies");
  }
  for (const BodySpec& body : model.bodies) {
    for (const CollisionSpec& collision : body.collisions) validateShape(collision.shape);
  }
  std::lock_guard<std::mutex> lock(odeGlobalStateMutex());
  const ModelId id = static_cast<ModelId>(models_.size());
  ModelState state;
  state.first_joint = joints_.size();
  state.joint_count = model.joints.size();
  const dSpaceID model_space = dSimpleSpaceCreate(dynamic_space_);  // destroyed with dynamic_space_
  state.space = model_space;

  for (int b = 0; b < body_count; ++b) {
    const BodySpec& spec = model.bodies[b];
    const bool kinematic = model.fixed_to_world && b == 0;
    dBodyID body = dBodyCreate(world_);
    const Pose com_world = root_pose * spec.initial_pose_in_model * spec.inertial_frame;
    dBodySetPosition(body, com_world.position.x, com_world.position.y, com_world.position.z);
    dQuaternion q;
    toOde(com_world.orientation, q);
    dBodySetQuaternion(body, q);

    double mass_kg = spec.mass_kg;
    Vec3 inertia_kgm2 = spec.principal_inertia_kgm2;
    if (!finitePositive(mass_kg)) {
      mass_kg = kTinyMassKg;
      inertia_kgm2 = Vec3(kTinyInertiaKgm2, kTinyInertiaKgm2, kTinyInertiaKgm2);
    }
    dMass mass;
    dMassSetZero(&mass);
    dMassSetParameters(&mass, mass_kg, 0, 0, 0, std::max(inertia_kgm2.x, kMinInertiaKgm2),
                       std::max(inertia_kgm2.y, kMinInertiaKgm2), std::max(inertia_kgm2.z, kMinInertiaKgm2), 0, 0, 0);
    dBodySetMass(body, &mass);
    if (kinematic) dBodySetKinematic(body);  // infinite mass, zero velocity: exactly still

    const Pose link_in_body = spec.inertial_frame.inverse();
    for (const CollisionSpec& collision : spec.collisions) {
      dGeomID geom = createGeom(collision.shape);
      dGeomSetBody(geom, body);
      const Pose offset = link_in_body * collision.pose_in_link;
      dGeomSetOffsetPosition(geom, offset.position.x, offset.position.y, offset.position.z);
      dQuaternion oq;
      toOde(offset.orientation, oq);
      dGeomSetOffsetQuaternion(geom, oq);
      GeomInfo& info = registerGeom(geom, id, collision.surface, kinematic ? static_space_ : model_space);
      info.body = static_cast<int>(state.bodies.size());
      if (kinematic) state.static_geoms.push_back(geom);
      if (!kinematic && isWheelCollision(model, b, collision) &&
          canBeTyre(collision.shape.radius_m, collision.shape.length_m)) {
        info.tyre = true;
        info.tyre_radius_m = collision.shape.radius_m;
        info.tyre_width_m = collision.shape.length_m;
      }
    }
    state.bodies.push_back(body);
    state.link_in_body.push_back(link_in_body);
  }

  for (const JointSpec& spec : model.joints) {
    const Pose joint_world = root_pose * model.bodies[spec.parent_body].initial_pose_in_model * spec.pose_in_parent;
    const Vec3 axis = joint_world.orientation.rotate(spec.axis.normalized());
    dBodyID child = state.bodies[spec.child_body];
    dBodyID parent = state.bodies[spec.parent_body];
    JointState joint;
    joint.hinge = spec.type != JointType::kPrismatic;
    joint.damping = std::max(0.0, spec.damping);
    joint.friction = std::max(0.0, spec.friction);
    joint.effort_limit = std::max(0.0, spec.effort_limit);
    joint.velocity_limit = std::max(0.0, spec.velocity_limit);
    // Anchor and axis are set after attaching: ODE records the current relative pose as zero.
    if (joint.hinge) {
      joint.id = dJointCreateHinge(world_, nullptr);
      dJointAttach(joint.id, child, parent);
      dJointSetHingeAnchor(joint.id, joint_world.position.x, joint_world.position.y, joint_world.position.z);
      dJointSetHingeAxis(joint.id, axis.x, axis.y, axis.z);
      joint.raw_at_attach_rad = joint.last_raw_rad = dJointGetHingeAngle(joint.id);
    } else {
      joint.id = dJointCreateSlider(world_, nullptr);
      dJointAttach(joint.id, child, parent);
      dJointSetSliderAxis(joint.id, axis.x, axis.y, axis.z);
    }
    *joint.feedback = dJointFeedback{};
    dJointSetFeedback(joint.id, joint.feedback.get());  // the child is body 1
    if (spec.type != JointType::kContinuous && spec.has_position_limits) {
      // Lo first: ODE ignores a LoStop above the current HiStop (initially +inf).
      if (joint.hinge) {
        dJointSetHingeParam(joint.id, dParamLoStop, spec.lower);
        dJointSetHingeParam(joint.id, dParamHiStop, spec.upper);
      } else {
        dJointSetSliderParam(joint.id, dParamLoStop, spec.lower);
        dJointSetSliderParam(joint.id, dParamHiStop, spec.upper);
      }
    }
    setMotorParams(joint, 0.0, 0.0);  // motor off: friction only
    joints_.push_back(std::move(joint));
  }
  models_.push_back(std::move(state));
  ray_scene_.addModel(id, model);
  return id;
}

void OdeEngine::removeModel(ModelId model) {
  modelAt(model);  // validates
  std::lock_guard<std::mutex> lock(odeGlobalStateMutex());
  ModelState& m = models_[static_cast<size_t>(model)];
  last_contacts_.clear();
  for (size_t j = 0; j < m.joint_count; ++j) {
    JointState& joint = joints_[m.first_joint + j];
    dJointDestroy(joint.id);
    joint.id = nullptr;  // step() skips it
  }
  for (dGeomID geom : m.static_geoms) dGeomDestroy(geom);
  dSpaceDestroy(m.space);  // and its geoms
  for (dBodyID body : m.bodies) dBodyDestroy(body);
  m = ModelState();
  m.removed = true;
  ray_scene_.removeModel(model);
}

const ModelState& OdeEngine::modelAt(ModelId model) const {
  if (model < 0 || static_cast<size_t>(model) >= models_.size() || models_[static_cast<size_t>(model)].removed)
    throw std::out_of_range("ode: unknown model id " + std::to_string(model));
  return models_[static_cast<size_t>(model)];
}

dBodyID OdeEngine::bodyAt(ModelId model, int body) const {
  const ModelState& m = modelAt(model);
  if (body < 0 || static_cast<size_t>(body) >= m.bodies.size())
    throw std::out_of_range("ode: unknown body index " + std::to_string(body));
  return m.bodies[static_cast<size_t>(body)];
}

const JointState& OdeEngine::jointAt(ModelId model, int joint) const {
  const ModelState& m = modelAt(model);
  if (joint < 0 || static_cast<size_t>(joint) >= m.joint_count)
    throw std::out_of_range("ode: unknown joint index " + std::to_string(joint));
  return joints_[m.first_joint + static_cast<size_t>(joint)];
}

void OdeEngine::setMotorParams(const JointState& joint, double velocity, double max_effort) {
  // No motor: a zero-velocity motor whose strength is the Coulomb friction (0 disables it).
  if (!(max_effort > 0.0)) {
    velocity = 0.0;
    max_effort = joint.friction;
  }
  if (joint.hinge) {
    dJointSetHingeParam(joint.id, dParamVel, velocity);
    dJointSetHingeParam(joint.id, dParamFMax, max_effort);
  } else {
    dJointSetSliderParam(joint.id, dParamVel, velocity);
    dJointSetSliderParam(joint.id, dParamFMax, max_effort);
  }
}

void OdeEngine::setJointVelocityMotor(ModelId model, int joint, double velocity, double max_effort) {
  const JointState& j = jointAt(model, joint);
  if (j.velocity_limit > 0.0) velocity = std::clamp(velocity, -j.velocity_limit, j.velocity_limit);
  if (j.effort_limit > 0.0) max_effort = std::min(max_effort, j.effort_limit);
  setMotorParams(j, velocity, max_effort);
}

void OdeEngine::addJointEffort(ModelId model, int joint, double effort) {
  jointAt(model, joint).pending_effort += effort;
}

JointWrench OdeEngine::jointWrench(ModelId model, int joint) const {
  const dJointFeedback& f = *jointAt(model, joint).feedback;  // ODE bodies sit at the centre of mass
  return JointWrench{Vec3(f.f1[0], f.f1[1], f.f1[2]), Vec3(f.t1[0], f.t1[1], f.t1[2])};
}

// Called for pairs whose bounding boxes overlap; a model's space stands for all its geoms.
void OdeEngine::nearCallback(void* data, dGeomID a, dGeomID b) {
  if (dGeomIsSpace(a) || dGeomIsSpace(b)) {
    dSpaceCollide2(a, b, data, &OdeEngine::nearCallback);
    return;
  }
  static_cast<OdeEngine*>(data)->collidePair(a, b);
}

// One contact at the deepest point of the rounded tread (tyre.h), normal out of the plane into
// the tyre; 0 when the tyre does not touch. -1 when the wheel lies on its face: use dCollide.
int OdeEngine::tyreOnPlaneContact(dGeomID tyre, const GeomInfo& info, dGeomID plane) {
  dVector4 plane_params;  // unit normal (a, b, c) and offset d of a x + b y + c z = d
  dGeomPlaneGetParams(plane, plane_params);
  const dReal* r = dGeomGetRotation(tyre);  // 3x4 row-major: the cylinder axis is column z
  TyreContact tc;
  const Vec3 normal(plane_params[0], plane_params[1], plane_params[2]);
  const Vec3 axis(r[2], r[6], r[10]);
  const Vec3 centre = toVec3(dGeomGetPosition(tyre));
  switch (tyreOnPlane(centre, axis, info.tyre_radius_m, info.tyre_width_m, normal, plane_params[3], tc)) {
    case TyreOnPlane::kApart:
      return 0;
    case TyreOnPlane::kOnFace:
      return -1;
    case TyreOnPlane::kTouching:
      break;
  }
  dContactGeom& c = contacts_[0].geom;
  c.pos[0] = tc.point_m.x;
  c.pos[1] = tc.point_m.y;
  c.pos[2] = tc.point_m.z;
  c.normal[0] = normal.x;
  c.normal[1] = normal.y;
  c.normal[2] = normal.z;
  c.depth = tc.depth_m;
  c.g1 = tyre;
  c.g2 = plane;
  c.side1 = c.side2 = -1;
  return 1;
}

void OdeEngine::collidePair(dGeomID a, dGeomID b) {
  // Static-static pairs never get here (separate spaces), nor pairs within one model's space;
  // bodies of one model do not collide, so skip a welded model's parts meeting its static root.
  const auto* info_a = static_cast<const GeomInfo*>(dGeomGetData(a));
  const auto* info_b = static_cast<const GeomInfo*>(dGeomGetData(b));
  if (info_a->model >= 0 && info_a->model == info_b->model) return;

  int count = -1;
  if (info_b->tyre && dGeomGetClass(a) == dPlaneClass) {  // tyre first: the normal points into it
    std::swap(a, b);
    std::swap(info_a, info_b);
  }
  if (info_a->tyre && dGeomGetClass(b) == dPlaneClass) count = tyreOnPlaneContact(a, *info_a, b);
  if (count < 0) count = dCollide(a, b, max_contacts_per_pair_, &contacts_[0].geom, sizeof(dContact));
  if (count <= 0) return;

  dSurfaceParameters surface{};
  surface.mode = dContactApprox1 | dContactMu2;
  surface.mu = std::max(0.0, std::min(info_a->surface.mu, info_b->surface.mu));
  surface.mu2 = std::max(0.0, std::min(info_a->surface.mu2, info_b->surface.mu2));
  // Springs in series (Gazebo); a stiffness of 0 is rigid, so the other surface's one applies.
  const double kp_a = info_a->surface.stiffness_npm, kp_b = info_b->surface.stiffness_npm;
  const double kp_npm = kp_a > 0.0 && kp_b > 0.0 ? 1.0 / (1.0 / kp_a + 1.0 / kp_b) : std::max({kp_a, kp_b, 0.0});
  if (kp_npm > 0.0) {
    const double kd_nspm = std::max(0.0, info_a->surface.damping_nspm) + std::max(0.0, info_b->surface.damping_nspm);
    const double hkp = settings_.step_s * kp_npm;
    surface.mode |= dContactSoftERP | dContactSoftCFM;
    surface.soft_erp = hkp / (hkp + kd_nspm);
    surface.soft_cfm = 1.0 / (hkp + kd_nspm);
  }

  // A rigid contact's correcting velocity is capped as Gazebo caps it (contact_correction.h).
  const double solver_depth_m = kp_npm > 0.0 ? 1e9
                                             : rigidContactSolverDepthM(settings_.contact_surface_layer_m,
                                                                        settings_.contact_erp, settings_.step_s);
  dBodyID body_a = dGeomGetBody(a), body_b = dGeomGetBody(b);
  const ContactSide side_a{info_a->model, info_a->body, info_a->static_shape};
  const ContactSide side_b{info_b->model, info_b->body, info_b->static_shape};
  for (int i = 0; i < count; ++i) {
    contacts_[i].surface = surface;
    const dReal depth_m = contacts_[i].geom.depth;
    contacts_[i].geom.depth = std::min<dReal>(depth_m, solver_depth_m);
    dJointID contact = dJointCreateContact(world_, contact_group_, &contacts_[i]);
    contacts_[i].geom.depth = depth_m;  // reported as it is
    dJointAttach(contact, body_a, body_b);
    feedback_.emplace_back();
    dJointSetFeedback(contact, &feedback_.back());
    feedback_reversed_.push_back(body_a == nullptr);
    const dContactGeom& g = contacts_[i].geom;
    Contact c;
    c.a = side_a;
    c.b = side_b;
    c.position_m = toVec3(g.pos);
    c.normal = toVec3(g.normal);  // ODE: g1 (a) moves along +normal
    c.depth_m = std::max(0.0, static_cast<double>(g.depth));
    last_contacts_.push_back(c);
  }
}

void OdeEngine::step() {
  ensureOdeThreadData();
  std::lock_guard<std::mutex> lock(odeGlobalStateMutex());
  // Viscous damping as an explicit torque from the last velocity: stable while
  // damping * step_s < 2 * (moment of inertia seen by the joint).
  for (JointState& j : joints_) {
    if (j.id == nullptr) continue;  // removed with its model
    double effort = j.pending_effort;
    j.pending_effort = 0.0;
    if (j.hinge) {
      if (j.damping > 0.0) effort -= j.damping * dJointGetHingeAngleRate(j.id);
      if (effort != 0.0) dJointAddHingeTorque(j.id, effort);
    } else {
      if (j.damping > 0.0) effort -= j.damping * dJointGetSliderPositionRate(j.id);
      if (effort != 0.0) dJointAddSliderForce(j.id, effort);
    }
  }
  last_contacts_.clear();
  feedback_.clear();
  feedback_reversed_.clear();
  dSpaceCollide(dynamic_space_, this, &OdeEngine::nearCallback);  // model x model
  dSpaceCollide2(reinterpret_cast<dGeomID>(dynamic_space_), reinterpret_cast<dGeomID>(static_space_), this,
                 &OdeEngine::nearCallback);
  dRandSetSeed(rand_seed_);
  dWorldQuickStep(world_, settings_.step_s);
  rand_seed_ = dRandGetSeed();
  // The joint's first body is a's when a has one; otherwise ODE attached b first (reversed).
  for (size_t i = 0; i < last_contacts_.size(); ++i) {
    Contact& c = last_contacts_[i];
    const Vec3 f1 = toVec3(feedback_[i].f1);
    c.force_on_a_N = feedback_reversed_[i] ? Vec3(-f1.x, -f1.y, -f1.z) : f1;
    c.has_force = true;
  }
  dJointGroupEmpty(contact_group_);

  // Count hinge revolutions: ODE's angle wraps at ±pi; assumes < pi rad per step.
  for (JointState& j : joints_) {
    if (!j.hinge || j.id == nullptr) continue;
    const double raw_rad = dJointGetHingeAngle(j.id);
    const double delta_rad = raw_rad - j.last_raw_rad;
    if (delta_rad > M_PI)
      --j.turns;
    else if (delta_rad < -M_PI)
      ++j.turns;
    j.last_raw_rad = raw_rad;
  }
}

Pose OdeEngine::bodyPose(ModelId model, int body) const {
  dBodyID b = bodyAt(model, body);
  return Pose(toVec3(dBodyGetPosition(b)), toQuat(dBodyGetQuaternion(b))) *
         models_[static_cast<size_t>(model)].link_in_body[static_cast<size_t>(body)];
}

void OdeEngine::setBodyState(ModelId model, int body, const Pose& link_pose, const Twist& twist) {
  dBodyID b = bodyAt(model, body);
  if (dBodyIsKinematic(b)) return;  // the root of a model welded to the world
  const Pose com = link_pose * models_[static_cast<size_t>(model)].link_in_body[static_cast<size_t>(body)].inverse();
  dBodySetPosition(b, com.position.x, com.position.y, com.position.z);
  dQuaternion q;
  toOde(com.orientation.normalized(), q);
  dBodySetQuaternion(b, q);
  const Vec3 v_com = twist.linear_mps + twist.angular_radps.cross(com.position - link_pose.position);
  dBodySetLinearVel(b, v_com.x, v_com.y, v_com.z);
  dBodySetAngularVel(b, twist.angular_radps.x, twist.angular_radps.y, twist.angular_radps.z);
}

void OdeEngine::addBodyWrench(ModelId model, int body, const Vec3& force_N, const Vec3& torque_Nm,
                              const Vec3& point_world) {
  dBodyID b = bodyAt(model, body);  // ODE clears the accumulators after each step
  dBodyAddForceAtPos(b, force_N.x, force_N.y, force_N.z, point_world.x, point_world.y, point_world.z);
  dBodyAddTorque(b, torque_Nm.x, torque_Nm.y, torque_Nm.z);
}

Twist OdeEngine::bodyTwist(ModelId model, int body) const {
  const Pose link = bodyPose(model, body);  // also validates the indices
  dBodyID b = models_[static_cast<size_t>(model)].bodies[static_cast<size_t>(body)];
  dVector3 v;
  dBodyGetPointVel(b, link.position.x, link.position.y, link.position.z, v);
  Twist twist;
  twist.linear_mps = toVec3(v);
  twist.angular_radps = toVec3(dBodyGetAngularVel(b));
  return twist;
}

double OdeEngine::jointPosition(ModelId model, int joint) const {
  const JointState& j = jointAt(model, joint);
  if (!j.hinge) return dJointGetSliderPosition(j.id);
  return j.last_raw_rad - j.raw_at_attach_rad + kTwoPi * static_cast<double>(j.turns);
}

double OdeEngine::jointVelocity(ModelId model, int joint) const {
  const JointState& j = jointAt(model, joint);
  return j.hinge ? dJointGetHingeAngleRate(j.id) : dJointGetSliderPositionRate(j.id);
}

}  // namespace

std::unique_ptr<PhysicsEngine> createOdeEngine(const PhysicsSettings& settings) {
  return std::make_unique<OdeEngine>(settings);
}

}  // namespace conde_physics
