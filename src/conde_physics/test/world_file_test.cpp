// World file loader: a valid world field by field, the defaults, and one fixture per error with
// the exact message a user sees (fixtures in test/worlds/).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "conde_physics/world_file.h"

namespace cp = conde_physics;

namespace {

const std::string kDir = CONDE_WORLD_TEST_DIR;

// Resolves only "fixture_pkg", to the fixture folder.
std::string fixturePackages(const std::string& package) { return package == "fixture_pkg" ? kDir : std::string(); }

std::string fixture(const std::string& name) { return kDir + "/" + name + ".world.yaml"; }

cp::WorldDescription load(const std::string& name) { return cp::loadWorldFile(fixture(name), fixturePackages); }

// The message of the WorldFileError that loading `name` throws ("" when it loads).
std::string errorOf(const std::string& path) {
  try {
    cp::loadWorldFile(path, fixturePackages);
  } catch (const cp::WorldFileError& e) {
    return e.what();
  }
  return "";
}

// Expects "<fixture path>:<line>: <rest>".
void expectError(const std::string& name, int line, const std::string& rest) {
  const std::string path = fixture(name);
  EXPECT_EQ(errorOf(path), path + ":" + std::to_string(line) + ": " + rest);
}

void expectVec(const cp::Vec3& v, double x, double y, double z) {
  EXPECT_DOUBLE_EQ(v.x, x);
  EXPECT_DOUBLE_EQ(v.y, y);
  EXPECT_DOUBLE_EQ(v.z, z);
}

void expectQuatNear(const cp::Quat& a, const cp::Quat& b) {
  EXPECT_NEAR(a.w, b.w, 1e-12);
  EXPECT_NEAR(a.x, b.x, 1e-12);
  EXPECT_NEAR(a.y, b.y, 1e-12);
  EXPECT_NEAR(a.z, b.z, 1e-12);
}

const std::string kObjectKeys =
    "name, shape, size_m, radius_m, length_m, pose, color_rgb, texture, display_topic, static, mass_kg, "
    "collision, friction";

}  // namespace

// --- Valid worlds -------------------------------------------------------------------------------

