// A drive command of two values (speed and yaw rate, speed and steering angle, ...) with the
// simulated time it arrived at, for the drives' command timeouts. Free of ROS.
#pragma once

#include <cmath>

namespace conde_sim {

struct TimedCommand {
  double first = 0.0, second = 0.0;  // in the units of the drive that keeps it
  double time_s = 0.0;               // simulated time of arrival
  bool received = false;

  // Returns false, keeping the previous command, when a value is NaN or infinite.
  bool set(double first_value, double second_value, double now_s) {
    if (!std::isfinite(first_value) || !std::isfinite(second_value)) return false;
    first = first_value;
    second = second_value;
    time_s = now_s;
    received = true;
    return true;
  }
  // True when a command came and none followed for more than timeout_s (0 = never times out).
  bool timedOut(double now_s, double timeout_s) const {
    return received && timeout_s > 0.0 && now_s - time_s > timeout_s;
  }
  void reset() { *this = TimedCommand(); }
};

}  // namespace conde_sim
