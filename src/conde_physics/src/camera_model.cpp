// Camera models: plumb_bob distortion and its inverse, Gazebo's wide-angle lenses, intrinsics
// from a field of view, projection.
#include "conde_physics/camera_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "render_detail.h"

namespace conde_physics {

using render_detail::checkImageSize;
using render_detail::kPi;
using render_detail::text;

namespace {

// Jacobian of distort() at (x, y).
void distortionJacobian(const LensDistortion& d, double x, double y, double j[2][2]) {
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  const double g = d.k1 + r2 * (2.0 * d.k2 + 3.0 * d.k3 * r2);  // d(radial)/d(r2)
  j[0][0] = radial + 2.0 * x * x * g + 2.0 * d.p1 * y + 6.0 * d.p2 * x;
  j[0][1] = 2.0 * x * y * g + 2.0 * d.p1 * x + 2.0 * d.p2 * y;
  j[1][0] = 2.0 * x * y * g + 2.0 * d.p1 * x + 2.0 * d.p2 * y;
  j[1][1] = radial + 2.0 * y * y * g + 6.0 * d.p1 * y + 2.0 * d.p2 * x;
}

}  // namespace

namespace render_detail {

// plumb_bob: normalised undistorted (x, y) -> normalised distorted (xd, yd).
void distort(const LensDistortion& d, double x, double y, double& xd, double& yd) {
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  xd = x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
  yd = y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
}

bool undistort(const LensDistortion& d, double xd, double yd, double& x, double& y) {
  constexpr double kTolerance = 1e-12;  // normalised units: ~1e-10 px
  x = xd;
  y = yd;
  double ex = 0.0, ey = 0.0;
  distort(d, x, y, ex, ey);
  ex -= xd;
  ey -= yd;
  double error = std::hypot(ex, ey);
  for (int iteration = 0; iteration < 100 && error > kTolerance; ++iteration) {
    double j[2][2];
    distortionJacobian(d, x, y, j);
    const double det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    if (!(det > 0.0)) return false;
    const double step_x = (j[1][1] * ex - j[0][1] * ey) / det;
    const double step_y = (-j[1][0] * ex + j[0][0] * ey) / det;
    bool improved = false;
    for (double scale = 1.0; scale > 1e-6; scale *= 0.5) {
      const double nx = x - scale * step_x, ny = y - scale * step_y;
      double fx = 0.0, fy = 0.0;
      distort(d, nx, ny, fx, fy);
      const double next_error = std::hypot(fx - xd, fy - yd);
      if (next_error < error) {
        x = nx;
        y = ny;
        ex = fx - xd;
        ey = fy - yd;
        error = next_error;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  if (!(error <= kTolerance)) return false;
  double j[2][2];
  distortionJacobian(d, x, y, j);
  return j[0][0] * j[1][1] - j[0][1] * j[1][0] > 0.0;
}

}  // namespace render_detail

using render_detail::distort;

// --- Wide-angle lens ---------------------------------------------------------------------------

LensMapping LensMapping::ofType(const std::string& type) {
  // c1, c2, fun of Gazebo's named lenses (c3 = 0, f = 1).
  if (type == "gnomonical") return custom(1.0, 1.0, 0.0, "tan");
  if (type == "stereographic") return custom(2.0, 2.0, 0.0, "tan");
  if (type == "equidistant") return custom(1.0, 1.0, 0.0, "id");
  if (type == "equisolid_angle") return custom(2.0, 2.0, 0.0, "sin");
  if (type == "orthographic") return custom(1.0, 1.0, 0.0, "sin");
  throw std::invalid_argument("unknown lens type '" + type +
                              "' (expected gnomonical, stereographic, equidistant, equisolid_angle, orthographic "
                              "or custom)");
}

LensMapping LensMapping::custom(double c1, double c2, double c3, const std::string& fun) {
  if (!(c1 != 0.0 && c2 != 0.0 && std::isfinite(c1) && std::isfinite(c2) && std::isfinite(c3)))
    throw std::invalid_argument("lens custom_function needs finite c1, c2, c3 with c1 and c2 not zero (got c1 " +
                                text(c1) + ", c2 " + text(c2) + ", c3 " + text(c3) + ")");
  LensMapping lens;
  lens.pinhole = false;
  lens.c1 = c1;
  lens.c2 = c2;
  lens.c3 = c3;
  if (fun == "tan") {
    lens.fun = LensFunction::kTan;
  } else if (fun == "sin") {
    lens.fun = LensFunction::kSin;
  } else if (fun == "id") {
    lens.fun = LensFunction::kIdentity;
  } else {
    throw std::invalid_argument("unknown lens function '" + fun + "' (expected tan, sin or id)");
  }
  return lens;
}

double LensMapping::radius(double theta_rad) const {
  const double a = theta_rad / c2 + c3;
  switch (fun) {
    case LensFunction::kTan:
      return c1 * std::tan(a);
    case LensFunction::kSin:
      return c1 * std::sin(a);
    case LensFunction::kIdentity:
      break;
  }
  return c1 * a;
}

bool LensMapping::rayAt(double x, double y, Vec3& ray) const {
  if (pinhole) {
    ray = Vec3(x, y, 1.0).normalized();
    return true;
  }
  // Invert r = c1 fun(theta / c2 + c3) on the branch that starts at the axis.
  const double r = std::hypot(x, y), q = r / c1;
  double a = 0.0;
  switch (fun) {
    case LensFunction::kTan:
      a = std::atan(q);
      break;
    case LensFunction::kSin:
      if (std::abs(q) > 1.0) return false;
      a = std::asin(q);
      break;
    case LensFunction::kIdentity:
      a = q;
      break;
  }
  const double theta = c2 * (a - c3);
  if (!(theta >= 0.0 && theta <= cutoff_angle_rad)) return false;
  const double s = std::sin(theta);
  ray = r > 0.0 ? Vec3(s * x / r, s * y / r, std::cos(theta)) : Vec3(0.0, 0.0, 1.0);
  return true;
}

CameraModel CameraModel::fromHorizontalFov(int width_px, int height_px, double horizontal_fov_rad) {
  checkImageSize(width_px, height_px);
  if (!(horizontal_fov_rad > 0.0 && horizontal_fov_rad < kPi))
    throw std::invalid_argument("camera horizontal_fov must be in (0, pi) rad (got " + text(horizontal_fov_rad) + ")");
  CameraModel model;
  model.width_px = width_px;
  model.height_px = height_px;
  model.fx_px = width_px / (2.0 * std::tan(horizontal_fov_rad / 2.0));
  model.fy_px = model.fx_px;
  model.cx_px = (width_px - 1) / 2.0;
  model.cy_px = (height_px - 1) / 2.0;
  return model;
}

CameraModel CameraModel::fromWideAngle(int width_px, int height_px, double horizontal_fov_rad, const LensMapping& lens,
                                       bool scale_to_hfov, double focal_scale) {
  checkImageSize(width_px, height_px);
  if (!(horizontal_fov_rad > 0.0 && horizontal_fov_rad <= 2.0 * kPi))
    throw std::invalid_argument("wide-angle camera horizontal_fov must be in (0, 2 pi] rad (got " +
                                text(horizontal_fov_rad) + ")");
  if (!(lens.cutoff_angle_rad > 0.0 && lens.cutoff_angle_rad <= kPi))
    throw std::invalid_argument("lens cutoff_angle must be in (0, pi] rad (got " + text(lens.cutoff_angle_rad) + ")");
  double focal = focal_scale;
  if (scale_to_hfov) {
    // The lens function must still rise at the image edge (tan below pi/2, sin up to pi/2).
    const double argument = horizontal_fov_rad / 2.0 / lens.c2 + lens.c3;
    const bool rising = lens.fun == LensFunction::kIdentity ||
                        (lens.fun == LensFunction::kTan ? argument < kPi / 2 - 1e-6 : argument <= kPi / 2);
    const double edge = rising ? lens.radius(horizontal_fov_rad / 2.0) : 0.0;
    if (!(edge > 0.0 && std::isfinite(edge)))
      throw std::invalid_argument("lens cannot show half the horizontal_fov (" + text(horizontal_fov_rad / 2.0) +
                                  " rad) at the image edge: its radius there is " + text(edge));
    focal = 1.0 / edge;
  }
  if (!(focal > 0.0 && std::isfinite(focal)))
    throw std::invalid_argument("lens focal length f must be positive (got " + text(focal) + ")");
  CameraModel model = fromHorizontalFov(width_px, height_px, kPi / 2);
  model.fx_px = model.fy_px = focal * width_px / 2.0;
  model.lens = lens;
  model.distortion_in_image_units = true;
  return model;
}

void CameraModel::setDistortionCenter(double center_x, double center_y) {
  cx_px = center_x * width_px - 0.5;
  cy_px = center_y * height_px - 0.5;
}

bool CameraModel::project(const Vec3& p, double& u_px, double& v_px) const {
  double x = 0.0, y = 0.0;
  if (lens.pinhole) {
    if (!(p.z > 0.0)) return false;
    x = p.x / p.z;
    y = p.y / p.z;
  } else {
    const double off_axis = std::hypot(p.x, p.y);
    const double theta = std::atan2(off_axis, p.z);
    if (!(theta <= lens.cutoff_angle_rad) || p.norm() == 0.0) return false;
    const double r = lens.radius(theta);
    if (off_axis > 0.0) {
      x = r * p.x / off_axis;
      y = r * p.y / off_axis;
    }
  }
  const double unit_x = distortion_in_image_units ? width_px : fx_px;
  const double unit_y = distortion_in_image_units ? height_px : fy_px;
  double xd = 0.0, yd = 0.0;
  distort(distortion, x * fx_px / unit_x, y * fy_px / unit_y, xd, yd);
  u_px = unit_x * xd + cx_px;
  v_px = unit_y * yd + cy_px;
  return true;
}

}  // namespace conde_physics
