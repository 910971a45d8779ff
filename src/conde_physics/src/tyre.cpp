#include "conde_physics/tyre.h"

#include <cmath>

namespace conde_physics {

namespace {
// Below this length of the normal's part across the axis (sine of the angle between axis and
// normal, ~15 degrees) the wheel rests on its face: no single lowest point.
constexpr double kMinAcrossAxis = 0.25;
}  // namespace

bool isWheelCollision(const ArticulatedModel& model, int body, const CollisionSpec& collision) {
  if (collision.shape.type != ShapeType::kCylinder || body < 0 || body >= static_cast<int>(model.bodies.size()))
    return false;
  // In the model frame: the rigid pose the model is added with moves cylinder and joint alike.
  const Pose cylinder = model.bodies[body].initial_pose_in_model * collision.pose_in_link;
  const Vec3 cylinder_axis = cylinder.orientation.rotate(Vec3(0, 0, 1));
  for (const JointSpec& j : model.joints) {
    if (j.child_body != body || j.type == JointType::kPrismatic || j.parent_body < 0 ||
        j.parent_body >= static_cast<int>(model.bodies.size()))
      continue;
    const Pose joint = model.bodies[j.parent_body].initial_pose_in_model * j.pose_in_parent;
    const Vec3 joint_axis = joint.orientation.rotate(j.axis.normalized());
    const double off_axis_m = (cylinder.position - joint.position).cross(joint_axis).norm();
    if (std::abs(cylinder_axis.dot(joint_axis)) > 1.0 - 1e-6 && off_axis_m < 0.01 * collision.shape.radius_m)
      return true;
  }
  return false;
}

bool canBeTyre(double radius_m, double length_m) { return length_m > 0.0 && 0.5 * length_m < radius_m; }

TyreOnPlane tyreOnPlane(const Vec3& centre_m, const Vec3& axis, double radius_m, double width_m, const Vec3& normal,
                        double offset_m, TyreContact& contact) {
  // Direction in the mid-plane towards the plane: minus the normal's part across the axis.
  const Vec3 across = normal - axis * normal.dot(axis);
  const double across_norm = across.norm();
  if (across_norm < kMinAcrossAxis) return TyreOnPlane::kOnFace;
  const double rounding_m = 0.5 * width_m;
  // Edge of the core disk nearest the plane, then down by the rounding radius.
  const Vec3 rim_m = centre_m - across * ((radius_m - rounding_m) / across_norm);
  contact.point_m = rim_m - normal * rounding_m;
  contact.depth_m = offset_m - normal.dot(contact.point_m);
  return contact.depth_m > 0.0 ? TyreOnPlane::kTouching : TyreOnPlane::kApart;
}

}  // namespace conde_physics
