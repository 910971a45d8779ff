// The simulated world without ROS: one physics engine, the world file's ground and objects, the
// robots, and simulated time counted in whole fixed steps (so time never drifts).
// The node (sim_node.cpp) adds ROS around it; tests use it directly and step it.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "conde_physics/camera_renderer.h"
#include "conde_physics/gazebo_blocks.h"
#include "conde_physics/physics_engine.h"
#include "conde_physics/resource_path.h"
#include "conde_physics/world_file.h"

namespace conde_sim {

struct RobotSpec {
  std::string name;                // unique robot name; "" = the URDF's robot name
  std::string ros_namespace;       // "" keeps global topics (/cmd_vel, /odom)
  std::string frame_prefix;        // prepended to TF frames this robot's plugins publish ("" = none)
  std::string source;              // where the URDF came from, for messages
  std::string urdf_xml;            // already xacro-processed
  conde_physics::Pose spawn_pose;  // root link pose in the world
};

struct Robot {
  RobotSpec spec;
  conde_physics::ArticulatedModel model;
  conde_physics::GazeboBlocks gazebo;  // the URDF's <gazebo> blocks: plugins to load
  conde_physics::ModelId id = -1;
  bool removed = false;  // deleted while running: kept so that robot indices stay valid
};

// A model as Gazebo's interface sees it: a robot or a dynamic (non-static) world object.
struct ModelRef {
  int robot = -1;   // index of a robot, or
  int object = -1;  // index of a world object
  bool valid() const { return robot >= 0 || object >= 0; }
};

class Simulation {
 public:
  Simulation(conde_physics::WorldDescription world, std::string engine_name, conde_physics::PackageResolver packages);

  // Parses the URDF and adds the robot at its spawn pose; returns its index.
  // Throws conde_physics::ModelError.
  int addRobot(const RobotSpec& spec, std::vector<std::string>* warnings = nullptr);
  // Adds world objects while running (a spawned SDF model), at their poses: they collide, are
  // hit by rays and are drawn from the next step on, and resetWorld() puts them back there.
  // Throws std::invalid_argument (nothing added) when a name is taken by an object or a robot.
  void addObjects(const std::vector<conde_physics::WorldObject>& objects);
  // Puts every robot and object back to its start; simulated time goes on.
  void resetWorld();
  // Takes a robot out of the world (physics, ray casts, cameras); its index stays valid but
  // findRobot() and findModel() no longer find it, and resetWorld() does not bring it back.
  void removeRobot(int robot);
  // Takes a dynamic world object (of the world file or spawned) out of the world, as removeRobot():
  // findModel() no longer finds it, its name is free again, resetWorld() does not bring it back.
  // Throws std::invalid_argument for a static object (static shapes stay in the engine).
  void removeObject(int object);
  // Index of the robot with this name; "" names the only robot. -1 when there is none.
  int findRobot(const std::string& name) const;
  // New start pose of a robot (root link pose); takes effect at the next resetWorld().
  void setStartPose(int robot, const conde_physics::Pose& pose) { robots_.at(robot).spec.spawn_pose = pose; }
  void step();

  std::uint64_t stepCount() const { return step_count_; }
  double stepS() const { return world_.physics.step_s; }
  double timeS() const { return static_cast<double>(step_count_) * world_.physics.step_s; }

  conde_physics::PhysicsEngine& engine() { return *engine_; }
  const conde_physics::PhysicsEngine& engine() const { return *engine_; }
  const std::string& engineName() const { return engine_name_; }
  const conde_physics::WorldDescription& world() const { return world_; }
  const conde_physics::PackageResolver& packages() const { return packages_; }
  Robot& robot(int index) { return robots_.at(index); }
  const Robot& robot(int index) const { return robots_.at(index); }
  int robotCount() const { return static_cast<int>(robots_.size()); }

  // Pose in the world of any link of a robot (merged into a body or not).
  conde_physics::Pose linkPose(int robot, const std::string& link) const;
  // Velocity of that link's origin and the angular velocity, world coordinates.
  conde_physics::Twist linkTwist(int robot, const std::string& link) const;

