#include "conde_sim/plugin_loader.h"

#include <set>

namespace conde_sim {

namespace {

std::string knownPluginNames() {
  std::string names;
  for (const auto& entry : pluginRegistry()) names += (names.empty() ? "" : ", ") + entry.first;
  return names;
}

// Model-level <gazebo> children that are not plugins, accepted as Gazebo accepts them.
const std::set<std::string> kModelKeys = {"static", "self_collide", "allow_auto_disable", "enable_wind"};

}  // namespace

std::vector<std::unique_ptr<SimPlugin>> loadRobotPlugins(PluginContext& ctx) {
  const Robot& robot = ctx.sim->robot(ctx.robot);
  const std::string& source = robot.spec.source;
  tinyxml2::XMLDocument doc;
  if (doc.Parse(robot.spec.urdf_xml.c_str()) != tinyxml2::XML_SUCCESS) {
    throw PluginError(source + ": XML error at line " + std::to_string(doc.ErrorLineNum()));
  }
  std::vector<std::unique_ptr<SimPlugin>> plugins;
  auto load = [&](const tinyxml2::XMLElement* plugin, const tinyxml2::XMLElement* sensor, const std::string& link) {
    PluginParams params(plugin, sensor, source, link);
    const auto it = pluginRegistry().find(params.filename());
    if (it == pluginRegistry().end()) {
      throw PluginError(params.where() + ": unknown plugin '" + params.filename() + "' (known: " + knownPluginNames() +
                        ")");
    }
    std::unique_ptr<SimPlugin> p = it->second();
    p->load(ctx, params);
    params.checkAllUsed();
    plugins.push_back(std::move(p));
  };
  const tinyxml2::XMLElement* root = doc.FirstChildElement("robot");
  for (const auto* g = root ? root->FirstChildElement("gazebo") : nullptr; g; g = g->NextSiblingElement("gazebo")) {
    const char* reference = g->Attribute("reference");
    if (!reference) {
      for (const auto* e = g->FirstChildElement(); e; e = e->NextSiblingElement()) {
        const std::string key = e->Name();
        if (key == "plugin") {
          load(e, nullptr, "");
        } else if (!kModelKeys.count(key)) {
          throw PluginError(source + ":" + std::to_string(e->GetLineNum()) + ": <gazebo>: unknown element <" + key +
                            ">");
        }
      }
      continue;
    }
    for (const auto* sensor = g->FirstChildElement("sensor"); sensor; sensor = sensor->NextSiblingElement("sensor")) {
      const auto* plugin = sensor->FirstChildElement("plugin");
      if (!plugin) {
        ROS_WARN("%s:%d: sensor '%s' has no plugin: nothing publishes its data", source.c_str(), sensor->GetLineNum(),
                 sensor->Attribute("name") ? sensor->Attribute("name") : "");
        continue;
      }
      load(plugin, sensor, reference);
    }
  }
  return plugins;
}

}  // namespace conde_sim
