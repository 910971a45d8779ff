// The SDF <sensor type="ray"> block of a Gazebo ray sensor (laser, sonar, IR, block laser) ->
// the ray grid a LaserScanner casts. No ROS.
//
//   LaserScanConfig rays = rayFromSdf(params, sim.robot(robot).model, /*vertical_allowed=*/true);
//
// Reads <pose>, <ray><scan><horizontal> and <vertical> (samples x resolution rays from
// min_angle to max_angle; SDF defaults 640 x 1 horizontally, 1 x 1 vertically, angles 0),
// <ray><range> (min, max; resolution accepted, not applied, as in Gazebo), <ray><noise>
// (gaussian), <always_on> (accepted; sensors here are always on). The plugins' <gaussianNoise>
// is read by rayPluginNoiseStddev(); each plugin applies it in its own way.
// A 2-D scanner (vertical_allowed false) refuses more than one vertical ray. Throws PluginError
// naming the element at fault. The caller sets noise_seed.
#pragma once

#include "conde_physics/model.h"
#include "conde_sim/laser_scanner.h"
#include "conde_sim/plugin_params.h"

namespace conde_sim {

LaserScanConfig rayFromSdf(PluginParams& params, const conde_physics::ArticulatedModel& model, bool vertical_allowed);

// Publishing rate [Hz] of a plugin with its own <updateRate> in a ray sensor (range, block
// laser): Gazebo calls such a plugin at the sensor's <update_rate> and the plugin skips calls
// closer than 1 / updateRate, so the lower of the two positive rates wins; 0 = every step.
double rayPluginRateHz(PluginParams& params);

// The plugin's <gaussianNoise> [m] (default 0); a PluginError when negative.
double rayPluginNoiseStddev(PluginParams& params);

}  // namespace conde_sim
