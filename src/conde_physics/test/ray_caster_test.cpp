// The engine-independent ray caster: exact distances to each shape type, the fan path (one
// origin, azimuth bins) against the per-ray path on random scenes, ignored models, rays that
// start inside a shape, the ground plane.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "conde_physics/physics_engine.h"
#include "conde_physics/ray_caster.h"
#include "test_models.h"

namespace cp = conde_physics;

namespace {

const double kPi = 3.14159265358979323846;

cp::Shape box(double x, double y, double z) {
  cp::Shape s;
  s.type = cp::ShapeType::kBox;
  s.box_size_m = cp::Vec3(x, y, z);
  return s;
}
cp::Shape cylinder(double r, double l) {
  cp::Shape s;
  s.type = cp::ShapeType::kCylinder;
  s.radius_m = r;
  s.length_m = l;
  return s;
}
cp::Shape sphere(double r) {
  cp::Shape s;
  s.type = cp::ShapeType::kSphere;
  s.radius_m = r;
  return s;
}

// One ray through the per-ray path: a second, different origin keeps the call off the fan path.
cp::RayHit castAlone(const cp::RayScene& scene, const cp::RayScene::BodyPoseFn& poses, const cp::Vec3& o,
                     const cp::Vec3& d, double range, int ignore) {
  std::vector<cp::RayHit> hits;
  scene.cast(poses, {o, o + cp::Vec3(0, 0, 1e-3)}, {d, d}, range, ignore, hits);
  return hits[0];
}

const cp::RayScene::BodyPoseFn kNoBodies = [](int, int) { return cp::Pose(); };

TEST(RayCaster, ExactDistanceToEachShape) {
  double t = 0;
  // Box 1 x 2 x 0.5 seen along x from -3: its face at x = -0.5.
  ASSERT_TRUE(cp::RayScene::hitShape(box(1, 2, 0.5), cp::Vec3(-3, 0.3, 0.1), cp::Vec3(1, 0, 0), 10, t));
  EXPECT_DOUBLE_EQ(t, 2.5);
  // Cylinder r 0.2, length 1 (axis z): side from -x, cap from above.
  ASSERT_TRUE(cp::RayScene::hitShape(cylinder(0.2, 1.0), cp::Vec3(-2, 0, 0.3), cp::Vec3(1, 0, 0), 10, t));
  EXPECT_NEAR(t, 1.8, 1e-12);
  ASSERT_TRUE(cp::RayScene::hitShape(cylinder(0.2, 1.0), cp::Vec3(0.1, 0, 2), cp::Vec3(0, 0, -1), 10, t));
  EXPECT_NEAR(t, 1.5, 1e-12);
  // Sphere r 0.5 from (0, 0, -4) up the z axis; a slanted ray at a known tangent misses.
  ASSERT_TRUE(cp::RayScene::hitShape(sphere(0.5), cp::Vec3(0, 0, -4), cp::Vec3(0, 0, 1), 10, t));
  EXPECT_NEAR(t, 3.5, 1e-12);
  EXPECT_FALSE(cp::RayScene::hitShape(sphere(0.5), cp::Vec3(-4, 0.51, 0), cp::Vec3(1, 0, 0), 10, t));
  // Beyond the range: no hit.
  EXPECT_FALSE(cp::RayScene::hitShape(box(1, 1, 1), cp::Vec3(-3, 0, 0), cp::Vec3(1, 0, 0), 2.4, t));
  // A closed cube mesh (12 triangles) gives the box's distance.
  const cp::Shape mesh = conde_physics_test::cubeMesh(0.5);
  const cp::Vec3 d = cp::Vec3(1, 0.1, 0.05).normalized();
  double t_box = 0;
  ASSERT_TRUE(cp::RayScene::hitShape(box(1, 1, 1), cp::Vec3(-3, 0, 0), d, 10, t_box));
  ASSERT_TRUE(cp::RayScene::hitShape(mesh, cp::Vec3(-3, 0, 0), d, 10, t));
  EXPECT_NEAR(t, t_box, 1e-12);
}

TEST(RayCaster, RaysStartingInsideAShapeDoNotSeeIt) {
  double t = 0;
  EXPECT_FALSE(cp::RayScene::hitShape(box(1, 1, 1), cp::Vec3(0.1, 0, 0), cp::Vec3(1, 0, 0), 10, t));
  EXPECT_FALSE(cp::RayScene::hitShape(cylinder(0.5, 1), cp::Vec3(0, 0.1, 0), cp::Vec3(0, 1, 0), 10, t));
  EXPECT_FALSE(cp::RayScene::hitShape(sphere(0.5), cp::Vec3(0, 0, 0.2), cp::Vec3(0, 0, 1), 10, t));
}

TEST(RayCaster, PosedShapesGroundAndIgnoredModels) {
  cp::RayScene scene;
  scene.addGroundPlane();
  scene.addStatic(box(0.1, 4, 1), cp::Pose::fromXyzRpy(3, 0, 0.5, 0, 0, 0));  // a wall, face at x = 2.95
  cp::ArticulatedModel model;
  model.name = "robot";
  model.bodies.resize(1);
  cp::CollisionSpec c;
  c.shape = cylinder(0.1, 0.4);
  c.pose_in_link = cp::Pose::fromXyzRpy(0, 0, 0.2, 0, 0, 0);
  model.bodies[0].collisions.push_back(c);
  scene.addModel(7, model);
  // The model's body stands at (1.5, 0) rotated; its cylinder (radius 0.1) is in the way.
  const cp::RayScene::BodyPoseFn poses = [](int m, int b) {
    EXPECT_EQ(m, 7);
    EXPECT_EQ(b, 0);
    return cp::Pose::fromXyzRpy(1.5, 0, 0, 0, 0, 0.7);
  };
  std::vector<cp::RayHit> hits;
  const cp::Vec3 o(0, 0, 0.2);
  scene.cast(poses, {o, o, o}, {cp::Vec3(1, 0, 0), cp::Vec3(0, 0, -1), cp::Vec3(-1, 0, 0)}, 10, -1, hits);
  ASSERT_EQ(hits.size(), 3u);
  EXPECT_TRUE(hits[0].hit);
  EXPECT_NEAR(hits[0].distance_m, 1.4, 1e-12);  // the cylinder's side
  EXPECT_TRUE(hits[1].hit);
  EXPECT_NEAR(hits[1].distance_m, 0.2, 1e-12);  // the ground
  EXPECT_FALSE(hits[2].hit);
  EXPECT_EQ(hits[2].distance_m, 10.0);
  scene.cast(poses, {o}, {cp::Vec3(1, 0, 0)}, 10, 7, hits);  // the model ignored: the wall
  EXPECT_TRUE(hits[0].hit);
  EXPECT_NEAR(hits[0].distance_m, 2.95, 1e-12);
  scene.cast(poses, {o}, {cp::Vec3(1, 0, 0)}, 2.0, 7, hits);  // ... beyond the range
  EXPECT_FALSE(hits[0].hit);
  EXPECT_EQ(hits[0].distance_m, 2.0);
}

// The fan path (all rays from one origin, culled by azimuth) gives exactly what testing every
// shape for every ray gives, on random scenes with long walls around and through the origin,
// small objects, tilted shapes and rays with elevation.
TEST(RayCaster, FanMatchesRayByRayOnRandomScenes) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int scene_index = 0; scene_index < 30; ++scene_index) {
    cp::RayScene scene;
    scene.addGroundPlane();
    const double half = 4.0;
    scene.addStatic(box(2 * half, 0.1, 0.5), cp::Pose::fromXyzRpy(0, half, 0.25, 0, 0, 0));
    scene.addStatic(box(2 * half, 0.1, 0.5), cp::Pose::fromXyzRpy(0, -half, 0.25, 0, 0, 0));
    scene.addStatic(box(0.1, 2 * half, 0.5), cp::Pose::fromXyzRpy(half, 0, 0.25, 0, 0, 0));
    scene.addStatic(box(0.1, 2 * half, 0.5), cp::Pose::fromXyzRpy(-half, 0, 0.25, 0, 0, 0));
    for (int k = 0; k < 25; ++k) {
      const cp::Pose pose =
          cp::Pose::fromXyzRpy(3.5 * u(rng), 3.5 * u(rng), 0.3 + 0.3 * u(rng), u(rng), u(rng), kPi * u(rng));
      const int kind = k % 4;
      const cp::Shape s = kind == 0   ? box(0.05 + 0.4 * (1 + u(rng)), 0.05 + 0.2 * (1 + u(rng)), 0.3)
                          : kind == 1 ? cylinder(0.05 + 0.1 * (1 + u(rng)), 0.3)
                          : kind == 2 ? sphere(0.05 + 0.1 * (1 + u(rng)))
                                      : box(3.0, 0.05, 0.4);  // a long wall somewhere inside
      scene.addStatic(s, pose);
    }
    const cp::Vec3 origin(0.5 * u(rng), 0.5 * u(rng), 0.25);
    std::vector<cp::Vec3> origins, dirs;
    const double elevation = scene_index % 3 == 0 ? 0.0 : 0.3 * u(rng);
    for (int i = 0; i < 1081; ++i) {
      const double az = -0.75 * kPi + 1.5 * kPi * i / 1080.0 + scene_index;
      dirs.push_back(cp::Vec3(std::cos(az) * std::cos(elevation + 0.01 * u(rng)), std::sin(az) * std::cos(elevation),
                              std::sin(elevation))
                         .normalized());
      // Half the scenes start their rays 6 cm out, as a LiDAR with a minimum range does.
      origins.push_back(origin + dirs.back() * (scene_index % 2 == 0 ? 0.0 : 0.06));
    }
    std::vector<cp::RayHit> fan;
    scene.cast(kNoBodies, origins, dirs, 10.0, -1, fan);
    int hits = 0;
    for (size_t i = 0; i < dirs.size(); ++i) {
      const cp::RayHit alone = castAlone(scene, kNoBodies, origins[i], dirs[i], 10.0, -1);
      ASSERT_EQ(fan[i].hit, alone.hit) << "scene " << scene_index << " ray " << i;
      ASSERT_DOUBLE_EQ(fan[i].distance_m, alone.distance_m) << "scene " << scene_index << " ray " << i;
      hits += fan[i].hit;
    }
    if (elevation == 0.0) {
      EXPECT_EQ(hits, 1081) << "the walls close the scene";
    } else {
      EXPECT_GT(hits, 0);
    }
  }
}

