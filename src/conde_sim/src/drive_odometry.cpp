#include "conde_sim/drive_odometry.h"

#include <cmath>

#include "conde_sim/simulation.h"

namespace conde_sim {

namespace cp = conde_physics;

void integrateArc(double distance_m, double dyaw_rad, double& x_m, double& y_m, double& yaw_rad) {
  if (std::abs(dyaw_rad) < 1e-9) {
    x_m += distance_m * std::cos(yaw_rad + dyaw_rad / 2.0);
    y_m += distance_m * std::sin(yaw_rad + dyaw_rad / 2.0);
  } else {
    const double r = distance_m / dyaw_rad;
    x_m += r * (std::sin(yaw_rad + dyaw_rad) - std::sin(yaw_rad));
    y_m -= r * (std::cos(yaw_rad + dyaw_rad) - std::cos(yaw_rad));
  }
  yaw_rad = std::remainder(yaw_rad + dyaw_rad, 2.0 * M_PI);
}

void groundTruthOdometry(const Simulation& sim, int robot, const std::string& link, cp::Pose& pose,
                         cp::Twist& twist_in_link) {
  pose = sim.linkPose(robot, link);
  const cp::Twist world = sim.linkTwist(robot, link);
  const cp::Quat to_link = pose.orientation.conjugate();
  twist_in_link.linear_mps = to_link.rotate(world.linear_mps);
  twist_in_link.angular_radps = to_link.rotate(world.angular_radps);
}

}  // namespace conde_sim
