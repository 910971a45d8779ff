// libgazebo_ros_control.so: ros_control-style joint controllers configured by the usual
// controller YAML on the parameter server, each listening on <namespace>/<controller>/command
// (std_msgs/Float64), so that setups written for gazebo_ros_control + controller_manager run
// without them (Debian packages neither).
//
//   <gazebo><plugin name="gazebo_ros_control" filename="libgazebo_ros_control.so">
//     <robotNamespace>/</robotNamespace>
//     <controllers>joint_state_ctrlr left_steering_ctrlr right_steering_ctrlr</controllers>  <!-- optional -->
//   </plugin></gazebo>
//
// and, loaded with <rosparam file="...yaml"/> into the same namespace before the simulator starts:
//   left_steering_ctrlr:
//     type: effort_controllers/JointPositionController
//     joint: left_steering_joint
//     pid: {p: 4.0, i: 0.0, d: 1.0, i_clamp: 0.0}
//   joint_state_ctrlr:
//     type: joint_state_controller/JointStateController
//     publish_rate: 30
//
// Controllers: the names in <controllers> (our extension; in Gazebo setups `controller_manager
// spawner` names them), or else every `<namespace>/<name>/type` naming a ros_control controller
// (`package/SomethingController`). Supported types: see joint_controller.h, plus
// joint_state_controller/JointStateController (all movable joints on <namespace>/joint_states,
// at publish_rate, efforts = the controllers' outputs). Any other type, an unknown key or an
// unknown joint stops the simulator with a message naming the controller, the key and the value.
// pid accepts p, i, d, i_clamp (or i_clamp_min = -i_clamp_max), antiwindup, publish_state.
//
// position_controllers/JointTrajectoryController (as in ros_controllers): `joints: [...]`
// (optional `mimic_joints: {follower: master}`, masters among `joints`), listening on
// <controller>/command (trajectory_msgs/JointTrajectory, joint_names = the controller's joints in
// any order). A trajectory replaces the one before; it starts at header.stamp (0 = on receipt)
// from the joints' current targets and is sampled every step (joint_trajectory.h: linear without
// velocities, cubic with them); each joint is driven like a position_controllers joint.
// Not supported: goal constraints, the follow_joint_trajectory action, partial goals.
//
// Coupled joints (our extension): a joint controller may list `mimic_joints: [name, ...]`, joints
// that get a controller of the same type and gains with the same command, as if one motor drove
// them all (the NAO's two HipYawPitch joints). URDF <mimic> tags are ignored by the physics
// (conde_physics warns), so this is how a mimic joint follows its master on both engines;
// multiplier 1 and offset 0 only.
//
// Gazebo keys: <controlPeriod> [s] (default: every physics step), <robotSimType> (only
// gazebo_ros_control/DefaultRobotHWSim), <eStopTopic> (std_msgs/Bool: while true, no effort,
// velocity 0, positions held); <robotParam> and <legacyModeNS> are accepted and have no effect
// (the robot is the URDF this block sits in). Differences: the namespace defaults to the robot's
// namespace (Gazebo: the model name); controller_manager's services (list_controllers, ...) are
// not offered, because controller_manager_msgs is not packaged for Debian.
#include <sensor_msgs/JointState.h>
#include <std_msgs/Bool.h>
#include <std_msgs/Float64.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "conde_sim/joint_controller.h"
#include "conde_sim/joint_trajectory.h"
#include "conde_sim/plugin.h"
#include "conde_sim/update_timer.h"

