// SDF worlds (libsdformat) and meshes (assimp): conversion, both engines, laser and camera.
// Fixtures: test/data/sdf (shapes.world includes models/mesh_block; meshes from make_meshes.py).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <string>

#include "conde_physics/camera_renderer.h"
#include "conde_physics/mesh_bvh.h"
#include "conde_physics/mesh_file.h"
#include "conde_physics/physics_engine.h"
#include "conde_physics/ray_caster.h"
#include "conde_physics/render_scene.h"
#include "conde_physics/sdf_world.h"
#include "conde_physics/urdf_model.h"
#include "conde_physics/world_file.h"
#include "test_models.h"

namespace cp = conde_physics;
using conde_physics_test::lookAt;

namespace {

const std::string kDir = CONDE_SDF_TEST_DIR;

cp::WorldDescription shapesWorld() { return cp::loadWorldFile(kDir + "/shapes.world", nullptr); }

const cp::WorldObject& find(const cp::WorldDescription& world, const std::string& name) {
  for (const cp::WorldObject& o : world.objects) {
    if (o.name == name) return o;
  }
  throw std::runtime_error("no object " + name);
}

std::string errorOf(const std::string& file) {
  try {
    cp::loadWorldFile(kDir + "/" + file, nullptr);
  } catch (const cp::WorldFileError& e) {
    return e.what();
  }
  return "(no error)";
}

// The engine with the world in it, as conde_sim's Simulation builds it.
struct EngineWorld {
  std::unique_ptr<cp::PhysicsEngine> engine;
  std::map<std::string, cp::ModelId> dynamic;
};

EngineWorld build(const std::string& engine_name, const cp::WorldDescription& world) {
  EngineWorld w;
  w.engine = cp::createPhysicsEngine(engine_name, world.physics);
  w.engine->addGroundPlane(world.ground.friction);
  for (const cp::WorldObject& o : world.objects) {
    if (!o.collision) continue;
    if (o.is_static) {
      w.engine->addStaticShape(cp::collisionShapeOf(o), o.pose, o.friction);
    } else {
      w.dynamic[o.name] = w.engine->addModel(cp::modelOfDynamicObject(o), o.pose);
    }
  }
  return w;
}

double castOne(const cp::PhysicsEngine& engine, const cp::Vec3& origin, const cp::Vec3& direction) {
  std::vector<cp::RayHit> hits;
  engine.castRays({origin}, {direction.normalized()}, 10.0, -1, hits);
  return hits[0].hit ? hits[0].distance_m : -1.0;
}

}  // namespace

