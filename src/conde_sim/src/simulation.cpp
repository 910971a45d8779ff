#include "conde_sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "conde_physics/mesh_bvh.h"
#include "conde_physics/render_scene.h"
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
  object_models_.assign(world_.objects.size(), cp::ArticulatedModel());
  static_shape_objects_.clear();
  object_removed_.resize(world_.objects.size(), 0);
  for (size_t i = 0; i < world_.objects.size(); ++i) {
    if (!object_removed_[i]) addObjectToEngine(i);
  }
  for (Robot& robot : robots_) {
    if (!robot.removed) robot.id = engine_->addModel(robot.model, robot.spec.spawn_pose);
  }
  render_scene_synced_ = false;
}

void Simulation::addObjectToEngine(size_t i) {
  const cp::WorldObject& object = world_.objects[i];
  if (!object.collision) return;  // visual only
  if (object.is_static) {
    engine_->addStaticShape(cp::collisionShapeOf(object), object.pose, object.friction);
    static_shape_objects_.push_back(static_cast<int>(i));
  } else {
    object_models_[i] = cp::modelOfDynamicObject(object);
    object_model_ids_[i] = engine_->addModel(object_models_[i], object.pose);
  }
}

void Simulation::addObjects(const std::vector<cp::WorldObject>& objects) {
  std::set<std::string> names;
  for (const cp::WorldObject& object : objects) {
    bool taken = findRobot(object.name) >= 0;
    for (size_t i = 0; i < world_.objects.size(); ++i)
      taken |= !object_removed_[i] && world_.objects[i].name == object.name;
    if (object.name.empty() || taken || !names.insert(object.name).second)
      throw std::invalid_argument("an object or robot named '" + object.name + "' already exists");
  }
  for (const cp::WorldObject& object : objects) {
    const size_t i = world_.objects.size();
    world_.objects.push_back(object);
    object_removed_.push_back(0);
    object_model_ids_.push_back(-1);
    object_models_.emplace_back();
    addObjectToEngine(i);
    if (!render_scene_) continue;  // built from world_ on first use
    RenderedShape shape;
    shape.world_object = static_cast<int>(i);
    shape.scene_index = render_scene_->addObject(cp::renderObjectOf(object));
    if (!object.is_static) rendered_shapes_.push_back(shape);
  }
  render_scene_synced_ = false;
}

int Simulation::addRobot(const RobotSpec& spec, std::vector<std::string>* warnings) {
  Robot robot;
  robot.spec = spec;
  robot.model = cp::buildModelFromUrdf(spec.urdf_xml, spec.source, packages_, warnings, &robot.gazebo);
  if (robot.spec.name.empty()) robot.spec.name = robot.model.name;
  for (const Robot& r : robots_) {
    if (!r.removed && r.spec.name == robot.spec.name) {
      throw cp::ModelError(spec.source + ": a robot named '" + robot.spec.name + "' already exists");
    }
  }
  robot.id = engine_->addModel(robot.model, spec.spawn_pose);
  robots_.push_back(std::move(robot));
  if (render_scene_) addRobotToScene(robotCount() - 1);
  return robotCount() - 1;
}

void Simulation::resetWorld() {
  pending_wrenches_.clear();
  last_wrenches_.clear();
  buildWorld();
}

Simulation::ContactOwner Simulation::contactOwner(const cp::ContactSide& side) const {
  ContactOwner owner;
  if (side.model < 0) {
    if (side.static_shape >= 0 && side.static_shape < static_cast<int>(static_shape_objects_.size()))
      owner.object = static_shape_objects_[side.static_shape];
    return owner;
  }
  for (int r = 0; r < robotCount(); ++r) {
    if (!robots_[r].removed && robots_[r].id == side.model) {
      owner.robot = r;
      owner.body = side.body;
      return owner;
    }
  }
  for (size_t i = 0; i < object_model_ids_.size(); ++i) {
    if (object_model_ids_[i] == side.model) owner.object = static_cast<int>(i);
  }
  return owner;
}

