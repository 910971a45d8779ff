// Bounding-volume hierarchy over the triangles of a mesh: ray queries in O(log n) instead of
// testing every triangle, shared by the laser ray caster and the camera renderer.
//
// Usage:
//   auto bvh = std::make_shared<const MeshBvh>(shape.mesh_vertices_m, shape.mesh_triangles);
//   double t; int triangle;
//   if (bvh->intersect(origin, direction, 0.0, max_range_m, t, triangle)) { ... }
//
// Axis-aligned boxes, split at the median of the triangle centroids along the longest axis,
// at most kLeafTriangles triangles per leaf. Triangles are two-sided (Moeller-Trumbore).
#pragma once

#include <vector>

#include "conde_physics/math.h"

namespace conde_physics {

class MeshBvh {
 public:
  // `triangles` holds 3 vertex indices per triangle. Throws std::invalid_argument for an index
  // out of range or a count that is not a multiple of 3.
  MeshBvh(const std::vector<Vec3>& vertices_m, const std::vector<int>& triangles);

  // Nearest triangle along o + t d for t in [t_min, t_max] (d need not be unit; t is in units
  // of |d|). `triangle` is the index into the input triangle list.
  bool intersect(const Vec3& o, const Vec3& d, double t_min, double t_max, double& t, int& triangle) const;

  int triangleCount() const { return static_cast<int>(original_index_.size()); }
  // Unit normal of input triangle i (a x b order of its vertices; zero for a degenerate one).
  const Vec3& normal(int triangle) const { return normals_[triangle]; }
  // Bounding sphere of the vertices (centre of the bounding box, radius to the farthest vertex).
  const Vec3& boundCentre() const { return bound_centre_; }
  double boundRadius() const { return bound_radius_m_; }

 private:
  static constexpr int kLeafTriangles = 4;
  struct Node {
    double lo[3], hi[3];
    int first = 0;  // leaf: first triangle (in BVH order); inner: index of the right child
    int count = 0;  // leaf: triangle count; inner: 0 (the left child follows the node)
  };
  struct Triangle {  // in BVH order
    Vec3 a, e1, e2;
  };

  int build(std::vector<int>& order, const std::vector<Vec3>& centroids, const std::vector<Vec3>& vertices,
            const std::vector<int>& triangles, int begin, int end);

  std::vector<Node> nodes_;
  std::vector<Triangle> triangles_;
  std::vector<int> original_index_;
  std::vector<Vec3> normals_;  // by input index
  Vec3 bound_centre_;
  double bound_radius_m_ = 0.0;
};

}  // namespace conde_physics
