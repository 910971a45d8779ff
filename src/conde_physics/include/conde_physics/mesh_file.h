// Mesh files (STL, Collada .dae, and whatever else assimp reads, e.g. OBJ) as triangle lists.
//
// Usage:
//   MeshData mesh = loadMeshFile("/abs/path/part.dae", Vec3(1, 1, 1));  // throws MeshFileError
//   shape.type = ShapeType::kMesh; shape.mesh_vertices_m = mesh.vertices_m; ...
//
// Assumptions: node transforms are baked into the vertices; Collada files come out z-up
// whatever their <up_axis> (as Gazebo shows them); each triangle takes the diffuse colour of its
// material (textures are not read). Units: the file's numbers times `scale` are metres.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "conde_physics/math.h"

namespace conde_physics {

class MeshFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct MeshData {
  std::vector<Vec3> vertices_m;    // scaled
  std::vector<int> triangles;      // 3 vertex indices per triangle
  std::vector<Vec3> triangle_rgb;  // one 0..1 colour per triangle; empty when no material has one
};

// Throws MeshFileError "mesh file '<path>': <reason>" when the file is missing, assimp rejects
// it, or it holds no triangles.
MeshData loadMeshFile(const std::string& path, const Vec3& scale);

}  // namespace conde_physics
