#include "conde_physics/ray_caster.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "conde_physics/mesh_bvh.h"
#include "conde_physics/physics_engine.h"

namespace conde_physics {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kAzimuthBins = 720;  // half a degree each

// Entry distance of the ray into the axis-aligned box |x| <= half; false if it misses, enters
// beyond t_max, or starts inside.
bool hitBox(const Vec3& half, const Vec3& o, const Vec3& d, double t_max, double& t) {
  const double oc[3] = {o.x, o.y, o.z}, dc[3] = {d.x, d.y, d.z}, hc[3] = {half.x, half.y, half.z};
  double t_enter = -std::numeric_limits<double>::infinity(), t_exit = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (dc[k] == 0.0) {
      if (oc[k] < -hc[k] || oc[k] > hc[k]) return false;
      continue;
    }
    const double inv = 1.0 / dc[k];
    double t0 = (-hc[k] - oc[k]) * inv, t1 = (hc[k] - oc[k]) * inv;
    if (t0 > t1) std::swap(t0, t1);
    t_enter = std::max(t_enter, t0);
    t_exit = std::min(t_exit, t1);
    if (t_enter > t_exit) return false;
  }
  if (t_enter < 0.0 || t_enter > t_max) return false;
  t = t_enter;
  return true;
}

bool hitSphere(double r, const Vec3& o, const Vec3& d, double t_max, double& t) {
  const double b = o.dot(d);
  const double c = o.dot(o) - r * r;
  if (c < 0.0) return false;  // starts inside
  const double disc = b * b - c;
  if (disc < 0.0) return false;
  const double t0 = -b - std::sqrt(disc);
  if (t0 < 0.0 || t0 > t_max) return false;
  t = t0;
  return true;
}

// Cylinder of radius r around local z, |z| <= h.
bool hitCylinder(double r, double h, const Vec3& o, const Vec3& d, double t_max, double& t) {
  if (o.x * o.x + o.y * o.y <= r * r && std::abs(o.z) <= h) return false;  // starts inside
  double best = std::numeric_limits<double>::infinity();
  const double a = d.x * d.x + d.y * d.y;
  if (a > 1e-18) {
    const double b = o.x * d.x + o.y * d.y;
    const double c = o.x * o.x + o.y * o.y - r * r;
    const double disc = b * b - a * c;
    if (disc >= 0.0) {
      const double t0 = (-b - std::sqrt(disc)) / a;
      if (t0 >= 0.0 && std::abs(o.z + t0 * d.z) <= h) best = t0;
    }
  }
  if (d.z != 0.0) {
    for (double zc : {h, -h}) {
      const double tc = (zc - o.z) / d.z;
      if (tc < 0.0 || tc >= best) continue;
      const double x = o.x + tc * d.x, y = o.y + tc * d.y;
      if (x * x + y * y <= r * r) best = tc;
    }
  }
  if (best > t_max) return false;
  t = best;
  return true;
}

// Nearest triangle (both sides) of a mesh, Moeller-Trumbore.
bool hitMesh(const Shape& mesh, const Vec3& o, const Vec3& d, double t_max, double& t) {
  if (mesh.mesh_bvh) {
    int triangle = -1;
    return mesh.mesh_bvh->intersect(o, d, 0.0, t_max, t, triangle);
  }
  double best = t_max;
  bool found = false;
  const auto& v = mesh.mesh_vertices_m;
  for (size_t i = 0; i + 2 < mesh.mesh_triangles.size(); i += 3) {
    const Vec3& a = v[mesh.mesh_triangles[i]];
    const Vec3 e1 = v[mesh.mesh_triangles[i + 1]] - a, e2 = v[mesh.mesh_triangles[i + 2]] - a;
    const Vec3 p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-15) continue;
    const double inv = 1.0 / det;
    const Vec3 s = o - a;
    const double u = s.dot(p) * inv;
    if (u < 0.0 || u > 1.0) continue;
    const Vec3 q = s.cross(e1);
    const double w = d.dot(q) * inv;
    if (w < 0.0 || u + w > 1.0) continue;
    const double ti = e2.dot(q) * inv;
    if (ti >= 0.0 && ti <= best) {
      best = ti;
      found = true;
    }
  }
  if (found) t = best;
  return found;
}

