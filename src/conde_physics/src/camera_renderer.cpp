// CPU ray caster behind CameraRenderer. Per frame: the world pose of the optical frame gives one
// rotation for the precomputed pixel rays; the ground plane is hit by every ray (a division and
// a bilinear texture read per pixel); each object is transformed once into its own frame and
// tested only on the image tiles whose ray cone meets its bounding sphere, with a depth test
// against the ground and the objects already drawn.
#include "conde_physics/camera_renderer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "ground_pass.h"
#include "render_detail.h"

namespace conde_physics {

namespace rd = render_detail;
using rd::kPi;
using rd::text;
using rd::toByte;

namespace {

std::atomic<bool> wide_vectors_allowed{true};  // CameraRenderer::allowWideVectors

// Object lighting: ambient plus Lambert diffuse from a fixed sun above (tilted so that the sides
// of a box differ). The ground and face images are drawn with their own colours.
constexpr double kAmbient = 0.4;
constexpr double kDiffuse = 0.6;
Vec3 toSunWorld() { return Vec3(0.3, 0.4, 1.0).normalized(); }

// --- Noise -------------------------------------------------------------------------------------

// 65536 quantiles of the standard normal distribution: one 16-bit random number picks one, so a
// 32-bit draw gives two samples (a few ns each instead of ~20 ns for std::normal_distribution).
constexpr int kNormalTableBits = 16;
constexpr int kNormalTableSize = 1 << kNormalTableBits;

std::vector<float> makeNormalQuantiles() {
  std::vector<float> table(kNormalTableSize);
  const double inv_sqrt2 = 1.0 / std::sqrt(2.0);
  const double inv_sqrt_2pi = 1.0 / std::sqrt(2.0 * kPi);
  double x = 0.0;
  // Upper half by Newton's method, each start from the previous quantile: the CDF is concave
  // there, so the iterates approach the root from below and cannot overshoot.
  for (int i = kNormalTableSize / 2; i < kNormalTableSize; ++i) {
    const double p = (i + 0.5) / kNormalTableSize;
    for (int iteration = 0; iteration < 100; ++iteration) {
      const double cdf = 0.5 * std::erfc(-x * inv_sqrt2);
      const double step = (p - cdf) / (inv_sqrt_2pi * std::exp(-0.5 * x * x));
      x += step;
      if (std::abs(step) < 1e-12) break;
    }
    table[i] = static_cast<float>(x);
    table[kNormalTableSize - 1 - i] = static_cast<float>(-x);
  }
  return table;
}

const std::vector<float>& normalQuantiles() {
  static const std::vector<float> table = makeNormalQuantiles();
  return table;
}

void addNoise(double stddev_unit, std::mt19937& rng, RgbImage& image) {
  const float* table = normalQuantiles().data();
  const float scale = static_cast<float>(stddev_unit * 255.0);
  std::uint8_t* p = image.data.data();
  const size_t n = image.data.size();
  auto noisy = [&](std::uint8_t value, std::uint32_t index) {
    const long v = std::lrint(value + scale * table[index]);
    return static_cast<std::uint8_t>(std::clamp(v, 0L, 255L));
  };
  size_t i = 0;
  for (; i + 1 < n; i += 2) {
    const std::uint32_t bits = rng();
    p[i] = noisy(p[i], bits & 0xFFFFu);
    p[i + 1] = noisy(p[i + 1], bits >> 16);
  }
  if (i < n) p[i] = noisy(p[i], rng() & 0xFFFFu);
}

// --- Textures ----------------------------------------------------------------------------------

// Bilinear read at texel coordinates (fu, fv) (texel centres at integers), clamped to the edge
// texels; 8-bit weights.
inline void sampleBilinear(const RgbImage& texture, float fu, float fv, std::uint8_t* out) {
  const int w = texture.width, h = texture.height;
  fu = std::clamp(fu, 0.0f, static_cast<float>(w - 1));
  fv = std::clamp(fv, 0.0f, static_cast<float>(h - 1));
  const int iu = static_cast<int>(fu), iv = static_cast<int>(fv);  // non-negative: truncation = floor
  const int wu = static_cast<int>((fu - iu) * 256.0f), wv = static_cast<int>((fv - iv) * 256.0f);
  const int du = iu + 1 < w ? 3 : 0;
  const int dv = iv + 1 < h ? 3 * w : 0;
  const std::uint8_t* p00 = texture.data.data() + (static_cast<size_t>(iv) * w + iu) * 3;
  const std::uint8_t* p10 = p00 + dv;
  for (int c = 0; c < 3; ++c) {
    const int top = p00[c] * (256 - wu) + p00[c + du] * wu;
    const int bottom = p10[c] * (256 - wu) + p10[c + du] * wu;
    out[c] = static_cast<std::uint8_t>((top * (256 - wv) + bottom * wv + 32768) >> 16);
  }
}

// --- Objects -----------------------------------------------------------------------------------

// What one frame needs of an object that may be in view.
struct ObjectInView {
  const RenderObject* object = nullptr;
  // Bounding sphere as seen from the camera: direction (optical frame, unit) and angular radius.
  Vec3 direction_optical;
  double angular_radius_rad = 0.0, cos_angular = 1.0, sin_angular = 0.0;
  bool surrounds_camera = false;  // the camera is inside the bounding sphere: test every tile
  double nearest_m = 0.0;         // distance from the camera to the bounding sphere
  // Unless surrounds_camera: the sphere's centre in the optical frame [m], its squared distance
  // [m^2] and its radius grown by a hair against rounding, squared [m^2] (the per-pixel test).
  Vec3 centre_optical;
  double centre_sq_m2 = 0.0, reach_sq_m2 = 0.0;
  double local_R_optical[3][3];
  double origin_local[3];  // camera position in the object frame
  Vec3 to_sun_local;
  std::uint8_t face_rgb[6][3];  // box faces +x, -x, +y, -y, +z, -z, lit
};

double boundingRadius(const RenderObject& o) {
  switch (o.shape) {
    case RenderShape::kBox:
      return 0.5 * o.size_m.norm();
    case RenderShape::kCylinder:
    case RenderShape::kCone:
      return std::hypot(o.radius_m, 0.5 * o.length_m);
    case RenderShape::kSphere:
      return o.radius_m;
    case RenderShape::kMesh:  // about boundingCentre
      return o.mesh ? o.mesh->boundRadius() : 0.0;
  }
  return 0.0;
}

// World centre of the bounding sphere: the object's origin, except for a mesh (its vertices'
// bounding box centre, which may lie far from the origin).
Vec3 boundingCentre(const RenderObject& o) {
  if (o.shape == RenderShape::kMesh && o.mesh) return o.pose * o.mesh->boundCentre();
  return o.pose.position;
}

void shadeInto(const ObjectInView& view, const Vec3& normal_local, std::uint8_t* out) {
  const double light = kAmbient + kDiffuse * std::max(0.0, normal_local.dot(view.to_sun_local));
  const Vec3& c = view.object->color_rgb;
  out[0] = toByte(c.x * light);
  out[1] = toByte(c.y * light);
  out[2] = toByte(c.z * light);
}

// Each hit function finds the nearest surface point along o + t d (object frame, |d| = 1) with
// t in [t_near, t_limit] and writes its colour. Back faces count, so a near clip that cuts an
// object shows its inside.

bool hitBox(const ObjectInView& view, const double o[3], const double d[3], double t_near, double t_limit, double& t,
            std::uint8_t* rgb) {
  const RenderObject& box = *view.object;
  const double half[3] = {0.5 * box.size_m.x, 0.5 * box.size_m.y, 0.5 * box.size_m.z};
  double t_enter = -std::numeric_limits<double>::infinity(), t_exit = std::numeric_limits<double>::infinity();
  int enter_face = -1, exit_face = -1;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (o[k] < -half[k] || o[k] > half[k]) return false;
      continue;
    }
    const double inv = 1.0 / d[k];
    double t_low = (-half[k] - o[k]) * inv, t_high = (half[k] - o[k]) * inv;
    int face_low = 2 * k + 1, face_high = 2 * k;  // the -k face, the +k face
    if (t_low > t_high) {
      std::swap(t_low, t_high);
      std::swap(face_low, face_high);
    }
    if (t_low > t_enter) {
      t_enter = t_low;
      enter_face = face_low;
    }
    if (t_high < t_exit) {
      t_exit = t_high;
      exit_face = face_high;
    }
  }
  if (t_enter > t_exit) return false;
  int face;
  if (t_enter >= t_near) {
    t = t_enter;
    face = enter_face;
  } else if (t_exit >= t_near) {
    t = t_exit;
    face = exit_face;
  } else {
    return false;
  }
  if (t > t_limit) return false;
  if (face == 4 && box.face_image.width > 0) {
    // Column 0 at local -x, row 0 at local +y.
    const double x = o[0] + t * d[0], y = o[1] + t * d[1];
    const float fu = static_cast<float>((x / box.size_m.x + 0.5) * box.face_image.width - 0.5);
    const float fv = static_cast<float>((0.5 - y / box.size_m.y) * box.face_image.height - 0.5);
    sampleBilinear(box.face_image, fu, fv, rgb);
  } else {
    std::memcpy(rgb, view.face_rgb[face], 3);
  }
  return true;
}

