#include "conde_physics/mesh_file.h"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <cctype>
#include <fstream>

namespace conde_physics {

MeshData loadMeshFile(const std::string& path, const Vec3& scale) {
  const std::string where = "mesh file '" + path + "'";
  if (!std::ifstream(path).good()) throw MeshFileError(where + ": cannot open it");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                     aiProcess_PreTransformVertices | aiProcess_SortByPType);
  if (scene == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || scene->mNumMeshes == 0) {
    std::string reason = importer.GetErrorString();
    if (reason.empty()) reason = "no meshes in it";
    throw MeshFileError(where + ": " + reason);
  }
  std::string extension =
      path.substr(path.find_last_of('.') == std::string::npos ? path.size() : path.find_last_of('.'));
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  // assimp turns Collada scenes y-up (rotating z-up files); ROS and Gazebo want z-up.
  const bool y_up = extension == ".dae";

  MeshData mesh;
  bool any_colour = false;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* part = scene->mMeshes[m];
    if ((part->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;  // points and lines
    const int first = static_cast<int>(mesh.vertices_m.size());
    for (unsigned v = 0; v < part->mNumVertices; ++v) {
      const aiVector3D& p = part->mVertices[v];
      const Vec3 z_up = y_up ? Vec3(p.x, -p.z, p.y) : Vec3(p.x, p.y, p.z);
      mesh.vertices_m.emplace_back(z_up.x * scale.x, z_up.y * scale.y, z_up.z * scale.z);
    }
    Vec3 rgb(0.7, 0.7, 0.7);
    aiColor4D diffuse;
    // STL has no materials (assimp makes up a grey one), nor has assimp's default material.
    const aiMaterial* material = extension != ".stl" && part->mMaterialIndex < scene->mNumMaterials
                                     ? scene->mMaterials[part->mMaterialIndex]
                                     : nullptr;
    if (material != nullptr && material->GetName() != aiString(AI_DEFAULT_MATERIAL_NAME) &&
        material->Get(AI_MATKEY_COLOR_DIFFUSE, diffuse) == AI_SUCCESS) {
      rgb = Vec3(diffuse.r, diffuse.g, diffuse.b);
      any_colour = true;
    }
    for (unsigned f = 0; f < part->mNumFaces; ++f) {
      const aiFace& face = part->mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (int k = 0; k < 3; ++k) mesh.triangles.push_back(first + static_cast<int>(face.mIndices[k]));
      mesh.triangle_rgb.push_back(rgb);
    }
  }
  if (mesh.triangles.empty()) throw MeshFileError(where + ": it holds no triangles");
  if (!any_colour) mesh.triangle_rgb.clear();
  return mesh;
}

}  // namespace conde_physics
