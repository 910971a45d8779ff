#include "conde_sim/joint_controller.h"

#include <algorithm>
#include <cmath>

#include "conde_sim/simulation.h"

namespace conde_sim {

namespace cp = conde_physics;

namespace {

struct TypeName {
  JointControllerType type;
  const char* name;
};

const TypeName kTypeNames[] = {
    {JointControllerType::kEffortPosition, "effort_controllers/JointPositionController"},
    {JointControllerType::kEffortVelocity, "effort_controllers/JointVelocityController"},
    {JointControllerType::kEffort, "effort_controllers/JointEffortController"},
    {JointControllerType::kVelocity, "velocity_controllers/JointVelocityController"},
    {JointControllerType::kPosition, "position_controllers/JointPositionController"},
};

// Motor strength for joints without an effort limit in the URDF [N m or N].
constexpr double kUnlimitedMotorEffort = 1e3;

}  // namespace

const char* jointControllerTypeName(JointControllerType type) {
  for (const TypeName& t : kTypeNames) {
    if (t.type == type) return t.name;
  }
  return "";
}

bool parseJointControllerType(const std::string& name, JointControllerType& type) {
  for (const TypeName& t : kTypeNames) {
    if (name == t.name) {
      type = t.type;
      return true;
    }
  }
  return false;
}

bool jointControllerUsesPid(JointControllerType type) {
  return type == JointControllerType::kEffortPosition || type == JointControllerType::kEffortVelocity;
}

JointController::JointController(Simulation& sim, int robot, int joint, JointControllerType type,
                                 const PidController::Gains& pid)
    : sim_(sim), robot_(robot), joint_(joint), type_(type), pid_(pid) {
  const cp::JointSpec& spec = sim.robot(robot).model.joints.at(joint);
  effort_limit_ = spec.effort_limit;
  velocity_limit_ = spec.velocity_limit;
  has_limits_ = spec.has_position_limits && spec.type != cp::JointType::kContinuous && spec.lower < spec.upper;
  lower_ = spec.lower;
  upper_ = spec.upper;
  continuous_ = spec.type == cp::JointType::kContinuous;
  reset();
}

bool JointController::setCommand(double command) {
  if (!std::isfinite(command)) return false;
  if ((type_ == JointControllerType::kEffortPosition || type_ == JointControllerType::kPosition) && has_limits_) {
    command = std::clamp(command, lower_, upper_);
  }
  if (type_ == JointControllerType::kEffortVelocity || type_ == JointControllerType::kVelocity) {
    if (velocity_limit_ > 0.0) command = std::clamp(command, -velocity_limit_, velocity_limit_);
  }
  if (type_ == JointControllerType::kEffort && effort_limit_ > 0.0) {
    command = std::clamp(command, -effort_limit_, effort_limit_);
  }
  command_ = command;
  return true;
}

void JointController::setStopped(bool stopped) {
  if (stopped && !stopped_) held_position_ = sim_.engine().jointPosition(sim_.robot(robot_).id, joint_);
  stopped_ = stopped;
}

void JointController::reset() {
  const cp::ModelId id = sim_.robot(robot_).id;
  pid_.reset();
  effort_ = motor_velocity_ = 0.0;
  // A position controller starts by holding where the joint is (ros_controllers' starting()).
  const bool position = type_ == JointControllerType::kEffortPosition || type_ == JointControllerType::kPosition;
  command_ = position ? sim_.engine().jointPosition(id, joint_) : 0.0;
}

void JointController::update(double dt_s) {
  const cp::PhysicsEngine& engine = sim_.engine();
  const cp::ModelId id = sim_.robot(robot_).id;
  effort_ = 0.0;
  switch (type_) {
    case JointControllerType::kEffortPosition:
      if (!stopped_) {
        // Continuous joints take the shortest way round (angles::shortest_angular_distance).
        const double error = command_ - engine.jointPosition(id, joint_);
        effort_ = pid_.update(continuous_ ? cp::wrapAngle(error) : error, dt_s);
      }
      break;
    case JointControllerType::kEffortVelocity:
      if (!stopped_) effort_ = pid_.update(command_ - engine.jointVelocity(id, joint_), dt_s);
      break;
    case JointControllerType::kEffort:
      if (!stopped_) effort_ = command_;
      break;
    case JointControllerType::kVelocity:
      motor_velocity_ = stopped_ ? 0.0 : command_;
      break;
    case JointControllerType::kPosition:
      break;  // recomputed at every step in apply()
  }
  if (effort_limit_ > 0.0) effort_ = std::clamp(effort_, -effort_limit_, effort_limit_);
}

void JointController::apply() {
  cp::PhysicsEngine& engine = sim_.engine();
  const cp::ModelId id = sim_.robot(robot_).id;
  const double max_effort = effort_limit_ > 0.0 ? effort_limit_ : kUnlimitedMotorEffort;
  switch (type_) {
    case JointControllerType::kEffortPosition:
    case JointControllerType::kEffortVelocity:
    case JointControllerType::kEffort:
      if (effort_ != 0.0) engine.addJointEffort(id, joint_, effort_);
      break;
    case JointControllerType::kVelocity:
      engine.setJointVelocityMotor(id, joint_, motor_velocity_, max_effort);
      break;
    case JointControllerType::kPosition: {
      const double target = stopped_ ? held_position_ : command_;
      double velocity = (target - engine.jointPosition(id, joint_)) / sim_.stepS();
      if (velocity_limit_ > 0.0) velocity = std::clamp(velocity, -velocity_limit_, velocity_limit_);
      engine.setJointVelocityMotor(id, joint_, velocity, max_effort);
      break;
    }
  }
}

}  // namespace conde_sim
