// The render scene: images, the ground texture's mipmap, the objects, and the scene of a world
// file.
#include "conde_physics/render_scene.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>

#include "render_detail.h"

namespace conde_physics {

using render_detail::checkImage;
using render_detail::text;

namespace {

void checkIndex(int index, int count) {
  if (index < 0 || index >= count)
    throw std::out_of_range("render object index " + std::to_string(index) + " out of range (the scene has " +
                            std::to_string(count) + " objects)");
}

}  // namespace

// --- Images ------------------------------------------------------------------------------------

RgbImage loadRgbImage(const std::string& path) {
  // A file that does not open gets the same message, without OpenCV's warning on stderr.
  if (!std::ifstream(path).good()) throw std::runtime_error("cannot decode image '" + path + "'");
  cv::Mat bgr = cv::imread(path, cv::IMREAD_COLOR);
  if (bgr.empty()) throw std::runtime_error("cannot decode image '" + path + "'");
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  RgbImage image;
  image.resize(rgb.cols, rgb.rows);
  for (int v = 0; v < rgb.rows; ++v) std::memcpy(image.pixel(0, v), rgb.ptr(v), static_cast<size_t>(rgb.cols) * 3);
  return image;
}

// --- Scene -------------------------------------------------------------------------------------

void RenderScene::setGround(const RgbImage& texture, double x_min_m, double x_max_m, double y_min_m, double y_max_m,
                            const Vec3& ground_rgb) {
  checkImage(texture, "ground texture");
  if (texture.width > 0 && texture.height > 0 && !(x_min_m < x_max_m && y_min_m < y_max_m))
    throw std::invalid_argument("ground texture ranges must have min < max (got x [" + text(x_min_m) + ", " +
                                text(x_max_m) + "] m, y [" + text(y_min_m) + ", " + text(y_max_m) + "] m)");
  ground_levels_.clear();
  ground_texels_.clear();
  if (texture.width > 0 && texture.height > 0) {
    size_t texel_count = 0;
    for (int w = texture.width, h = texture.height;; w = (w + 1) / 2, h = (h + 1) / 2) {
      ground_levels_.push_back({w, h, texel_count});
      texel_count += static_cast<size_t>(w + 1) * (h + 1);
      if (w == 1 && h == 1) break;
    }
    ground_texels_.resize(texel_count);
    auto texel = [this](const TextureLevel& level, int u, int v) -> std::uint32_t& {
      return ground_texels_[level.first_texel + static_cast<size_t>(v) * (level.width_px + 1) + u];
    };
    // Level 0 from the image, each further level from the one before by rounded 2x2 averages
    // (where a size is odd, the repeated column or row of the finer level stands in).
    for (size_t l = 0; l < ground_levels_.size(); ++l) {
      const TextureLevel& level = ground_levels_[l];
      for (int v = 0; v <= level.height_px; ++v) {
        for (int u = 0; u <= level.width_px; ++u) {
          const int iu = std::min(u, level.width_px - 1), iv = std::min(v, level.height_px - 1);
          std::uint32_t packed = 0;
          for (int c = 0; c < 3; ++c) {
            std::uint32_t value;
            if (l == 0) {
              value = texture.pixel(iu, iv)[c];
            } else {
              const TextureLevel& fine = ground_levels_[l - 1];
              value = 2;
              for (const std::uint32_t t : {texel(fine, 2 * iu, 2 * iv), texel(fine, 2 * iu + 1, 2 * iv),
                                            texel(fine, 2 * iu, 2 * iv + 1), texel(fine, 2 * iu + 1, 2 * iv + 1)})
                value += (t >> (8 * c)) & 0xFFu;
              value /= 4;
            }
            packed |= value << (8 * c);
          }
          texel(level, u, v) = packed;
        }
      }
    }
  }
  ground_x_min_m_ = x_min_m;
  ground_x_max_m_ = x_max_m;
  ground_y_min_m_ = y_min_m;
  ground_y_max_m_ = y_max_m;
  ground_rgb_ = ground_rgb;
}

void RenderScene::setGroundColor(const Vec3& ground_rgb) { ground_rgb_ = ground_rgb; }

void RenderScene::setSkyColor(const Vec3& sky_rgb) { sky_rgb_ = sky_rgb; }

int RenderScene::addObject(const RenderObject& object) {
  const std::string what = "render object " + std::to_string(objects_.size());
  switch (object.shape) {
    case RenderShape::kBox:
      if (!(object.size_m.x > 0.0 && object.size_m.y > 0.0 && object.size_m.z > 0.0))
        throw std::invalid_argument(what + ": box size must be positive (got " + text(object.size_m.x) + " x " +
                                    text(object.size_m.y) + " x " + text(object.size_m.z) + " m)");
      break;
    case RenderShape::kCylinder:
    case RenderShape::kCone:
      if (!(object.length_m > 0.0))
        throw std::invalid_argument(what + ": length must be positive (got " + text(object.length_m) + " m)");
      [[fallthrough]];
    case RenderShape::kSphere:
      if (!(object.radius_m > 0.0))
        throw std::invalid_argument(what + ": radius must be positive (got " + text(object.radius_m) + " m)");
      if (object.face_image.width > 0) throw std::invalid_argument(what + ": only boxes show a face image");
      break;
  }
  checkImage(object.face_image, what + " face image");
  objects_.push_back(object);
  objects_.back().pose.orientation = object.pose.orientation.normalized();
  return static_cast<int>(objects_.size()) - 1;
}

void RenderScene::setObjectPose(int index, const Pose& pose) {
  checkIndex(index, objectCount());
  objects_[index].pose = Pose(pose.position, pose.orientation.normalized());
}

void RenderScene::setObjectHidden(int index, bool hidden) {
  checkIndex(index, objectCount());
  objects_[index].hidden = hidden;
}

void RenderScene::setObjectImage(int index, const RgbImage& image) {
  checkIndex(index, objectCount());
  if (objects_[index].shape != RenderShape::kBox)
    throw std::invalid_argument("render object " + std::to_string(index) + ": only boxes show a face image");
  checkImage(image, "render object " + std::to_string(index) + " face image");
  objects_[index].face_image = image;
}

void RenderScene::addLightRegion(const LightRegion& region) {
  const std::string what = "light region '" + region.name + "'";
  if (region.polygon_xy_m.size() < 3)
    throw std::invalid_argument(what + ": needs at least 3 corners (got " + std::to_string(region.polygon_xy_m.size()) +
                                ")");
  if (!(region.z_min_m < region.z_max_m))
    throw std::invalid_argument(what + ": z range must have min < max (got " + text(region.z_min_m) + ", " +
                                text(region.z_max_m) + " m)");
  if (!(region.light >= 0.0 && region.light <= 1.0))
    throw std::invalid_argument(what + ": light must be in 0..1 (got " + text(region.light) + ")");
  ShadedRegion shaded{region, region.polygon_xy_m[0][0], region.polygon_xy_m[0][0], region.polygon_xy_m[0][1],
                      region.polygon_xy_m[0][1]};
  for (const auto& corner : region.polygon_xy_m) {
    shaded.x_min_m = std::min(shaded.x_min_m, corner[0]);
    shaded.x_max_m = std::max(shaded.x_max_m, corner[0]);
    shaded.y_min_m = std::min(shaded.y_min_m, corner[1]);
    shaded.y_max_m = std::max(shaded.y_max_m, corner[1]);
  }
  // About one edge per band on a long, curved polygon (a tunnel's), each edge in the bands its y
  // range meets: lightAt tests a few edges instead of all of them, with the same result (an edge
  // the even-odd rule counts has the point's y in its y range, so in one of its bands; band() is
  // monotonic in y).
  const auto& corners = region.polygon_xy_m;
  shaded.band_count = static_cast<int>(corners.size());
  shaded.band_height_m = std::max((shaded.y_max_m - shaded.y_min_m) / shaded.band_count, 1e-9);
  std::vector<std::vector<int>> per_band(static_cast<size_t>(shaded.band_count));
  for (size_t i = 0, j = corners.size() - 1; i < corners.size(); j = i++) {
    const int b0 = lightBand(shaded, std::min(corners[i][1], corners[j][1]));
    const int b1 = lightBand(shaded, std::max(corners[i][1], corners[j][1]));
    for (int b = b0; b <= b1; ++b) per_band[static_cast<size_t>(b)].push_back(static_cast<int>(i));
  }
  shaded.band_first.push_back(0);
  for (const std::vector<int>& edges : per_band) {
    shaded.band_edges.insert(shaded.band_edges.end(), edges.begin(), edges.end());
    shaded.band_first.push_back(static_cast<int>(shaded.band_edges.size()));
  }
  light_regions_.push_back(std::move(shaded));
}

int RenderScene::lightBand(const ShadedRegion& s, double y_m) {
  const int last = s.band_count - 1;
  const double band = std::floor((y_m - s.y_min_m) / s.band_height_m);
  return !(band > 0.0) ? 0 : band >= last ? last : static_cast<int>(band);  // NaN: band 0, no cast
}

double RenderScene::lightAt(const Vec3& p) const {
  double light = 1.0;
  for (const ShadedRegion& s : light_regions_) {
    if (p.x < s.x_min_m || p.x > s.x_max_m || p.y < s.y_min_m || p.y > s.y_max_m || p.z < s.region.z_min_m ||
        p.z > s.region.z_max_m || s.region.light >= light)
      continue;
    // Even-odd rule: count the polygon edges that a ray from p along +x crosses (those of p's band).
    const auto& corners = s.region.polygon_xy_m;
    const int band = lightBand(s, p.y);
    bool inside = false;
    for (int e = s.band_first[static_cast<size_t>(band)]; e < s.band_first[static_cast<size_t>(band) + 1]; ++e) {
      const size_t i = static_cast<size_t>(s.band_edges[static_cast<size_t>(e)]);
      const size_t j = i == 0 ? corners.size() - 1 : i - 1;
      const double xi = corners[i][0], yi = corners[i][1], xj = corners[j][0], yj = corners[j][1];
      if ((yi > p.y) != (yj > p.y) && p.x < xi + (p.y - yi) * (xj - xi) / (yj - yi)) inside = !inside;
    }
    if (inside) light = s.region.light;
  }
  return light;
}

RenderObject renderObjectOf(const WorldObject& w) {
  RenderObject o;
  o.shape = w.shape == ObjectShape::kBox        ? RenderShape::kBox
            : w.shape == ObjectShape::kCylinder ? RenderShape::kCylinder
            : w.shape == ObjectShape::kCone     ? RenderShape::kCone
            : w.shape == ObjectShape::kSphere   ? RenderShape::kSphere
                                                : RenderShape::kMesh;
  if (w.shape == ObjectShape::kMesh) {
    o.mesh = w.mesh_bvh;
    if (w.mesh && !w.mesh->triangle_rgb.empty())
      o.mesh_triangle_rgb = std::shared_ptr<const std::vector<Vec3>>(w.mesh, &w.mesh->triangle_rgb);
  }
  o.hidden = !w.visible;  // kept, so that object i of the world stays object i of the scene
  o.size_m = w.size_m;
  o.radius_m = w.radius_m;
  o.length_m = w.length_m;
  o.pose = w.pose;
  o.color_rgb = w.color_rgb;
  if (!w.texture_path.empty()) o.face_image = loadRgbImage(w.texture_path);
  return o;
}

RenderScene renderSceneFromWorld(const WorldDescription& world) {
  RenderScene scene;
  const GroundSpec& g = world.ground;
  if (g.texture_path.empty()) {
    scene.setGroundColor(g.color_rgb);
  } else {
    scene.setGround(loadRgbImage(g.texture_path), g.x_min_m, g.x_max_m, g.y_min_m, g.y_max_m, g.color_rgb);
  }
  for (const WorldObject& w : world.objects) scene.addObject(renderObjectOf(w));
  for (const LightRegion& region : world.light_regions) scene.addLightRegion(region);
  return scene;
}

}  // namespace conde_physics