TEST(RayCaster, EnginesAgreeOnRays) {
  // Both backends answer castRays from the same geometry: identical ranges.
  std::vector<std::vector<cp::RayHit>> results;
  for (const std::string name : {"ode", "bullet"}) {
    auto engine = cp::createPhysicsEngine(name, cp::PhysicsSettings());
    engine->addGroundPlane(cp::SurfaceParams());
    engine->addStaticShape(box(0.2, 3, 1), cp::Pose::fromXyzRpy(2, 0, 0.5, 0, 0, 0.3), cp::SurfaceParams());
    engine->addStaticShape(cylinder(0.3, 1), cp::Pose::fromXyzRpy(-1, 1, 0.5, 0, 0, 0), cp::SurfaceParams());
    std::vector<cp::Vec3> origins, dirs;
    for (int i = 0; i < 360; ++i) {
      origins.push_back(cp::Vec3(0, 0, 0.3));
      dirs.push_back(cp::Vec3(std::cos(i * kPi / 180), std::sin(i * kPi / 180), -0.05).normalized());
    }
    results.emplace_back();
    engine->castRays(origins, dirs, 8.0, -1, results.back());
  }
  for (size_t i = 0; i < results[0].size(); ++i) {
    EXPECT_EQ(results[0][i].hit, results[1][i].hit);
    EXPECT_DOUBLE_EQ(results[0][i].distance_m, results[1][i].distance_m);
  }
}

}  // namespace
