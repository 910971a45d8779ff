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
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace conde_physics {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kNoHit = std::numeric_limits<float>::infinity();
std::atomic<bool> wide_vectors_allowed{true};  // CameraRenderer::allowWideVectors

// Four lanes of floats / ints (GCC and Clang vector extensions: one SSE2 register on plain
// x86-64, NEON on ARM; wider vectors get split badly without AVX). Comparisons give Ints masks,
// -1 for true. Where the CPU has AVX2 (checked at run time), the ground pass runs on eight
// lanes instead; its helpers are always inlined, so no 32-byte vector crosses a call without
// AVX (which is what -Wpsabi warns about).
#pragma GCC diagnostic ignored "-Wpsabi"
typedef float Floats __attribute__((vector_size(16)));
typedef std::int32_t Ints __attribute__((vector_size(16)));
typedef float Floats8 __attribute__((vector_size(32)));
typedef std::int32_t Ints8 __attribute__((vector_size(32)));
template <typename V, typename T>
__attribute__((always_inline)) inline V loadLanes(const T* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <typename V, typename T>
__attribute__((always_inline)) inline void storeLanes(T* p, const V& v) {
  std::memcpy(p, &v, sizeof v);
}

// Object lighting: ambient plus Lambert diffuse from a fixed sun above (tilted so that the sides
// of a box differ). The ground and face images are drawn with their own colours.
constexpr double kAmbient = 0.4;
constexpr double kDiffuse = 0.6;
Vec3 toSunWorld() { return Vec3(0.3, 0.4, 1.0).normalized(); }

std::string text(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

std::uint8_t toByte(double unit_value) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(unit_value, 0.0, 1.0) * 255.0));
}

void checkImage(const RgbImage& image, const std::string& what) {
  if (image.width < 0 || image.height < 0 || image.data.size() != static_cast<size_t>(image.width) * image.height * 3)
    throw std::invalid_argument(what + ": image data size " + std::to_string(image.data.size()) + " does not match " +
                                std::to_string(image.width) + "x" + std::to_string(image.height) + " RGB");
}

void checkImageSize(int width_px, int height_px) {
  if (width_px <= 0 || height_px <= 0)
    throw std::invalid_argument("camera image size must be positive (got " + std::to_string(width_px) + "x" +
                                std::to_string(height_px) + ")");
}

void checkIndex(int index, int count) {
  if (index < 0 || index >= count)
    throw std::out_of_range("render object index " + std::to_string(index) + " out of range (the scene has " +
                            std::to_string(count) + " objects)");
}

// --- Lens --------------------------------------------------------------------------------------

// plumb_bob: normalised undistorted (x, y) -> normalised distorted (xd, yd), and its Jacobian.
void distort(const LensDistortion& d, double x, double y, double& xd, double& yd) {
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  xd = x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x);
  yd = y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y;
}

void distortionJacobian(const LensDistortion& d, double x, double y, double j[2][2]) {
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  const double g = d.k1 + r2 * (2.0 * d.k2 + 3.0 * d.k3 * r2);  // d(radial)/d(r2)
  j[0][0] = radial + 2.0 * x * x * g + 2.0 * d.p1 * y + 6.0 * d.p2 * x;
  j[0][1] = 2.0 * x * y * g + 2.0 * d.p1 * x + 2.0 * d.p2 * y;
  j[1][0] = 2.0 * x * y * g + 2.0 * d.p1 * x + 2.0 * d.p2 * y;
  j[1][1] = radial + 2.0 * y * y * g + 6.0 * d.p1 * y + 2.0 * d.p2 * x;
}

// Inverts the distortion by damped Newton steps from (xd, yd). False when it does not converge
// or lands where the lens model folds over (Jacobian not positive), i.e. no unique ray exists.
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
  }
  return 0.0;
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
  }
  return false;
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

// --- Camera model ------------------------------------------------------------------------------

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

