#include "conde_sim/plugin_loader.h"

#include <ros/console.h>

#include <set>

namespace conde_sim {

namespace {

std::string knownPluginNames() {
  std::string names;
  for (const auto& entry : pluginRegistry()) names += (names.empty() ? "" : ", ") + entry.first;
  return names;
}

// Keys Gazebo reads that have no effect here, at INFO, once per plugin file name and key.
void logAcceptedWithoutEffect(const PluginParams& params) {
  static std::set<std::string> logged;
  std::string keys;
  for (const std::string& key : params.acceptedWithoutEffect()) {
    if (logged.insert(params.filename() + key).second) keys += (keys.empty() ? "" : ", ") + key;
  }
  if (!keys.empty()) ROS_INFO("%s: accepted without effect: %s", params.where().c_str(), keys.c_str());
}

}  // namespace

std::vector<std::unique_ptr<SimPlugin>> loadRobotPlugins(PluginContext& ctx) {
  const Robot& robot = ctx.sim->robot(ctx.robot);
  const std::string& source = robot.spec.source;
  std::vector<std::unique_ptr<SimPlugin>> plugins;
  for (const conde_physics::GazeboPluginBlock& block : robot.gazebo.plugins) {
    if (!block.plugin) {
      ROS_WARN("%s:%d: sensor '%s' has no plugin: nothing publishes its data", source.c_str(),
               block.sensor->GetLineNum(), block.sensor->Attribute("name") ? block.sensor->Attribute("name") : "");
      continue;
    }
    PluginParams params(block.plugin, block.sensor, source, block.link);
    const auto it = pluginRegistry().find(params.filename());
    if (it == pluginRegistry().end()) {
      throw PluginError(params.where() + ": unknown plugin '" + params.filename() + "' (known: " + knownPluginNames() +
                        ")");
    }
    std::unique_ptr<SimPlugin> p = it->second();
    p->load(ctx, params);
    params.checkAllUsed();
    logAcceptedWithoutEffect(params);
    plugins.push_back(std::move(p));
  }
  return plugins;
}

}  // namespace conde_sim