TEST(WorldFile, ValidWorldFieldByField) {
  const cp::WorldDescription w = load("valid");
  EXPECT_EQ(w.name, "test_track");
  EXPECT_EQ(w.source_path, kDir + "/valid.world.yaml");

  EXPECT_DOUBLE_EQ(w.physics.step_s, 0.002);
  expectVec(w.physics.gravity_mps2, 0, 0.5, -9.8);
  EXPECT_EQ(w.physics.solver_iterations, 80);
  EXPECT_EQ(w.physics.max_contacts, 4);
  // Not in the file format: stay at PhysicsSettings defaults.
  EXPECT_DOUBLE_EQ(w.physics.contact_erp, cp::PhysicsSettings().contact_erp);

  // "textures/../textures/checker.png" relative to the file, normalised.
  EXPECT_EQ(w.ground.texture_path, kDir + "/textures/checker.png");
  EXPECT_DOUBLE_EQ(w.ground.x_min_m, -3.475);
  EXPECT_DOUBLE_EQ(w.ground.x_max_m, 3.975);
  EXPECT_DOUBLE_EQ(w.ground.y_min_m, -8.35);
  EXPECT_DOUBLE_EQ(w.ground.y_max_m, 8.35);
  expectVec(w.ground.color_rgb, 0.1, 0.2, 0.3);
  EXPECT_DOUBLE_EQ(w.ground.friction.mu, 100);
  EXPECT_DOUBLE_EQ(w.ground.friction.mu2, 50);

  ASSERT_EQ(w.objects.size(), 4u);
  const cp::WorldObject& monitor = w.objects[0];
  EXPECT_EQ(monitor.name, "monitor_lcd2");
  EXPECT_EQ(monitor.shape, cp::ObjectShape::kBox);
  expectVec(monitor.size_m, 0.4758, 0.2673, 0.01);
  expectVec(monitor.pose.position, 2.2, 0.0, 1.0);
  expectQuatNear(monitor.pose.orientation, cp::Quat::fromRpy(M_PI / 2, 0, 0));
  expectVec(monitor.color_rgb, 0.69, 0.69, 0.69);
  EXPECT_EQ(monitor.texture_path, kDir + "/textures/checker.png");  // via package://fixture_pkg
  EXPECT_EQ(monitor.display_topic, "/monitor2/image2");
  EXPECT_TRUE(monitor.is_static);
  EXPECT_DOUBLE_EQ(monitor.mass_kg, 0.0);
  EXPECT_TRUE(monitor.collision);

  const cp::WorldObject& barrel = w.objects[1];
  EXPECT_EQ(barrel.name, "barrel");
  EXPECT_EQ(barrel.shape, cp::ObjectShape::kCylinder);
  EXPECT_DOUBLE_EQ(barrel.radius_m, 0.1);
  EXPECT_DOUBLE_EQ(barrel.length_m, 0.3);
  expectVec(barrel.size_m, 0, 0, 0);
  expectVec(barrel.pose.position, 1, 2, 0.15);
  expectQuatNear(barrel.pose.orientation, cp::Quat());
  EXPECT_FALSE(barrel.is_static);
  EXPECT_DOUBLE_EQ(barrel.mass_kg, 2.5);
  EXPECT_DOUBLE_EQ(barrel.friction.mu, 0.5);
  EXPECT_DOUBLE_EQ(barrel.friction.mu2, 1.0);  // default of the key left out
  EXPECT_EQ(barrel.texture_path, "");
  EXPECT_EQ(barrel.display_topic, "");

  const cp::WorldObject& cone = w.objects[2];
  EXPECT_EQ(cone.shape, cp::ObjectShape::kCone);
  EXPECT_DOUBLE_EQ(cone.radius_m, 0.2);
  EXPECT_DOUBLE_EQ(cone.length_m, 0.4);
  expectQuatNear(cone.pose.orientation, cp::Quat::fromRpy(0, 0, 0.5));
  EXPECT_DOUBLE_EQ(cone.mass_kg, 4);

  const cp::WorldObject& ghost = w.objects[3];
  EXPECT_EQ(ghost.shape, cp::ObjectShape::kSphere);
  EXPECT_DOUBLE_EQ(ghost.radius_m, 0.05);
  EXPECT_DOUBLE_EQ(ghost.length_m, 0.0);
  EXPECT_FALSE(ghost.collision);
  EXPECT_TRUE(ghost.is_static);

  ASSERT_EQ(w.spawns.size(), 2u);
  EXPECT_EQ(w.spawns[0].name, "conde");
  EXPECT_EQ(w.spawns[1].name, "other");
  const cp::SpawnPose* conde = w.findSpawn("conde");
  ASSERT_NE(conde, nullptr);
  expectVec(conde->pose.position, 2.14, -0.5, 0.0);
  expectQuatNear(conde->pose.orientation, cp::Quat::fromRpy(0, 0, 1.5708));
  const cp::SpawnPose* other = w.findSpawn("other");
  ASSERT_NE(other, nullptr);
  expectQuatNear(other->pose.orientation, cp::Quat());  // yaw defaults to 0
  EXPECT_EQ(w.findSpawn("nobody"), nullptr);
}

TEST(WorldFile, Defaults) {
  const cp::WorldDescription w = load("minimal");
  EXPECT_EQ(w.name, "plain");
  const cp::PhysicsSettings d;
  EXPECT_DOUBLE_EQ(w.physics.step_s, 0.001);
  EXPECT_DOUBLE_EQ(d.step_s, 0.001);  // the documented default is PhysicsSettings' default
  expectVec(w.physics.gravity_mps2, 0, 0, -9.81);
  EXPECT_EQ(w.physics.solver_iterations, 50);
  EXPECT_EQ(w.physics.max_contacts, 10);
  EXPECT_EQ(w.ground.texture_path, "");
  EXPECT_DOUBLE_EQ(w.ground.x_min_m, 0.0);
  EXPECT_DOUBLE_EQ(w.ground.x_max_m, 0.0);
  expectVec(w.ground.color_rgb, 0.7, 0.7, 0.7);
  EXPECT_DOUBLE_EQ(w.ground.friction.mu, 1.0);
  EXPECT_DOUBLE_EQ(w.ground.friction.mu2, 1.0);
  EXPECT_TRUE(w.objects.empty());
  EXPECT_TRUE(w.spawns.empty());
}

