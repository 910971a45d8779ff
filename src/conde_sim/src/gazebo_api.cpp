#include "gazebo_api.h"

#include <gazebo_msgs/LinkStates.h>
#include <gazebo_msgs/ModelStates.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <exception>

#include "conde_physics/sdf_world.h"
#include "conde_sim/ros_conversions.h"

namespace conde_sim {

namespace cp = conde_physics;

namespace {

bool isWorldFrame(const std::string& frame) {
  return frame.empty() || frame == "world" || frame == "map" || frame == "/map";
}

bool finite(const geometry_msgs::Pose& p) {
  return std::isfinite(p.position.x) && std::isfinite(p.position.y) && std::isfinite(p.position.z) &&
         std::isfinite(p.orientation.x) && std::isfinite(p.orientation.y) && std::isfinite(p.orientation.z) &&
         std::isfinite(p.orientation.w);
}

using conde_sim::finite;  // the overloads below hide those of ros_conversions.h otherwise
using conde_sim::fromMsg;
bool finite(const geometry_msgs::Twist& t) { return finite(t.linear) && finite(t.angular); }

// A quaternion of zeros (an unset field) is the identity, as Gazebo normalises it.
cp::Pose fromMsg(const geometry_msgs::Pose& p) {
  const geometry_msgs::Quaternion& q = p.orientation;
  const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  const cp::Quat rotation = norm > 1e-12 ? cp::Quat(q.w / norm, q.x / norm, q.y / norm, q.z / norm) : cp::Quat();
  return cp::Pose(fromMsg(p.position), rotation);
}

cp::Twist fromMsg(const geometry_msgs::Twist& t) {
  cp::Twist twist;
  twist.linear_mps = fromMsg(t.linear);
  twist.angular_radps = fromMsg(t.angular);
  return twist;
}

geometry_msgs::Twist toTwistMsg(const cp::Twist& t) {
  geometry_msgs::Twist msg;
  msg.linear = toVector3Msg(t.linear_mps);
  msg.angular = toVector3Msg(t.angular_radps);
  return msg;
}

// World state seen from `frame`: pose relative to it, velocities in its axes, relative to its.
void toFrame(const cp::Pose& frame_pose, const cp::Twist& frame_twist, cp::Pose& pose, cp::Twist& twist) {
  const cp::Quat to_frame = frame_pose.orientation.conjugate();
  pose = frame_pose.inverse() * pose;
  twist.linear_mps = to_frame.rotate(twist.linear_mps - frame_twist.linear_mps);
  twist.angular_radps = to_frame.rotate(twist.angular_radps - frame_twist.angular_radps);
}

// A state given in `frame` into the world, as Gazebo's set_*_state: the pose composed with the
// frame's, the velocities rotated (not offset by the frame's own).
void fromFrame(const cp::Pose& frame_pose, cp::Pose& pose, cp::Twist& twist) {
  pose = frame_pose * pose;
  twist.linear_mps = frame_pose.orientation.rotate(twist.linear_mps);
  twist.angular_radps = frame_pose.orientation.rotate(twist.angular_radps);
}

}  // namespace

GazeboApi::GazeboApi(SimHost& host, Simulation& sim, const std::string& ns, ros::NodeHandle& service_nh,
                     double states_rate_hz, double poses_rate_hz)
    : host_(host), sim_(sim), states_timer_(states_rate_hz, sim.stepS()), poses_timer_(poses_rate_hz, sim.stepS()) {
  const std::string p = ns + "/";
  services_.push_back(service_nh.advertiseService(p + "get_model_state", &GazeboApi::onGetModelState, this));
  services_.push_back(service_nh.advertiseService(p + "set_model_state", &GazeboApi::onSetModelState, this));
  services_.push_back(service_nh.advertiseService(p + "get_link_state", &GazeboApi::onGetLinkState, this));
  services_.push_back(service_nh.advertiseService(p + "set_link_state", &GazeboApi::onSetLinkState, this));
  services_.push_back(service_nh.advertiseService(p + "get_world_properties", &GazeboApi::onGetWorldProperties, this));
  services_.push_back(service_nh.advertiseService(p + "get_model_properties", &GazeboApi::onGetModelProperties, this));
  services_.push_back(
      service_nh.advertiseService(p + "get_physics_properties", &GazeboApi::onGetPhysicsProperties, this));
  services_.push_back(service_nh.advertiseService(p + "reset_simulation", &GazeboApi::onResetWorld, this));
  services_.push_back(service_nh.advertiseService(p + "reset_world", &GazeboApi::onResetWorld, this));
  services_.push_back(service_nh.advertiseService(p + "pause_physics", &GazeboApi::onPause, this));
  services_.push_back(service_nh.advertiseService(p + "unpause_physics", &GazeboApi::onUnpause, this));
  services_.push_back(service_nh.advertiseService(p + "apply_body_wrench", &GazeboApi::onApplyBodyWrench, this));
  services_.push_back(service_nh.advertiseService(p + "clear_body_wrenches", &GazeboApi::onClearBodyWrenches, this));
  services_.push_back(service_nh.advertiseService(p + "spawn_urdf_model", &GazeboApi::onSpawnUrdf, this));
  services_.push_back(service_nh.advertiseService(p + "spawn_sdf_model", &GazeboApi::onSpawnSdf, this));
  services_.push_back(service_nh.advertiseService(p + "delete_model", &GazeboApi::onDeleteModel, this));
  // Topics on the global queue: the loop's thread.
  ros::NodeHandle nh;
  model_states_pub_ = nh.advertise<gazebo_msgs::ModelStates>(p + "model_states", 1);
  link_states_pub_ = nh.advertise<gazebo_msgs::LinkStates>(p + "link_states", 1);
  model_poses_pub_ = ros::NodeHandle("~").advertise<tf2_msgs::TFMessage>("model_poses", 10);
  model_state_sub_ = nh.subscribe(p + "set_model_state", 10,
                                  &GazeboApi::onStateTopic<gazebo_msgs::ModelState, &GazeboApi::setModelState>, this);
  link_state_sub_ = nh.subscribe(p + "set_link_state", 10,
                                 &GazeboApi::onStateTopic<gazebo_msgs::LinkState, &GazeboApi::setLinkState>, this);
}

// --- frames and names (loop thread) ---

bool GazeboApi::findLink(const std::string& scoped, ModelRef& model, std::string& link) const {
  const size_t sep = scoped.find("::");
  if (sep == std::string::npos) return false;
  model = sim_.findModel(scoped.substr(0, sep));
  link = scoped.substr(sep + 2);
  return model.valid() && !link.empty() && sim_.hasLink(model, link);
}

bool GazeboApi::frameState(const std::string& frame, Frame& state) const {
  if (isWorldFrame(frame)) {
    state = Frame();
    return true;
  }
  ModelRef model = sim_.findModel(frame);
  std::string link;
  if (!model.valid() && !findLink(frame, model, link)) return false;
  state.pose = sim_.linkPose(model, link);
  state.twist = sim_.linkTwist(model, link);
  return true;
}

// --- per step (loop thread) ---

void GazeboApi::beforeStep() {
  const double t = sim_.timeS();
  for (auto it = wrenches_.begin(); it != wrenches_.end();) {
    ModelRef model = sim_.findModel(it->model);
    if (!model.valid() || (it->end_s >= 0.0 && t >= it->end_s - 1e-9)) {
      it = wrenches_.erase(it);
      continue;
    }
    if (t >= it->start_s - 1e-9) {
      const cp::Vec3 point = sim_.linkPose(model, it->link) * it->point_in_link;
      sim_.addLinkWrench(model, it->link, it->force_N, it->torque_Nm, point);
    }
    ++it;
  }
}

void GazeboApi::afterStep() {
  const bool states_due = states_timer_.due(sim_.stepCount());  // first: the cheaper tests, every step
  const bool poses_due = poses_timer_.due(sim_.stepCount());
  if (!states_due && !poses_due) return;
  const bool models = states_due && model_states_pub_.getNumSubscribers() > 0;
  const bool links = states_due && link_states_pub_.getNumSubscribers() > 0;
  const bool poses = poses_due && model_poses_pub_.getNumSubscribers() > 0;
  if (!models && !links && !poses) return;
  gazebo_msgs::ModelStates model_states;
  gazebo_msgs::LinkStates link_states;
  tf2_msgs::TFMessage model_poses;
  const ros::Time stamp(sim_.timeS());
  for (const ModelRef& model : sim_.models()) {
    const std::string name = sim_.modelName(model);
    if (poses) {
      geometry_msgs::TransformStamped t;
      t.header.stamp = stamp;
      t.header.frame_id = "world";
      t.child_frame_id = name;
      const geometry_msgs::Pose pose = toMsg(sim_.linkPose(model, ""));
      t.transform.translation.x = pose.position.x;
      t.transform.translation.y = pose.position.y;
      t.transform.translation.z = pose.position.z;
      t.transform.rotation = pose.orientation;
      model_poses.transforms.push_back(t);
    }
    if (models) {
      model_states.name.push_back(name);
      model_states.pose.push_back(toMsg(sim_.linkPose(model, "")));
      model_states.twist.push_back(toTwistMsg(sim_.linkTwist(model, "")));
    }
    if (!links) continue;
    for (const std::string& link : sim_.bodyLinkNames(model)) {
      link_states.name.push_back(name + "::" + link);
      link_states.pose.push_back(toMsg(sim_.linkPose(model, link)));
      link_states.twist.push_back(toTwistMsg(sim_.linkTwist(model, link)));
    }
  }
  if (models) model_states_pub_.publish(model_states);
  if (links) link_states_pub_.publish(link_states);
  if (poses) model_poses_pub_.publish(model_poses);
}

void GazeboApi::forgetModel(const std::string& model_name) {
  for (auto it = wrenches_.begin(); it != wrenches_.end();) it = it->model == model_name ? wrenches_.erase(it) : it + 1;
}

// --- state services ---

bool GazeboApi::onGetModelState(gazebo_msgs::GetModelState::Request& req, gazebo_msgs::GetModelState::Response& res) {
  host_.runOnLoop([&] {
    res.header.stamp = ros::Time(sim_.timeS());
    const ModelRef model = sim_.findModel(req.model_name);
    Frame frame;
    if (!model.valid()) {
      res.success = false;
      res.status_message = "GetModelState: model [" + req.model_name + "] does not exist";
      return;
    }
    if (!frameState(req.relative_entity_name, frame)) {
      res.success = false;
      res.status_message = "GetModelState: reference relative_entity_name [" + req.relative_entity_name +
                           "] not found, did you forget to scope the link by model name?";
      return;
    }
    res.header.frame_id = isWorldFrame(req.relative_entity_name) ? "world" : req.relative_entity_name;
    stateSeenFrom(frame, model, "", res.pose, res.twist);
    res.success = true;
    res.status_message = "GetModelState: got properties";
  });
  return true;
}

bool GazeboApi::stateInWorld(const std::string& service, const std::string& frame_field,
                             const std::string& reference_frame, const geometry_msgs::Pose& pose_msg,
                             const geometry_msgs::Twist& twist_msg, cp::Pose& pose, cp::Twist& twist,
                             std::string& message) const {
  Frame frame;
  if (!finite(pose_msg) || !finite(twist_msg)) {
    message = service + ": pose and twist must be finite";
    return false;
  }
  if (!frameState(reference_frame, frame)) {
    message = service + ": " + frame_field + " [" + reference_frame + "] does not exist";
    return false;
  }
  pose = fromMsg(pose_msg);
  twist = fromMsg(twist_msg);
  fromFrame(frame.pose, pose, twist);
  return true;
}

void GazeboApi::stateSeenFrom(const Frame& frame, const ModelRef& model, const std::string& link,
                              geometry_msgs::Pose& pose_msg, geometry_msgs::Twist& twist_msg) const {
  cp::Pose pose = sim_.linkPose(model, link);
  cp::Twist twist = sim_.linkTwist(model, link);
  toFrame(frame.pose, frame.twist, pose, twist);
  pose_msg = toMsg(pose);
  twist_msg = toTwistMsg(twist);
}

bool GazeboApi::setModelState(const gazebo_msgs::ModelState& state, std::string& message) {
  const ModelRef model = sim_.findModel(state.model_name);
  cp::Pose pose;
  cp::Twist twist;
  if (!model.valid()) {
    message = "SetModelState: model [" + state.model_name + "] does not exist";
    return false;
  }
  if (!stateInWorld("SetModelState", "specified reference frame entity", state.reference_frame, state.pose, state.twist,
                    pose, twist, message)) {
    return false;
  }
  if (sim_.articulatedModel(model).fixed_to_world) {
    message = "SetModelState: model [" + state.model_name + "] is fixed to the world";
    return false;
  }
  sim_.setModelState(model, pose, twist);
  message = "SetModelState: set model state done";
  return true;
}

bool GazeboApi::onSetModelState(gazebo_msgs::SetModelState::Request& req, gazebo_msgs::SetModelState::Response& res) {
  host_.runOnLoop([&] { res.success = setModelState(req.model_state, res.status_message); });
  return true;
}

bool GazeboApi::onGetLinkState(gazebo_msgs::GetLinkState::Request& req, gazebo_msgs::GetLinkState::Response& res) {
  host_.runOnLoop([&] {
    ModelRef model;
    std::string link;
    Frame frame;
    res.link_state.link_name = req.link_name;
    res.link_state.reference_frame = req.reference_frame;
    if (!findLink(req.link_name, model, link)) {
      res.success = false;
      res.status_message = "GetLinkState: link [" + req.link_name + "] does not exist (name it model::link)";
      return;
    }
    if (!frameState(req.reference_frame, frame)) {
      res.success = false;
      res.status_message = "GetLinkState: reference_frame [" + req.reference_frame + "] does not exist";
      return;
    }
    stateSeenFrom(frame, model, link, res.link_state.pose, res.link_state.twist);
    res.success = true;
    res.status_message = "GetLinkState: got state";
  });
  return true;
}

bool GazeboApi::setLinkState(const gazebo_msgs::LinkState& state, std::string& message) {
  ModelRef model;
  std::string link;
  cp::Pose pose;
  cp::Twist twist;
  if (!findLink(state.link_name, model, link)) {
    message = "SetLinkState: link [" + state.link_name + "] does not exist (name it model::link)";
    return false;
  }
  if (!stateInWorld("SetLinkState", "reference_frame", state.reference_frame, state.pose, state.twist, pose, twist,
                    message)) {
    return false;
  }
  sim_.setLinkState(model, link, pose, twist);
  message = "SetLinkState: success";
  return true;
}

bool GazeboApi::onSetLinkState(gazebo_msgs::SetLinkState::Request& req, gazebo_msgs::SetLinkState::Response& res) {
  host_.runOnLoop([&] { res.success = setLinkState(req.link_state, res.status_message); });
  return true;
}

// --- properties ---

bool GazeboApi::onGetWorldProperties(gazebo_msgs::GetWorldProperties::Request&,
                                     gazebo_msgs::GetWorldProperties::Response& res) {
  host_.runOnLoop([&] {
    res.sim_time = sim_.timeS();
    for (const ModelRef& model : sim_.models()) res.model_names.push_back(sim_.modelName(model));
    res.rendering_enabled = true;  // cameras render on the CPU
    res.success = true;
    res.status_message = "GetWorldProperties: got properties";
  });
  return true;
}

bool GazeboApi::onGetModelProperties(gazebo_msgs::GetModelProperties::Request& req,
                                     gazebo_msgs::GetModelProperties::Response& res) {
  host_.runOnLoop([&] {
    const ModelRef model = sim_.findModel(req.model_name);
    if (!model.valid()) {
      res.success = false;
      res.status_message = "GetModelProperties: model [" + req.model_name + "] does not exist";
      return;
    }
    const cp::ArticulatedModel& m = sim_.articulatedModel(model);
    res.body_names = sim_.bodyLinkNames(model);
    res.canonical_body_name = res.body_names.front();
    for (const cp::BodySpec& body : m.bodies) {
      for (size_t c = 0; c < body.collisions.size(); ++c) {
        res.geom_names.push_back(body.name + "_collision_" + std::to_string(c));
      }
    }
    for (const cp::JointSpec& joint : m.joints) res.joint_names.push_back(joint.name);
    res.is_static = m.fixed_to_world;
    res.success = true;
    res.status_message = "GetModelProperties: got properties";
  });
  return true;
}

bool GazeboApi::onGetPhysicsProperties(gazebo_msgs::GetPhysicsProperties::Request&,
                                       gazebo_msgs::GetPhysicsProperties::Response& res) {
  const cp::PhysicsSettings& s = sim_.world().physics;  // fixed after start-up: no hand-over
  res.time_step = s.step_s;
  res.pause = host_.paused();
  res.max_update_rate = host_.realTimeFactor() > 0 ? host_.realTimeFactor() / s.step_s : 0.0;
  res.gravity = toVector3Msg(s.gravity_mps2);
  res.ode_config.auto_disable_bodies = false;
  res.ode_config.sor_pgs_iters = static_cast<std::uint32_t>(s.solver_iterations);
  res.ode_config.sor_pgs_w = 1.3;  // ODE's QuickStep default; not a parameter here
  res.ode_config.contact_surface_layer = s.contact_surface_layer_m;
  res.ode_config.contact_max_correcting_vel = s.max_contact_correcting_vel_mps;
  res.ode_config.cfm = s.contact_cfm;
  res.ode_config.erp = s.contact_erp;
  res.ode_config.max_contacts = static_cast<std::uint32_t>(s.max_contacts);
  res.success = true;
  res.status_message = "GetPhysicsProperties: got properties";
  return true;
}

// --- control ---

bool GazeboApi::onResetWorld(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  host_.runOnLoop([&] { host_.resetWorldNow(); });
  return true;
}

bool GazeboApi::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  host_.requestPause(true);
  return true;
}

