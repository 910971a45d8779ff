// Odometry that the diff drive and the Ackermann drive compute alike, free of ROS: dead reckoning
// along an arc, and ground truth of the base link in the form odometry reports it.
#pragma once

#include <string>

#include "conde_physics/math.h"

namespace conde_sim {

class Simulation;

// Dead reckoning over one update: moves the planar pose (x_m, y_m, yaw_rad) `distance_m` along
// a constant-curvature arc that turns it by `dyaw_rad` (exact; for dyaw near 0 the chord at the
// midpoint heading). The yaw stays in [-pi, pi].
void integrateArc(double distance_m, double dyaw_rad, double& x_m, double& y_m, double& yaw_rad);

// Ground-truth odometry of `link` ("world" odometry): its pose in the world, and its twist
// expressed in its own frame (REP 105), as nav_msgs/Odometry carries it.
void groundTruthOdometry(const Simulation& sim, int robot, const std::string& link, conde_physics::Pose& pose,
                         conde_physics::Twist& twist_in_link);

}  // namespace conde_sim
