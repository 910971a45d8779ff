// conde_sim: the physics node. Loads a world file and robots (URDF with Gazebo plugin blocks),
// steps ODE or Bullet at a fixed step, owns /clock, and runs the plugins between steps.
//
// Parameters (private):
//   ~world_file        path of the *.world.yaml, or an SDF *.world / *.sdf (required)
//   ~physics_engine    ode | bullet                                   [ode]
//   ~real_time_factor  1.0 paces to the wall clock, 0 runs as fast as possible   [1.0]
//   ~paused            start paused (use ~step / ~unpause_physics)    [false]
//   ~clock_rate_hz     /clock messages per simulated second           [1000]
//   ~max_sim_time_s    stop cleanly at this simulated time, 0 = never [0]
//   ~robots            list of {name, namespace, description_param, spawn, frame_prefix}; without
//                      it one robot is read from /robot_description and spawned at ~spawn
//   ~spawn             name of a world spawn pose, or "x y yaw"       [first spawn in the world]
//                      (~robots: [] starts with no robot, as gazebo_ros/empty_world.launch)
//   ~gazebo_namespace  namespace of Gazebo's services and topics (gazebo_api.h)  [/gazebo]
//   ~gazebo_states_rate_hz  <ns>/model_states and link_states per simulated second  [100]
//   ~model_poses_rate_hz  ~model_poses (gazebo_api.h) per simulated second  [~gazebo_states_rate_hz]
//   ~lockstep          wait, after each step, for the answers of the nodes listed in
//                      ~lockstep_config (lockstep_frames.h); no real-time pacing   [false]
//   ~lockstep_config   {timeout_s, rules: [{answer, inputs, rate_hz, wait_for_first_answer}]}
//   ~contacts_rate_hz  ~contacts (gazebo_msgs/ContactsState: robots against world objects and
//                      robots, not the ground; contacts.h) per simulated second, while subscribed  [50]
//   ~loop_stall_s      wall-clock time [s] the step loop may stand still (no step, no callback,
//                      no lock-step poll) before the node logs, once per stall, where it stands
//                      and the call stack of every thread (loop_watch.h); 0 = not watched   [60]
// Topics: ~lockstep_timeouts (std_msgs/UInt64, latched): frames given up at the lock-step timeout.
// Services: ~pause_physics, ~unpause_physics, ~reset_world (std_srvs/Empty),
//           ~step (conde_msgs/StepSimulation), ~set_start_pose (conde_msgs/SetStartPose);
//           ~wait_for_messages (conde_msgs/WaitForMessages): acknowledged delivery, see onWaitForMessages;
//           Gazebo's under ~gazebo_namespace (gazebo_api.h). When the node is named like that
//           namespace (gazebo_ros/empty_world.launch names it "gazebo"), its pause, unpause
//           and reset_world are Gazebo's.
#include <conde_msgs/SetStartPose.h>
#include <conde_msgs/StepSimulation.h>
#include <conde_msgs/WaitForMessages.h>
#include <ros/callback_queue.h>
#include <ros/package.h>
#include <ros/publication.h>
#include <ros/ros.h>
#include <ros/topic_manager.h>
#include <rosgraph_msgs/Clock.h>
#include <std_msgs/UInt64.h>
#include <std_srvs/Empty.h>
#include <sys/resource.h>
#include <topic_tools/shape_shifter.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <functional>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include <unistd.h>

#include "conde_sim/contacts.h"
#include "conde_sim/lockstep_frames.h"
#include "conde_sim/loop_watch.h"
#include "conde_sim/message_counts.h"
#include "conde_sim/plugin_loader.h"
#include "conde_sim/simulation.h"
#include "conde_sim/step_loop.h"
#include "conde_sim/thread_backtraces.h"
#include "conde_sim/update_timer.h"
#include "conde_sim/world_displays.h"
#include "conde_sim/world_markers.h"
#include "gazebo_api.h"

