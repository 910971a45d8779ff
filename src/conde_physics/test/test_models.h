// Pieces that the conde_physics gtests build their models and views from: a joint between two
// bodies, a closed cube mesh, a camera's optical frame looking at a point.
#pragma once

#include <string>

#include "conde_physics/physics_engine.h"

namespace conde_physics_test {

namespace cp = conde_physics;

// Adds to `m` a joint of `type` about +y (the axle of every test model) from body `parent` to
// body `child` at `pose_in_parent`; returns it for limits and the like.
inline cp::JointSpec& addJoint(cp::ArticulatedModel& m, const std::string& name, cp::JointType type, int parent,
                               int child, const cp::Pose& pose_in_parent) {
  cp::JointSpec& joint = m.joints.emplace_back();
  joint.name = name;
  joint.type = type;
  joint.parent_body = parent;
  joint.child_body = child;
  joint.pose_in_parent = pose_in_parent;
  joint.axis = cp::Vec3(0, 1, 0);
  return joint;
}

// A closed cube mesh of half size `half_m`, centred on its origin: 8 vertices, 12 triangles with
// outward normals.
inline cp::Shape cubeMesh(double half_m) {
  const double h = half_m;
  cp::Shape mesh;
  mesh.type = cp::ShapeType::kMesh;
  mesh.mesh_vertices_m = {{-h, -h, -h}, {h, -h, -h}, {h, h, -h}, {-h, h, -h},
                          {-h, -h, h},  {h, -h, h},  {h, h, h},  {-h, h, h}};
  mesh.mesh_triangles = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                         1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
  return mesh;
}

// Optical frame (z forward, x right, y down) at `eye` looking at `target`, image up towards `up`.
inline cp::Pose lookAt(const cp::Vec3& eye, const cp::Vec3& target, const cp::Vec3& up = {0, 0, 1}) {
  const cp::Vec3 z = (target - eye).normalized();
  const cp::Vec3 x = z.cross(up).normalized();
  const cp::Vec3 y = z.cross(x);
  const double m[3][3] = {{x.x, y.x, z.x}, {x.y, y.y, z.y}, {x.z, y.z, z.z}};
  return cp::Pose(eye, cp::Quat::fromMatrix(m));
}

}  // namespace conde_physics_test