void Simulation::removeRobot(int robot) {
  Robot& r = robots_.at(robot);
  if (r.removed) return;
  engine_->removeModel(r.id);
  r.removed = true;
  r.id = -1;
  if (!render_scene_) return;
  for (const RenderedShape& shape : rendered_shapes_) {
    if (shape.robot == robot) render_scene_->setObjectHidden(shape.scene_index, true);
  }
}

void Simulation::removeObject(int object) {
  if (world_.objects.at(object).is_static)
    throw std::invalid_argument("'" + world_.objects[object].name +
                                "' is static: static objects cannot be removed yet");
  if (object_removed_.at(object)) return;
  if (object_model_ids_.at(object) >= 0) engine_->removeModel(object_model_ids_[object]);
  object_model_ids_[object] = -1;
  object_removed_[object] = 1;
  if (!render_scene_) return;
  for (const RenderedShape& shape : rendered_shapes_) {
    if (shape.robot < 0 && shape.world_object == object) render_scene_->setObjectHidden(shape.scene_index, true);
  }
}

int Simulation::findRobot(const std::string& name) const {
  int found = -1, present = 0;
  for (int r = 0; r < robotCount(); ++r) {
    if (robots_[r].removed) continue;
    ++present;
    if (name.empty()) found = r;
    if (robots_[r].spec.name == name) return r;
  }
  return name.empty() && present == 1 ? found : -1;
}

ModelRef Simulation::findModel(const std::string& name) const {
  ModelRef ref;
  if (name.empty()) return ref;
  ref.robot = findRobot(name);
  if (ref.robot >= 0) return ref;
  for (size_t i = 0; i < world_.objects.size(); ++i) {
    if (object_model_ids_[i] >= 0 && world_.objects[i].name == name) ref.object = static_cast<int>(i);
  }
  return ref;
}

std::vector<ModelRef> Simulation::models() const {
  std::vector<ModelRef> refs;
  for (int r = 0; r < robotCount(); ++r) {
    if (!robots_[r].removed) refs.push_back(ModelRef{r, -1});
  }
  for (size_t i = 0; i < world_.objects.size(); ++i) {
    if (object_model_ids_[i] >= 0) refs.push_back(ModelRef{-1, static_cast<int>(i)});
  }
  return refs;
}

std::string Simulation::modelName(const ModelRef& model) const {
  return model.robot >= 0 ? robots_.at(model.robot).spec.name : world_.objects.at(model.object).name;
}

const cp::ArticulatedModel& Simulation::articulatedModel(const ModelRef& model) const {
  return model.robot >= 0 ? robots_.at(model.robot).model : object_models_.at(model.object);
}

cp::ModelId Simulation::engineId(const ModelRef& model) const {
  return model.robot >= 0 ? robots_.at(model.robot).id : object_model_ids_.at(model.object);
}

std::vector<std::string> Simulation::bodyLinkNames(const ModelRef& model) const {
  std::vector<std::string> names;
  for (const cp::BodySpec& body : articulatedModel(model).bodies) names.push_back(body.name);
  return names;
}

int Simulation::bodyOf(const ModelRef& model, const std::string& link, cp::Pose& link_in_body) const {
  const cp::ArticulatedModel& m = articulatedModel(model);
  if (link.empty()) {
    link_in_body = cp::Pose();
    return 0;
  }
  int body = -1;
  if (!m.linkInBody(link, body, link_in_body)) {
    throw std::out_of_range("model '" + modelName(model) + "' has no link '" + link + "'");
  }
  return body;
}

bool Simulation::hasLink(const ModelRef& model, const std::string& link) const {
  int body = -1;
  cp::Pose link_in_body;
  return link.empty() || articulatedModel(model).linkInBody(link, body, link_in_body);
}

cp::Pose Simulation::linkPose(const ModelRef& model, const std::string& link) const {
  cp::Pose link_in_body;
  const int body = bodyOf(model, link, link_in_body);
  return engine_->bodyPose(engineId(model), body) * link_in_body;
}

cp::Twist Simulation::linkTwist(const ModelRef& model, const std::string& link) const {
  cp::Pose link_in_body;
  const int body = bodyOf(model, link, link_in_body);
  const cp::ModelId id = engineId(model);
  const cp::Pose body_pose = engine_->bodyPose(id, body);
  cp::Twist t = engine_->bodyTwist(id, body);
  t.linear_mps += t.angular_radps.cross(body_pose.orientation.rotate(link_in_body.position));
  return t;
}