namespace conde_sim {
namespace {

namespace cp = conde_physics;

class StartupError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::string packagePath(const std::string& name) { return ros::package::getPath(name); }

// Gazebo's model path as gazebo_ros sets it up: GAZEBO_MODEL_PATH first, then the folders ROS
// packages export with <export><gazebo_ros gazebo_model_path="${prefix}/models"/></export>,
// then gazebo_ros' own stock models (sun, ground_plane), so that model:// URIs resolve in world
// files and spawned SDF models alike. Written back to GAZEBO_MODEL_PATH, which the SDF loader reads.
void addGazeboModelPaths() {
  std::vector<std::string> dirs;
  const char* env = std::getenv("GAZEBO_MODEL_PATH");
  if (env != nullptr && *env != '\0') dirs.push_back(env);
  std::vector<std::pair<std::string, std::string>> exports;  // (package, folder)
  ros::package::getPlugins("gazebo_ros", "gazebo_model_path", exports);
  for (const auto& exported : exports) dirs.push_back(exported.second);
  const std::string stock = packagePath("gazebo_ros");  // gazebo_ros exports it: only if rospack did not list it
  if (!stock.empty() && std::find(dirs.begin(), dirs.end(), stock + "/models") == dirs.end())
    dirs.push_back(stock + "/models");
  std::string path;
  for (const std::string& dir : dirs) path += (path.empty() ? "" : ":") + dir;
  setenv("GAZEBO_MODEL_PATH", path.c_str(), 1);
  ROS_DEBUG("conde_sim: GAZEBO_MODEL_PATH=%s", path.c_str());
}

double wallNowS() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// ~lockstep_config: {timeout_s, rules: [{answer, inputs, rate_hz, wait_for_first_answer}]}, topic
// names resolved by `nh`. Unknown keys are refused.
std::unique_ptr<LockstepFrames> loadLockstepConfig(const ros::NodeHandle& nh, const std::string& where,
                                                   XmlRpc::XmlRpcValue config) {
  auto number = [&](XmlRpc::XmlRpcValue& v, const std::string& name) {
    if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) return static_cast<double>(v);
    if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<double>(static_cast<int>(v));
    throw StartupError(name + ": expected a number");
  };
  auto topic = [&](XmlRpc::XmlRpcValue& v, const std::string& name) {
    if (v.getType() != XmlRpc::XmlRpcValue::TypeString) throw StartupError(name + ": expected a topic name");
    return nh.resolveName(static_cast<std::string>(v));
  };
  if (config.getType() != XmlRpc::XmlRpcValue::TypeStruct) {
    throw StartupError(where + ": expected a dictionary {timeout_s, rules} (load the lock-step YAML there)");
  }
  double timeout_s = 1.0;
  std::vector<LockstepRule> rules;
  for (auto& kv : config) {
    const std::string key = where + "/" + kv.first;
    if (kv.first == "timeout_s") {
      timeout_s = number(kv.second, key);
    } else if (kv.first == "rules") {
      if (kv.second.getType() != XmlRpc::XmlRpcValue::TypeArray) throw StartupError(key + ": expected a list");
      for (int i = 0; i < kv.second.size(); ++i) {
        const std::string item = key + "[" + std::to_string(i) + "]";
        XmlRpc::XmlRpcValue& r = kv.second[i];
        if (r.getType() != XmlRpc::XmlRpcValue::TypeStruct) throw StartupError(item + ": expected a dictionary");
        LockstepRule rule;
        for (auto& field : r) {
          const std::string name = item + "." + field.first;
          if (field.first == "answer") {
            rule.answer_topic = topic(field.second, name);
          } else if (field.first == "inputs") {
            if (field.second.getType() != XmlRpc::XmlRpcValue::TypeArray)
              throw StartupError(name + ": expected a list");
            for (int j = 0; j < field.second.size(); ++j) rule.trigger_topics.push_back(topic(field.second[j], name));
          } else if (field.first == "rate_hz") {
            rule.rate_hz = number(field.second, name);
          } else if (field.first == "wait_for_first_answer") {
            if (field.second.getType() != XmlRpc::XmlRpcValue::TypeBoolean)
              throw StartupError(name + ": expected true or false");
            rule.wait_for_first_answer = static_cast<bool>(field.second);
          } else {
            throw StartupError(item + ": unknown key '" + field.first +
                               "' (expected answer, inputs, rate_hz, wait_for_first_answer)");
          }
        }
        if (rule.answer_topic.empty()) throw StartupError(item + ": 'answer' (a topic name) is required");
        if (rule.trigger_topics.empty()) throw StartupError(item + ": 'inputs' (a list of topic names) is required");
        if (rule.rate_hz < 0) throw StartupError(item + ".rate_hz: must be >= 0");
        rules.push_back(rule);
      }
    } else {
      throw StartupError(where + ": unknown key '" + kv.first + "' (expected timeout_s, rules)");
    }
  }
  if (!(timeout_s > 0)) throw StartupError(where + "/timeout_s: must be > 0");
  if (rules.empty()) throw StartupError(where + "/rules: at least one rule is needed");
  return std::make_unique<LockstepFrames>(rules, timeout_s);
}

cp::Pose parseSpawn(const std::string& spawn, const cp::WorldDescription& world, const std::string& where) {
  if (spawn.empty()) return world.spawns.empty() ? cp::Pose() : world.spawns.front().pose;
  if (const cp::SpawnPose* named = world.findSpawn(spawn)) return named->pose;
  std::istringstream in(spawn);
  double x, y, yaw;
  std::string rest;
  if (in >> x >> y >> yaw && !(in >> rest)) return cp::Pose::fromXyzRpy(x, y, 0.0, 0.0, 0.0, yaw);
  std::string names;
  for (const auto& s : world.spawns) names += (names.empty() ? "" : ", ") + s.name;
  throw StartupError(where + ": '" + spawn + "' is neither a spawn pose of world '" + world.name + "' (" + names +
                     ") nor 'x y yaw'");
}

// <gazebo reference> keys that Gazebo knows and that have no effect here: one INFO line per key
// for the node's life, where it was first seen.
void logKeysWithoutEffect(const cp::GazeboBlocks& blocks) {
  static std::set<std::string> logged;
  for (const auto& [key, where] : blocks.without_effect) {
    if (logged.insert(key).second)
      ROS_INFO("%s <%s>: accepted, without effect in conde_sim", where.c_str(), key.c_str());
  }
}

// Gazebo's way with a visual mesh it cannot load: an error in the log, the robot spawns.
void logVisualErrors(const cp::ArticulatedModel& model) {
  for (const auto& e : model.visual_errors) ROS_ERROR("%s (the visual is left out)", e.c_str());
}

class SimNode : public SimHost {
 public:
  SimNode() : pnh_("~") {}
  ~SimNode() override { stopLoopWatch(); }