TEST(WorldFile, RelativePathOfTheWorldFileResolvesTexturesFromItsFolder) {
  // A path relative to the working directory: textures still resolve to absolute paths.
  const std::string cwd_relative = std::string(CONDE_WORLD_TEST_DIR) + "/./valid.world.yaml";
  const cp::WorldDescription w = cp::loadWorldFile(cwd_relative, fixturePackages);
  EXPECT_EQ(w.source_path, kDir + "/valid.world.yaml");
  EXPECT_EQ(w.ground.texture_path, kDir + "/textures/checker.png");
}

TEST(WorldFile, TextureLoads) {
  EXPECT_TRUE(cp::textureLoads(kDir + "/textures/checker.png"));
  EXPECT_FALSE(cp::textureLoads(kDir + "/textures/corrupt.png"));
  EXPECT_FALSE(cp::textureLoads(kDir + "/textures/missing.png"));
}

// --- Shapes and models of objects ----------------------------------------------------------------

TEST(WorldFile, CollisionShapes) {
  const cp::WorldDescription w = load("valid");
  const cp::Shape box = cp::collisionShapeOf(w.objects[0]);
  EXPECT_EQ(box.type, cp::ShapeType::kBox);
  expectVec(box.box_size_m, 0.4758, 0.2673, 0.01);
  const cp::Shape cylinder = cp::collisionShapeOf(w.objects[1]);
  EXPECT_EQ(cylinder.type, cp::ShapeType::kCylinder);
  EXPECT_DOUBLE_EQ(cylinder.radius_m, 0.1);
  EXPECT_DOUBLE_EQ(cylinder.length_m, 0.3);
  const cp::Shape cone = cp::collisionShapeOf(w.objects[2]);  // the cylinder of its base
  EXPECT_EQ(cone.type, cp::ShapeType::kCylinder);
  EXPECT_DOUBLE_EQ(cone.radius_m, 0.2);
  EXPECT_DOUBLE_EQ(cone.length_m, 0.4);
  const cp::Shape sphere = cp::collisionShapeOf(w.objects[3]);
  EXPECT_EQ(sphere.type, cp::ShapeType::kSphere);
  EXPECT_DOUBLE_EQ(sphere.radius_m, 0.05);
}

TEST(WorldFile, ModelOfDynamicCylinder) {
  const cp::WorldDescription w = load("valid");
  const cp::ArticulatedModel m = cp::modelOfDynamicObject(w.objects[1]);
  EXPECT_EQ(m.name, "barrel");
  EXPECT_FALSE(m.fixed_to_world);
  EXPECT_TRUE(m.joints.empty());
  ASSERT_EQ(m.bodies.size(), 1u);
  const cp::BodySpec& b = m.bodies[0];
  EXPECT_EQ(b.name, "barrel");
  EXPECT_EQ(m.bodyIndex("barrel"), 0);
  EXPECT_DOUBLE_EQ(b.mass_kg, 2.5);
  expectVec(b.inertial_frame.position, 0, 0, 0);
  const double ixx = 2.5 * (3 * 0.1 * 0.1 + 0.3 * 0.3) / 12.0;
  expectVec(b.principal_inertia_kgm2, ixx, ixx, 2.5 * 0.1 * 0.1 / 2.0);
  ASSERT_EQ(b.collisions.size(), 1u);
  EXPECT_EQ(b.collisions[0].shape.type, cp::ShapeType::kCylinder);
  expectVec(b.collisions[0].pose_in_link.position, 0, 0, 0);
  EXPECT_DOUBLE_EQ(b.collisions[0].surface.mu, 0.5);
}

TEST(WorldFile, ModelOfDynamicConeHasItsCentreOfMassLow) {
  const cp::WorldDescription w = load("valid");
  const cp::BodySpec b = cp::modelOfDynamicObject(w.objects[2]).bodies.at(0);
  // Solid cone, m = 4 kg, r = 0.2 m, h = 0.4 m, apex at +z.
  expectVec(b.inertial_frame.position, 0, 0, -0.1);
  const double ixx = 4 * (3 * 0.04 / 20 + 3 * 0.16 / 80);
  expectVec(b.principal_inertia_kgm2, ixx, ixx, 3 * 4 * 0.04 / 10);
}