  // --- Models (robots and dynamic world objects) by name, as the /gazebo/ services see them ---
  // Robots first, then dynamic world objects; an invalid ref when there is no such model.
  ModelRef findModel(const std::string& name) const;
  std::vector<ModelRef> models() const;  // in the order of modelNames()
  std::string modelName(const ModelRef& model) const;
  const conde_physics::ArticulatedModel& articulatedModel(const ModelRef& model) const;
  // Links of a model that are bodies (fixed-joint children are merged into their parent body,
  // as Gazebo lumps them), root first.
  std::vector<std::string> bodyLinkNames(const ModelRef& model) const;
  // Any link of the model, merged or not; "" is the root link. False when unknown.
  bool hasLink(const ModelRef& model, const std::string& link) const;
  // Link frame pose and the velocity of its origin + angular velocity, world coordinates.
  // Throws std::out_of_range for an unknown link.
  conde_physics::Pose linkPose(const ModelRef& model, const std::string& link) const;
  conde_physics::Twist linkTwist(const ModelRef& model, const std::string& link) const;
  // Moves the whole model rigidly so that its root link is at `root_pose`, every body moving
  // with the rigid-body velocity `twist` of the root link's origin (world coordinates).
  void setModelState(const ModelRef& model, const conde_physics::Pose& root_pose, const conde_physics::Twist& twist);
  // Moves only the body that holds `link` (its joints pull it back).
  void setLinkState(const ModelRef& model, const std::string& link, const conde_physics::Pose& link_pose,
                    const conde_physics::Twist& twist);
  // Force [N] at `point_world` and torque [N m] on the body holding `link`, next step only.
  void addLinkWrench(const ModelRef& model, const std::string& link, const conde_physics::Vec3& force_N,
                     const conde_physics::Vec3& torque_Nm, const conde_physics::Vec3& point_world);
  // The same at the centre of mass of that body (as Gazebo's Link::AddForce and AddTorque).
  void addLinkWrenchAtCentreOfMass(const ModelRef& model, const std::string& link, const conde_physics::Vec3& force_N,
                                   const conde_physics::Vec3& torque_Nm);
  // What the wrench calls above applied to the body holding `link` during the last step: the sum
  // of the forces [N] and the torque [N m] about the body's centre of mass, world coordinates
  // (Gazebo's Link::WorldForce and WorldTorque: applied forces only, not gravity or contacts).
  conde_physics::Twist lastAppliedWrench(const ModelRef& model, const std::string& link) const;

  // Who one side of a physics contact (PhysicsEngine::lastContacts()) is: a robot's body, a
  // world object (static or dynamic, index into world().objects), or the ground (neither).
  struct ContactOwner {
    int robot = -1, body = -1;  // robot index and body index in its model
    int object = -1;            // world object index
    bool ground() const { return robot < 0 && object < 0; }
  };
  ContactOwner contactOwner(const conde_physics::ContactSide& side) const;

  // What cameras see: the world's ground and objects (object i of the world file is scene
  // object i) and every robot's collision shapes (group = robot index; meshes as their bounding
  // boxes). Built on first use; poses follow the physics, synced at most once per step.
  conde_physics::RenderScene& renderScene();
  // Scene objects drawn for one link of a robot (its body's shapes), for display panels.
  std::vector<int> renderObjectsOfLink(int robot, const std::string& link);

 private:
  struct RenderedShape {
    int robot = -1;  // -1: a dynamic world object (model = object_model_ids_[object])
    int body = 0;
    int world_object = -1;
    conde_physics::Pose pose_in_body;
    int scene_index = -1;
  };
  void buildWorld();
  void addObjectToEngine(size_t object);
  void addRobotToScene(int robot);
  void syncRenderScene();

  conde_physics::WorldDescription world_;
  std::string engine_name_;
  conde_physics::PackageResolver packages_;
  std::unique_ptr<conde_physics::PhysicsEngine> engine_;
  std::vector<Robot> robots_;
  conde_physics::ModelId engineId(const ModelRef& model) const;
  int bodyOf(const ModelRef& model, const std::string& link, conde_physics::Pose& link_in_body) const;

  std::vector<conde_physics::ModelId> object_model_ids_;        // per world object; -1 = static
  std::vector<conde_physics::ArticulatedModel> object_models_;  // per world object; empty for static ones
  std::vector<int> static_shape_objects_;                       // world object of each static shape
  std::vector<char> object_removed_;                            // per world object: removeObject() took it out
  std::uint64_t step_count_ = 0;
  // Wrenches applied per (engine model, body) for the coming step and during the last one
  // (force in linear_mps, torque about the centre of mass in angular_radps).
  std::map<std::pair<conde_physics::ModelId, int>, conde_physics::Twist> pending_wrenches_, last_wrenches_;

  std::unique_ptr<conde_physics::RenderScene> render_scene_;
  std::vector<RenderedShape> rendered_shapes_;  // those that move
  bool render_scene_synced_ = false;
  std::uint64_t render_scene_step_ = 0;
};

}  // namespace conde_sim