  void start() {
    std::string world_file;
    if (!pnh_.getParam("world_file", world_file) || world_file.empty()) {
      throw StartupError("parameter " + pnh_.resolveName("world_file") + " is required (path of a *.world.yaml)");
    }
    pnh_.param("physics_engine", engine_name_, std::string("ode"));
    pnh_.param("real_time_factor", real_time_factor_, 1.0);
    pnh_.param("paused", paused_, false);
    pnh_.param("clock_rate_hz", clock_rate_hz_, 1000.0);
    pnh_.param("max_sim_time_s", max_sim_time_s_, 0.0);
    pnh_.param("gazebo_namespace", gazebo_ns_, std::string("/gazebo"));
    pnh_.param("gazebo_states_rate_hz", gazebo_states_rate_hz_, 100.0);
    pnh_.param("lockstep", lockstep_enabled_, false);
    pnh_.param("loop_stall_s", loop_stall_s_, 60.0);
    if (!(loop_stall_s_ >= 0)) throw StartupError("parameter ~loop_stall_s must be >= 0 (0 = not watched)");
    if (gazebo_states_rate_hz_ <= 0) throw StartupError("parameter ~gazebo_states_rate_hz must be > 0");
    pnh_.param("model_poses_rate_hz", model_poses_rate_hz_, gazebo_states_rate_hz_);
    if (!(model_poses_rate_hz_ > 0))
      throw StartupError((std::ostringstream() << "parameter " << pnh_.resolveName("model_poses_rate_hz")
                                               << " must be > 0 (got " << model_poses_rate_hz_ << ")")
                             .str());
    gazebo_ns_ = ros::names::resolve(gazebo_ns_);
    if (real_time_factor_ < 0) throw StartupError("parameter ~real_time_factor must be >= 0 (0 = as fast as possible)");
    if (clock_rate_hz_ <= 0) throw StartupError("parameter ~clock_rate_hz must be > 0");
    const auto engines = cp::availablePhysicsEngines();
    if (std::find(engines.begin(), engines.end(), engine_name_) == engines.end()) {
      throw StartupError("parameter " + pnh_.resolveName("physics_engine") + ": unknown physics engine '" +
                         engine_name_ + "' (expected one of: ode, bullet)");
    }

    addGazeboModelPaths();
    cp::WorldDescription world = cp::loadWorldFile(world_file, packagePath);
    for (const std::string& note : world.notes) ROS_INFO("conde_sim: %s", note.c_str());
    // An SDF world's <real_time_factor> applies unless the parameter is set.
    if (world.real_time_factor && !pnh_.hasParam("real_time_factor")) real_time_factor_ = *world.real_time_factor;
    sim_ = std::make_unique<Simulation>(world, engine_name_, packagePath);
    loadRobots();
    for (int r = 0; r < sim_->robotCount(); ++r) {
      for (auto& plugin : loadPlugins(r)) plugins_.push_back(std::move(plugin));
    }
    world_displays_ = std::make_unique<WorldDisplays>(nh_, *sim_);
    // ~contacts: robots against world objects and robots, only while subscribed (contacts.h).
    contacts_ = std::make_unique<ContactsPublisher>(pnh_, "contacts", *sim_, pnh_.param("contacts_rate_hz", 50.0));
    loop_ = std::make_unique<StepLoop>(*sim_);
    clock_hook_.timer = UpdateTimer(clock_rate_hz_, sim_->stepS());
    clock_hook_.node = this;

    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
    if (lockstep_enabled_) startLockstep();
    markers_pub_ = pnh_.advertise<visualization_msgs::MarkerArray>("world_markers", 1, true);
    const char* ros_home = std::getenv("ROS_HOME");
    const char* home = std::getenv("HOME");
    const std::string cache =
        ros_home ? std::string(ros_home) + "/conde_sim" : std::string(home ? home : "/tmp") + "/.ros/conde_sim";
    markers_pub_.publish(worldMarkers(sim_->world(), writeGroundMesh(sim_->world(), cache)));

    // Services run on their own thread and hand the work to the step loop, which is the only
    // thread that touches the simulation.
    service_nh_.setCallbackQueue(&service_queue_);
    if (pnh_.getNamespace() != gazebo_ns_) {
      services_.push_back(service_nh_.advertiseService("pause_physics", &SimNode::onPause, this));
      services_.push_back(service_nh_.advertiseService("unpause_physics", &SimNode::onUnpause, this));
      services_.push_back(service_nh_.advertiseService("reset_world", &SimNode::onReset, this));
    }
    services_.push_back(service_nh_.advertiseService("set_start_pose", &SimNode::onSetStartPose, this));
    services_.push_back(service_nh_.advertiseService("step", &SimNode::onStep, this));
    services_.push_back(service_nh_.advertiseService("wait_for_messages", &SimNode::onWaitForMessages, this));
    gazebo_ = std::make_unique<GazeboApi>(*this, *sim_, gazebo_ns_, service_nh_, gazebo_states_rate_hz_,
                                          model_poses_rate_hz_);
    rebuildLoop();
    service_spinner_ = std::make_unique<ros::AsyncSpinner>(1, &service_queue_);
    service_spinner_->start();

    publishClock();
    ROS_INFO("conde_sim: world '%s' (%s), engine %s, step %.4f s, real-time factor %s, %d robot(s), %zu plugin(s)%s",
             sim_->world().name.c_str(), world_file.c_str(), engine_name_.c_str(), sim_->stepS(),
             lockstep_               ? "lock-step (as fast as the nodes answer)"
             : real_time_factor_ > 0 ? std::to_string(real_time_factor_).c_str()
                                     : "unlimited",
             sim_->robotCount(), plugins_.size(), paused_ ? ", paused" : "");
  }