// Bounding sphere of a shape in its own frame.
void boundingSphere(const Shape& s, Vec3& centre, double& radius) {
  centre = Vec3();
  switch (s.type) {
    case ShapeType::kBox:
      radius = 0.5 * s.box_size_m.norm();
      return;
    case ShapeType::kCylinder:
      radius = std::hypot(s.radius_m, 0.5 * s.length_m);
      return;
    case ShapeType::kSphere:
      radius = s.radius_m;
      return;
    case ShapeType::kMesh: {
      if (s.mesh_vertices_m.empty()) {
        radius = 0.0;
        return;
      }
      Vec3 lo = s.mesh_vertices_m[0], hi = lo;
      for (const Vec3& p : s.mesh_vertices_m) {
        lo = Vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
        hi = Vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
      }
      centre = (lo + hi) * 0.5;
      radius = 0.0;
      for (const Vec3& p : s.mesh_vertices_m) radius = std::max(radius, (p - centre).norm());
      return;
    }
  }
  radius = 0.0;
}

// A cheap stand-in for the azimuth atan2(y, x): in [0, 4), increasing with the azimuth from
// -pi (0) through -pi/2 (1), 0 (2), pi/2 (3) to pi (4), exact at those points; the bins of the
// fan are uniform in it.
double pseudoAzimuth(double x, double y) {
  const double sum = std::abs(x) + std::abs(y);
  if (sum == 0.0) return 2.0;
  const double p = y / sum;  // -1 .. 1 on each half
  return x >= 0.0 ? 2.0 + p : (y >= 0.0 ? 4.0 - p : -p);
}

// Whether every ray starts at apex + s directions[i] for one apex and one s >= 0 (a fan).
bool findApex(const std::vector<Vec3>& origins, const std::vector<Vec3>& directions, Vec3& apex, double& s) {
  s = 0.0;
  apex = origins[0];
  size_t other = 1;
  while (other < origins.size() && (directions[other] - directions[0]).norm() < 1e-6) ++other;
  if (other < origins.size()) {
    const Vec3 dd = directions[0] - directions[other];
    s = (origins[0] - origins[other]).dot(dd) / dd.dot(dd);
    apex = origins[0] - directions[0] * s;
  }
  if (!(s >= 0.0)) return false;
  for (size_t i = 0; i < origins.size(); ++i) {
    const Vec3 e = origins[i] - directions[i] * s - apex;
    if (e.dot(e) > 1e-18) return false;
  }
  return true;
}

int azimuthBin(double pseudo) {
  const int bin = static_cast<int>(pseudo * (kAzimuthBins / 4.0));
  return std::min(std::max(bin, 0), kAzimuthBins - 1);
}

int azimuthBinOfAngle(double azimuth_rad) {
  return azimuthBin(pseudoAzimuth(std::cos(azimuth_rad), std::sin(azimuth_rad)));
}

// Half-width [rad] of the azimuth interval around `centre_rad` that a box covers seen from the
// origin (its eight corners relative to the origin given), or a negative number when the origin
// is inside the box's vertical prism or the interval is not narrower than the bounding sphere's.
double boxAzimuthHalfWidth(const Vec3 corners[8], double centre_rad) {
  const double c = std::cos(centre_rad), s = std::sin(centre_rad);
  double widest = 0.0;
  for (int k = 0; k < 8; ++k) {
    const Vec3& p = corners[k];
    const double along = c * p.x + s * p.y, across = -s * p.x + c * p.y;
    if (along <= 0.0) return -1.0;  // a corner beside or behind the origin: no narrow interval
    widest = std::max(widest, std::abs(std::atan2(across, along)));
  }
  return widest;
}

}  // namespace

bool RayScene::hitShape(const Shape& shape, const Vec3& o, const Vec3& d, double t_max, double& t) {
  switch (shape.type) {
    case ShapeType::kBox:
      return hitBox(shape.box_size_m * 0.5, o, d, t_max, t);
    case ShapeType::kSphere:
      return hitSphere(shape.radius_m, o, d, t_max, t);
    case ShapeType::kCylinder:
      return hitCylinder(shape.radius_m, 0.5 * shape.length_m, o, d, t_max, t);
    case ShapeType::kMesh:
      return hitMesh(shape, o, d, t_max, t);
  }
  return false;
}