namespace conde_sim {
namespace {

constexpr char kJointStateType[] = "joint_state_controller/JointStateController";
constexpr char kTrajectoryType[] = "position_controllers/JointTrajectoryController";

std::string supportedTypes() {
  std::string s;
  for (auto t : {JointControllerType::kEffortPosition, JointControllerType::kEffortVelocity,
                 JointControllerType::kEffort, JointControllerType::kVelocity, JointControllerType::kPosition}) {
    s += std::string(jointControllerTypeName(t)) + ", ";
  }
  return s + kTrajectoryType + ", " + kJointStateType;
}

// A ros_control controller type by convention: "package/NameController".
bool looksLikeControllerType(const std::string& type) {
  const size_t slash = type.find('/');
  return slash != std::string::npos && slash > 0 && type.size() > 10 &&
         type.compare(type.size() - 10, 10, "Controller") == 0;
}

std::string typeName(XmlRpc::XmlRpcValue::Type t) {
  using V = XmlRpc::XmlRpcValue;
  static const std::map<V::Type, std::string> names = {{V::TypeBoolean, "a boolean"}, {V::TypeInt, "an integer"},
                                                       {V::TypeDouble, "a number"},   {V::TypeString, "a string"},
                                                       {V::TypeArray, "a list"},      {V::TypeStruct, "a dictionary"}};
  const auto it = names.find(t);
  return it == names.end() ? "something else" : it->second;
}

class RosControlPlugin : public SimPlugin {
 public:
  void configure(PluginParams& params, ros::NodeHandle& nh) override {
    params_where_ = params.where();
    nh_ = nh;
    const std::string sim_type = params.getString("robotSimType", "gazebo_ros_control/DefaultRobotHWSim");
    if (sim_type != "gazebo_ros_control/DefaultRobotHWSim") {
      throw params.error("robotSimType",
                         "only gazebo_ros_control/DefaultRobotHWSim is supported, got '" + sim_type + "'");
    }
    const double period_s = params.getDouble("controlPeriod", 0.0);
    if (period_s < 0) throw params.error("controlPeriod", "must not be negative");
    control_timer_ = period_s > 0 ? UpdateTimer::everySteps(std::llround(period_s / ctx_.sim->stepS())) : UpdateTimer();
    const std::string estop_topic = params.getString("eStopTopic", "");
    params.ignore({"robotParam", "legacyModeNS"});

    std::vector<std::string> names = params.getList("controllers");
    const bool listed = params.has("controllers");
    if (!listed) names = findControllers();
    for (const std::string& name : names) loadController(name, listed);
    if (names.empty()) {
      ROS_WARN("%s: no controllers found under %s (give <controllers> or load the controller YAML first)",
               params_where_.c_str(), nh_.getNamespace().c_str());
    }
    if (!estop_topic.empty()) estop_sub_ = nh_.subscribe(estop_topic, 1, &RosControlPlugin::onEStop, this);
    std::string summary;
    for (const auto& c : controllers_) summary += " " + c.name;
    for (const auto& t : trajectories_) summary += " " + t->name;
    if (joint_state_pub_) summary += " " + joint_state_name_;
    ROS_INFO("%s: ros_control controllers in %s:%s", ctx_.sim->robot(ctx_.robot).spec.name.c_str(),
             nh_.getNamespace().c_str(), summary.c_str());
  }

  void reset() override {
    for (auto& c : controllers_) {
      for (JointController* j : c.all()) j->reset();
    }
    for (auto& t : trajectories_) {
      for (auto& j : t->controllers) j->reset();
      t->trajectory = JointTrajectory();
    }
  }

  void beforeStep() override {
    for (auto& t : trajectories_) followTrajectory(*t);
    if (control_timer_.due(ctx_.sim->stepCount())) {
      for (auto& c : controllers_) {
        for (JointController* j : c.all()) j->update(control_timer_.stepsPerUpdate() * ctx_.sim->stepS());
      }
      for (auto& t : trajectories_) {
        for (auto& j : t->controllers) j->update(control_timer_.stepsPerUpdate() * ctx_.sim->stepS());
      }
    }
    for (auto& c : controllers_) {
      for (JointController* j : c.all()) j->apply();
    }
    for (auto& t : trajectories_) {
      for (auto& j : t->controllers) j->apply();
    }
  }

  void afterStep() override {
    if (!joint_state_pub_ || !joint_state_timer_.due(ctx_.sim->stepCount())) return;
    if (joint_state_pub_.getNumSubscribers() == 0) return;
    const cp::PhysicsEngine& e = ctx_.sim->engine();
    const cp::ModelId id = ctx_.sim->robot(ctx_.robot).id;
    joint_state_.header.stamp = ctx_.now();
    for (size_t j = 0; j < joint_state_.name.size(); ++j) {
      joint_state_.position[j] = e.jointPosition(id, static_cast<int>(j));
      joint_state_.velocity[j] = e.jointVelocity(id, static_cast<int>(j));
      joint_state_.effort[j] = 0.0;
    }
    for (const auto& c : controllers_) {
      for (const JointController* j : c.all()) joint_state_.effort[j->joint()] = j->effort();
    }
    for (const auto& t : trajectories_) {
      for (const auto& j : t->controllers) joint_state_.effort[j->joint()] = j->effort();
    }
    joint_state_pub_.publish(joint_state_);
  }