  // --- SimHost: what the Gazebo interface asks of the node ---
  bool runOnLoop(const std::function<void()>& task) override {
    std::unique_lock<std::mutex> lock(mutex_);
    auto done = std::make_shared<bool>(false);
    tasks_.push_back([task, done] {
      task();
      *done = true;
    });
    done_.wait(lock, [&] { return *done || !ros::ok(); });
    return *done;
  }

  void requestPause(bool paused) override {
    std::lock_guard<std::mutex> lock(mutex_);
    requested_paused_ = paused;
  }

  bool paused() const override {
    std::lock_guard<std::mutex> lock(mutex_);
    return requested_paused_;
  }

  double realTimeFactor() const override { return real_time_factor_; }

  void resetWorldNow() override {
    sim_->resetWorld();
    for (auto& p : plugins_) p.plugin->reset();
    if (lockstep_) lockstep_->reset();
    ROS_INFO("conde_sim: world reset at t = %.3f s", sim_->timeS());
  }

  int spawnRobot(const RobotSpec& spec) override {
    std::vector<std::string> warnings;
    const int robot = sim_->addRobot(spec, &warnings);
    for (const auto& w : warnings) ROS_WARN("%s", w.c_str());
    logVisualErrors(sim_->robot(robot).model);
    logKeysWithoutEffect(sim_->robot(robot).gazebo);
    try {
      for (auto& plugin : loadPlugins(robot)) plugins_.push_back(std::move(plugin));
    } catch (...) {
      deleteRobot(robot);
      throw;
    }
    rebuildLoop();
    const cp::Pose& p = spec.spawn_pose;
    ROS_INFO("conde_sim: robot '%s' spawned at (%.3f, %.3f, %.3f) yaw %.3f rad%s%s", spec.name.c_str(), p.position.x,
             p.position.y, p.position.z, p.orientation.yaw(), spec.ros_namespace.empty() ? "" : ", namespace ",
             spec.ros_namespace.c_str());
    return robot;
  }

  void deleteRobot(int robot) override {
    plugins_.erase(
        std::remove_if(plugins_.begin(), plugins_.end(), [robot](const LoadedPlugin& p) { return p.robot == robot; }),
        plugins_.end());
    rebuildLoop();
    sim_->removeRobot(robot);
    ROS_INFO("conde_sim: robot '%s' deleted", sim_->robot(robot).spec.name.c_str());
  }