TEST(SdfWorld, ConvertsIntoTheWorldDescription) {
  const cp::WorldDescription w = shapesWorld();
  EXPECT_EQ(w.name, "sdf_shapes");
  EXPECT_DOUBLE_EQ(w.physics.step_s, 0.002);
  EXPECT_DOUBLE_EQ(w.physics.gravity_mps2.z, -9.8);
  ASSERT_TRUE(w.real_time_factor.has_value());
  EXPECT_DOUBLE_EQ(*w.real_time_factor, 0.0);
  EXPECT_NEAR(w.ground.color_rgb.x, 0.5, 1e-9);  // the ground_plane model's visual
  ASSERT_EQ(w.objects.size(), 11u);

  // The included model (model://mesh_block), its STL mesh, collision and visual apart.
  const cp::WorldObject& block = find(w, "mesh_block__link__collision");
  EXPECT_EQ(block.shape, cp::ObjectShape::kMesh);
  EXPECT_TRUE(block.is_static);
  EXPECT_TRUE(block.collision);
  EXPECT_FALSE(block.visible);
  EXPECT_NEAR(block.pose.position.x, 2.0, 1e-12);
  ASSERT_TRUE(block.mesh);
  EXPECT_EQ(block.mesh->triangles.size(), 36u);
  const cp::WorldObject& block_visual = find(w, "mesh_block__link__visual");
  EXPECT_FALSE(block_visual.collision);
  EXPECT_TRUE(block_visual.visible);
  EXPECT_NEAR(block_visual.color_rgb.y, 1.0, 1e-6);  // <diffuse> over <ambient>
  EXPECT_NEAR(block_visual.color_rgb.x, 0.0, 1e-6);

  // Collada: z-up, red material per triangle.
  const cp::WorldObject& red = find(w, "tall_red__link__visual");
  ASSERT_TRUE(red.mesh);
  ASSERT_EQ(red.mesh->triangle_rgb.size(), 12u);
  EXPECT_NEAR(red.mesh->triangle_rgb[0].x, 1.0, 1e-6);
  EXPECT_NEAR(red.mesh->triangle_rgb[0].y, 0.0, 1e-6);
  EXPECT_NEAR(red.mesh_bvh->boundCentre().z, 0.3, 1e-6);  // 0.6 m tall along z

  const cp::WorldObject& wall = find(w, "wall__link__visual");
  EXPECT_EQ(wall.shape, cp::ObjectShape::kBox);
  EXPECT_NEAR(wall.size_m.y, 4.0, 1e-12);
  EXPECT_NEAR(wall.color_rgb.z, 1.0, 1e-9);  // Gazebo/Blue
  EXPECT_EQ(find(w, "post__link__collision").shape, cp::ObjectShape::kCylinder);
  EXPECT_NEAR(find(w, "post__link__collision").radius_m, 0.1, 1e-12);

  const cp::WorldObject& box = find(w, "falling_box__link");
  EXPECT_FALSE(box.is_static);
  EXPECT_DOUBLE_EQ(box.mass_kg, 1.0);
  EXPECT_NEAR(box.pose.position.z, 1.0, 1e-12);
  EXPECT_NEAR(box.color_rgb.x, 1.0, 1e-6);  // <ambient> alone
  EXPECT_EQ(find(w, "falling_ball__link").shape, cp::ObjectShape::kSphere);
  const cp::WorldObject& falling_block = find(w, "falling_block__link");  // <include> with <static>false
  EXPECT_FALSE(falling_block.is_static);
  EXPECT_EQ(falling_block.shape, cp::ObjectShape::kMesh);
  EXPECT_DOUBLE_EQ(falling_block.mass_kg, 2.0);

  // Lights and <scene> accepted with one note each.
  int light_notes = 0, scene_notes = 0;
  for (const std::string& note : w.notes) {
    light_notes += note.find("<light> accepted and ignored") != std::string::npos;
    scene_notes += note.find("<scene> accepted and ignored") != std::string::npos;
  }
  EXPECT_EQ(light_notes, 1);
  EXPECT_EQ(scene_notes, 1);
}

TEST(SdfWorld, ModelPathComesFromGazeboModelPath) {
  // A world elsewhere finds the model only through GAZEBO_MODEL_PATH.
  const std::string world = ::testing::TempDir() + "/include_only.world";
  {
    std::FILE* f = std::fopen(world.c_str(), "w");
    ASSERT_TRUE(f);
    std::fputs(
        "<?xml version='1.0'?><sdf version='1.6'><world name='w'><include><uri>model://mesh_block</uri>"
        "<pose>1 2 0 0 0 0</pose></include></world></sdf>",
        f);
    std::fclose(f);
  }
  unsetenv("GAZEBO_MODEL_PATH");
  try {
    cp::loadWorldFile(world, nullptr);
    ADD_FAILURE() << "loads without GAZEBO_MODEL_PATH";
  } catch (const cp::WorldFileError& e) {
    EXPECT_NE(std::string(e.what()).find("Unable to find uri[model://mesh_block]"), std::string::npos) << e.what();
  }
  setenv("GAZEBO_MODEL_PATH", (kDir + "/models").c_str(), 1);
  const cp::WorldDescription w = cp::loadWorldFile(world, nullptr);
  unsetenv("GAZEBO_MODEL_PATH");
  ASSERT_EQ(w.objects.size(), 2u);
  EXPECT_NEAR(w.objects[0].pose.position.y, 2.0, 1e-12);
}