void RenderScene::setObjectImage(int index, const RgbImage& image) {
  checkIndex(index, objectCount());
  if (objects_[index].shape != RenderShape::kBox)
    throw std::invalid_argument("render object " + std::to_string(index) + ": only boxes show a face image");
  checkImage(image, "render object " + std::to_string(index) + " face image");
  objects_[index].face_image = image;
}

RenderScene renderSceneFromWorld(const WorldDescription& world) {
  RenderScene scene;
  const GroundSpec& g = world.ground;
  if (g.texture_path.empty()) {
    scene.setGroundColor(g.color_rgb);
  } else {
    scene.setGround(loadRgbImage(g.texture_path), g.x_min_m, g.x_max_m, g.y_min_m, g.y_max_m, g.color_rgb);
  }
  for (const WorldObject& w : world.objects) {
    RenderObject o;
    switch (w.shape) {
      case ObjectShape::kBox:
        o.shape = RenderShape::kBox;
        break;
      case ObjectShape::kCylinder:
        o.shape = RenderShape::kCylinder;
        break;
      case ObjectShape::kCone:
        o.shape = RenderShape::kCone;
        break;
      case ObjectShape::kSphere:
        o.shape = RenderShape::kSphere;
        break;
    }
    o.size_m = w.size_m;
    o.radius_m = w.radius_m;
    o.length_m = w.length_m;
    o.pose = w.pose;
    o.color_rgb = w.color_rgb;
    if (!w.texture_path.empty()) o.face_image = loadRgbImage(w.texture_path);
    scene.addObject(o);
  }
  return scene;
}

// --- Renderer ----------------------------------------------------------------------------------

void CameraRenderer::allowWideVectors(bool allowed) { wide_vectors_allowed.store(allowed); }