void RayScene::addPrimitive(const Shape& shape, const Pose& pose, int model, int body) {
  shapes_.push_back(std::make_unique<Shape>(shape));
  if (shape.type == ShapeType::kMesh && !shape.mesh_bvh && !shape.mesh_triangles.empty())
    shapes_.back()->mesh_bvh = std::make_shared<const MeshBvh>(shape.mesh_vertices_m, shape.mesh_triangles);
  Primitive p;
  p.shape = shapes_.back().get();
  p.pose = pose;
  p.model = model;
  p.body = body;
  boundingSphere(shape, p.centre_local, p.radius_m);
  if (p.radius_m > 0.0) primitives_.push_back(p);
}

void RayScene::addStatic(const Shape& shape, const Pose& world_pose) { addPrimitive(shape, world_pose, -1, -1); }

void RayScene::addModel(int model_id, const ArticulatedModel& model) {
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    for (const CollisionSpec& c : model.bodies[b].collisions)
      addPrimitive(c.shape, c.pose_in_link, model_id, static_cast<int>(b));
  }
}

void RayScene::removeModel(int model_id) {
  // The shapes stay owned by shapes_ (a few per model, freed with the scene).
  primitives_.erase(std::remove_if(primitives_.begin(), primitives_.end(),
                                   [model_id](const Primitive& p) { return p.model == model_id; }),
                    primitives_.end());
}

void RayScene::testPlaced(const Placed& p, const Vec3& origin, const Vec3& direction, RayHit& hit) const {
  // Bounding sphere first, then the exact test in the shape's frame.
  const Vec3 v = p.centre - origin;
  const double r = p.primitive->radius_m;
  const double along = v.dot(direction);
  if (along < -r || along - r > hit.distance_m) return;
  if (v.dot(v) - along * along > r * r) return;
  const Vec3 rel = origin - p.position;
  const double(*m)[3] = p.world_R_local;
  const Vec3 o(m[0][0] * rel.x + m[1][0] * rel.y + m[2][0] * rel.z, m[0][1] * rel.x + m[1][1] * rel.y + m[2][1] * rel.z,
               m[0][2] * rel.x + m[1][2] * rel.y + m[2][2] * rel.z);
  const Vec3 d(m[0][0] * direction.x + m[1][0] * direction.y + m[2][0] * direction.z,
               m[0][1] * direction.x + m[1][1] * direction.y + m[2][1] * direction.z,
               m[0][2] * direction.x + m[1][2] * direction.y + m[2][2] * direction.z);
  double t = 0.0;
  if (hitShape(*p.primitive->shape, o, d, hit.distance_m, t)) {
    hit.hit = true;
    hit.distance_m = t;
  }
}