bool hitSphere(const ObjectInView& view, const double o[3], const double d[3], double t_near, double t_limit, double& t,
               std::uint8_t* rgb) {
  const double r = view.object->radius_m;
  const double b = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
  const double c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - r * r;
  const double disc = b * b - c;
  if (disc < 0.0) return false;
  const double s = std::sqrt(disc);
  t = -b - s;
  if (t < t_near) t = -b + s;
  if (t < t_near || t > t_limit) return false;
  shadeInto(view, Vec3(o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]) / r, rgb);
  return true;
}

// Cylinder (cone = false) or cone (apex at z = +length/2, base at -length/2) around local z.
bool hitRound(const ObjectInView& view, bool cone, const double o[3], const double d[3], double t_near, double t_limit,
              double& t, std::uint8_t* rgb) {
  const double r = view.object->radius_m;
  const double h = 0.5 * view.object->length_m;
  double best = t_limit;
  bool found = false;
  Vec3 normal;
  // Side: x^2 + y^2 = rho(z)^2 with rho = r (cylinder) or k (h - z), k = r / length (cone),
  // written A t^2 + 2 B t + C = 0.
  double a, b, c;
  const double k2 = cone ? (r / view.object->length_m) * (r / view.object->length_m) : 0.0;
  if (cone) {
    const double w0 = h - o[2];
    a = d[0] * d[0] + d[1] * d[1] - k2 * d[2] * d[2];
    b = o[0] * d[0] + o[1] * d[1] + k2 * w0 * d[2];
    c = o[0] * o[0] + o[1] * o[1] - k2 * w0 * w0;
  } else {
    a = d[0] * d[0] + d[1] * d[1];
    b = o[0] * d[0] + o[1] * d[1];
    c = o[0] * o[0] + o[1] * o[1] - r * r;
  }
  double roots[2];
  int root_count = 0;
  if (std::abs(a) > 1e-12) {
    const double disc = b * b - a * c;
    if (disc >= 0.0) {
      const double s = std::sqrt(disc);
      roots[root_count++] = (-b - s) / a;
      roots[root_count++] = (-b + s) / a;
    }
  } else if (b != 0.0) {
    roots[root_count++] = -c / (2.0 * b);
  }
  for (int i = 0; i < root_count; ++i) {
    const double ti = roots[i];
    if (ti < t_near || ti > best) continue;
    const double z = o[2] + ti * d[2];
    if (z < -h || z > h) continue;
    const double x = o[0] + ti * d[0], y = o[1] + ti * d[1];
    best = ti;
    found = true;
    normal = cone ? Vec3(x, y, k2 * (h - z)).normalized() : Vec3(x, y, 0.0) / r;
  }
  // Caps: a cylinder has two, a cone only its base.
  if (d[2] != 0.0) {
    for (int side = cone ? 1 : 0; side < 2; ++side) {
      const double zc = side == 0 ? h : -h;
      const double ti = (zc - o[2]) / d[2];
      if (ti < t_near || ti > best) continue;
      const double x = o[0] + ti * d[0], y = o[1] + ti * d[1];
      if (x * x + y * y > r * r) continue;
      best = ti;
      found = true;
      normal = Vec3(0.0, 0.0, side == 0 ? 1.0 : -1.0);
    }
  }
  if (!found) return false;
  t = best;
  shadeInto(view, normal, rgb);
  return true;
}