TEST(WorldFile, ModelOfStaticObjectIsRefused) {
  const cp::WorldDescription w = load("valid");
  EXPECT_THROW(cp::modelOfDynamicObject(w.objects[0]), std::invalid_argument);
}

// --- Files that cannot be read -------------------------------------------------------------------

TEST(WorldFile, MissingFile) {
  const std::string path = kDir + "/no_such.world.yaml";
  EXPECT_EQ(errorOf(path), "cannot open world file '" + path + "': No such file or directory");
}

TEST(WorldFile, DirectoryInsteadOfFile) {
  EXPECT_EQ(errorOf(kDir), "cannot open world file '" + kDir + "': Is a directory");
}

TEST(WorldFile, SyntaxError) { expectError("syntax_error", 5, "YAML syntax error: end of sequence flow not found"); }

TEST(WorldFile, EmptyFile) { expectError("empty", 1, "expected a map with keys format, name, ..., got nothing"); }

TEST(WorldFile, NotAMap) { expectError("not_a_map", 1, "expected a map with keys format, name, ..., got a list"); }

// --- Top level -----------------------------------------------------------------------------------

TEST(WorldFile, BadFormat) { expectError("bad_format", 1, "format: expected 'conde_world/1', got 'foo'"); }

TEST(WorldFile, MissingFormat) { expectError("missing_format", 1, "missing required key 'format'"); }

TEST(WorldFile, UnknownTopLevelKey) {
  expectError("unknown_top_key", 4,
              "unknown key 'lights' (expected one of: format, name, physics, ground, objects, spawn, "
              "light_regions)");
}

TEST(WorldFile, LightRegions) {
  const cp::WorldDescription w = load("light_regions");
  ASSERT_EQ(w.light_regions.size(), 1u);
  const cp::LightRegion& r = w.light_regions[0];
  EXPECT_EQ(r.name, "tunnel");
  ASSERT_EQ(r.polygon_xy_m.size(), 4u);
  EXPECT_DOUBLE_EQ(r.polygon_xy_m[2][0], 2.0);
  EXPECT_DOUBLE_EQ(r.polygon_xy_m[2][1], 1.0);
  EXPECT_DOUBLE_EQ(r.z_min_m, -0.01);
  EXPECT_DOUBLE_EQ(r.z_max_m, 1.0);
  EXPECT_DOUBLE_EQ(r.light, 0.25);
  EXPECT_TRUE(load("minimal").light_regions.empty());
}

TEST(WorldFile, LightOutOfRange) {
  expectError("bad_light", 8, "light_regions[0] (tunnel).light: must be in 0..1, got 1.5");
}

TEST(WorldFile, LightRegionWithTwoCorners) {
  expectError("bad_light_polygon", 6,
              "light_regions[0] (tunnel).polygon_xy_m: expected a list of at least 3 [x, y] corners, got 2");
}

TEST(WorldFile, MissingGround) { expectError("missing_ground", 1, "missing required key 'ground'"); }

// --- physics -------------------------------------------------------------------------------------

TEST(WorldFile, StepOutOfRange) { expectError("bad_step", 4, "physics.step_s: must be in (0, 0.01], got 0.02"); }

TEST(WorldFile, SolverIterationsOutOfRange) {
  expectError("bad_solver_iterations", 4, "physics.solver_iterations: must be in 1..1000, got 0");
}

TEST(WorldFile, NonInteger) { expectError("non_integer", 4, "physics.max_contacts: expected an integer, got '2.5'"); }

TEST(WorldFile, QuotedNumber) { expectError("quoted_number", 4, "physics.step_s: expected a number, got \"0.001\""); }

TEST(WorldFile, NotFinite) {
  expectError("not_finite", 4, "physics.gravity_mps2[2]: expected a finite number, got '.nan'");
}

// --- ground --------------------------------------------------------------------------------------

TEST(WorldFile, MissingTexture) {
  expectError("missing_texture", 4,
              "ground.texture: cannot load image '" + kDir + "/textures/missing.png': No such file or directory");
}

