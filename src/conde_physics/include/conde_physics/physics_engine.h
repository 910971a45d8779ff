// The one interface the simulator uses for physics. Backends: ODE and Bullet.
//
// Usage:
//   auto engine = conde_physics::createPhysicsEngine("ode", settings);   // or "bullet"
//   engine->addGroundPlane(ground_surface);
//   ModelId robot = engine->addModel(model, spawn_pose);
//   engine->setJointVelocityMotor(robot, left_wheel, 10.0, 7.5);
//   for (...) engine->step();        // fixed step settings.step_s
//   Pose base = engine->bodyPose(robot, 0);
//
// Contract every backend meets (checked by test/engine_conformance_test.cpp on both engines):
// same calls in the same order give bit-identical results; bodies of one model do not collide
// with each other; joint positions are 0 in the pose the model was added in.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "conde_physics/math.h"
#include "conde_physics/model.h"
#include "conde_physics/ray_caster.h"

namespace conde_physics {

using ModelId = int;

struct RayHit {
  bool hit = false;
  double distance_m = 0.0;  // from the ray origin; max range when no hit
};

// One side of a contact: a body of a model, a static shape, or the ground plane.
struct ContactSide {
  ModelId model = -1;     // >= 0: body `body` of this model; -1: the static world
  int body = -1;          // body index within the model (model >= 0)
  int static_shape = -1;  // model == -1: index of the static shape in addStaticShape order; -1: ground
  bool isGround() const { return model < 0 && static_shape < 0; }
};

// One contact point found in the last step. `normal` (unit, world) points from b towards a:
// a is pushed along +normal, b along -normal.
struct Contact {
  ContactSide a, b;
  Vec3 position_m;         // world
  Vec3 normal;             // world, unit, from b towards a
  double depth_m = 0.0;    // penetration, >= 0
  Vec3 force_on_a_N;       // contact force on a during the step (world); b gets the opposite
  bool has_force = false;  // false when the backend could not tell
};

// What a joint exerts on its child body: force [N] and torque [N m] in world coordinates, the
// torque about the child body's centre of mass.
struct JointWrench {
  Vec3 force_N;
  Vec3 torque_Nm;
};

class PhysicsEngine {
 public:
  virtual ~PhysicsEngine() = default;
  virtual std::string name() const = 0;
  const PhysicsSettings& settings() const { return settings_; }

  // Static world. The ground is the infinite plane z = 0 with +z up.
  virtual void addGroundPlane(const SurfaceParams& surface) = 0;
  virtual void addStaticShape(const Shape& shape, const Pose& world_pose, const SurfaceParams& surface) = 0;

  // Adds a model with its root body's link frame at `root_pose` and all joints at zero.
  // Bodies with zero mass in a non-fixed model get a tiny mass (the builder warns earlier).
  virtual ModelId addModel(const ArticulatedModel& model, const Pose& root_pose) = 0;
  // Takes a model out of the world (bodies, joints, contacts, ray casts). Its id is not reused;
  // any later call with it throws std::out_of_range, as for an id never given out.
  virtual void removeModel(ModelId model) = 0;

  // Advances the world by settings().step_s.
  virtual void step() = 0;

  // The contact points of the last step() (pairs touching or penetrating; empty before the
  // first step). Pairs of one model never appear. Valid until the next step() or removeModel().
  const std::vector<Contact>& lastContacts() const { return last_contacts_; }

  // Link frame of body `body` of a model, in world coordinates.
  virtual Pose bodyPose(ModelId model, int body) const = 0;
  // Velocity of the body's link-frame origin and its angular velocity, world coordinates.
  virtual Twist bodyTwist(ModelId model, int body) const = 0;
  // Teleports one body: its link frame to `link_pose` and the velocity of the link-frame origin
  // and the angular velocity to `twist` (world coordinates). Joints are not checked: move every
  // body of a model by the same transform to keep them together. A model welded to the world
  // keeps its root where it is.
  virtual void setBodyState(ModelId model, int body, const Pose& link_pose, const Twist& twist) = 0;
  // Force [N] at the world point `point_world` [m] and torque [N m], world coordinates, on one
  // body during the next step only (apply_body_wrench calls it every step it lasts).
  virtual void addBodyWrench(ModelId model, int body, const Vec3& force_N, const Vec3& torque_Nm,
                             const Vec3& point_world) = 0;

  virtual double jointPosition(ModelId model, int joint) const = 0;  // [rad] or [m]
  virtual double jointVelocity(ModelId model, int joint) const = 0;  // [rad/s] or [m/s]
  // A velocity motor that holds `velocity` with at most `max_effort` [N m or N] until changed.
  // max_effort = 0 switches the motor off.
  virtual void setJointVelocityMotor(ModelId model, int joint, double velocity, double max_effort) = 0;
  // Effort [N m or N] applied during the next step only (effort control, PID plugins).
  virtual void addJointEffort(ModelId model, int joint, double effort) = 0;
  // The wrench the joint's constraint (with its limits and its motor, without addJointEffort)
  // exerted on the child body during the last step; zero before the first step. Measured by the
  // solver (ODE dJointFeedback, Bullet btJointFeedback), kept for every joint.
  virtual JointWrench jointWrench(ModelId model, int joint) const = 0;

  // Casts rays against every shape (static and dynamic). `origins` and `directions` (unit) in
  // world coordinates; results have max_range_m where nothing is hit within it. A ray that
  // starts inside a shape does not see that shape. Shapes of `ignore_model` (e.g. the robot
  // carrying the sensor) are skipped; -1 skips none. The same exact geometry on every backend
  // (ray_caster.h), at the bodies' current poses. Throws std::invalid_argument when the two
  // lists differ in length.
  void castRays(const std::vector<Vec3>& origins, const std::vector<Vec3>& directions, double max_range_m,
                ModelId ignore_model, std::vector<RayHit>& hits) const;

 protected:
  explicit PhysicsEngine(const PhysicsSettings& settings) : settings_(settings) {}
  PhysicsSettings settings_;
  RayScene ray_scene_;                  // every backend registers its ground plane, static shapes and models here
  std::vector<Contact> last_contacts_;  // every backend fills it in step()
  int static_shape_count_ = 0;          // every backend counts addStaticShape calls (ContactSide)
};

// Names accepted by createPhysicsEngine, in the order they are documented.
std::vector<std::string> availablePhysicsEngines();

// Throws std::invalid_argument("unknown physics engine 'x' (expected one of: ode, bullet)").
std::unique_ptr<PhysicsEngine> createPhysicsEngine(const std::string& name, const PhysicsSettings& settings);

}  // namespace conde_physics