 private:
  struct Loaded {
    std::string name;
    std::unique_ptr<JointController> controller;
    std::vector<std::unique_ptr<JointController>> mimics;  // mimic_joints, same command
    ros::Subscriber sub;

    std::vector<JointController*> all() const {
      std::vector<JointController*> v = {controller.get()};
      for (const auto& m : mimics) v.push_back(m.get());
      return v;
    }
  };

  // A position_controllers/JointTrajectoryController: one position-motor controller per joint
  // (masters first, in `joints` order, then the mimic joints), the trajectory being followed.
  struct TrajectoryLoaded {
    std::string name;
    std::vector<std::string> joint_names;  // the masters, in `joints` order
    std::vector<std::unique_ptr<JointController>> controllers;
    std::vector<size_t> master_of;  // per controller: index into joint_names
    JointTrajectory trajectory;
    double start_s = 0.0;  // simulated time of the trajectory's start
    ros::Subscriber sub;
  };

  // The index of the movable joint `joint` named by `key` of controller `name`; an error if the
  // robot has no such joint or another controller already drives it.
  int jointKey(const std::string& name, const std::string& key, const std::string& joint) const {
    const int index = ctx_.sim->robot(ctx_.robot).model.jointIndex(joint);
    if (index < 0) {
      throw controllerError(
          name, key,
          "robot '" + ctx_.sim->robot(ctx_.robot).spec.name + "' has no movable joint named '" + joint + "'");
    }
    for (const auto& c : controllers_) {
      for (const JointController* j : c.all()) {
        if (j->joint() == index) {
          throw controllerError(name, key, "joint '" + joint + "' is already controlled by '" + c.name + "'");
        }
      }
    }
    for (const auto& t : trajectories_) {
      for (const auto& j : t->controllers) {
        if (j->joint() == index) {
          throw controllerError(name, key, "joint '" + joint + "' is already controlled by '" + t->name + "'");
        }
      }
    }
    return index;
  }