TEST(WorldFile, UnknownPackage) {
  expectError("unknown_package", 4,
              "ground.texture: unknown package 'no_such_pkg' in 'package://no_such_pkg/track.png'");
}

TEST(WorldFile, TextureNeedsRanges) {
  expectError("missing_range", 4, "ground: missing required key 'y_range_m' (needed with a texture)");
}

TEST(WorldFile, EmptyRange) {
  expectError("bad_range", 4, "ground.x_range_m: expected [min, max] with min < max, got [3, -3]");
}

TEST(WorldFile, ColourOutOfRange) { expectError("bad_color", 4, "ground.color_rgb[1]: must be in 0..1, got 1.5"); }

TEST(WorldFile, NegativeFriction) { expectError("negative_friction", 4, "ground.friction.mu: must be >= 0, got -1"); }

// --- objects -------------------------------------------------------------------------------------

TEST(WorldFile, UnknownObjectKey) {
  expectError("unknown_key", 7, "objects[1] (box_a): unknown key 'colour' (expected one of: " + kObjectKeys + ")");
}

TEST(WorldFile, CorruptTexture) {
  expectError(
      "corrupt_texture", 9,
      "objects[0] (sign).texture: cannot load image '" + kDir + "/textures/corrupt.png': not a decodable image");
}

TEST(WorldFile, NegativeSize) {
  expectError("negative_size", 7, "objects[0] (plate).size_m[2]: must be > 0, got -0.1");
}

TEST(WorldFile, WrongType) {
  expectError("wrong_type", 8, "objects[0] (plate).pose.xyz[1]: expected a number, got 'two'");
}

TEST(WorldFile, WrongLength) {
  expectError("wrong_length", 7, "objects[0] (plate).size_m: expected a list of 3 numbers, got a list of 2");
}

TEST(WorldFile, DuplicateObjectName) {
  expectError("duplicate_name", 13,
              "objects[2] (box_a).name: duplicate object name 'box_a' (first used by objects[0] at line 5)");
}

TEST(WorldFile, DuplicateKey) {
  expectError("duplicate_key", 8, "objects[0]: duplicate key 'size_m' (first at line 7)");
}

TEST(WorldFile, BadName) {
  expectError("bad_name", 5, "objects[0].name: invalid name 'box a' (use letters, digits and '_')");
}

TEST(WorldFile, UnknownShape) {
  expectError("unknown_shape", 6,
              "objects[0] (tent).shape: unknown shape 'pyramid' (expected one of: box, cylinder, cone, sphere)");
}

TEST(WorldFile, KeyOfAnotherShape) {
  expectError("shape_key_mismatch", 8, "objects[0] (ball): key 'size_m' does not apply to shape 'sphere'");
}

TEST(WorldFile, MissingLength) {
  expectError("missing_length", 5, "objects[0] (post): missing required key 'length_m' for shape 'cylinder'");
}

TEST(WorldFile, TextureOnSphere) {
  expectError("texture_on_sphere", 9,
              "objects[0] (ball): key 'texture' does not apply to shape 'sphere' (only boxes show textures)");
}

TEST(WorldFile, BadTopic) {
  expectError("bad_topic", 9, "objects[0] (monitor).display_topic: invalid topic name '/monitor/2image'");
}

TEST(WorldFile, DynamicWithoutMass) {
  expectError("dynamic_without_mass", 5,
              "objects[0] (crate): missing required key 'mass_kg' for a dynamic object (static: false)");
}

TEST(WorldFile, MassOnStaticObject) {
  expectError("mass_on_static", 9,
              "objects[0] (crate): key 'mass_kg' does not apply to static objects (set static: false)");
}

TEST(WorldFile, DynamicWithoutCollision) {
  expectError("dynamic_without_collision", 11,
              "objects[0] (crate).collision: a dynamic object must collide (it would fall through the ground)");
}

TEST(WorldFile, MissingPose) { expectError("missing_pose", 5, "objects[0] (crate): missing required key 'pose'"); }

// --- spawn ---------------------------------------------------------------------------------------

TEST(WorldFile, UnknownSpawnKey) {
  expectError("bad_spawn", 6, "spawn.conde2: unknown key 'z' (expected one of: xyz, yaw)");
}