// Nearest triangle through the mesh's BVH, lit by its normal turned towards the camera (the
// triangles are two-sided), in its own colour or the object's.
bool hitMesh(const ObjectInView& view, const double o[3], const double d[3], double t_near, double t_limit, double& t,
             std::uint8_t* rgb) {
  const RenderObject& object = *view.object;
  if (!object.mesh) return false;
  int triangle = -1;
  const Vec3 direction(d[0], d[1], d[2]);
  if (!object.mesh->intersect(Vec3(o[0], o[1], o[2]), direction, t_near, t_limit, t, triangle)) return false;
  Vec3 normal = object.mesh->normal(triangle);
  if (normal.dot(direction) > 0.0) normal = -normal;
  const Vec3& c = object.mesh_triangle_rgb && !object.mesh_triangle_rgb->empty() ? (*object.mesh_triangle_rgb)[triangle]
                                                                                 : object.color_rgb;
  const double light = kAmbient + kDiffuse * std::max(0.0, normal.dot(view.to_sun_local));
  rgb[0] = toByte(c.x * light);
  rgb[1] = toByte(c.y * light);
  rgb[2] = toByte(c.z * light);
  return true;
}

bool hitObject(const ObjectInView& view, const Vec3& ray_optical, double t_near, double t_limit, double& t,
               std::uint8_t* rgb) {
  const double(*m)[3] = view.local_R_optical;
  const double d[3] = {m[0][0] * ray_optical.x + m[0][1] * ray_optical.y + m[0][2] * ray_optical.z,
                       m[1][0] * ray_optical.x + m[1][1] * ray_optical.y + m[1][2] * ray_optical.z,
                       m[2][0] * ray_optical.x + m[2][1] * ray_optical.y + m[2][2] * ray_optical.z};
  switch (view.object->shape) {
    case RenderShape::kBox:
      return hitBox(view, view.origin_local, d, t_near, t_limit, t, rgb);
    case RenderShape::kSphere:
      return hitSphere(view, view.origin_local, d, t_near, t_limit, t, rgb);
    case RenderShape::kCylinder:
      return hitRound(view, false, view.origin_local, d, t_near, t_limit, t, rgb);
    case RenderShape::kCone:
      return hitRound(view, true, view.origin_local, d, t_near, t_limit, t, rgb);
    case RenderShape::kMesh:
      return hitMesh(view, view.origin_local, d, t_near, t_limit, t, rgb);
  }
  return false;
}

