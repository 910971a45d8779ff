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
// The camera model (intrinsics, lens, projection) is in camera_model.h, the scene in
// render_scene.h.
#pragma once

#include <random>
#include <vector>

#include "conde_physics/camera_model.h"
#include "conde_physics/math.h"
#include "conde_physics/render_scene.h"

namespace conde_physics {

// Depth image of a frame (row-major, width x height): the z-depth of each pixel's nearest hit
// along the optical axis in metres (the optical frame's z of the surface point, as a depth
// camera's 32FC1 image), +infinity where the ray meets nothing between the clip distances.
struct DepthImage {
  int width = 0, height = 0;
  std::vector<float> depth_m;
  void resize(int w, int h) {
    width = w;
    height = h;
    depth_m.assign(static_cast<size_t>(w) * h, 0.0f);
  }
  float at(int u, int v) const { return depth_m[static_cast<size_t>(v) * width + u]; }
};

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
  // The same, and the depth image of the same pass into `depth` (resized to the model's size)
  // unless it is nullptr. The near and far clips apply to the distance along each ray. Pixels
  // beyond a wide-angle lens's cut-off are +infinity. Noise is on the colour image only.
  void render(const RenderScene& scene, const Pose& world_T_optical, int exclude_group, std::mt19937* noise_rng,
              RgbImage& image, DepthImage* depth) const;

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
