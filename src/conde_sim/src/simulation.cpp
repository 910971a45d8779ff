#include "conde_sim/simulation.h"

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
  for (const cp::WorldObject& object : world_.objects) {
    if (!object.collision) continue;  // visual only
    if (object.is_static) {
      engine_->addStaticShape(cp::collisionShapeOf(object), object.pose, object.friction);
    } else {
      engine_->addModel(cp::modelOfDynamicObject(object), object.pose);
    }
  }
  for (Robot& robot : robots_) robot.id = engine_->addModel(robot.model, robot.spec.spawn_pose);
}

int Simulation::addRobot(const RobotSpec& spec, std::vector<std::string>* warnings) {
  Robot robot;
  robot.spec = spec;
  robot.model = cp::buildModelFromUrdf(spec.urdf_xml, spec.source, packages_, warnings);
  if (robot.spec.name.empty()) robot.spec.name = robot.model.name;
  for (const Robot& r : robots_) {
    if (r.spec.name == robot.spec.name) {
      throw cp::ModelError(spec.source + ": a robot named '" + robot.spec.name + "' already exists");
    }
  }
  robot.id = engine_->addModel(robot.model, spec.spawn_pose);
  robots_.push_back(std::move(robot));
  return robotCount() - 1;
}

void Simulation::resetWorld() { buildWorld(); }

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

std::uint64_t updatePeriodSteps(double rate_hz, double step_s) {
  if (rate_hz <= 0.0) return 1;
  const double steps = std::round(1.0 / (rate_hz * step_s));
  return steps < 1.0 ? 1 : static_cast<std::uint64_t>(steps);
}

}  // namespace conde_sim