// False when the unit ray cannot hit the object nearer than depth_m: it misses the bounding sphere
// (grown by a hair), or enters it beyond depth_m (+ 1 um against rounding). For a camera outside
// the sphere; every point of the object is inside it, so this only skips what hitObject rejects.
inline bool raySphereMayHit(const ObjectInView& view, const Vec3& ray_optical, float depth_m) {
  const double along_m = ray_optical.dot(view.centre_optical);
  const double miss_sq_m2 = view.centre_sq_m2 - along_m * along_m;  // centre to the ray's line, squared
  if (miss_sq_m2 > view.reach_sq_m2) return false;
  return along_m - std::sqrt(view.reach_sq_m2 - miss_sq_m2) <= static_cast<double>(depth_m) + 1e-6;
}

// True when some ray of a cone (axis, half angle) may meet the bounding sphere of `view`: the
// angle between the cone's axis and the sphere's direction is at most half + angular radius.
inline bool coneMeetsSphere(const Vec3& axis, double half_rad, double cos_half, double sin_half,
                            const ObjectInView& view) {
  if (view.surrounds_camera || half_rad + view.angular_radius_rad >= kPi) return true;
  const double cos_sum = cos_half * view.cos_angular - sin_half * view.sin_angular;
  return axis.dot(view.direction_optical) >= cos_sum;
}

}  // namespace

// --- Renderer ----------------------------------------------------------------------------------

void CameraRenderer::allowWideVectors(bool allowed) { wide_vectors_allowed.store(allowed); }

