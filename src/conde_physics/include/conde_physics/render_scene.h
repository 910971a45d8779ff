// What cameras see: RGB images, the textured ground plane and the objects on it (boxes with an
// optional face image, cylinders, cones, spheres, triangle meshes), built from a world file or by
// hand.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "conde_physics/math.h"
#include "conde_physics/mesh_bvh.h"
#include "conde_physics/world_file.h"

namespace conde_physics {

class CameraRenderer;

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

enum class RenderShape { kBox, kCylinder, kCone, kSphere, kMesh };

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
  // kMesh: the triangles (object frame) and, optionally, one colour per triangle (index as in
  // the BVH's input; null or empty: color_rgb). Shared, never copied per frame.
  std::shared_ptr<const MeshBvh> mesh;
  std::shared_ptr<const std::vector<Vec3>> mesh_triangle_rgb;
  int group = -1;       // e.g. the model id of a robot; cameras may exclude one group
  bool hidden = false;  // not drawn (a robot deleted while the simulation runs)
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
  void setObjectHidden(int index, bool hidden);
  void setObjectImage(int index, const RgbImage& image);  // kBox only; replaces the face image
  const RenderObject& object(int index) const { return objects_[index]; }

  // Shade (a tunnel): what the cameras see at a surface point inside a light region has its
  // colour scaled by the region's light (the darkest region wins where they overlap). Throws
  // std::invalid_argument for fewer than 3 corners, z_min_m >= z_max_m or light outside 0..1.
  void addLightRegion(const LightRegion& region);
  bool hasLightRegions() const { return !light_regions_.empty(); }
  double lightAt(const Vec3& point_world) const;  // 0..1; 1 outside every region
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
  struct ShadedRegion {
    LightRegion region;
    double x_min_m, x_max_m, y_min_m, y_max_m;  // bounding box of the polygon
    // The even-odd test looks only at the edges whose y range can hold the point's y: the box's
    // y range cut into bands of band_height_m, band b's edges (index of the edge's end corner i,
    // its start being i - 1) are band_edges[band_first[b] .. band_first[b + 1]).
    double band_height_m = 1.0;
    int band_count = 1;
    std::vector<int> band_first;
    std::vector<int> band_edges;
  };
  std::vector<ShadedRegion> light_regions_;
  static int lightBand(const ShadedRegion& s, double y_m);  // the band that holds y (clamped)
};

// The ground and every object of a world file (textures loaded; display panels start with their
// texture or their colour) and its light regions. Object i of the world is object i of the scene.
RenderScene renderSceneFromWorld(const WorldDescription& world);
// How the scene draws one world object (its texture loaded); hidden when it only collides.
RenderObject renderObjectOf(const WorldObject& object);

}  // namespace conde_physics