void Simulation::setModelState(const ModelRef& model, const cp::Pose& root_pose, const cp::Twist& twist) {
  const cp::ModelId id = engineId(model);
  const size_t bodies = articulatedModel(model).bodies.size();
  const cp::Pose moved = root_pose * engine_->bodyPose(id, 0).inverse();  // world -> world
  std::vector<cp::Pose> poses(bodies);
  for (size_t b = 0; b < bodies; ++b) poses[b] = moved * engine_->bodyPose(id, static_cast<int>(b));
  for (size_t b = 0; b < bodies; ++b) {
    cp::Twist body_twist = twist;
    body_twist.linear_mps += twist.angular_radps.cross(poses[b].position - root_pose.position);
    engine_->setBodyState(id, static_cast<int>(b), poses[b], body_twist);
  }
  render_scene_synced_ = false;
}

void Simulation::setLinkState(const ModelRef& model, const std::string& link, const cp::Pose& link_pose,
                              const cp::Twist& twist) {
  cp::Pose link_in_body;
  const int body = bodyOf(model, link, link_in_body);
  const cp::Pose body_pose = link_pose * link_in_body.inverse();
  cp::Twist body_twist = twist;  // velocity of the body's link-frame origin
  body_twist.linear_mps += twist.angular_radps.cross(body_pose.position - link_pose.position);
  engine_->setBodyState(engineId(model), body, body_pose, body_twist);
  render_scene_synced_ = false;
}

void Simulation::addLinkWrench(const ModelRef& model, const std::string& link, const cp::Vec3& force_N,
                               const cp::Vec3& torque_Nm, const cp::Vec3& point_world) {
  cp::Pose link_in_body;
  const int body = bodyOf(model, link, link_in_body);
  const cp::ModelId id = engineId(model);
  engine_->addBodyWrench(id, body, force_N, torque_Nm, point_world);
  const cp::Vec3 com = (engine_->bodyPose(id, body) * articulatedModel(model).bodies[body].inertial_frame).position;
  cp::Twist& sum = pending_wrenches_[{id, body}];
  sum.linear_mps = sum.linear_mps + force_N;
  sum.angular_radps = sum.angular_radps + torque_Nm + (point_world - com).cross(force_N);
}

void Simulation::addLinkWrenchAtCentreOfMass(const ModelRef& model, const std::string& link, const cp::Vec3& force_N,
                                             const cp::Vec3& torque_Nm) {
  cp::Pose link_in_body;
  const int body = bodyOf(model, link, link_in_body);
  const cp::Pose com = engine_->bodyPose(engineId(model), body) * articulatedModel(model).bodies[body].inertial_frame;
  addLinkWrench(model, link, force_N, torque_Nm, com.position);
}

cp::Twist Simulation::lastAppliedWrench(const ModelRef& model, const std::string& link) const {
  cp::Pose link_in_body;
  const int body = bodyOf(model, link, link_in_body);
  const auto it = last_wrenches_.find({engineId(model), body});
  return it == last_wrenches_.end() ? cp::Twist() : it->second;
}

void Simulation::step() {
  engine_->step();
  last_wrenches_.swap(pending_wrenches_);
  pending_wrenches_.clear();
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

// Render objects for one collision shape (meshes as their triangles).
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
    case cp::ShapeType::kMesh:
      if (shape.mesh_triangles.empty()) return false;
      object.shape = cp::RenderShape::kMesh;
      object.mesh = shape.mesh_bvh ? shape.mesh_bvh
                                   : std::make_shared<const cp::MeshBvh>(shape.mesh_vertices_m, shape.mesh_triangles);
      return true;
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
      if (object_removed_[i]) render_scene_->setObjectHidden(moving.scene_index, true);
    }
    for (int r = 0; r < robotCount(); ++r) {
      if (!robots_[r].removed) addRobotToScene(r);
    }
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
      if (r.removed) continue;
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
