// Ray casts against the collision shapes of a world, exact and engine-independent.
//
// Both physics backends register their shapes here (the ground plane, static shapes, every
// body's collisions) and answer PhysicsEngine::castRays with it: the rays see exactly the
// geometry of the URDF and the world file (boxes, cylinders, spheres, triangle meshes, the plane
// z = 0), whatever each engine does to it for contacts (Bullet rounds its tyres), and both
// engines give the same ranges for the same poses.
//
// Speed: a LiDAR scan is a fan of rays from one origin. For such a call every shape is culled by
// its bounding sphere once (too far, or outside the azimuth interval it covers) and tested exactly
// only against the rays whose azimuth falls into that interval; rays from different origins are
// tested shape by shape behind a bounding-sphere check.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "conde_physics/math.h"
#include "conde_physics/model.h"

namespace conde_physics {

struct RayHit;

class RayScene {
 public:
  using BodyPoseFn = std::function<Pose(int model, int body)>;

  void addGroundPlane() { ground_plane_ = true; }
  void addStatic(const Shape& shape, const Pose& world_pose);
  // Every collision of every body of `model`, which the engine knows as `model_id`.
  void addModel(int model_id, const ArticulatedModel& model);
  // Forgets every shape of that model.
  void removeModel(int model_id);

  // hits[i]: the nearest surface along origins[i] + t directions[i] (unit) for t in
  // [0, max_range_m]; a ray that starts inside a shape does not see that shape. Shapes of
  // `ignore_model` are skipped (-1 skips none). Body poses come from `body_pose`.
  void cast(const BodyPoseFn& body_pose, const std::vector<Vec3>& origins, const std::vector<Vec3>& directions,
            double max_range_m, int ignore_model, std::vector<RayHit>& hits) const;

  // The exact test of one shape in its local frame (origin o, unit direction d): the entry
  // distance t in [0, t_max], if any. Exposed for the tests.
  static bool hitShape(const Shape& shape, const Vec3& o, const Vec3& d, double t_max, double& t);

 private:
  struct Primitive {
    const Shape* shape;  // owned by shapes_
    Pose pose;           // static: world pose; dynamic: pose in the body's link frame
    int model = -1;      // -1: static
    int body = -1;
    Vec3 centre_local;    // bounding sphere centre in the shape's frame
    double radius_m = 0;  // bounding sphere radius
  };
  struct Placed {  // a primitive at its world pose for one cast
    const Primitive* primitive;
    Vec3 position;
    double world_R_local[3][3];
    Vec3 centre;
  };

  void addPrimitive(const Shape& shape, const Pose& pose, int model, int body);
  void testPlaced(const Placed& p, const Vec3& origin, const Vec3& direction, RayHit& hit) const;

  bool ground_plane_ = false;
  std::vector<std::unique_ptr<Shape>> shapes_;
  std::vector<Primitive> primitives_;
};

}  // namespace conde_physics
