#include "conde_physics/model.h"

namespace conde_physics {

int ArticulatedModel::bodyIndex(const std::string& link_name) const {
  int body = -1;
  Pose unused;
  return linkInBody(link_name, body, unused) ? body : -1;
}

int ArticulatedModel::jointIndex(const std::string& joint_name) const {
  for (size_t i = 0; i < joints.size(); ++i) {
    if (joints[i].name == joint_name) return static_cast<int>(i);
  }
  return -1;
}

bool ArticulatedModel::linkInBody(const std::string& link_name, int& body, Pose& link_in_body) const {
  for (size_t b = 0; b < bodies.size(); ++b) {
    for (size_t l = 0; l < bodies[b].merged_links.size(); ++l) {
      if (bodies[b].merged_links[l] == link_name) {
        body = static_cast<int>(b);
        link_in_body = bodies[b].merged_link_poses[l];
        return true;
      }
    }
  }
  return false;
}

Inertia boxInertia(double m, const Vec3& s) {
  Inertia i;
  i.ixx = m * (s.y * s.y + s.z * s.z) / 12.0;
  i.iyy = m * (s.x * s.x + s.z * s.z) / 12.0;
  i.izz = m * (s.x * s.x + s.y * s.y) / 12.0;
  return i;
}

Inertia cylinderInertia(double m, double r, double l) {
  Inertia i;
  i.ixx = i.iyy = m * (3 * r * r + l * l) / 12.0;
  i.izz = m * r * r / 2.0;
  return i;
}

Inertia sphereInertia(double m, double r) {
  Inertia i;
  i.ixx = i.iyy = i.izz = 2.0 * m * r * r / 5.0;
  return i;
}

}  // namespace conde_physics
