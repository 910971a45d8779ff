// Small rigid-body math used across conde_physics: vectors, unit quaternions and poses.
// Engine-neutral on purpose: the Bullet and ODE backends convert at their boundary.
// Conventions: right-handed frames, SI units, quaternions (w, x, y, z) in Hamilton form,
// Pose a_T_b maps coordinates in frame b to frame a (p_a = a_T_b * p_b).
#pragma once

#include <cmath>

namespace conde_physics {

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;
  Vec3() = default;
  Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  Vec3 operator-() const { return {-x, -y, -z}; }
  Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
  Vec3& operator+=(const Vec3& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  double dot(const Vec3& o) const { return x * o.x + y * o.y + z * o.z; }
  Vec3 cross(const Vec3& o) const { return {y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x}; }
  double norm() const { return std::sqrt(dot(*this)); }
  Vec3 normalized() const {
    double n = norm();
    return n > 0.0 ? *this / n : Vec3();
  }
};

struct Quat {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
  Quat() = default;
  Quat(double w_, double x_, double y_, double z_) : w(w_), x(x_), y(y_), z(z_) {}

  // Fixed-axis roll-pitch-yaw as in URDF and SDF: R = Rz(yaw) * Ry(pitch) * Rx(roll).
  static Quat fromRpy(double roll_rad, double pitch_rad, double yaw_rad);
  static Quat fromAxisAngle(const Vec3& axis, double angle_rad);
  // Rotation by |v| [rad] about v (the identity for v = 0): small rotations, e.g. sensor noise.
  static Quat fromRotationVector(const Vec3& rotation_rad);
  // Rotation matrix (row-major) to quaternion.
  static Quat fromMatrix(const double m[3][3]);
  void toMatrix(double m[3][3]) const;
  void toRpy(double& roll_rad, double& pitch_rad, double& yaw_rad) const;
  double yaw() const;

  Quat operator*(const Quat& o) const {
    return {w * o.w - x * o.x - y * o.y - z * o.z, w * o.x + x * o.w + y * o.z - z * o.y,
            w * o.y - x * o.z + y * o.w + z * o.x, w * o.z + x * o.y - y * o.x + z * o.w};
  }
  Quat conjugate() const { return {w, -x, -y, -z}; }
  Quat normalized() const;
  Vec3 rotate(const Vec3& v) const;
};

struct Pose {
  Vec3 position;
  Quat orientation;
  Pose() = default;
  Pose(const Vec3& p, const Quat& q) : position(p), orientation(q) {}
  static Pose fromXyzRpy(double x, double y, double z, double roll, double pitch, double yaw) {
    return Pose(Vec3(x, y, z), Quat::fromRpy(roll, pitch, yaw));
  }
  // a_T_c = a_T_b * b_T_c
  Pose operator*(const Pose& o) const {
    return Pose(position + orientation.rotate(o.position), (orientation * o.orientation).normalized());
  }
  Vec3 operator*(const Vec3& p) const { return position + orientation.rotate(p); }
  Pose inverse() const {
    Quat qi = orientation.conjugate();
    return Pose(-qi.rotate(position), qi);
  }
};

// Linear velocity of a frame's origin and angular velocity, both in world coordinates [m/s, rad/s].
struct Twist {
  Vec3 linear_mps;
  Vec3 angular_radps;
};

// Symmetric 3x3 inertia tensor [kg m^2] in some frame.
struct Inertia {
  double ixx = 0.0, ixy = 0.0, ixz = 0.0, iyy = 0.0, iyz = 0.0, izz = 0.0;
};

// Rotates an inertia tensor: I_a = R * I_b * R^T, with R = a_R_b.
Inertia rotateInertia(const Inertia& inertia_b, const Quat& a_R_b);

// Principal axes of a symmetric tensor: `principal_moments` in the frame given by `axes`
// (a rotation from the principal frame to the tensor's frame). Jacobi iteration; exact enough
// for physics (residual off-diagonal terms < 1e-12 of the trace).
void principalAxes(const Inertia& inertia, Vec3& principal_moments, Quat& axes);

double wrapAngle(double angle_rad);  // to (-pi, pi]

}  // namespace conde_physics
