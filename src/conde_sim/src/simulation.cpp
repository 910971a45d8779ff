#include "conde_sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "conde_physics/urdf_model.h"

namespace conde_sim {

namespace cp = conde_physics;

Simulation::Simulation(cp::WorldDescription world, std::string engine_name, cp::PackageResolver packages)
    : world_(std::move(world)), engine_name_(std::move(engine_name)), packages_(std::move(packages)) {
  buildWorld();
}

void Simulation::buildWorld() {
  engine_ = cp::createPhysicsEngine(engine_name_, world_.physics);
  engine_->addGroundPlane(world_.ground.friction);
  object_model_ids_.assign(world_.objects.size(), -1);
  for (size_t i = 0; i < world_.objects.size(); ++i) {
    const cp::WorldObject& object = world_.objects[i];
    if (!object.collision) continue;  // visual only
    if (object.is_static) {
      engine_->addStaticShape(cp::collisionShapeOf(object), object.pose, object.friction);
    } else {
      object_model_ids_[i] = engine_->addModel(cp::modelOfDynamicObject(object), object.pose);
    }
  }
  for (Robot& robot : robots_) robot.id = engine_->addModel(robot.model, robot.spec.spawn_pose);
  render_scene_synced_ = false;
}

int Simulation::addRobot(const RobotSpec& spec, std::vector<std::string>* warnings) {
  Robot robot;
  robot.spec = spec;
  robot.model = cp::buildModelFromUrdf(spec.urdf_xml, spec.source, packages_, warnings, &robot.gazebo);
  if (robot.spec.name.empty()) robot.spec.name = robot.model.name;
  for (const Robot& r : robots_) {
    if (r.spec.name == robot.spec.name) {
      throw cp::ModelError(spec.source + ": a robot named '" + robot.spec.name + "' already exists");
    }
  }
  robot.id = engine_->addModel(robot.model, spec.spawn_pose);
  robots_.push_back(std::move(robot));
  if (render_scene_) addRobotToScene(robotCount() - 1);
  return robotCount() - 1;
}

void Simulation::resetWorld() { buildWorld(); }

int Simulation::findRobot(const std::string& name) const {
  if (name.empty()) return robotCount() == 1 ? 0 : -1;
  for (int r = 0; r < robotCount(); ++r) {
    if (robots_[r].spec.name == name) return r;
  }
  return -1;
}

void Simulation::step() {
  engine_->step();
  ++step_count_;
}

// Body holding `link` and the link's pose in that body's frame; throws for an unknown link.
static int bodyOfLink(const Robot& r, const std::string& link, cp::Pose& link_in_body) {
  int body = -1;
  if (!r.model.linkInBody(link, body, link_in_body)) {
    throw std::out_of_range("robot '" + r.spec.name + "' has no link '" + link + "'");
  }
  return body;
}

cp::Pose Simulation::linkPose(int robot, const std::string& link) const {
  const Robot& r = robots_.at(robot);
  cp::Pose link_in_body;
  const int body = bodyOfLink(r, link, link_in_body);
  return engine_->bodyPose(r.id, body) * link_in_body;
}

cp::Twist Simulation::linkTwist(int robot, const std::string& link) const {
  const Robot& r = robots_.at(robot);
  cp::Pose link_in_body;
  const int body = bodyOfLink(r, link, link_in_body);
  const cp::Pose body_pose = engine_->bodyPose(r.id, body);
  cp::Twist t = engine_->bodyTwist(r.id, body);
  t.linear_mps += t.angular_radps.cross(body_pose.orientation.rotate(link_in_body.position));
  return t;
}

// Render objects for one collision shape; meshes become their bounding box.
static bool renderObjectOfShape(const cp::Shape& shape, cp::RenderObject& object) {
  switch (shape.type) {
    case cp::ShapeType::kBox:
      object.shape = cp::RenderShape::kBox;
      object.size_m = shape.box_size_m;
      return true;
    case cp::ShapeType::kCylinder:
      object.shape = cp::RenderShape::kCylinder;
      object.radius_m = shape.radius_m;
      object.length_m = shape.length_m;
      return true;
    case cp::ShapeType::kSphere:
      object.shape = cp::RenderShape::kSphere;
      object.radius_m = shape.radius_m;
      return true;
    case cp::ShapeType::kMesh: {
      if (shape.mesh_vertices_m.empty()) return false;
      cp::Vec3 lo = shape.mesh_vertices_m.front(), hi = lo;
      for (const cp::Vec3& v : shape.mesh_vertices_m) {
        lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
        hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
      }
      object.shape = cp::RenderShape::kBox;
      object.size_m = hi - lo;
      object.pose.position = object.pose.position + object.pose.orientation.rotate((lo + hi) * 0.5);
      return true;
    }
  }
  return false;
}

cp::RenderScene& Simulation::renderScene() {
  if (!render_scene_) {
    render_scene_ = std::make_unique<cp::RenderScene>(cp::renderSceneFromWorld(world_));
    for (size_t i = 0; i < world_.objects.size(); ++i) {
      if (world_.objects[i].is_static) continue;
      RenderedShape moving;
      moving.world_object = static_cast<int>(i);
      moving.scene_index = static_cast<int>(i);
      rendered_shapes_.push_back(moving);
    }
    for (int r = 0; r < robotCount(); ++r) addRobotToScene(r);
  }
  if (!render_scene_synced_ || render_scene_step_ != step_count_) syncRenderScene();
  return *render_scene_;
}

void Simulation::addRobotToScene(int robot) {
  const Robot& r = robots_.at(robot);
  for (size_t b = 0; b < r.model.bodies.size(); ++b) {
    for (const cp::CollisionSpec& collision : r.model.bodies[b].collisions) {
      cp::RenderObject object;
      object.pose = collision.pose_in_link;
      if (!renderObjectOfShape(collision.shape, object)) continue;
      object.color_rgb = {0.35, 0.35, 0.4};
      object.group = robot;
      RenderedShape moving;
      moving.robot = robot;
      moving.body = static_cast<int>(b);
      moving.pose_in_body = object.pose;
      moving.scene_index = render_scene_->addObject(object);
      rendered_shapes_.push_back(moving);
    }
  }
  render_scene_synced_ = false;
}

void Simulation::syncRenderScene() {
  for (const RenderedShape& moving : rendered_shapes_) {
    if (moving.robot >= 0) {
      const Robot& r = robots_[moving.robot];
      render_scene_->setObjectPose(moving.scene_index, engine_->bodyPose(r.id, moving.body) * moving.pose_in_body);
    } else if (object_model_ids_[moving.world_object] >= 0) {
      render_scene_->setObjectPose(moving.scene_index, engine_->bodyPose(object_model_ids_[moving.world_object], 0));
    }
  }
  render_scene_synced_ = true;
  render_scene_step_ = step_count_;
}

std::vector<int> Simulation::renderObjectsOfLink(int robot, const std::string& link) {
  renderScene();
  cp::Pose link_in_body;
  const int body = bodyOfLink(robots_.at(robot), link, link_in_body);
  std::vector<int> indices;
  for (const RenderedShape& moving : rendered_shapes_) {
    if (moving.robot == robot && moving.body == body) indices.push_back(moving.scene_index);
  }
  return indices;
}

}  // namespace conde_sim