CameraRenderer::CameraRenderer(const CameraModel& model) : model_(model) {
  const int w = model.width_px, h = model.height_px;
  checkImageSize(w, h);
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
      if (!lens.isZero() && !undistort(lens, x, y, x, y))
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

namespace {

// What a ray sees of the ground: nothing (sky), the plain ground, or the texture.
constexpr std::int32_t kSky = 0, kPlainGround = 1, kTexture = 2;

// The per-frame numbers of the ground pass (see render()).
struct GroundFrame {
  float rot[3][3];  // world_R_optical
  float camera_height = 0.0f, near = 0.0f, far = 0.0f;
  float u_at_camera = 0.0f, v_at_camera = 0.0f, tex_u_per_m = 0.0f, tex_v_per_m = 0.0f;
  float u_limit = 0.0f, v_limit = 0.0f, footprint_area_scale = 0.0f;
  std::int32_t max_level = 0;
  // The texture: packed texels (R in the low byte, then G, B), its mipmap levels,
  // and the packed colours of the plain ground and the sky.
  const std::uint32_t* texels = nullptr;
  const RenderScene::TextureLevel* levels = nullptr;
  std::uint32_t ground_packed = 0, sky_packed = 0;
};

// Per pixel of a tile: depth of the ground hit, kind, mipmap level, top-left texel and 8-bit
// bilinear weights.
struct GroundTile {
  float* depth;
  std::int32_t *kind, *level, *texel_u, *texel_v, *weight_u, *weight_v;
};

// Bilinear read of one pixel's texels: red and blue, then green, in 16-bit lanes of one word.
inline std::uint32_t bilinearTexel(const GroundFrame& g, const GroundTile& t, int k) {
  const RenderScene::TextureLevel& level = g.levels[t.level[k]];
  const int stride = level.width_px + 1;
  const std::uint32_t* p = g.texels + level.first_texel + static_cast<size_t>(t.texel_v[k]) * stride + t.texel_u[k];
  const std::uint32_t wu = static_cast<std::uint32_t>(t.weight_u[k]), wv = static_cast<std::uint32_t>(t.weight_v[k]);
  const std::uint32_t p00 = p[0], p01 = p[1], p10 = p[stride], p11 = p[stride + 1];
  constexpr std::uint32_t kPair = 0x00FF00FFu;
  const std::uint32_t rb_top = (((p00 & kPair) * (256 - wu) + (p01 & kPair) * wu) >> 8) & kPair;
  const std::uint32_t rb_bottom = (((p10 & kPair) * (256 - wu) + (p11 & kPair) * wu) >> 8) & kPair;
  const std::uint32_t g_top = ((((p00 >> 8) & kPair) * (256 - wu) + ((p01 >> 8) & kPair) * wu) >> 8) & kPair;
  const std::uint32_t g_bottom = ((((p10 >> 8) & kPair) * (256 - wu) + ((p11 >> 8) & kPair) * wu) >> 8) & kPair;
  const std::uint32_t rb = ((rb_top * (256 - wv) + rb_bottom * wv) >> 8) & kPair;
  const std::uint32_t gg = ((g_top * (256 - wv) + g_bottom * wv) >> 8) & kPair;
  return rb | (gg << 8);
}

// Ground hit of `count` rays (a multiple of the lane count) and their texel addresses, one
// vector of lanes at a time.
template <typename F, typename I>
__attribute__((always_inline)) inline void groundPass(const GroundFrame& g, const float* __restrict rx,
                                                      const float* __restrict ry, const float* __restrict rz, int count,
                                                      const GroundTile& out) {
  constexpr int kWidth = sizeof(F) / sizeof(float);
  for (int i = 0; i < count; i += kWidth) {
    const F x = loadLanes<F>(rx + i), y = loadLanes<F>(ry + i), z = loadLanes<F>(rz + i);
    const F dx = g.rot[0][0] * x + g.rot[0][1] * y + g.rot[0][2] * z;
    const F dy = g.rot[1][0] * x + g.rot[1][1] * y + g.rot[1][2] * z;
    const F dz = g.rot[2][0] * x + g.rot[2][1] * y + g.rot[2][2] * z;
    const F down = -1.0f / dz;  // > 0 for rays that go down
    const F t = g.camera_height * down;
    const I hit = (dz < 0.0f) & (t >= g.near) & (t <= g.far);
    const F u = g.u_at_camera + t * dx * g.tex_u_per_m;
    const F v = g.v_at_camera - t * dy * g.tex_v_per_m;
    const I on_texture = (u >= -0.5f) & (u <= g.u_limit) & (v >= -0.5f) & (v <= g.v_limit);
    // Mipmap level from the exponent bits of 2 rho^2, and 2^-level the same way. (Lanes
    // without a ground hit may hold inf or NaN here; their kind is kSky.)
    const F area2 = g.footprint_area_scale * (down * down * down);
    I l = ((reinterpret_cast<const I&>(area2) >> 23) - 127) >> 1;
    l = l < 0 ? 0 : l;
    l = l > g.max_level ? g.max_level : l;
    const I scale_bits = (127 - l) << 23;
    const F scale = reinterpret_cast<const F&>(scale_bits);
    const F uc = u > g.u_limit ? g.u_limit : (u < -0.5f ? -0.5f : u);
    const F vc = v > g.v_limit ? g.v_limit : (v < -0.5f ? -0.5f : v);
    F ul = (uc + 0.5f) * scale - 0.5f;
    F vl = (vc + 0.5f) * scale - 0.5f;
    ul = ul < 0.0f ? 0.0f : ul;
    vl = vl < 0.0f ? 0.0f : vl;
    const I iu = __builtin_convertvector(ul, I), iv = __builtin_convertvector(vl, I);
    storeLanes(out.depth + i, F(hit ? t : kNoHit));
    storeLanes(out.kind + i, I(hit & (on_texture ? kTexture : kPlainGround)));
    storeLanes(out.level + i, l);
    storeLanes(out.texel_u + i, iu);
    storeLanes(out.texel_v + i, iv);
    storeLanes(out.weight_u + i, __builtin_convertvector((ul - __builtin_convertvector(iu, F)) * 256.0f, I));
    storeLanes(out.weight_v + i, __builtin_convertvector((vl - __builtin_convertvector(iv, F)) * 256.0f, I));
  }
}

void groundPass4(const GroundFrame& g, const float* rx, const float* ry, const float* rz, int count,
                 const GroundTile& out) {
  groundPass<Floats, Ints>(g, rx, ry, rz, count, out);
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same on eight lanes. (The bilinear read stays scalar, in render(): AVX2 gathers made it
// slower on this machine.)
__attribute__((target("avx2"))) void groundPass8(const GroundFrame& g, const float* rx, const float* ry,
                                                 const float* rz, int count, const GroundTile& out) {
  groundPass<Floats8, Ints8>(g, rx, ry, rz, count, out);
}
#endif

using GroundPassFunction = void (*)(const GroundFrame&, const float*, const float*, const float*, int,
                                    const GroundTile&);

bool haveAvx2() {
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool have = __builtin_cpu_supports("avx2");
  return have;
#else
  return false;
#endif
}

GroundPassFunction groundPassFunction() {
#if defined(__x86_64__) && defined(__GNUC__)
  if (haveAvx2() && wide_vectors_allowed.load(std::memory_order_relaxed)) return groundPass8;
#endif
  return groundPass4;
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

bool CameraRenderer::wideVectorsAvailable() { return haveAvx2(); }

void CameraRenderer::render(const RenderScene& scene, const Pose& world_T_optical, int exclude_group,
                            std::mt19937* noise_rng, RgbImage& image) const {
  const int w = model_.width_px, h = model_.height_px;
  if (image.width != w || image.height != h || image.data.size() != static_cast<size_t>(w) * h * 3) image.resize(w, h);
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
    if (exclude_group != -1 && object.group == exclude_group) continue;
    const Vec3 offset_world = object.pose.position - camera_world;
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
    if (!view.surrounds_camera) {
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
  GroundFrame frame;
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
  const GroundPassFunction ground_pass = groundPassFunction();

  alignas(64) float depth[kTilePixels];
  alignas(64) std::int32_t kind[kTilePixels];
  alignas(64) std::int32_t level[kTilePixels];
  alignas(64) std::int32_t texel_u[kTilePixels], texel_v[kTilePixels];    // top-left texel of the read
  alignas(64) std::int32_t weight_u[kTilePixels], weight_v[kTilePixels];  // 0..255: right column, lower row
  const GroundTile ground{depth, kind, level, texel_u, texel_v, weight_u, weight_v};
  for (size_t tile_index = 0; tile_index < tiles_.size(); ++tile_index) {
    const Tile& tile = tiles_[tile_index];
    const size_t first = tile_index * kTilePixels;
    ground_pass(frame, tile_ray_x_.data() + first, tile_ray_y_.data() + first, tile_ray_z_.data() + first, kTilePixels,
                ground);
    for (int j = 0; j < tile.height; ++j) {
      std::uint8_t* out = image.pixel(tile.u0, tile.v0 + j);
      for (int i = 0; i < tile.width; ++i, out += 3) {
        const int k = j * kTileWidth + i;
        const std::uint32_t c = kind[k] == kTexture ? bilinearTexel(frame, ground, k)
                                : kind[k] == kSky   ? frame.sky_packed
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
          double t = 0.0;
          if (hitObject(view, ray[i], near_m, std::min(far_m, static_cast<double>(depth[k])), t, out))
            depth[k] = static_cast<float>(t);
        }
      }
    }
  }

  for (int pixel : unseen_pixels_) std::memset(&image.data[static_cast<size_t>(pixel) * 3], 0, 3);
  if (model_.noise_stddev > 0.0 && noise_rng) addNoise(model_.noise_stddev, *noise_rng, image);
}

}  // namespace conde_physics