CameraRenderer::CameraRenderer(const CameraModel& model) : model_(model) {
  const int w = model.width_px, h = model.height_px;
  rd::checkImageSize(w, h);
  if (!(model.fx_px > 0.0 && model.fy_px > 0.0 && std::isfinite(model.fx_px) && std::isfinite(model.fy_px)))
    throw std::invalid_argument("camera focal length must be positive (got fx " + text(model.fx_px) + " px, fy " +
                                text(model.fy_px) + " px)");
  if (!(std::isfinite(model.cx_px) && std::isfinite(model.cy_px)))
    throw std::invalid_argument("camera principal point must be finite (got cx " + text(model.cx_px) + " px, cy " +
                                text(model.cy_px) + " px)");
  if (!(model.near_clip_m > 0.0 && model.far_clip_m > model.near_clip_m))
    throw std::invalid_argument("camera clip distances must satisfy 0 < near < far (got near " +
                                text(model.near_clip_m) + " m, far " + text(model.far_clip_m) + " m)");
  if (!(model.noise_stddev >= 0.0 && std::isfinite(model.noise_stddev)))
    throw std::invalid_argument("camera noise_stddev must be >= 0 (got " + text(model.noise_stddev) + ")");
  const LensDistortion& lens = model.distortion;
  if (!(std::isfinite(lens.k1) && std::isfinite(lens.k2) && std::isfinite(lens.k3) && std::isfinite(lens.p1) &&
        std::isfinite(lens.p2)))
    throw std::invalid_argument("camera distortion coefficients must be finite");

  const double unit_x = model.distortion_in_image_units ? w : model.fx_px;
  const double unit_y = model.distortion_in_image_units ? h : model.fy_px;
  rays_optical_.resize(static_cast<size_t>(w) * h);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      double x = (u - model.cx_px) / unit_x, y = (v - model.cy_px) / unit_y;
      if (!lens.isZero() && !rd::undistort(lens, x, y, x, y))
        throw std::invalid_argument("camera distortion (k1 " + text(lens.k1) + ", k2 " + text(lens.k2) + ", k3 " +
                                    text(lens.k3) + ", p1 " + text(lens.p1) + ", p2 " + text(lens.p2) +
                                    ") cannot be inverted at pixel (" + std::to_string(u) + ", " + std::to_string(v) +
                                    "): the lens model folds over inside the image");
      Vec3& ray = rays_optical_[static_cast<size_t>(v) * w + u];
      if (!model.lens.rayAt(x * unit_x / model.fx_px, y * unit_y / model.fy_px, ray)) {
        unseen_pixels_.push_back(v * w + u);
        ray = Vec3(0.0, 0.0, 1.0);  // inside every cone; the pixel is painted black after drawing
      }
    }
  }

  // A cone around the mean direction of the given pixels' rays that holds them all (plus a hair,
  // so rounding never drops a pixel).
  auto coneOf = [this, w](int u0, int v0, int cw, int ch) {
    Vec3 sum;
    for (int v = v0; v < v0 + ch; ++v)
      for (int u = u0; u < u0 + cw; ++u) sum += rays_optical_[static_cast<size_t>(v) * w + u];
    RayCone cone;
    cone.axis = sum.normalized();
    double min_cos = 1.0;
    for (int v = v0; v < v0 + ch; ++v)
      for (int u = u0; u < u0 + cw; ++u)
        min_cos = std::min(min_cos, cone.axis.dot(rays_optical_[static_cast<size_t>(v) * w + u]));
    cone.half_angle_rad = std::acos(std::clamp(min_cos, -1.0, 1.0)) + 1e-6;
    cone.cos_half = std::cos(cone.half_angle_rad);
    cone.sin_half = std::sin(cone.half_angle_rad);
    return cone;
  };
  image_cone_ = coneOf(0, 0, w, h);
  for (int v0 = 0; v0 < h; v0 += kTileHeight) {
    for (int u0 = 0; u0 < w; u0 += kTileWidth) {
      Tile tile;
      tile.u0 = u0;
      tile.v0 = v0;
      tile.width = std::min(kTileWidth, w - u0);
      tile.height = std::min(kTileHeight, h - v0);
      tile.cone = coneOf(u0, v0, tile.width, tile.height);
      tiles_.push_back(tile);
      for (int j = 0; j < kTileHeight; ++j) {
        for (int i = 0; i < kTileWidth; ++i) {
          const bool inside = i < tile.width && j < tile.height;
          const Vec3& ray = rays_optical_[static_cast<size_t>(inside ? v0 + j : v0) * w + (inside ? u0 + i : u0)];
          tile_ray_x_.push_back(static_cast<float>(ray.x));
          tile_ray_y_.push_back(static_cast<float>(ray.y));
          tile_ray_z_.push_back(static_cast<float>(ray.z));
        }
      }
    }
  }
}

