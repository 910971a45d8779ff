// Camera models: pinhole with plumb_bob distortion, and the wide-angle lenses of Gazebo's
// <sensor type="wideanglecamera">. What CameraInfo must report, and what CameraRenderer draws.
//
// Frames: the camera pose is that of its *optical* frame (REP 103: +z forward, +x right in the
// image, +y down in the image). Pixel (u, v) has its centre at integer coordinates (OpenCV
// convention): u = 0 is the left column, v = 0 the top row.
//
// Projection (what CameraInfo must report): a camera-frame point (X, Y, Z), Z > 0, has the
// normalised coordinates x = X/Z, y = Y/Z; distortion (OpenCV / ROS plumb_bob):
//   r2 = x^2 + y^2, radial = 1 + k1 r2 + k2 r2^2 + k3 r2^3
//   xd = x radial + 2 p1 x y + p2 (r2 + 2 x^2),  yd = y radial + p1 (r2 + 2 y^2) + 2 p2 x y
// and it lands at u = fx xd + cx, v = fy yd + cy. The renderer inverts this per pixel, so an
// image rendered with distortion and undistorted with cv::undistort and the same numbers gives
// back the pinhole image.
#pragma once

#include <string>

#include "conde_physics/math.h"

namespace conde_physics {

struct LensDistortion {  // plumb_bob, the ROS / OpenCV order is k1 k2 p1 p2 k3
  double k1 = 0.0, k2 = 0.0, k3 = 0.0, p1 = 0.0, p2 = 0.0;
  bool isZero() const { return k1 == 0.0 && k2 == 0.0 && k3 == 0.0 && p1 == 0.0 && p2 == 0.0; }
};

// Wide-angle lens of Gazebo's <sensor type="wideanglecamera"> (its <lens> element): a ray at the
// angle theta from the optical axis lands at the radius r = c1 fun(theta / c2 + c3) from the
// principal point, in units of the focal length (pixels: r fx). Rays farther than cutoff_angle
// from the axis are not seen; their pixels are black. The default is the pinhole (gnomonical,
// r = tan theta); stereographic, Gazebo's default lens, is r = 2 tan(theta / 2).
// Plumb_bob distortion, when given, acts on the lens's image (in units of the image size, as
// Gazebo's distortion compositor): pixel -> (undistort) -> radius -> angle.
enum class LensFunction { kTan, kSin, kIdentity };

struct LensMapping {
  double c1 = 1.0, c2 = 1.0, c3 = 0.0;
  LensFunction fun = LensFunction::kTan;
  double cutoff_angle_rad = 3.14159265358979323846 / 2;
  bool pinhole = true;  // the plain projection x = X/Z, y = Y/Z (no cut-off beyond z > 0)

  // Gazebo's named types: gnomonical, stereographic, equidistant, equisolid_angle, orthographic.
  // Throws std::invalid_argument naming the type and the known ones.
  static LensMapping ofType(const std::string& type);
  // c1, c2, c3 and fun ("tan", "sin" or "id") of a <custom_function>; throws for another fun.
  static LensMapping custom(double c1, double c2, double c3, const std::string& fun);
  // r(theta) in units of the focal length.
  double radius(double theta_rad) const;
  // The unit ray (optical frame) of the normalised, undistorted image point (x, y); false when
  // no ray maps there or it is beyond the cut-off angle.
  bool rayAt(double x, double y, Vec3& ray) const;
};

struct CameraModel {
  int width_px = 0;
  int height_px = 0;
  double fx_px = 0.0, fy_px = 0.0, cx_px = 0.0, cy_px = 0.0;
  LensDistortion distortion;
  LensMapping lens;  // pinhole unless made by fromWideAngle
  // Units of the distortion's normalised coordinates: the focal length (OpenCV / ROS, what
  // CameraInfo means: x = (u - cx) / fx) or, as Gazebo's wide-angle camera applies <distortion>
  // to its lens image, the image size (x = (u - cx) / width, y = (v - cy) / height).
  bool distortion_in_image_units = false;
  double near_clip_m = 0.1;   // nothing nearer than this (along the ray) is drawn
  double far_clip_m = 100.0;  // nor farther
  double noise_stddev = 0.0;  // Gaussian noise on each channel, in units of full scale (0..1),
                              // as Gazebo's <noise type="gaussian"> on cameras

  // Gazebo's intrinsics: fx = fy = width / (2 tan(hfov / 2)). The principal point is the image
  // centre in OpenCV's convention, ((width - 1) / 2, (height - 1) / 2), i.e. where the rendered
  // image really is centred (Gazebo reports (width + 1) / 2, one pixel off).
  // Throws std::invalid_argument for a non-positive size or hfov outside (0, pi).
  static CameraModel fromHorizontalFov(int width_px, int height_px, double horizontal_fov_rad);

  // Gazebo's wide-angle camera: with scale_to_hfov the horizontal field of view spans the image
  // width, f = (width / 2) / (c1 fun(hfov / 2 / c2 + c3)); without it f = focal_scale * width / 2
  // (the <custom_function>'s f). Principal point as above. Throws std::invalid_argument for a
  // non-positive size, an hfov outside (0, 2 pi], a cut-off angle outside (0, pi], or a lens that
  // cannot map half the hfov to a positive radius.
  static CameraModel fromWideAngle(int width_px, int height_px, double horizontal_fov_rad, const LensMapping& lens,
                                   bool scale_to_hfov, double focal_scale = 1.0);

  // Moves the principal point to where Gazebo's <distortion><center> puts the centre of the
  // distortion (fractions of the image size, 0.5 0.5 = the middle): cx = center_x width - 0.5.
  void setDistortionCenter(double center_x, double center_y);

  // Pixel of a point given in the optical frame (lens, then distortion). False when z <= 0 for a
  // pinhole, or beyond the lens's cut-off angle.
  bool project(const Vec3& point_optical, double& u_px, double& v_px) const;
};

}  // namespace conde_physics
