// rviz view of the world: the textured ground as a mesh and the world objects as primitives.
#pragma once

#include <visualization_msgs/MarkerArray.h>

#include <string>

#include "conde_physics/world_file.h"

namespace conde_sim {

// Writes a Collada file of the textured ground rectangle (and a copy of its texture) into
// `cache_dir` and returns its path; returns "" when the world's ground has no texture.
// rviz loads textures relative to the mesh file, hence the copy next to it.
std::string writeGroundMesh(const conde_physics::WorldDescription& world, const std::string& cache_dir);

// Markers in frame "world": the ground mesh (if `ground_mesh_path` is set) and every object.
visualization_msgs::MarkerArray worldMarkers(const conde_physics::WorldDescription& world,
                                             const std::string& ground_mesh_path);

}  // namespace conde_sim
