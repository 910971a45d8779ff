// URDF (already xacro-processed) -> ArticulatedModel for the physics engines.
//
// Links joined by fixed joints are merged into one rigid body (masses and inertias combined
// with the parallel-axis theorem); revolute, continuous and prismatic joints become engine
// joints. A root link named "world" welds the model to the world, as in Gazebo.
// Contact parameters come from Gazebo's <gazebo reference="link"> tags (mu1, mu2, kp, kd;
// gazebo_blocks.h reads them).
// Assumptions: floating and planar joints are not supported (an error); <mimic> is ignored with
// a warning; visual elements are not used by physics. Meshes: a collision mesh that does not load
// (missing file, unknown package, a file assimp rejects) is a ModelError; a visual mesh that does
// not load is listed in ArticulatedModel::visual_errors and the model loads (Gazebo prints an
// error and goes on without that visual).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "conde_physics/gazebo_blocks.h"
#include "conde_physics/model.h"
#include "conde_physics/resource_path.h"

namespace conde_physics {

class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// `source` names the description in messages (a file name or a parameter name). Throws
// ModelError with a one-line message naming the source and the element at fault. `gazebo`, when
// given, receives the URDF's <gazebo> blocks (the plugins to load).
ArticulatedModel buildModelFromUrdf(const std::string& urdf_xml, const std::string& source,
                                    const PackageResolver& packages, std::vector<std::string>* warnings = nullptr,
                                    GazeboBlocks* gazebo = nullptr);

// A kMesh collision shape (with its ray-query hierarchy) from any mesh file assimp reads (STL,
// Collada, OBJ; mesh_file.h), vertices scaled by `scale`. Throws ModelError
// "mesh file '<path>': <reason>".
Shape meshShapeFromFile(const std::string& path, const Vec3& scale);

}  // namespace conde_physics