bool GazeboApi::onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  host_.requestPause(false);
  return true;
}

bool GazeboApi::onApplyBodyWrench(gazebo_msgs::ApplyBodyWrench::Request& req,
                                  gazebo_msgs::ApplyBodyWrench::Response& res) {
  host_.runOnLoop([&] {
    res.success = false;
    ModelRef model;
    std::string link;
    Frame frame;
    if (!findLink(req.body_name, model, link)) {
      res.status_message = "ApplyBodyWrench: body [" + req.body_name + "] does not exist (name it model::link)";
      return;
    }
    if (!frameState(req.reference_frame, frame)) {
      res.status_message = "ApplyBodyWrench: reference_frame [" + req.reference_frame + "] does not exist";
      return;
    }
    if (!finite(req.wrench.force) || !finite(req.wrench.torque) || !std::isfinite(req.reference_point.x) ||
        !std::isfinite(req.reference_point.y) || !std::isfinite(req.reference_point.z)) {
      res.status_message = "ApplyBodyWrench: wrench and reference_point must be finite";
      return;
    }
    Wrench w;
    w.model = sim_.modelName(model);
    w.link = link;
    w.force_N = frame.pose.orientation.rotate(fromMsg(req.wrench.force));
    w.torque_Nm = frame.pose.orientation.rotate(fromMsg(req.wrench.torque));
    w.point_in_link = sim_.linkPose(model, link).inverse() * (frame.pose * fromMsg(req.reference_point));
    const double now_s = sim_.timeS();
    w.start_s = req.start_time.isZero() ? now_s : std::max(now_s, req.start_time.toSec());
    w.end_s = req.duration.toSec() < 0 ? -1.0 : w.start_s + req.duration.toSec();
    wrenches_.push_back(w);
    res.success = true;
    res.status_message = "";
  });
  return true;
}

