// Loader of world files: `*.world.yaml` (format `conde_world/1`) and SDF worlds (`*.world`,
// `*.sdf`, read by libsdformat; sdf_world.h), see docs/world_format.md.
//
// Usage:
//   WorldDescription world = loadWorldFile(path, [](const std::string& pkg) { return ros::package::getPath(pkg); });
//   engine->addGroundPlane(world.ground.friction);
//   for (const WorldObject& o : world.objects) {
//     if (!o.collision) continue;
//     if (o.is_static) engine->addStaticShape(collisionShapeOf(o), o.pose, o.friction);
//     else engine->addModel(modelOfDynamicObject(o), o.pose);
//   }
//
// Validation is strict: any problem throws WorldFileError with a one-line message
// "<file>:<line>: <where>: <what>", e.g.
//   "w.world.yaml:7: objects[1] (box_a): unknown key 'colour' (expected one of: name, ...)".
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "conde_physics/math.h"
#include "conde_physics/mesh_file.h"
#include "conde_physics/model.h"
#include "conde_physics/resource_path.h"

namespace conde_physics {

enum class ObjectShape { kBox, kCylinder, kCone, kSphere, kMesh };

// The infinite plane z = 0. The texture covers [x_min_m, x_max_m] x [y_min_m, y_max_m]:
// image columns run along +x, row 0 is at y_max_m. Elsewhere (or everywhere without a
// texture) the plane has colour `color_rgb`.
struct GroundSpec {
  std::string texture_path;             // absolute, already checked to decode; "" = none
  double x_min_m = 0.0, x_max_m = 0.0;  // both 0 when the file gives no x_range_m
  double y_min_m = 0.0, y_max_m = 0.0;
  Vec3 color_rgb{0.7, 0.7, 0.7};  // 0..1
  SurfaceParams friction;         // only mu and mu2 come from the file
};

struct WorldObject {
  std::string name;  // unique within the world, [A-Za-z0-9_]+
  ObjectShape shape = ObjectShape::kBox;
  Vec3 size_m;            // kBox: full edge lengths; zero for other shapes
  double radius_m = 0.0;  // kCylinder, kCone (base radius), kSphere
  double length_m = 0.0;  // kCylinder, kCone: height along local z
  // Centre of the shape (for a cone: centre of its bounding cylinder; base at local
  // z = -length_m/2, apex at z = +length_m/2).
  Pose pose;
  Vec3 color_rgb{0.7, 0.7, 0.7};  // 0..1
  std::string texture_path;       // kBox only: absolute, checked to decode; "" = none
  std::string display_topic;      // kBox only: sensor_msgs/Image shown on the +z face; "" = none
  bool is_static = true;
  double mass_kg = 0.0;    // > 0 for dynamic objects, 0 for static ones
  bool collision = true;   // false: seen by cameras only (static objects only)
  SurfaceParams friction;  // only mu and mu2 come from the file
  bool visible = true;     // false: collides but cameras do not see it (an SDF <collision>)
  // kMesh (SDF worlds): the triangles in the object frame (scaled), their colours (empty: all
  // color_rgb), a ray-query hierarchy over them, and the file they came from (absolute).
  std::shared_ptr<const MeshData> mesh;
  std::shared_ptr<const MeshBvh> mesh_bvh;
  std::string mesh_path;
};

// Where the cameras see less light (a tunnel under its roof): every surface point inside the
// vertical prism over `polygon_xy_m` with z_min_m <= z <= z_max_m is drawn with its colour times
// `light`. The scene has no light sources, so this is how shade is modelled.
struct LightRegion {
  std::string name;
  std::vector<std::array<double, 2>> polygon_xy_m;  // world (x, y) corners, >= 3, either winding
  double z_min_m = 0.0, z_max_m = 0.0;
  double light = 1.0;  // 0..1
};

// A named start pose for a robot: root link at `pose` (position + yaw only).
struct SpawnPose {
  std::string name;
  Pose pose;
};

struct WorldDescription {
  std::string name;
  std::string source_path;  // absolute, normalised path of the world file
  PhysicsSettings physics;  // file values over PhysicsSettings defaults
  GroundSpec ground;
  std::vector<WorldObject> objects;        // in file order
  std::vector<SpawnPose> spawns;           // in file order
  std::vector<LightRegion> light_regions;  // in file order
  // SDF <physics><real_time_factor>, when the file gives one (the node's parameter wins).
  std::optional<double> real_time_factor;
  // What the loader accepted but ignores, one line each (the node logs them as INFO).
  std::vector<std::string> notes;

  const SpawnPose* findSpawn(const std::string& name) const;  // nullptr when absent
};

class WorldFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads and validates a world file, by its name: `*.world` and `*.sdf` are SDF (loadSdfWorld),
// anything else YAML. For YAML `texture` paths are resolved relative to the file or
// through `packages` (package://) and must decode as images. Throws WorldFileError.
WorldDescription loadWorldFile(const std::string& path, const PackageResolver& packages);

// True when OpenCV can decode the image at `path` (decodes it fully, then drops it).
bool textureLoads(const std::string& path);

// Collision geometry of an object in its own frame. A cone collides as the cylinder of its
// base radius and height (documented simplification); a mesh as its triangles.
Shape collisionShapeOf(const WorldObject& object);

// A one-body model for a dynamic object: link frame = object frame (place it at object.pose),
// uniform-solid inertia of the true shape from mass_kg (a cone's centre of mass lies
// length_m/4 below the object centre; a mesh counts as its solid bounding box), the collision of collisionShapeOf with
// the object's friction. Throws std::invalid_argument for static objects (add those with addStaticShape).
ArticulatedModel modelOfDynamicObject(const WorldObject& object);

}  // namespace conde_physics