bool CameraRenderer::wideVectorsAvailable() { return rd::haveAvx2(); }

void CameraRenderer::render(const RenderScene& scene, const Pose& world_T_optical, int exclude_group,
                            std::mt19937* noise_rng, RgbImage& image) const {
  render(scene, world_T_optical, exclude_group, noise_rng, image, nullptr);
}

void CameraRenderer::render(const RenderScene& scene, const Pose& world_T_optical, int exclude_group,
                            std::mt19937* noise_rng, RgbImage& image, DepthImage* depth_out) const {
  const int w = model_.width_px, h = model_.height_px;
  if (image.width != w || image.height != h || image.data.size() != static_cast<size_t>(w) * h * 3) image.resize(w, h);
  if (depth_out &&
      (depth_out->width != w || depth_out->height != h || depth_out->depth_m.size() != static_cast<size_t>(w) * h))
    depth_out->resize(w, h);
  const double near_m = model_.near_clip_m, far_m = model_.far_clip_m;

  double world_R_optical[3][3];
  world_T_optical.orientation.normalized().toMatrix(world_R_optical);
  const Vec3& camera_world = world_T_optical.position;

  // Objects that may be in view, with everything the per-pixel tests need (kept between frames
  // so that drawing allocates nothing; one list per thread so threads may render at once).
  thread_local std::vector<ObjectInView> in_view;
  in_view.clear();
  const Vec3 to_sun_world = toSunWorld();
  for (const RenderObject& object : scene.objects_) {
    if (object.hidden || (exclude_group != -1 && object.group == exclude_group)) continue;
    const Vec3 offset_world = boundingCentre(object) - camera_world;
    // Optical coordinates of the bounding sphere centre: optical_R_world = world_R_optical^T.
    Vec3 centre;
    centre.x = world_R_optical[0][0] * offset_world.x + world_R_optical[1][0] * offset_world.y +
               world_R_optical[2][0] * offset_world.z;
    centre.y = world_R_optical[0][1] * offset_world.x + world_R_optical[1][1] * offset_world.y +
               world_R_optical[2][1] * offset_world.z;
    centre.z = world_R_optical[0][2] * offset_world.x + world_R_optical[1][2] * offset_world.y +
               world_R_optical[2][2] * offset_world.z;
    const double radius = boundingRadius(object);
    const double distance = centre.norm();
    if (distance - radius > far_m || distance + radius < near_m) continue;
    ObjectInView view;
    view.object = &object;
    view.surrounds_camera = distance <= radius;
    view.nearest_m = std::max(0.0, distance - radius);
    if (!view.surrounds_camera) {
      view.centre_optical = centre;
      view.centre_sq_m2 = centre.dot(centre);
      const double reach_m = radius * (1.0 + 1e-9) + 1e-9;
      view.reach_sq_m2 = reach_m * reach_m;
      view.direction_optical = centre / distance;
      view.sin_angular = radius / distance;
      view.angular_radius_rad = std::asin(view.sin_angular);
      view.cos_angular = std::cos(view.angular_radius_rad);
      if (!coneMeetsSphere(image_cone_.axis, image_cone_.half_angle_rad, image_cone_.cos_half, image_cone_.sin_half,
                           view))
        continue;
    }
    double world_R_local[3][3];
    object.pose.orientation.toMatrix(world_R_local);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        view.local_R_optical[r][c] = world_R_local[0][r] * world_R_optical[0][c] +
                                     world_R_local[1][r] * world_R_optical[1][c] +
                                     world_R_local[2][r] * world_R_optical[2][c];
      }
    }
    const Vec3 origin_local = object.pose.orientation.conjugate().rotate(camera_world - object.pose.position);
    view.origin_local[0] = origin_local.x;
    view.origin_local[1] = origin_local.y;
    view.origin_local[2] = origin_local.z;
    view.to_sun_local = object.pose.orientation.conjugate().rotate(to_sun_world);
    const Vec3 face_normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int f = 0; f < 6; ++f) shadeInto(view, face_normals[f], view.face_rgb[f]);
    in_view.push_back(view);
  }
  // Nearest first: the depth test then rejects most of what lies behind (a mesh's hierarchy at its
  // root box). Stable, so that objects at the same distance keep the scene's order.
  std::stable_sort(in_view.begin(), in_view.end(),
                   [](const ObjectInView& a, const ObjectInView& b) { return a.nearest_m < b.nearest_m; });

  // Ground and sky.
  const bool textured = !scene.ground_levels_.empty();
  const int texture_width = textured ? scene.ground_levels_[0].width_px : 0;
  const int texture_height = textured ? scene.ground_levels_[0].height_px : 0;
  const float tex_u_per_m =
      textured ? texture_width / static_cast<float>(scene.ground_x_max_m_ - scene.ground_x_min_m_) : 0.0f;
  const float tex_v_per_m =
      textured ? texture_height / static_cast<float>(scene.ground_y_max_m_ - scene.ground_y_min_m_) : 0.0f;
  // Level-0 texel coordinates (texel centres at integers) of the ground point at t along a ray:
  // u = (x_camera + t dx - x_min) * u_per_m - 0.5, v = (y_max - y_camera - t dy) * v_per_m - 0.5.
  const float u_at_camera = static_cast<float>((camera_world.x - scene.ground_x_min_m_) * tex_u_per_m - 0.5);
  const float v_at_camera = static_cast<float>((scene.ground_y_max_m_ - camera_world.y) * tex_v_per_m - 0.5);
  // The texture covers u, v in [-0.5, size - 0.5] (nothing without a texture); reads clamp to
  // the edge texels.
  const float u_limit = textured ? texture_width - 0.5f : -1.0f;
  const float v_limit = textured ? texture_height - 0.5f : -1.0f;
  // Mipmap level: a pixel (angular size ~1/f) sees the ground at distance t = h / -dz, stretched
  // by 1 / -dz along the ray, so it covers rho^2 = (h texels_per_m / f)^2 / -dz^3 texels (area).
  // level = round(log2 rho) = floor(log2(2 rho^2) / 2): the level whose texel matches the
  // footprint's area (sharper than a GPU's choice by the longer axis, a little aliasing at
  // grazing angles instead of a blur).
  const double footprint_m =
      std::max(tex_u_per_m, tex_v_per_m) / std::min(model_.fx_px, model_.fy_px) * std::max(camera_world.z, 0.0);
  const float footprint_area_scale = static_cast<float>(2.0 * footprint_m * footprint_m);
  const std::int32_t max_level = textured ? static_cast<std::int32_t>(scene.ground_levels_.size()) - 1 : 0;
  rd::GroundFrame frame;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) frame.rot[r][c] = static_cast<float>(world_R_optical[r][c]);
  frame.camera_height = static_cast<float>(camera_world.z);
  frame.near = static_cast<float>(near_m);
  frame.far = static_cast<float>(far_m);
  frame.u_at_camera = u_at_camera;
  frame.v_at_camera = v_at_camera;
  frame.tex_u_per_m = tex_u_per_m;
  frame.tex_v_per_m = tex_v_per_m;
  frame.u_limit = u_limit;
  frame.v_limit = v_limit;
  frame.footprint_area_scale = footprint_area_scale;
  frame.max_level = max_level;
  frame.texels = scene.ground_texels_.data();
  frame.levels = scene.ground_levels_.data();
  auto packed = [](const Vec3& rgb) {
    return static_cast<std::uint32_t>(toByte(rgb.x)) | static_cast<std::uint32_t>(toByte(rgb.y)) << 8 |
           static_cast<std::uint32_t>(toByte(rgb.z)) << 16;
  };
  frame.ground_packed = packed(scene.ground_rgb_);
  frame.sky_packed = packed(scene.sky_rgb_);
  const rd::GroundPassFunction ground_pass =
      rd::groundPassFunction(wide_vectors_allowed.load(std::memory_order_relaxed));

  alignas(64) float depth[kTilePixels];
  alignas(64) std::int32_t kind[kTilePixels];
  alignas(64) std::int32_t level[kTilePixels];
  alignas(64) std::int32_t texel_u[kTilePixels], texel_v[kTilePixels];    // top-left texel of the read
  alignas(64) std::int32_t weight_u[kTilePixels], weight_v[kTilePixels];  // 0..255: right column, lower row
  const rd::GroundTile ground{depth, kind, level, texel_u, texel_v, weight_u, weight_v};
  for (size_t tile_index = 0; tile_index < tiles_.size(); ++tile_index) {
    const Tile& tile = tiles_[tile_index];
    const size_t first = tile_index * kTilePixels;
    ground_pass(frame, tile_ray_x_.data() + first, tile_ray_y_.data() + first, tile_ray_z_.data() + first, kTilePixels,
                ground);
    for (int j = 0; j < tile.height; ++j) {
      std::uint8_t* out = image.pixel(tile.u0, tile.v0 + j);
      for (int i = 0; i < tile.width; ++i, out += 3) {
        const int k = j * kTileWidth + i;
        const std::uint32_t c = kind[k] == rd::kTexture ? rd::bilinearTexel(frame, ground, k)
                                : kind[k] == rd::kSky   ? frame.sky_packed
                                                        : frame.ground_packed;
        out[0] = static_cast<std::uint8_t>(c);
        out[1] = static_cast<std::uint8_t>(c >> 8);
        out[2] = static_cast<std::uint8_t>(c >> 16);
      }
    }
    // Objects, nearest hit wins.
    for (const ObjectInView& view : in_view) {
      if (!coneMeetsSphere(tile.cone.axis, tile.cone.half_angle_rad, tile.cone.cos_half, tile.cone.sin_half, view))
        continue;
      for (int j = 0; j < tile.height; ++j) {
        const Vec3* ray = &rays_optical_[static_cast<size_t>(tile.v0 + j) * w + tile.u0];
        std::uint8_t* out = image.pixel(tile.u0, tile.v0 + j);
        for (int i = 0; i < tile.width; ++i, out += 3) {
          const int k = j * kTileWidth + i;
          if (!view.surrounds_camera && !raySphereMayHit(view, ray[i], depth[k])) continue;
          double t = 0.0;
          if (hitObject(view, ray[i], near_m, std::min(far_m, static_cast<double>(depth[k])), t, out))
            depth[k] = static_cast<float>(t);
        }
      }
    }
    // Shade: each pixel that sees a surface (not the sky) in a light region is darkened.
    if (scene.hasLightRegions()) {
      for (int j = 0; j < tile.height; ++j) {
        const Vec3* ray = &rays_optical_[static_cast<size_t>(tile.v0 + j) * w + tile.u0];
        std::uint8_t* out = image.pixel(tile.u0, tile.v0 + j);
        for (int i = 0; i < tile.width; ++i, out += 3) {
          const double t = depth[j * kTileWidth + i];
          if (!(t <= far_m)) continue;
          const Vec3& r = ray[i];
          const Vec3 point(
              camera_world.x +
                  t * (world_R_optical[0][0] * r.x + world_R_optical[0][1] * r.y + world_R_optical[0][2] * r.z),
              camera_world.y +
                  t * (world_R_optical[1][0] * r.x + world_R_optical[1][1] * r.y + world_R_optical[1][2] * r.z),
              camera_world.z +
                  t * (world_R_optical[2][0] * r.x + world_R_optical[2][1] * r.y + world_R_optical[2][2] * r.z));
          const double light = scene.lightAt(point);
          if (light < 1.0)
            for (int c = 0; c < 3; ++c) out[c] = static_cast<std::uint8_t>(std::lround(out[c] * light));
        }
      }
    }
    // Ray parameter t (|ray| = 1) to z-depth: t times the ray's optical z; no hit stays +inf.
    if (depth_out) {
      for (int j = 0; j < tile.height; ++j) {
        const Vec3* ray = &rays_optical_[static_cast<size_t>(tile.v0 + j) * w + tile.u0];
        float* out = &depth_out->depth_m[static_cast<size_t>(tile.v0 + j) * w + tile.u0];
        for (int i = 0; i < tile.width; ++i) {
          const float t = depth[j * kTileWidth + i];
          out[i] = std::isfinite(t) ? static_cast<float>(t * ray[i].z) : std::numeric_limits<float>::infinity();
        }
      }
    }
  }

  for (int pixel : unseen_pixels_) {
    std::memset(&image.data[static_cast<size_t>(pixel) * 3], 0, 3);
    if (depth_out) depth_out->depth_m[static_cast<size_t>(pixel)] = std::numeric_limits<float>::infinity();
  }
  if (model_.noise_stddev > 0.0 && noise_rng) addNoise(model_.noise_stddev, *noise_rng, image);
}

}  // namespace conde_physics
