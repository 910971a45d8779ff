#include "conde_physics/mesh_bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace conde_physics {

namespace {

double component(const Vec3& v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }

}  // namespace

MeshBvh::MeshBvh(const std::vector<Vec3>& vertices_m, const std::vector<int>& triangles) {
  if (triangles.size() % 3 != 0) throw std::invalid_argument("MeshBvh: triangle index count is not a multiple of 3");
  for (int index : triangles) {
    if (index < 0 || static_cast<size_t>(index) >= vertices_m.size())
      throw std::invalid_argument("MeshBvh: triangle index out of range");
  }
  const int n = static_cast<int>(triangles.size() / 3);
  std::vector<Vec3> centroids(n);
  normals_.resize(n);
  for (int i = 0; i < n; ++i) {
    const Vec3& a = vertices_m[triangles[3 * i]];
    const Vec3& b = vertices_m[triangles[3 * i + 1]];
    const Vec3& c = vertices_m[triangles[3 * i + 2]];
    centroids[i] = (a + b + c) / 3.0;
    const Vec3 normal = (b - a).cross(c - a);
    const double length = normal.norm();
    normals_[i] = length > 0.0 ? normal / length : Vec3();
  }
  if (!vertices_m.empty()) {
    Vec3 lo = vertices_m[0], hi = lo;
    for (const Vec3& p : vertices_m) {
      lo = Vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
      hi = Vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
    }
    bound_centre_ = (lo + hi) * 0.5;
    for (const Vec3& p : vertices_m) bound_radius_m_ = std::max(bound_radius_m_, (p - bound_centre_).norm());
  }
  if (n == 0) return;
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  nodes_.reserve(2 * n / kLeafTriangles + 2);
  build(order, centroids, vertices_m, triangles, 0, n);
  original_index_ = order;
  triangles_.resize(n);
  for (int i = 0; i < n; ++i) {
    const int k = order[i];
    const Vec3& a = vertices_m[triangles[3 * k]];
    triangles_[i] = {a, vertices_m[triangles[3 * k + 1]] - a, vertices_m[triangles[3 * k + 2]] - a};
  }
}

int MeshBvh::build(std::vector<int>& order, const std::vector<Vec3>& centroids, const std::vector<Vec3>& vertices,
                   const std::vector<int>& triangles, int begin, int end) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Node node;
  for (int k = 0; k < 3; ++k) {
    node.lo[k] = std::numeric_limits<double>::infinity();
    node.hi[k] = -std::numeric_limits<double>::infinity();
  }
  double c_lo[3] = {node.lo[0], node.lo[1], node.lo[2]}, c_hi[3] = {node.hi[0], node.hi[1], node.hi[2]};
  for (int i = begin; i < end; ++i) {
    for (int v = 0; v < 3; ++v) {
      const Vec3& p = vertices[triangles[3 * order[i] + v]];
      for (int k = 0; k < 3; ++k) {
        node.lo[k] = std::min(node.lo[k], component(p, k));
        node.hi[k] = std::max(node.hi[k], component(p, k));
      }
    }
    for (int k = 0; k < 3; ++k) {
      c_lo[k] = std::min(c_lo[k], component(centroids[order[i]], k));
      c_hi[k] = std::max(c_hi[k], component(centroids[order[i]], k));
    }
  }
  if (end - begin <= kLeafTriangles) {
    node.first = begin;
    node.count = end - begin;
    nodes_[index] = node;
    return index;
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k) {
    if (c_hi[k] - c_lo[k] > c_hi[axis] - c_lo[axis]) axis = k;
  }
  const int middle = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end,
                   [&](int a, int b) { return component(centroids[a], axis) < component(centroids[b], axis); });
  nodes_[index] = node;
  build(order, centroids, vertices, triangles, begin, middle);  // left child: index + 1
  const int right = build(order, centroids, vertices, triangles, middle, end);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

bool MeshBvh::intersect(const Vec3& o, const Vec3& d, double t_min, double t_max, double& t, int& triangle) const {
  if (nodes_.empty()) return false;
  const double origin[3] = {o.x, o.y, o.z};
  // A zero component gets a huge finite inverse instead of infinity: (slab - origin) * inv is then
  // 0 rather than NaN for an origin on the slab plane, and no per-slab NaN test is needed.
  auto inverse = [](double v) { return v != 0.0 ? 1.0 / v : std::copysign(1e300, v); };
  const double inv[3] = {inverse(d.x), inverse(d.y), inverse(d.z)};
  double best = t_max;
  int best_triangle = -1;
  // Entry distance of the ray into a node's box, or +inf when it misses within [t_min, best].
  auto enter = [&](const Node& n) {
    double t0 = t_min, t1 = best;
    for (int k = 0; k < 3; ++k) {
      double a = (n.lo[k] - origin[k]) * inv[k], b = (n.hi[k] - origin[k]) * inv[k];
      if (a > b) std::swap(a, b);
      t0 = std::max(t0, a);
      t1 = std::min(t1, b);
      if (t0 > t1) return std::numeric_limits<double>::infinity();
    }
    return t0;
  };
  int stack[64];
  int depth = 0;
  if (enter(nodes_[0]) == std::numeric_limits<double>::infinity()) return false;
  stack[depth++] = 0;
  while (depth > 0) {
    const Node& node = nodes_[stack[--depth]];
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const Triangle& tri = triangles_[i];
        const Vec3 p = d.cross(tri.e2);
        const double det = tri.e1.dot(p);
        if (std::abs(det) < 1e-18) continue;
        const double inv_det = 1.0 / det;
        const Vec3 s = o - tri.a;
        const double u = s.dot(p) * inv_det;
        if (u < 0.0 || u > 1.0) continue;
        const Vec3 q = s.cross(tri.e1);
        const double w = d.dot(q) * inv_det;
        if (w < 0.0 || u + w > 1.0) continue;
        const double ti = tri.e2.dot(q) * inv_det;
        if (ti >= t_min && ti <= best) {
          best = ti;
          best_triangle = i;
        }
      }
      continue;
    }
    const int left = static_cast<int>(&node - nodes_.data()) + 1, right = node.first;
    const double t_left = enter(nodes_[left]), t_right = enter(nodes_[right]);
    const double inf = std::numeric_limits<double>::infinity();
    // Push the farther child first so that the nearer one is searched first.
    if (t_left <= t_right) {
      if (t_right != inf) stack[depth++] = right;
      if (t_left != inf) stack[depth++] = left;
    } else {
      if (t_left != inf) stack[depth++] = left;
      if (t_right != inf) stack[depth++] = right;
    }
  }
  if (best_triangle < 0) return false;
  t = best;
  triangle = original_index_[best_triangle];
  return true;
}

}  // namespace conde_physics
