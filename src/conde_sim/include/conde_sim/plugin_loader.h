// Loads our implementation of each Gazebo plugin block of a robot's URDF (read once, with the
// model, by conde_physics/gazebo_blocks.h): <gazebo><plugin filename="..."> (model plugins) and
// <gazebo reference="link"><sensor><plugin filename="..."> (sensor plugins), in document order.
#pragma once

#include <memory>
#include <vector>

#include "conde_sim/plugin.h"

namespace conde_sim {

// Throws PluginError for an unknown plugin file name, a bad parameter or an unknown key.
std::vector<std::unique_ptr<SimPlugin>> loadRobotPlugins(PluginContext& ctx);

}  // namespace conde_sim
