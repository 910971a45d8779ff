// Engine-neutral description of what the physics engines simulate.
//
// A robot from URDF is reduced (see urdf_model.h) to rigid bodies joined by movable joints:
// links connected by fixed joints are merged into one body, so the engines never see fixed
// joints. Each body keeps the frame of its root link ("link frame"); the engines place the body
// at its centre of mass with principal axes (`inertial_frame`), which both ODE and Bullet want.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "conde_physics/math.h"

namespace conde_physics {

class MeshBvh;

enum class ShapeType { kBox, kCylinder, kSphere, kMesh };

// Collision geometry. Cylinders have their axis along local z (URDF convention).
struct Shape {
  ShapeType type = ShapeType::kBox;
  Vec3 box_size_m;                    // kBox: full edge lengths
  double radius_m = 0.0;              // kCylinder, kSphere
  double length_m = 0.0;              // kCylinder
  std::vector<Vec3> mesh_vertices_m;  // kMesh: already scaled
  std::vector<int> mesh_triangles;    // kMesh: 3 vertex indices per triangle
  // kMesh, optional: a hierarchy over these triangles for ray queries, shared between copies
  // (the ray caster builds one when it is missing).
  std::shared_ptr<const MeshBvh> mesh_bvh;
};

// Contact properties, as in Gazebo's <gazebo reference="link"> tags. Two touching surfaces use
// the smaller friction coefficient; a stiffness of 0 means "rigid" (engine default contact).
struct SurfaceParams {
  double mu = 1.0;             // Coulomb friction coefficient (Gazebo mu1)
  double mu2 = 1.0;            // second direction (Gazebo mu2); engines use min(mu, mu2)
  double stiffness_npm = 0.0;  // Gazebo kp [N/m]
  double damping_nspm = 0.0;   // Gazebo kd [N s/m]
};

struct CollisionSpec {
  Shape shape;
  Pose pose_in_link;  // relative to the body's link frame
  SurfaceParams surface;
};

struct BodySpec {
  std::string name;                       // name of the root link of the merged group
  std::vector<std::string> merged_links;  // root link first, then links fixed to it
  std::vector<Pose> merged_link_poses;    // pose of each merged link in the body's link frame
  double mass_kg = 0.0;
  Pose inertial_frame;          // centre of mass + principal axes, in the link frame
  Vec3 principal_inertia_kgm2;  // diagonal inertia about `inertial_frame`
  std::vector<CollisionSpec> collisions;
  Pose initial_pose_in_model;  // link frame in the model frame at zero joint positions
};

enum class JointType { kRevolute, kContinuous, kPrismatic };

struct JointSpec {
  std::string name;
  JointType type = JointType::kRevolute;
  int parent_body = -1;  // index into ArticulatedModel::bodies
  int child_body = -1;
  // Joint frame in the parent body's link frame. At zero position the child's link frame
  // coincides with the joint frame (URDF convention).
  Pose pose_in_parent;
  Vec3 axis{1, 0, 0};  // unit axis in the joint frame
  bool has_position_limits = false;
  double lower = 0.0, upper = 0.0;  // [rad] or [m]
  double effort_limit = 0.0;        // [N m] or [N]; 0 = unlimited
  double velocity_limit = 0.0;      // [rad/s] or [m/s]; 0 = unlimited
  double damping = 0.0;             // viscous [N m s/rad] or [N s/m]
  double friction = 0.0;            // Coulomb [N m] or [N]
};

struct ArticulatedModel {
  std::string name;
  std::vector<BodySpec> bodies;  // body 0 is the root
  std::vector<JointSpec> joints;
  // True when the root body is welded to the world (URDF "world" link, or a static object).
  bool fixed_to_world = false;
  // What Gazebo reports as an error and goes on with: a visual mesh that does not load (physics
  // does not need it). One message each, naming the description, the link and the file.
  std::vector<std::string> visual_errors;

  int bodyIndex(const std::string& link_name) const;    // body holding that link, or -1
  int jointIndex(const std::string& joint_name) const;  // -1 when absent
  // Pose of any link (merged or not) relative to its body's link frame; false if unknown.
  bool linkInBody(const std::string& link_name, int& body, Pose& link_in_body) const;
};

// Global settings of a world's physics (defaults as in SDF's ODE defaults).
struct PhysicsSettings {
  Vec3 gravity_mps2{0.0, 0.0, -9.81};
  double step_s = 0.001;
  int solver_iterations = 50;
  double contact_erp = 0.2;
  double contact_cfm = 0.0;
  double contact_surface_layer_m = 0.001;
  double max_contact_correcting_vel_mps = 100.0;
  int max_contacts = 10;  // per pair of touching shapes
};

// Mass and inertia of uniform solids about their centre [kg, kg m^2] (axes as in Shape).
Inertia boxInertia(double mass_kg, const Vec3& size_m);
Inertia cylinderInertia(double mass_kg, double radius_m, double length_m);
Inertia sphereInertia(double mass_kg, double radius_m);

}  // namespace conde_physics