bool GazeboApi::onClearBodyWrenches(gazebo_msgs::BodyRequest::Request& req, gazebo_msgs::BodyRequest::Response&) {
  host_.runOnLoop([&] {
    ModelRef model;
    std::string link;
    if (!findLink(req.body_name, model, link)) return;
    const std::string name = sim_.modelName(model);
    for (auto it = wrenches_.begin(); it != wrenches_.end();)
      it = it->model == name && it->link == link ? wrenches_.erase(it) : it + 1;
  });
  return true;
}

// --- models added and removed ---

bool GazeboApi::spawnAllowed(const gazebo_msgs::SpawnModel::Request& req, cp::Pose& spawn_pose,
                             std::string& message) const {
  Frame frame;
  if (req.model_name.empty()) {
    message = "SpawnModel: Failure - model_name is empty";
    return false;
  }
  if (sim_.findModel(req.model_name).valid() || static_models_.count(req.model_name) > 0) {
    message = "SpawnModel: Failure - entity already exists.";  // Gazebo's words
    return false;
  }
  if (!finite(req.initial_pose)) {
    message = "SpawnModel: Failure - initial_pose must be finite";
    return false;
  }
  if (!frameState(req.reference_frame, frame)) {
    message = "SpawnModel: Failure - reference_frame [" + req.reference_frame + "] does not exist";
    return false;
  }
  spawn_pose = frame.pose * fromMsg(req.initial_pose);
  return true;
}