  // Controllers on the parameter server: direct children of the namespace with a `type` key
  // naming a ros_control controller, in name order.
  std::vector<std::string> findControllers() const {
    std::vector<std::string> all, names;
    ros::param::getParamNames(all);
    std::string ns = nh_.getNamespace();
    if (ns.empty() || ns.back() != '/') ns += "/";
    for (const std::string& key : all) {
      if (key.compare(0, ns.size(), ns) != 0) continue;
      const std::string rest = key.substr(ns.size());
      const size_t slash = rest.find('/');
      if (slash == std::string::npos || rest.substr(slash) != "/type") continue;
      std::string type;
      if (ros::param::get(key, type) && looksLikeControllerType(type)) names.push_back(rest.substr(0, slash));
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  PluginError controllerError(const std::string& name, const std::string& key, const std::string& what) const {
    return PluginError(params_where_ + ": controller '" + name + "': parameter " + nh_.resolveName(name + "/" + key) +
                       ": " + what);
  }

  void loadController(const std::string& name, bool listed) {
    XmlRpc::XmlRpcValue config;
    if (!nh_.getParam(name, config)) {
      throw controllerError(name, "type",
                            listed ? "not set: load the controller YAML before the simulator starts" : "not set");
    }
    if (config.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
      throw PluginError(params_where_ + ": controller '" + name + "': parameter " + nh_.resolveName(name) +
                        ": expected a dictionary, got " + typeName(config.getType()));
    }
    const std::string type = stringKey(name, config, "type");
    if (type == kJointStateType) {
      loadJointStateController(name, config);
      return;
    }
    if (type == kTrajectoryType) {
      loadTrajectoryController(name, config);
      return;
    }
    JointControllerType jtype;
    if (!parseJointControllerType(type, jtype)) {
      throw controllerError(name, "type",
                            "unsupported controller type '" + type + "' (supported: " + supportedTypes() + ")");
    }
    const std::vector<std::string> allowed = {"type", "joint", "pid", "mimic_joints"};
    checkKeys(name, config, "", allowed);
    const int index = jointKey(name, "joint", stringKey(name, config, "joint"));
    std::vector<int> mimic_indices;
    if (config.hasMember("mimic_joints")) {
      XmlRpc::XmlRpcValue& list = config["mimic_joints"];
      if (list.getType() != XmlRpc::XmlRpcValue::TypeArray) {
        throw controllerError(name, "mimic_joints", "expected a list of joint names, got " + typeName(list.getType()));
      }
      for (int k = 0; k < list.size(); ++k) {
        if (list[k].getType() != XmlRpc::XmlRpcValue::TypeString) {
          throw controllerError(name, "mimic_joints",
                                "expected a list of joint names, got " + typeName(list[k].getType()));
        }
        const int mimic = jointKey(name, "mimic_joints", static_cast<std::string>(list[k]));
        if (mimic == index || std::find(mimic_indices.begin(), mimic_indices.end(), mimic) != mimic_indices.end()) {
          throw controllerError(name, "mimic_joints",
                                "joint '" + static_cast<std::string>(list[k]) + "' is listed twice");
        }
        mimic_indices.push_back(mimic);
      }
    }
    PidController::Gains gains;
    if (jointControllerUsesPid(jtype)) {
      if (!config.hasMember("pid")) throw controllerError(name, "pid", "required for " + type + " (p, i, d, i_clamp)");
      gains = readPid(name, config["pid"]);
    } else if (config.hasMember("pid")) {
      throw controllerError(name, "pid", type + " has no PID");
    }
    Loaded loaded;
    loaded.name = name;
    loaded.controller = std::make_unique<JointController>(*ctx_.sim, ctx_.robot, index, jtype, gains);
    std::vector<JointController*> driven = {loaded.controller.get()};
    for (int mimic : mimic_indices) {
      loaded.mimics.push_back(std::make_unique<JointController>(*ctx_.sim, ctx_.robot, mimic, jtype, gains));
      driven.push_back(loaded.mimics.back().get());
    }
    const std::string topic = name + "/command";
    loaded.sub = nh_.subscribe<std_msgs::Float64>(topic, 1, [this, driven, name](const std_msgs::Float64::ConstPtr& m) {
      bool ok = true;
      for (JointController* c : driven) ok = c->setCommand(m->data) && ok;
      if (!ok) {
        ROS_WARN_THROTTLE(1.0, "%s: ignoring a non-finite command on %s", name.c_str(),
                          nh_.resolveName(name + "/command").c_str());
      }
    });
    controllers_.push_back(std::move(loaded));
  }

  void loadTrajectoryController(const std::string& name, XmlRpc::XmlRpcValue& config) {
    checkKeys(name, config, "", {"type", "joints", "mimic_joints"});
    auto t = std::make_unique<TrajectoryLoaded>();
    t->name = name;
    if (!config.hasMember("joints") || config["joints"].getType() != XmlRpc::XmlRpcValue::TypeArray ||
        config["joints"].size() == 0) {
      throw controllerError(name, "joints", "required: a list of joint names");
    }
    auto add = [&](const std::string& key, const std::string& joint, size_t master) {
      const int index = jointKey(name, key, joint);
      for (const auto& j : t->controllers) {
        if (j->joint() == index) throw controllerError(name, key, "joint '" + joint + "' is listed twice");
      }
      t->controllers.push_back(std::make_unique<JointController>(
          *ctx_.sim, ctx_.robot, index, JointControllerType::kPosition, PidController::Gains()));
      t->master_of.push_back(master);
    };
    for (int k = 0; k < config["joints"].size(); ++k) {
      if (config["joints"][k].getType() != XmlRpc::XmlRpcValue::TypeString) {
        throw controllerError(name, "joints", "expected a list of joint names");
      }
      t->joint_names.push_back(static_cast<std::string>(config["joints"][k]));
      add("joints", t->joint_names.back(), t->joint_names.size() - 1);
    }
    if (config.hasMember("mimic_joints")) {
      XmlRpc::XmlRpcValue& mimics = config["mimic_joints"];
      if (mimics.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
        throw controllerError(name, "mimic_joints", "expected {follower joint: master joint}");
      }
      for (auto& kv : mimics) {
        const std::string master =
            kv.second.getType() == XmlRpc::XmlRpcValue::TypeString ? static_cast<std::string>(kv.second) : "";
        const auto it = std::find(t->joint_names.begin(), t->joint_names.end(), master);
        if (it == t->joint_names.end()) {
          throw controllerError(name, "mimic_joints/" + kv.first, "the master must be one of `joints`");
        }
        add("mimic_joints", kv.first, static_cast<size_t>(it - t->joint_names.begin()));
      }
    }
    TrajectoryLoaded* loaded = t.get();
    t->sub = nh_.subscribe<trajectory_msgs::JointTrajectory>(
        name + "/command", 1,
        [this, loaded](const trajectory_msgs::JointTrajectory::ConstPtr& m) { onTrajectory(*loaded, *m); });
    trajectories_.push_back(std::move(t));
  }

  void onTrajectory(TrajectoryLoaded& t, const trajectory_msgs::JointTrajectory& msg) {
    const std::string topic = nh_.resolveName(t.name + "/command");
    // Column of each of the controller's joints in the message.
    std::vector<size_t> column(t.joint_names.size());
    if (msg.joint_names.size() != t.joint_names.size()) {
      ROS_WARN("%s: ignoring a trajectory with %zu joints (the controller has %zu)", topic.c_str(),
               msg.joint_names.size(), t.joint_names.size());
      return;
    }
    for (size_t j = 0; j < t.joint_names.size(); ++j) {
      const auto it = std::find(msg.joint_names.begin(), msg.joint_names.end(), t.joint_names[j]);
      if (it == msg.joint_names.end()) {
        ROS_WARN("%s: ignoring a trajectory without joint '%s'", topic.c_str(), t.joint_names[j].c_str());
        return;
      }
      column[j] = static_cast<size_t>(it - msg.joint_names.begin());
    }
    std::vector<TrajectoryPoint> points;
    for (const auto& p : msg.points) {
      TrajectoryPoint point;
      point.time_s = p.time_from_start.toSec();
      if (p.positions.size() != column.size() || (!p.velocities.empty() && p.velocities.size() != column.size())) {
        ROS_WARN("%s: ignoring a trajectory whose points do not give one position (and velocity) per joint",
                 topic.c_str());
        return;
      }
      for (size_t j = 0; j < column.size(); ++j) {
        point.positions.push_back(p.positions[column[j]]);
        if (!p.velocities.empty()) point.velocities.push_back(p.velocities[column[j]]);
      }
      for (double v : point.positions) {
        if (!std::isfinite(v)) {
          ROS_WARN("%s: ignoring a trajectory with a non-finite position", topic.c_str());
          return;
        }
      }
      points.push_back(point);
    }
    std::vector<double> start(t.joint_names.size());
    for (size_t c = 0; c < t.controllers.size(); ++c) {
      if (c < t.joint_names.size()) start[c] = t.controllers[c]->command();
    }
    try {
      t.trajectory = JointTrajectory(start, points);
    } catch (const std::invalid_argument& e) {
      ROS_WARN("%s: ignoring a trajectory: %s", topic.c_str(), e.what());
      return;
    }
    t.start_s = msg.header.stamp.isZero() ? ctx_.sim->timeS() : msg.header.stamp.toSec();
  }

  void followTrajectory(TrajectoryLoaded& t) {
    if (t.trajectory.empty()) return;
    const std::vector<double> target = t.trajectory.sample(ctx_.sim->timeS() - t.start_s);
    for (size_t c = 0; c < t.controllers.size(); ++c) t.controllers[c]->setCommand(target[t.master_of[c]]);
  }

  void loadJointStateController(const std::string& name, XmlRpc::XmlRpcValue& config) {
    checkKeys(name, config, "", {"type", "publish_rate", "extra_joints"});
    if (config.hasMember("extra_joints")) throw controllerError(name, "extra_joints", "is not supported");
    if (joint_state_pub_) {
      throw controllerError(name, "type",
                            "a second " + std::string(kJointStateType) + " (the first is '" + joint_state_name_ + "')");
    }
    double rate_hz = 50.0;  // joint_state_controller's default
    if (config.hasMember("publish_rate")) rate_hz = number(name, "publish_rate", config["publish_rate"]);
    if (rate_hz <= 0) throw controllerError(name, "publish_rate", "must be positive");
    joint_state_timer_ = UpdateTimer(rate_hz, ctx_.sim->stepS());
    joint_state_name_ = name;
    const cp::ArticulatedModel& model = ctx_.sim->robot(ctx_.robot).model;
    for (const cp::JointSpec& j : model.joints) joint_state_.name.push_back(j.name);
    joint_state_.position.resize(model.joints.size());
    joint_state_.velocity.resize(model.joints.size());
    joint_state_.effort.resize(model.joints.size());
    joint_state_pub_ = nh_.advertise<sensor_msgs::JointState>("joint_states", 10);
  }

  PidController::Gains readPid(const std::string& name, XmlRpc::XmlRpcValue& pid) {
    if (pid.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
      throw controllerError(name, "pid", "expected a dictionary (p, i, d, i_clamp), got " + typeName(pid.getType()));
    }
    checkKeys(name, pid, "pid/",
              {"p", "i", "d", "i_clamp", "i_clamp_min", "i_clamp_max", "antiwindup", "publish_state"});
    PidController::Gains g;
    auto get = [&](const char* key, double fallback) {
      return pid.hasMember(key) ? number(name, std::string("pid/") + key, pid[key]) : fallback;
    };
    g.p = get("p", 0.0);
    g.i = get("i", 0.0);
    g.d = get("d", 0.0);
    g.i_clamp = std::abs(get("i_clamp", 0.0));
    if (pid.hasMember("i_clamp_max") || pid.hasMember("i_clamp_min")) {
      const double hi = get("i_clamp_max", g.i_clamp), lo = get("i_clamp_min", -hi);
      if (std::abs(lo + hi) > 1e-12) {
        throw controllerError(name, "pid/i_clamp_min", "must be -i_clamp_max (asymmetric clamps are not supported)");
      }
      g.i_clamp = std::abs(hi);
    }
    if (g.i != 0.0 && g.i_clamp == 0.0) {
      // control_toolbox clamps the integral term to [0, 0] when no i_clamp is given: i has no effect.
      g.i = 0.0;
      ROS_WARN("%s: controller '%s': pid/i is ignored without pid/i_clamp (as in control_toolbox)",
               params_where_.c_str(), name.c_str());
    }
    return g;
  }

  void checkKeys(const std::string& name, XmlRpc::XmlRpcValue& config, const std::string& prefix,
                 const std::vector<std::string>& allowed) {
    for (auto& kv : config) {
      if (std::find(allowed.begin(), allowed.end(), kv.first) != allowed.end()) continue;
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw controllerError(name, prefix + kv.first, "unknown key (expected one of: " + list + ")");
    }
  }

  std::string stringKey(const std::string& name, XmlRpc::XmlRpcValue& config, const std::string& key) {
    if (!config.hasMember(key)) throw controllerError(name, key, "required key is missing");
    if (config[key].getType() != XmlRpc::XmlRpcValue::TypeString) {
      throw controllerError(name, key, "expected a string, got " + typeName(config[key].getType()));
    }
    return static_cast<std::string>(config[key]);
  }

  double number(const std::string& name, const std::string& key, XmlRpc::XmlRpcValue& v) {
    if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) return static_cast<double>(v);
    if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(v);
    if (v.getType() == XmlRpc::XmlRpcValue::TypeBoolean) return static_cast<bool>(v) ? 1.0 : 0.0;
    throw controllerError(name, key, "expected a number, got " + typeName(v.getType()));
  }

  void onEStop(const std_msgs::Bool::ConstPtr& msg) {
    for (auto& c : controllers_) c.controller->setStopped(msg->data);
  }

  ros::NodeHandle nh_;
  std::string params_where_;
  UpdateTimer control_timer_, joint_state_timer_;
  std::vector<Loaded> controllers_;
  std::vector<std::unique_ptr<TrajectoryLoaded>> trajectories_;
  std::string joint_state_name_;
  ros::Publisher joint_state_pub_;
  sensor_msgs::JointState joint_state_;
  ros::Subscriber estop_sub_;
};

}  // namespace

std::unique_ptr<SimPlugin> makeRosControlPlugin() { return std::make_unique<RosControlPlugin>(); }

}  // namespace conde_sim
