// A joint-space trajectory sampled in time, free of ROS: what
// position_controllers/JointTrajectoryController follows (trajectory_msgs/JointTrajectory).
//
// The trajectory starts at the joints' positions when it is received (time 0, velocity 0) and
// passes through its points at their time_from_start [s]. Between two points the segment is, as
// in ros_controllers' joint_trajectory_controller: linear when the points give no velocities, a
// cubic (Hermite) when both ends have velocities [rad/s]. Accelerations are not used (no quintic
// segments). Before 0 it holds the start, after the last point the last point.
//
//   JointTrajectory t({0.0, 0.0}, {{1.0, {0.5, -0.5}, {}}, {2.0, {1.0, 0.0}, {}}});
//   std::vector<double> p = t.sample(1.5);  // {0.75, -0.25}
#pragma once

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace conde_sim {

struct TrajectoryPoint {
  double time_s = 0.0;             // from the start of the trajectory
  std::vector<double> positions;   // [rad or m], one per joint
  std::vector<double> velocities;  // [rad/s or m/s], one per joint, or empty
};

class JointTrajectory {
 public:
  JointTrajectory() = default;
  // Throws std::invalid_argument when a point has the wrong number of values or the times do not
  // increase strictly (a first point at time 0 replaces the start).
  JointTrajectory(const std::vector<double>& start_positions, std::vector<TrajectoryPoint> points) {
    TrajectoryPoint start;
    start.positions = start_positions;
    start.velocities.assign(start_positions.size(), 0.0);
    const size_t n = start_positions.size();
    if (!points.empty() && points.front().time_s == 0.0) {
      start = points.front();
      if (start.velocities.empty()) start.velocities.assign(n, 0.0);
      points.erase(points.begin());
    }
    points_.push_back(start);
    for (const TrajectoryPoint& p : points) {
      if (p.positions.size() != n)
        throw std::invalid_argument("a point has " + std::to_string(p.positions.size()) + " positions for " +
                                    std::to_string(n) + " joints");
      if (!p.velocities.empty() && p.velocities.size() != n) {
        throw std::invalid_argument("a point has " + std::to_string(p.velocities.size()) + " velocities for " +
                                    std::to_string(n) + " joints");
      }
      if (!(p.time_s > points_.back().time_s)) {
        throw std::invalid_argument("time_from_start must increase from point to point (and be > 0)");
      }
      points_.push_back(p);
    }
  }

  bool empty() const { return points_.empty(); }
  double durationS() const { return points_.empty() ? 0.0 : points_.back().time_s; }

  // Positions at `t_s` seconds after the start.
  std::vector<double> sample(double t_s) const {
    if (points_.empty()) return {};
    if (t_s <= points_.front().time_s) return points_.front().positions;
    if (t_s >= points_.back().time_s) return points_.back().positions;
    size_t i = 1;
    while (points_[i].time_s < t_s) ++i;
    const TrajectoryPoint& a = points_[i - 1];
    const TrajectoryPoint& b = points_[i];
    const double h = b.time_s - a.time_s, s = (t_s - a.time_s) / h;
    const bool cubic =
        !a.velocities.empty() && !b.velocities.empty() && points_[i].velocities.size() == a.positions.size();
    std::vector<double> out(a.positions.size());
    for (size_t j = 0; j < out.size(); ++j) {
      if (cubic) {
        const double s2 = s * s, s3 = s2 * s;
        out[j] = (2 * s3 - 3 * s2 + 1) * a.positions[j] + (s3 - 2 * s2 + s) * h * a.velocities[j] +
                 (-2 * s3 + 3 * s2) * b.positions[j] + (s3 - s2) * h * b.velocities[j];
      } else {
        out[j] = a.positions[j] + s * (b.positions[j] - a.positions[j]);
      }
    }
    return out;
  }

 private:
  std::vector<TrajectoryPoint> points_;
};

}  // namespace conde_sim