TEST(SdfWorld, BadInputNamesFileAndLine) {
  EXPECT_EQ(errorOf("bad_syntax.world"),
            kDir +
                "/bad_syntax.world:7: XML error: Error=XML_ERROR_MISMATCHED_ELEMENT ErrorID=14 (0xe) Line number=7: "
                "XMLElement name=collision");
  EXPECT_EQ(errorOf("missing_include.world"),
            kDir + "/missing_include.world:4: Unable to find uri[model://no_such_model]");
  const std::string mesh_error = errorOf("bad_mesh.world");
  EXPECT_EQ(mesh_error.rfind(kDir + "/bad_mesh.world: link 'broken::link' collision 'collision': mesh file '" + kDir +
                                 "/models/mesh_block/meshes/broken.stl': ",
                             0),
            0u)
      << mesh_error;
  EXPECT_EQ(errorOf("no_such.world"), "cannot open world file '" + kDir + "/no_such.world': no such file");
}

TEST(MeshFile, MissingAndBrokenFilesAreNamed) {
  try {
    cp::loadMeshFile("/nonexistent/part.dae", cp::Vec3(1, 1, 1));
    FAIL();
  } catch (const cp::MeshFileError& e) {
    EXPECT_STREQ(e.what(), "mesh file '/nonexistent/part.dae': cannot open it");
  }
  // The same reader behind URDF collision meshes.
  EXPECT_THROW(cp::meshShapeFromFile(kDir + "/models/mesh_block/meshes/broken.stl", cp::Vec3(1, 1, 1)), cp::ModelError);
  const cp::Shape stl = cp::meshShapeFromFile(kDir + "/models/mesh_block/meshes/block.stl", cp::Vec3(2, 2, 2));
  EXPECT_EQ(stl.mesh_triangles.size(), 36u);
  ASSERT_TRUE(stl.mesh_bvh);
  EXPECT_NEAR(stl.mesh_bvh->boundCentre().z, 0.4, 1e-6);  // scaled by 2
}

TEST(MeshBvh, AgreesWithTestingEveryTriangle) {
  // A bumpy sphere of 20000 triangles; 2000 random rays, BVH against brute force.
  cp::Shape sphere;
  sphere.type = cp::ShapeType::kMesh;
  const int rings = 100, segments = 100;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> bump(0.9, 1.1);
  for (int r = 0; r <= rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
      const double radius = bump(rng);
      sphere.mesh_vertices_m.emplace_back(radius * std::sin(theta) * std::cos(phi),
                                          radius * std::sin(theta) * std::sin(phi), radius * std::cos(theta));
    }
  }
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      sphere.mesh_triangles.insert(sphere.mesh_triangles.end(), {a, a + segments, b, b, a + segments, b + segments});
    }
  }
  cp::Shape with_bvh = sphere;
  with_bvh.mesh_bvh = std::make_shared<const cp::MeshBvh>(sphere.mesh_vertices_m, sphere.mesh_triangles);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const cp::Vec3 o(3 * unit(rng), 3 * unit(rng), 3 * unit(rng));
    const cp::Vec3 d = (cp::Vec3(0.5 * unit(rng), 0.5 * unit(rng), 0.5 * unit(rng)) - o).normalized();
    double t_brute = -1, t_bvh = -1;
    const bool brute = cp::RayScene::hitShape(sphere, o, d, 10.0, t_brute);
    const bool fast = cp::RayScene::hitShape(with_bvh, o, d, 10.0, t_bvh);
    ASSERT_EQ(brute, fast) << i;
    if (brute) {
      ++hits;
      EXPECT_NEAR(t_brute, t_bvh, 1e-12) << i;
    }
  }
  EXPECT_GT(hits, 1000);
}

class SdfOnEngine : public ::testing::TestWithParam<std::string> {};