void RayScene::cast(const BodyPoseFn& body_pose, const std::vector<Vec3>& origins, const std::vector<Vec3>& directions,
                    double max_range_m, int ignore_model, std::vector<RayHit>& hits) const {
  hits.assign(origins.size(), RayHit{false, std::max(0.0, max_range_m)});
  if (!(max_range_m > 0.0) || origins.empty()) return;

  // The ground plane z = 0, from either side.
  if (ground_plane_) {
    for (size_t i = 0; i < origins.size(); ++i) {
      const double oz = origins[i].z, dz = directions[i].z;
      if (dz == 0.0 || oz == 0.0 || (oz > 0.0) == (dz > 0.0)) continue;
      const double t = -oz / dz;
      if (t <= hits[i].distance_m) hits[i] = RayHit{true, t};
    }
  }

  // Every shape at its pose now (one body pose per body and call).
  thread_local std::vector<Placed> placed;
  placed.clear();
  int cached_model = -2, cached_body = -2;
  Pose cached_pose;
  for (const Primitive& p : primitives_) {
    if (p.model >= 0 && p.model == ignore_model) continue;
    Pose world;
    if (p.model < 0) {
      world = p.pose;
    } else {
      if (p.model != cached_model || p.body != cached_body) {
        cached_pose = body_pose(p.model, p.body);
        cached_model = p.model;
        cached_body = p.body;
      }
      world = cached_pose * p.pose;
    }
    Placed q;
    q.primitive = &p;
    q.position = world.position;
    world.orientation.toMatrix(q.world_R_local);
    q.centre = world * p.centre_local;
    placed.push_back(q);
  }
  if (placed.empty()) return;

  Vec3 apex;
  double apex_to_start_m = 0.0;
  if (!findApex(origins, directions, apex, apex_to_start_m)) {
    for (size_t i = 0; i < origins.size(); ++i)
      for (const Placed& p : placed) testPlaced(p, origins[i], directions[i], hits[i]);
    return;
  }

  // A fan: every ray starts on the line from one apex along its direction (at the same distance
  // from it, e.g. a LiDAR's minimum range). Rays are sorted into azimuth bins; a shape whose
  // bounding sphere is rho > r away horizontally from the apex covers azimuths within
  // asin(r / rho) of its centre's, whatever the rays' elevation, so only the rays of those bins
  // are tested against it.
  thread_local std::vector<int> bin_start, order;
  bin_start.assign(kAzimuthBins + 1, 0);
  order.resize(origins.size());
  thread_local std::vector<int> ray_bin;
  ray_bin.resize(origins.size());
  for (size_t i = 0; i < origins.size(); ++i) {
    ray_bin[i] = azimuthBin(pseudoAzimuth(directions[i].x, directions[i].y));
    ++bin_start[ray_bin[i] + 1];
  }
  for (int b = 0; b < kAzimuthBins; ++b) bin_start[b + 1] += bin_start[b];
  {
    thread_local std::vector<int> fill;
    fill.assign(bin_start.begin(), bin_start.end() - 1);
    for (size_t i = 0; i < origins.size(); ++i) order[fill[ray_bin[i]]++] = static_cast<int>(i);
  }
  // The steepest ray: a shape entirely above or below every ray's height at its horizontal
  // distance is out of reach (a planar LiDAR sees only what spans its height).
  double max_slope = 0.0;
  for (const Vec3& d : directions) {
    const double horizontal = std::hypot(d.x, d.y);
    max_slope = horizontal > 1e-9 ? std::max(max_slope, std::abs(d.z) / horizontal) : HUGE_VAL;
  }
  const double margin_rad = 1e-6;  // bins are exact in the pseudo-azimuth; this covers rounding
  for (const Placed& p : placed) {
    const Vec3 v = p.centre - apex;
    const double r = p.primitive->radius_m;
    if (v.norm() - r > apex_to_start_m + max_range_m) continue;
    const double rho = std::hypot(v.x, v.y);
    if (max_slope < HUGE_VAL) {
      double z_half = r;  // half the shape's vertical extent
      if (p.primitive->shape->type == ShapeType::kBox) {
        const Vec3& size = p.primitive->shape->box_size_m;
        const double(*m)[3] = p.world_R_local;
        z_half = 0.5 * (std::abs(m[2][0]) * size.x + std::abs(m[2][1]) * size.y + std::abs(m[2][2]) * size.z);
      }
      const double reach = max_slope * (rho + r) + 1e-9;
      if (v.z - z_half > reach || v.z + z_half < -reach) continue;
    }
    // Half-width of the azimuth interval the shape covers, or < 0: every azimuth.
    const double centre = std::atan2(v.y, v.x);
    double half = rho > r ? std::asin(r / rho) : -1.0;
    if (p.primitive->shape->type == ShapeType::kBox) {  // long walls: their corners bound tighter
      const Vec3 h = p.primitive->shape->box_size_m * 0.5;
      const double(*m)[3] = p.world_R_local;
      Vec3 corners[8];
      for (int k = 0; k < 8; ++k) {
        const double lx = (k & 1) ? h.x : -h.x, ly = (k & 2) ? h.y : -h.y, lz = (k & 4) ? h.z : -h.z;
        corners[k] = Vec3(m[0][0] * lx + m[0][1] * ly + m[0][2] * lz, m[1][0] * lx + m[1][1] * ly + m[1][2] * lz,
                          m[2][0] * lx + m[2][1] * ly + m[2][2] * lz) +
                     (p.position - apex);
      }
      const double box_half = boxAzimuthHalfWidth(corners, centre);
      if (box_half >= 0.0) half = half < 0.0 ? box_half : std::min(half, box_half);
    }
    int first = 0, last = kAzimuthBins - 1;  // bins to test, inclusive (may wrap)
    if (half >= 0.0) {
      first = azimuthBinOfAngle(std::remainder(centre - half - margin_rad, 2.0 * kPi));
      last = azimuthBinOfAngle(std::remainder(centre + half + margin_rad, 2.0 * kPi));
    }
    auto test_bins = [&](int b0, int b1) {
      for (int k = bin_start[b0]; k < bin_start[b1 + 1]; ++k) {
        const int i = order[k];
        testPlaced(p, origins[i], directions[i], hits[i]);
      }
    };
    if (first <= last) {
      test_bins(first, last);
    } else {  // wraps through +-pi
      test_bins(first, kAzimuthBins - 1);
      test_bins(0, last);
    }
  }
}

}  // namespace conde_physics
