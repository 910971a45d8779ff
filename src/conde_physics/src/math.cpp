#include "conde_physics/math.h"

#include <algorithm>

namespace conde_physics {

Quat Quat::fromRpy(double roll, double pitch, double yaw) {
  const double cr = std::cos(roll / 2), sr = std::sin(roll / 2);
  const double cp = std::cos(pitch / 2), sp = std::sin(pitch / 2);
  const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
  return {cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
          cr * cp * sy - sr * sp * cy};
}

Quat Quat::fromAxisAngle(const Vec3& axis, double angle) {
  const Vec3 a = axis.normalized();
  const double s = std::sin(angle / 2);
  return {std::cos(angle / 2), a.x * s, a.y * s, a.z * s};
}

Quat Quat::fromRotationVector(const Vec3& v) {
  const double angle = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  if (angle == 0.0) return Quat();
  return fromAxisAngle(v, angle);
}

Quat Quat::fromMatrix(const double m[3][3]) {
  // Shepperd's method: pick the largest diagonal term for numerical stability.
  const double trace = m[0][0] + m[1][1] + m[2][2];
  Quat q;
  if (trace > 0) {
    const double s = std::sqrt(trace + 1.0) * 2;
    q = {0.25 * s, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s};
  } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
    const double s = std::sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2;
    q = {(m[2][1] - m[1][2]) / s, 0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s};
  } else if (m[1][1] > m[2][2]) {
    const double s = std::sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2;
    q = {(m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s};
  } else {
    const double s = std::sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2;
    q = {(m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s};
  }
  return q.normalized();
}

void Quat::toMatrix(double m[3][3]) const {
  m[0][0] = 1 - 2 * (y * y + z * z);
  m[0][1] = 2 * (x * y - w * z);
  m[0][2] = 2 * (x * z + w * y);
  m[1][0] = 2 * (x * y + w * z);
  m[1][1] = 1 - 2 * (x * x + z * z);
  m[1][2] = 2 * (y * z - w * x);
  m[2][0] = 2 * (x * z - w * y);
  m[2][1] = 2 * (y * z + w * x);
  m[2][2] = 1 - 2 * (x * x + y * y);
}

void Quat::toRpy(double& roll, double& pitch, double& yaw) const {
  const double sinp = std::clamp(2 * (w * y - z * x), -1.0, 1.0);
  roll = std::atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y));
  pitch = std::asin(sinp);
  yaw = std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z));
}

double Quat::yaw() const { return std::atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)); }

Quat Quat::normalized() const {
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  return n > 0 ? Quat(w / n, x / n, y / n, z / n) : Quat();
}

Vec3 Quat::rotate(const Vec3& v) const {
  // v' = v + 2w(u x v) + 2 u x (u x v), with u the vector part.
  const Vec3 u(x, y, z);
  const Vec3 t = u.cross(v) * 2.0;
  return v + t * w + u.cross(t);
}

Inertia rotateInertia(const Inertia& ib, const Quat& q) {
  double r[3][3];
  q.toMatrix(r);
  const double i[3][3] = {{ib.ixx, ib.ixy, ib.ixz}, {ib.ixy, ib.iyy, ib.iyz}, {ib.ixz, ib.iyz, ib.izz}};
  double out[3][3] = {};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 3; ++c)
        for (int d = 0; d < 3; ++d) out[a][b] += r[a][c] * i[c][d] * r[b][d];
  Inertia ia;
  ia.ixx = out[0][0];
  ia.ixy = out[0][1];
  ia.ixz = out[0][2];
  ia.iyy = out[1][1];
  ia.iyz = out[1][2];
  ia.izz = out[2][2];
  return ia;
}

void principalAxes(const Inertia& in, Vec3& moments, Quat& axes) {
  double a[3][3] = {{in.ixx, in.ixy, in.ixz}, {in.ixy, in.iyy, in.iyz}, {in.ixz, in.iyz, in.izz}};
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // columns are eigenvectors
  const double scale = std::abs(a[0][0]) + std::abs(a[1][1]) + std::abs(a[2][2]) + 1e-300;
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = std::abs(a[0][1]) + std::abs(a[0][2]) + std::abs(a[1][2]);
    if (off < 1e-14 * scale) break;
    for (int p = 0; p < 2; ++p) {
      for (int q = p + 1; q < 3; ++q) {
        if (std::abs(a[p][q]) < 1e-300) continue;
        const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        const double c = 1 / std::sqrt(t * t + 1), s = t * c;
        for (int k = 0; k < 3; ++k) {  // A = J^T A J
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
    }
  }
  // Make the eigenvector basis right-handed so it is a rotation.
  const Vec3 c0(v[0][0], v[1][0], v[2][0]), c1(v[0][1], v[1][1], v[2][1]), c2(v[0][2], v[1][2], v[2][2]);
  if (c0.cross(c1).dot(c2) < 0) {
    for (int k = 0; k < 3; ++k) v[k][2] = -v[k][2];
  }
  moments = Vec3(a[0][0], a[1][1], a[2][2]);
  axes = Quat::fromMatrix(v);
}

double wrapAngle(double a) {
  a = std::fmod(a + M_PI, 2 * M_PI);
  if (a <= 0) a += 2 * M_PI;
  return a - M_PI;
}

}  // namespace conde_physics
