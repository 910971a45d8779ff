// SDF worlds (`*.world`, `*.sdf`: Gazebo's format, parsed by Debian's libsdformat 12) converted
// into a WorldDescription, so the engines, the ray caster and the cameras take them like a
// `*.world.yaml`.
//
// Usage:
//   WorldDescription world = loadSdfWorld("/abs/shapes.world", packagePath);  // or loadWorldFile
//   for (const std::string& note : world.notes) ROS_INFO("%s", note.c_str());
//
// What becomes what (docs/world_format.md has the full list):
//   - every <collision> of every link becomes a WorldObject with visible = false, every <visual>
//     one with collision = false, both at model pose * link pose * own pose; geometry box,
//     cylinder, sphere, mesh (assimp) and plane (a horizontal plane at z = 0 is the ground, any
//     other plane a 1 mm thick box of its <size>);
//   - a dynamic (non-static) model must be one link with exactly one <collision>: that collision
//     becomes one dynamic object with the link's <mass> (inertia of the solid shape), drawn with
//     the colour of the link's first visual; its visuals are not drawn separately;
//   - <include> with model:// URIs is resolved through GAZEBO_MODEL_PATH, the world file's
//     directory (and its models/ folder), then ROS packages (model://<package>/<path>);
//     mesh URIs also take package://, file:// and paths relative to the SDF file;
//   - colours: <material><diffuse> (else <ambient>), or a Gazebo/<Name> script material;
//   - <physics>: max_step_size, real_time_factor; <gravity>;
//   - lights, scene, GUI, plugins, joints of static models, sensors: accepted, one note each.
// Anything libsdformat rejects throws WorldFileError "<file>:<line>: <libsdformat's message>".
#pragma once

#include <string>
#include <vector>

#include "conde_physics/resource_path.h"
#include "conde_physics/world_file.h"

namespace conde_physics {

WorldDescription loadSdfWorld(const std::string& path, const PackageResolver& packages);

// One SDF model to add to a running world (Gazebo's spawn_sdf_model), converted as a world's
// model is (above), in the model's frame: place each object at spawn_pose * object.pose.
struct SdfModelObjects {
  std::vector<WorldObject> objects;
  bool is_static = true;
  std::vector<std::string> notes;  // what was accepted but is ignored, one line each
};

// `sdf_xml`: an <sdf> holding one <model>, or a <world> with one model (Gazebo's form for a
// model of the model path: <world><include><uri>model://NAME</uri></include></world>). The
// model is renamed `model_name` (as Gazebo does): a dynamic model's object is named
// `model_name`, a static model's shapes `<model_name>__<link>__<collision or visual>`.
// `source` names the XML in messages; relative mesh URIs resolve against the working folder.
// Throws WorldFileError "<source>:<line>: <libsdformat's message>" and for what the world
// loader refuses (e.g. joints in a dynamic model).
SdfModelObjects loadSdfModel(const std::string& sdf_xml, const std::string& source, const std::string& model_name,
                             const PackageResolver& packages);

}  // namespace conde_physics