  // The step loop. Returns when ROS shuts down or ~max_sim_time_s is reached.
  void run() {
    const auto run_start = std::chrono::steady_clock::now();
    const double run_start_cpu_s = processCpuSeconds();
    double paused_cpu_s = 0.0;
    const double run_start_sim_s = sim_->timeS();
    auto wall_start = std::chrono::steady_clock::now();
    double sim_start_s = sim_->timeS();
    double paused_wall_s = 0.0;  // not counted in the real-time factor reported at the end
    auto& queue = *ros::getGlobalCallbackQueue();
    startLoopWatch();
    while (ros::ok()) {
      beat("serving requests (pause, step, reset, Gazebo services)");
      handleRequests();
      if (paused_ && pending_steps_ == 0) {
        const auto pause_start = std::chrono::steady_clock::now();
        const double pause_start_cpu_s = processCpuSeconds();
        beat("paused: serving callbacks");
        queue.callAvailable(ros::WallDuration(0.005));
        paused_wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - pause_start).count();
        paused_cpu_s += processCpuSeconds() - pause_start_cpu_s;
        wall_start = std::chrono::steady_clock::now();
        sim_start_s = sim_->timeS();
        continue;
      }
      beat("serving callbacks");
      queue.callAvailable();
      beat("stepping: plugins and physics");
      loop_->update();
      if (lockstep_) waitForAnswers(queue);
      beat("ending a step request");
      if (pending_steps_ > 0 && --pending_steps_ == 0) finishStepRequest();
      if (max_sim_time_s_ > 0 && sim_->timeS() >= max_sim_time_s_ - 1e-9) {
        ROS_INFO("conde_sim: reached ~max_sim_time_s = %.3f s; stopping", max_sim_time_s_);
        break;
      }
      if (real_time_factor_ > 0 && !paused_ && !lockstep_) {
        const auto target =
            wall_start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                             std::chrono::duration<double>((sim_->timeS() - sim_start_s) / real_time_factor_));
        if (target > std::chrono::steady_clock::now()) std::this_thread::sleep_until(target);
      }
    }
    stopLoopWatch();
    service_spinner_->stop();
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count() - paused_wall_s;
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const double cpu_s = processCpuSeconds() - run_start_cpu_s - paused_cpu_s;
    const double simulated_s = sim_->timeS() - run_start_sim_s;
    ROS_INFO(
        "conde_sim: simulated %.3f s in %.3f s of wall time, pauses not counted (real-time factor %.1f), "
        "peak RSS %.1f MB, CPU %.3f s (simulated seconds per CPU second %.1f)",
        simulated_s, wall_s, simulated_s / std::max(wall_s, 1e-9), usage.ru_maxrss / 1024.0, cpu_s,
        simulated_s / std::max(cpu_s, 1e-9));
    if (lockstep_) reportLockstep();
  }

 private:
  // User + system CPU time of the whole process (all threads) [s].
  static double processCpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
  }

  void loadRobots() {
    XmlRpc::XmlRpcValue list;
    if (!pnh_.getParam("robots", list)) {
      std::string spawn;
      pnh_.param("spawn", spawn, std::string());
      addRobot("", "", "/robot_description", parseSpawn(spawn, sim_->world(), pnh_.resolveName("spawn")), "");
      return;
    }
    const std::string where = pnh_.resolveName("robots");
    if (list.getType() != XmlRpc::XmlRpcValue::TypeArray) throw StartupError(where + ": expected a list of robots");
    for (int i = 0; i < list.size(); ++i) {
      const std::string item = where + "[" + std::to_string(i) + "]";
      if (list[i].getType() != XmlRpc::XmlRpcValue::TypeStruct) throw StartupError(item + ": expected a dictionary");
      std::string name, ns, description = "robot_description", spawn, prefix;
      for (auto& kv : list[i]) {
        if (kv.second.getType() != XmlRpc::XmlRpcValue::TypeString) {
          throw StartupError(item + "." + kv.first + ": expected a string");
        }
        const std::string value = static_cast<std::string>(kv.second);
        if (kv.first == "name")
          name = value;
        else if (kv.first == "namespace")
          ns = value;
        else if (kv.first == "description_param")
          description = value;
        else if (kv.first == "spawn")
          spawn = value;
        else if (kv.first == "frame_prefix")
          prefix = value;
        else
          throw StartupError(item + ": unknown key '" + kv.first +
                             "' (expected name, namespace, description_param, spawn, frame_prefix)");
      }
      const std::string param = ros::NodeHandle(ns.empty() ? "/" : ns).resolveName(description);
      addRobot(name, ns, param, parseSpawn(spawn, sim_->world(), item + ".spawn"), prefix);
    }
  }

  void addRobot(const std::string& name, const std::string& ns, const std::string& description_param,
                const cp::Pose& spawn, const std::string& prefix) {
    std::string urdf;
    if (!ros::param::get(description_param, urdf) || urdf.empty()) {
      throw StartupError("parameter " + description_param + " is not set: load the robot's URDF there (xacro output)");
    }
    RobotSpec spec;
    spec.ros_namespace = ns;
    spec.frame_prefix = prefix;
    spec.source = description_param;
    spec.urdf_xml = urdf;
    spec.spawn_pose = spawn;
    std::vector<std::string> warnings;
    spec.name = name;  // "" = the URDF's robot name
    const int index = sim_->addRobot(spec, &warnings);
    for (const auto& w : warnings) ROS_WARN("%s", w.c_str());
    logVisualErrors(sim_->robot(index).model);
    logKeysWithoutEffect(sim_->robot(index).gazebo);
    ROS_INFO("conde_sim: robot '%s' from %s at (%.3f, %.3f) yaw %.3f rad%s%s", sim_->robot(index).spec.name.c_str(),
             description_param.c_str(), spawn.position.x, spawn.position.y, spawn.orientation.yaw(),
             ns.empty() ? "" : ", namespace ", ns.c_str());
  }

  struct LoadedPlugin {
    int robot = -1;
    std::unique_ptr<SimPlugin> plugin;
  };

  std::vector<LoadedPlugin> loadPlugins(int robot) {
    PluginContext ctx;
    ctx.sim = sim_.get();
    ctx.robot = robot;
    const std::string& ns = sim_->robot(robot).spec.ros_namespace;
    ctx.robot_nh = ros::NodeHandle(ns.empty() ? "/" : ns);
    ctx.tf = &tf_;
    ctx.static_tf = &static_tf_;
    std::vector<LoadedPlugin> loaded;
    for (auto& plugin : loadRobotPlugins(ctx)) loaded.push_back(LoadedPlugin{robot, std::move(plugin)});
    return loaded;
  }

  // The step loop: every plugin in load order, the Gazebo interface, then /clock.
  void rebuildLoop() {
    loop_->clear();
    for (auto& p : plugins_) loop_->add(*p.plugin);
    loop_->add(*gazebo_);
    loop_->add(*contacts_);
    loop_->add(clock_hook_);
  }

  // /clock after every plugin, at ~clock_rate_hz of simulated time; a lock-step trigger.
  struct ClockHook : StepHooks {
    SimNode* node = nullptr;
    UpdateTimer timer;
    void afterStep() override {
      if (!timer.due(node->sim_->stepCount())) return;
      node->publishClock();
      if (node->lockstep_) node->lockstep_->onMessage("/clock", node->sim_->timeS(), wallNowS());
    }
  };

  // --- lock-step ---
  void startLockstep() {
    XmlRpc::XmlRpcValue config;
    const std::string where = pnh_.resolveName("lockstep_config");
    if (!pnh_.getParam("lockstep_config", config)) {
      throw StartupError("~lockstep is true but " + where + " is not set (load the lock-step YAML there)");
    }
    lockstep_ = loadLockstepConfig(nh_, where, config);
    lockstep_timeouts_pub_ = pnh_.advertise<std_msgs::UInt64>("lockstep_timeouts", 1, true);
    publishLockstepTimeouts();
    // Inputs the simulator publishes itself (camera images) are seen at once, after the step, by
    // their publication's sequence number: roscpp leaves what is published in a queue that its
    // poll thread sends (and numbers) later, so the loop sends that queue itself after each step
    // (Publication::processPublishQueue) before it reads the number. A sensor publishes only while someone
    // subscribes: an input nobody listens to owes nothing. Every other topic, of any type, is
    // subscribed to (the node only counts messages), with long queues: no answer may be dropped.
    for (const std::string& topic : lockstep_->topicsToWatch()) {
      if (const ros::PublicationPtr publication = ros::TopicManager::instance()->lookupPublication(topic)) {
        own_inputs_.push_back(OwnInput{topic, publication->getSequence()});
        continue;
      }
      boost::function<void(const topic_tools::ShapeShifter::ConstPtr&)> callback =
          [this, topic](const topic_tools::ShapeShifter::ConstPtr&) {
            lockstep_->onMessage(topic, sim_->timeS(), wallNowS());
          };
      lockstep_subs_.push_back(nh_.subscribe<topic_tools::ShapeShifter>(topic, 1000, callback));
    }
    for (const LockstepRule& rule : lockstep_->rules()) {
      std::string inputs;
      for (const auto& t : rule.trigger_topics) inputs += (inputs.empty() ? "" : ", ") + t;
      ROS_INFO("conde_sim: lock-step: %s answers %s%s%s", rule.answer_topic.c_str(), inputs.c_str(),
               rule.rate_hz > 0 ? (" at " + std::to_string(rule.rate_hz) + " Hz").c_str() : "",
               rule.wait_for_first_answer ? "" : " (once it has answered)");
    }
    ROS_INFO("conde_sim: lock-step: timeout %.3f s of wall time per frame; ~real_time_factor ignored",
             lockstep_->timeoutS());
  }

  // After a step: serve callbacks (the triggers just published, the answers) until nothing is
  // owed or the frame times out.
  void waitForAnswers(ros::CallbackQueue& queue) {
    beat("lock-step: sending the simulator's own inputs");
    for (OwnInput& input : own_inputs_) {
      const ros::PublicationPtr publication = ros::TopicManager::instance()->lookupPublication(input.topic);
      if (publication) publication->processPublishQueue();
      const std::uint32_t sequence = publication ? publication->getSequence() : input.sequence;
      if (sequence != input.sequence) lockstep_->onMessage(input.topic, sim_->timeS(), wallNowS());
      input.sequence = sequence;
    }
    beat("lock-step: serving callbacks");
    queue.callAvailable();
    while (lockstep_->waiting() && ros::ok()) {
      beat("lock-step: waiting for answers");
      queue.callAvailable(ros::WallDuration(0.001));
      const std::string missing = lockstep_->missing();
      if (lockstep_->checkTimeout(wallNowS())) {
        // Throttled on the wall clock: simulated time stands still while the loop waits, and
        // ROS_WARN_THROTTLE (simulated time) would stay silent through a whole stall.
        if (wallNowS() - last_timeout_warning_wall_s_ >= 1.0) {
          last_timeout_warning_wall_s_ = wallNowS();
          ROS_WARN(
              "conde_sim: lock-step: no answer within %.3f s at t = %.3f s: %s; going on (%lu frames timed out so "
              "far)",
              lockstep_->timeoutS(), sim_->timeS(), missing.c_str(),
              static_cast<unsigned long>(lockstep_->timedOutFrames()));
        }
        publishLockstepTimeouts();
      }
    }
  }

  // --- the loop's watch (loop_watch.h) ---
  void beat(const char* phase) {
    if (loop_watch_) loop_watch_->beat(phase, sim_->timeS(), wallNowS());
  }

  // A thread that logs where the loop stands, with every thread's stack, when it stops moving.
  // On stderr too, unbuffered: a stuck roscpp thread may be the one that sends /rosout.
  void startLoopWatch() {
    if (loop_stall_s_ <= 0) return;
    loop_watch_ = std::make_unique<LoopWatch>(loop_stall_s_);
    beat("starting the step loop");
    watch_thread_ = std::thread([this] {
      std::unique_lock<std::mutex> lock(watch_mutex_);
      while (!watch_stop_) {
        watch_cv_.wait_for(lock, std::chrono::seconds(1));
        std::string report;
        if (watch_stop_ || !loop_watch_->checkStall(wallNowS(), &report)) continue;
        ROS_ERROR("conde_sim: %s (the call stack of every thread follows on stderr)", report.c_str());
        std::fprintf(stderr, "conde_sim: error: %s; the call stack of every thread:\n", report.c_str());
        std::fflush(stderr);
        writeThreadBacktraces(STDERR_FILENO, 2.0);
      }
    });
  }

  void stopLoopWatch() {
    if (!watch_thread_.joinable()) return;
    {
      std::lock_guard<std::mutex> lock(watch_mutex_);
      watch_stop_ = true;
    }
    watch_cv_.notify_all();
    watch_thread_.join();
  }

  void publishLockstepTimeouts() {
    std_msgs::UInt64 msg;
    msg.data = lockstep_->timedOutFrames();
    lockstep_timeouts_pub_.publish(msg);
  }

  void reportLockstep() {
    ROS_INFO("conde_sim: lock-step: %lu frames waited for answers, %lu timed out (timeout %.3f s)",
             static_cast<unsigned long>(lockstep_->frames()), static_cast<unsigned long>(lockstep_->timedOutFrames()),
             lockstep_->timeoutS());
    for (std::size_t i = 0; i < lockstep_->rules().size(); ++i) {
      const LockstepRuleStats& s = lockstep_->stats(i);
      ROS_INFO("conde_sim: lock-step: %s: %lu owed, %lu answered, %lu timed out, %lu unsolicited",
               lockstep_->rules()[i].answer_topic.c_str(), static_cast<unsigned long>(s.triggers),
               static_cast<unsigned long>(s.answered), static_cast<unsigned long>(s.timeouts),
               static_cast<unsigned long>(s.unsolicited));
    }
  }

  void publishClock() {
    rosgraph_msgs::Clock clock;
    clock.clock = ros::Time(sim_->timeS());
    clock_pub_.publish(clock);
  }

  // --- requests from the service thread ---
  void handleRequests() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!tasks_.empty()) {
      for (auto& task : tasks_) task();
      tasks_.clear();
      done_.notify_all();
    }
    if (start_pose_requested_) {  // the robot is looked up here: only this thread reads the simulation
      start_pose_requested_ = false;
      const int robot = sim_->findRobot(start_pose_robot_name_);
      start_pose_success_ = robot >= 0;
      if (robot < 0) {
        start_pose_message_ = start_pose_robot_name_.empty() ? "there are several robots: name one"
                                                             : "no robot named '" + start_pose_robot_name_ + "'";
      } else {
        sim_->setStartPose(robot, start_pose_);
        start_pose_message_ = "robot '" + sim_->robot(robot).spec.name + "' reset to the new start pose";
        reset_requested_ = true;
      }
      start_pose_done_ = true;
      done_.notify_all();
    }
    if (reset_requested_) {
      resetWorldNow();
      reset_requested_ = false;
      done_.notify_all();
    }
    if (requested_steps_ > 0 && pending_steps_ == 0) {
      pending_steps_ = requested_steps_;
      requested_steps_ = 0;
    }
    paused_ = requested_paused_;
  }

  void finishStepRequest() {
    std::lock_guard<std::mutex> lock(mutex_);
    step_done_time_s_ = sim_->timeS();
    step_request_done_ = true;
    publishClock();
    done_.notify_all();
  }

  bool onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    std::lock_guard<std::mutex> lock(mutex_);
    requested_paused_ = true;
    return true;
  }

  bool onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    std::lock_guard<std::mutex> lock(mutex_);
    requested_paused_ = false;
    return true;
  }

  // The request is handed to the step loop, which owns the simulation (the robot is looked up
  // there); this thread only waits for the answer.
  bool onSetStartPose(conde_msgs::SetStartPose::Request& req, conde_msgs::SetStartPose::Response& res) {
    if (!std::isfinite(req.x_m) || !std::isfinite(req.y_m) || !std::isfinite(req.yaw_rad)) {
      res.success = false;
      res.message = "x_m, y_m and yaw_rad must be finite";
      return true;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    start_pose_robot_name_ = req.robot;
    start_pose_ = cp::Pose::fromXyzRpy(req.x_m, req.y_m, 0.0, 0.0, 0.0, req.yaw_rad);
    start_pose_done_ = false;
    start_pose_requested_ = true;
    done_.wait(lock, [this] { return (start_pose_done_ && !reset_requested_) || !ros::ok(); });
    res.success = start_pose_done_ && start_pose_success_;
    res.message = start_pose_done_ ? start_pose_message_ : "shutting down";
    return true;
  }

  bool onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    std::unique_lock<std::mutex> lock(mutex_);
    reset_requested_ = true;
    done_.wait(lock, [this] { return !reset_requested_ || !ros::ok(); });
    return true;
  }

  bool onStep(conde_msgs::StepSimulation::Request& req, conde_msgs::StepSimulation::Response& res) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!requested_paused_) {
      res.success = false;
      res.message = "the simulation is running: call pause_physics before stepping";
      return true;
    }
    if (req.steps == 0) {
      res.success = true;
      res.sim_time_s = step_done_time_s_;
      return true;
    }
    step_request_done_ = false;
    requested_steps_ = req.steps;
    done_.wait(lock, [this] { return step_request_done_ || !ros::ok(); });
    res.success = step_request_done_;
    res.sim_time_s = step_done_time_s_;
    res.message = res.success ? "" : "shutting down";
    return true;
  }

  // Acknowledged delivery: a node that publishes a command and then steps the simulator asks here
  // for its messages first. The counting subscription joins the plugin's subscription to the topic
  // (one roscpp Subscription per topic and process) and is added after it, at the first request
  // naming the topic: roscpp queues a message's callbacks in that order on the loop's queue, which
  // runs them in order, so when the count has the message the plugin has handled it. Until the
  // request is met the service thread waits; the simulation, paused, does not move.
  bool onWaitForMessages(
      ros::ServiceEvent<conde_msgs::WaitForMessages::Request, conde_msgs::WaitForMessages::Response>& event) {
    const conde_msgs::WaitForMessages::Request& req = event.getRequest();
    conde_msgs::WaitForMessages::Response& res = event.getResponse();
    const std::string caller = req.publisher.empty() ? event.getCallerName() : req.publisher;
    if (req.topic.empty() || req.topic[0] != '/') {
      res.message = "topic: '" + req.topic + "' (expected a resolved topic name, starting with /)";
      return true;
    }
    if (!(req.timeout_s >= 0) || !std::isfinite(req.timeout_s)) {
      res.message = "timeout_s must be finite and >= 0 (0 = 30 s)";
      return true;
    }
    const double timeout_s = req.timeout_s > 0 ? req.timeout_s : 30.0;
    std::unique_lock<std::mutex> lock(mutex_);
    if (message_counts_.watch(req.topic)) {
      const std::string topic = req.topic;
      boost::function<void(const ros::MessageEvent<topic_tools::ShapeShifter const>&)> count =
          [this, topic](const ros::MessageEvent<topic_tools::ShapeShifter const>& message) {
            std::lock_guard<std::mutex> guard(mutex_);
            message_counts_.onMessage(topic, message.getPublisherName());
            done_.notify_all();
          };
      count_subs_.push_back(nh_.subscribe<topic_tools::ShapeShifter>(topic, 1000, count));
    }
    res.success = done_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] {
      return message_counts_.met(req.topic, caller, req.count) || !ros::ok();
    }) && ros::ok();
    res.received = message_counts_.received(req.topic, caller);
    if (!res.success) res.message = message_counts_.describeMissing(req.topic, caller, req.count, timeout_s);
    return true;
  }

  ros::NodeHandle nh_, pnh_;
  ros::NodeHandle service_nh_{"~"};
  ros::CallbackQueue service_queue_;
  std::unique_ptr<ros::AsyncSpinner> service_spinner_;
  std::vector<ros::ServiceServer> services_;
  ros::Publisher clock_pub_, markers_pub_;
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<WorldDisplays> world_displays_;
  std::unique_ptr<ContactsPublisher> contacts_;
  std::vector<LoadedPlugin> plugins_;
  std::unique_ptr<GazeboApi> gazebo_;
  std::string engine_name_, gazebo_ns_;
  double gazebo_states_rate_hz_ = 100.0;
  double model_poses_rate_hz_ = 100.0;
  double real_time_factor_ = 1.0, clock_rate_hz_ = 1000.0, max_sim_time_s_ = 0.0;
  std::unique_ptr<StepLoop> loop_;
  ClockHook clock_hook_;
  bool lockstep_enabled_ = false;
  std::unique_ptr<LockstepFrames> lockstep_;  // null without ~lockstep
  std::vector<ros::Subscriber> lockstep_subs_;
  struct OwnInput {
    std::string topic;
    std::uint32_t sequence;  // of its publication after the last step
  };
  std::vector<OwnInput> own_inputs_;  // inputs the simulator publishes (advertised at start-up)
  ros::Publisher lockstep_timeouts_pub_;
  double last_timeout_warning_wall_s_ = -1e9;
  double loop_stall_s_ = 60.0;
  std::unique_ptr<LoopWatch> loop_watch_;  // null when ~loop_stall_s is 0
  std::thread watch_thread_;
  std::mutex watch_mutex_;
  std::condition_variable watch_cv_;
  bool watch_stop_ = false;  // guarded by watch_mutex_
  bool paused_ = false;
  std::uint64_t pending_steps_ = 0;

  // Shared with the service thread (guarded by mutex_).
  mutable std::mutex mutex_;
  std::vector<std::function<void()>> tasks_;  // from runOnLoop()
  std::condition_variable done_;
  bool requested_paused_ = false, reset_requested_ = false, step_request_done_ = false;
  // A set_start_pose request: the robot's name and pose in, the step loop's answer out.
  bool start_pose_requested_ = false, start_pose_done_ = false, start_pose_success_ = false;
  std::string start_pose_robot_name_, start_pose_message_;
  cp::Pose start_pose_;
  std::uint64_t requested_steps_ = 0;
  double step_done_time_s_ = 0.0;
  MessageCounts message_counts_;             // ~wait_for_messages: counted on the loop's thread
  std::vector<ros::Subscriber> count_subs_;  // one per topic counted

 public:
  void initialPause() { requested_paused_ = paused_; }
};

}  // namespace
}  // namespace conde_sim

int main(int argc, char** argv) {
  // Line by line into a log file too: what a stuck node wrote must survive the SIGKILL that ends it.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  conde_sim::installThreadBacktraceHandler();
  ros::init(argc, argv, "conde_sim");
  try {
    conde_sim::SimNode node;
    node.start();
    node.initialPause();
    node.run();
  } catch (const std::exception& e) {
    ROS_FATAL("conde_sim: %s", e.what());
    // Also on stderr without ROS decoration: launch files and scripts show it as is.
    std::fprintf(stderr, "conde_sim: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
