// CPU camera renderer: draws what a pinhole or wide-angle camera (optionally with plumb_bob lens
// distortion) sees of the world: the textured ground plane, boxes, cylinders, cones and spheres with flat
// shading, and textured box faces (signs, display panels whose image changes at run time).
//
// Usage:
//   RenderScene scene = renderSceneFromWorld(world);          // ground + world objects
//   int body = scene.addObject(box_object);                   // e.g. a robot link, group = model id
//   scene.setObjectPose(body, pose_in_world);                 // every frame for moving objects
//   CameraModel model = CameraModel::fromHorizontalFov(320, 240, 1.5708);
//   CameraRenderer camera(model);                             // precomputes one ray per pixel
//   RgbImage image;
//   camera.render(scene, world_T_optical, /*exclude_group=*/robot_id, &rng, image);
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

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "conde_physics/math.h"
#include "conde_physics/world_file.h"

namespace conde_physics {

// 8-bit RGB image, rows top to bottom, 3 bytes per pixel, no padding.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> data;  // size width * height * 3

  void resize(int w, int h) {
    width = w;
    height = h;
    data.assign(static_cast<size_t>(w) * h * 3, 0);
  }
  const std::uint8_t* pixel(int u, int v) const { return &data[(static_cast<size_t>(v) * width + u) * 3]; }
  std::uint8_t* pixel(int u, int v) { return &data[(static_cast<size_t>(v) * width + u) * 3]; }
};

// Reads an image file (any format OpenCV decodes) as RGB. Throws std::runtime_error naming
// the path when it does not decode.
RgbImage loadRgbImage(const std::string& path);

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

enum class RenderShape { kBox, kCylinder, kCone, kSphere };

struct RenderObject {
  RenderShape shape = RenderShape::kBox;
  Vec3 size_m;                    // kBox: full edge lengths
  double radius_m = 0.0;          // kCylinder, kCone (base), kSphere
  double length_m = 0.0;          // kCylinder, kCone: along local z; a cone's base is at z = -length/2
  Pose pose;                      // world pose of the shape centre
  Vec3 color_rgb{0.7, 0.7, 0.7};  // 0..1, flat shaded
  // kBox only: an image on the local +z face, column 0 at local -x, row 0 at local +y, so it is
  // upright and not mirrored for a viewer in front of the face (as libgazebo_ros_video). Drawn
  // unlit (like a screen). Empty = plain colour.
  RgbImage face_image;
  int group = -1;  // e.g. the model id of a robot; cameras may exclude one group
};

// The ground plane z = 0 and everything on it.
class RenderScene {
 public:
  // Ground: the texture covers [x_min, x_max] x [y_min, y_max], columns along +x, row 0 at
  // y_max, sampled bilinearly; outside it (or without one) the plane has colour ground_rgb.
  // Where a pixel's footprint on the ground covers two texels or more (far or grazing ground),
  // it is read bilinearly from the mipmap level whose texel best matches the footprint's area
  // (as OpenGL's LINEAR_MIPMAP_NEAREST, which picks by the longer axis): less aliasing, and
  // neighbouring pixels read neighbouring texels.
  void setGround(const RgbImage& texture, double x_min_m, double x_max_m, double y_min_m, double y_max_m,
                 const Vec3& ground_rgb);
  void setGroundColor(const Vec3& ground_rgb);
  void setSkyColor(const Vec3& sky_rgb);  // where a ray meets nothing; default (0.7, 0.8, 0.9)

  int addObject(const RenderObject& object);  // returns its index
  void setObjectPose(int index, const Pose& pose);
  void setObjectImage(int index, const RgbImage& image);  // kBox only; replaces the face image
  const RenderObject& object(int index) const { return objects_[index]; }
  int objectCount() const { return static_cast<int>(objects_.size()); }

  // The ground texture as a mipmap: level 0 is the image, level L + 1 averages 2x2 texels of
  // level L (its size rounded up, edges repeated). Texels are packed (R in the low byte, then G,
  // B, 0); each level has one more column and row repeating its last ones, so a bilinear read
  // never leaves it. (Layout for the renderer.)
  struct TextureLevel {
    int width_px = 0, height_px = 0;  // without the repeated column and row
    size_t first_texel = 0;           // in ground_texels_; rows of width_px + 1 texels
  };

 private:
  friend class CameraRenderer;
  std::vector<TextureLevel> ground_levels_;  // empty: no texture
  std::vector<std::uint32_t> ground_texels_;
  double ground_x_min_m_ = 0.0, ground_x_max_m_ = 0.0, ground_y_min_m_ = 0.0, ground_y_max_m_ = 0.0;
  Vec3 ground_rgb_{0.7, 0.7, 0.7};
  Vec3 sky_rgb_{0.7, 0.8, 0.9};
  std::vector<RenderObject> objects_;
};

// The ground and every object of a world file (textures loaded; display panels start with their
// texture or their colour). Object i of the world is object i of the scene.
RenderScene renderSceneFromWorld(const WorldDescription& world);

class CameraRenderer {
 public:
  // Throws std::invalid_argument for a non-positive size or focal length, clip planes with
  // near <= 0 or far <= near, a negative noise_stddev, or a lens distortion that cannot be
  // inverted at some pixel (the model folds over inside the image).
  explicit CameraRenderer(const CameraModel& model);
  const CameraModel& model() const { return model_; }

  // Renders into `image` (resized to the model's size). Objects whose group equals
  // exclude_group are not drawn (-1 excludes nothing). `noise_rng` is used only when the model
  // has noise; nullptr then means no noise. Allocates nothing once `image` has the right size
  // and a frame of the scene has been drawn on this thread.
  void render(const RenderScene& scene, const Pose& world_T_optical, int exclude_group, std::mt19937* noise_rng,
              RgbImage& image) const;

  // The ground pass uses AVX2 (eight lanes) where the CPU has it, else four lanes; both draw the
  // same pixels. false forces four lanes everywhere (tests and benchmarks compare the two).
  static void allowWideVectors(bool allowed);
  static bool wideVectorsAvailable();  // this CPU has AVX2 (and the build targets x86-64)

 private:
  // The image is drawn in tiles of kTileWidth x kTileHeight pixels (smaller at the right and
  // bottom edges); an object is tested only on the tiles whose ray cone its bounding sphere meets.
  static constexpr int kTileWidth = 16;
  static constexpr int kTileHeight = 8;
  static constexpr int kTilePixels = kTileWidth * kTileHeight;

  // A cone around `axis` (unit, optical frame) that holds the rays of a set of pixels.
  struct RayCone {
    Vec3 axis{0.0, 0.0, 1.0};
    double half_angle_rad = 0.0, cos_half = 1.0, sin_half = 0.0;
  };
  struct Tile {
    int u0 = 0, v0 = 0, width = 0, height = 0;  // pixels [u0, u0 + width) x [v0, v0 + height)
    RayCone cone;
  };

  CameraModel model_;
  std::vector<Vec3> rays_optical_;  // one unit direction per pixel, distortion already inverted
  std::vector<Tile> tiles_;
  RayCone image_cone_;  // holds every ray of the image
  // The rays again as floats in tile order, kTilePixels per tile, row by row inside a tile
  // (rows kTileWidth long; pixels outside a clipped tile repeat its first ray), for the ground pass.
  std::vector<float> tile_ray_x_, tile_ray_y_, tile_ray_z_;
  std::vector<int> unseen_pixels_;  // beyond a wide-angle lens's cut-off: drawn black
};

}  // namespace conde_physics