void GazeboApi::spawnUrdf(const gazebo_msgs::SpawnModel::Request& req, gazebo_msgs::SpawnModel::Response& res) {
  res.success = false;
  RobotSpec spec;
  if (!spawnAllowed(req, spec.spawn_pose, res.status_message)) return;
  spec.name = req.model_name;
  spec.ros_namespace = req.robot_namespace == "/" ? "" : req.robot_namespace;
  spec.source = "spawn_urdf_model '" + req.model_name + "'";
  spec.urdf_xml = req.model_xml;
  try {
    host_.spawnRobot(spec);
  } catch (const std::exception& e) {
    res.status_message = std::string("SpawnModel: Failure - ") + e.what();
    return;
  }
  res.success = true;
  res.status_message = "SpawnModel: Successfully spawned entity";
}

bool GazeboApi::onSpawnUrdf(gazebo_msgs::SpawnModel::Request& req, gazebo_msgs::SpawnModel::Response& res) {
  host_.runOnLoop([&] { spawnUrdf(req, res); });
  return true;
}

bool GazeboApi::onSpawnSdf(gazebo_msgs::SpawnModel::Request& req, gazebo_msgs::SpawnModel::Response& res) {
  res.success = false;
  // Gazebo's spawn_sdf_model takes URDF as well.
  const size_t root = req.model_xml.find_first_not_of(" \t\r\n");
  if (root != std::string::npos && req.model_xml.compare(root, 6, "<robot") == 0) {
    host_.runOnLoop([&] { spawnUrdf(req, res); });
    return true;
  }
  // Parsed here, on the service thread (meshes may take a while), in the model's frame.
  cp::SdfModelObjects model;
  try {
    model =
        cp::loadSdfModel(req.model_xml, "spawn_sdf_model '" + req.model_name + "'", req.model_name, sim_.packages());
  } catch (const std::exception& e) {
    res.status_message = std::string("SpawnModel: Failure - ") + e.what();
    return true;
  }
  host_.runOnLoop([&] {
    cp::Pose spawn_pose;
    if (!spawnAllowed(req, spawn_pose, res.status_message)) return;
    for (cp::WorldObject& object : model.objects) object.pose = spawn_pose * object.pose;
    try {
      sim_.addObjects(model.objects);
    } catch (const std::exception& e) {
      res.status_message = std::string("SpawnModel: Failure - ") + e.what();
      return;
    }
    if (model.is_static) static_models_.insert(req.model_name);
    res.success = true;
    res.status_message = "SpawnModel: Successfully spawned entity";
  });
  if (res.success) {
    for (const std::string& note : model.notes) ROS_INFO("%s", note.c_str());
  }
  return true;
}

bool GazeboApi::onDeleteModel(gazebo_msgs::DeleteModel::Request& req, gazebo_msgs::DeleteModel::Response& res) {
  host_.runOnLoop([&] {
    res.success = false;
    const ModelRef model = sim_.findModel(req.model_name);
    if (!model.valid()) {
      res.status_message = "DeleteModel: model [" + req.model_name + "] does not exist";
      return;
    }
    forgetModel(req.model_name);
    if (model.robot >= 0) {
      host_.deleteRobot(model.robot);
    } else {
      sim_.removeObject(model.object);
    }
    res.success = true;
    res.status_message = "DeleteModel: successfully deleted model";
  });
  return true;
}

}  // namespace conde_sim