TEST_P(SdfOnEngine, DynamicModelsFallOntoTheGround) {
  const cp::WorldDescription world = shapesWorld();
  EngineWorld w = build(GetParam(), world);
  ASSERT_EQ(w.dynamic.size(), 3u);
  const int steps = static_cast<int>(2.0 / world.physics.step_s);
  for (int i = 0; i < steps; ++i) w.engine->step();
  // Resting on z = 0: the box's and the ball's centres at 0.1 m, the mesh block's base (its
  // link origin) at 0. Bullet keeps a contact margin of a few mm.
  EXPECT_NEAR(w.engine->bodyPose(w.dynamic["falling_box__link"], 0).position.z, 0.1, 0.01);
  EXPECT_NEAR(w.engine->bodyPose(w.dynamic["falling_ball__link"], 0).position.z, 0.1, 0.01);
  const cp::Pose block = w.engine->bodyPose(w.dynamic["falling_block__link"], 0);
  EXPECT_NEAR(block.position.z, 0.0, 0.01);
  EXPECT_NEAR(block.position.x, -4.0, 0.01);
  // Nothing falls through a static mesh: a ball dropped onto the STL block stops on its top.
  cp::WorldObject ball = find(world, "falling_ball__link");
  ball.pose.position = cp::Vec3(2.0, 0.0, 1.0);
  const auto id = w.engine->addModel(cp::modelOfDynamicObject(ball), ball.pose);
  for (int i = 0; i < steps; ++i) w.engine->step();
  EXPECT_NEAR(w.engine->bodyPose(id, 0).position.z, 0.4 + 0.1, 0.01);
}

TEST_P(SdfOnEngine, LaserHitsTheMeshes) {
  const cp::WorldDescription world = shapesWorld();
  EngineWorld w = build(GetParam(), world);
  // Mesh vertices come through assimp as floats: 1e-6 m.
  // The STL block (0.4 m cube on z = 0 at x = 2) faces the origin at x = 1.8.
  EXPECT_NEAR(castOne(*w.engine, {0, 0, 0.2}, {1, 0, 0}), 1.8, 1e-6);
  // The Collada block at y = 2 is 0.6 m tall (z-up): its top at 0.6, its side at y = 1.8.
  EXPECT_NEAR(castOne(*w.engine, {0, 2, 1.0}, {0, 0, -1}), 0.4, 1e-6);
  EXPECT_NEAR(castOne(*w.engine, {0, 0, 0.5}, {0, 1, 0}), 1.8, 1e-6);
  // The wall (box) and the post (cylinder).
  EXPECT_NEAR(castOne(*w.engine, {0, 0, 0.5}, {-1, 0, 0}), 2.9, 1e-9);
  EXPECT_NEAR(castOne(*w.engine, {0, 0, 0.5}, {0, -1, 0}), 2.9, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(BothEngines, SdfOnEngine, ::testing::Values("ode", "bullet"),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

TEST(SdfRender, CameraSeesTheMeshesInTheirColours) {
  const cp::WorldDescription world = shapesWorld();
  const cp::RenderScene scene = cp::renderSceneFromWorld(world);
  const cp::CameraModel model = cp::CameraModel::fromHorizontalFov(160, 120, 1.0);
  const cp::CameraRenderer camera(model);
  cp::RgbImage image;
  // Towards the Collada block (red material) from the origin, 0.3 m up: the centre pixel.
  camera.render(scene, lookAt({0, 0, 0.3}, {0, 2, 0.3}), -1, nullptr, image);
  {
    const std::uint8_t* p = image.pixel(80, 60);
    EXPECT_GT(p[0], 60);
    EXPECT_EQ(p[1], 0);
    EXPECT_EQ(p[2], 0);
    // Above the block's top (0.6 m at 1.8 m: 0.3 m above the axis, v < 60 - f * 0.3 / 1.8): sky.
    const double f = model.fy_px;
    const int v_top = static_cast<int>(60 - f * 0.3 / 1.8);
    const std::uint8_t* sky = image.pixel(80, v_top - 3);
    EXPECT_GT(sky[2], 200);
    const std::uint8_t* below = image.pixel(80, v_top + 3);
    EXPECT_EQ(below[1], 0);
  }
  cv::Mat bgr(image.height, image.width, CV_8UC3);
  for (int v = 0; v < image.height; ++v) {
    for (int u = 0; u < image.width; ++u) {
      const std::uint8_t* p = image.pixel(u, v);
      bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(p[2], p[1], p[0]);
    }
  }
  cv::imwrite(::testing::TempDir() + "/sdf_red_mesh.png", bgr);
  // Towards the STL block: its visual is green (the collision object is invisible).
  camera.render(scene, lookAt({0, 0, 0.3}, {2, 0, 0.3}), -1, nullptr, image);
  const std::uint8_t* p = image.pixel(80, 60);
  EXPECT_EQ(p[0], 0);
  EXPECT_GT(p[1], 60);
  EXPECT_EQ(p[2], 0);
}
