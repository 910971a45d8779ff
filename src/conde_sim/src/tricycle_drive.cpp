#include "conde_sim/tricycle_drive.h"

#include <algorithm>
#include <cmath>

namespace conde_sim {

bool TricycleController::setCommand(double speed_mps, double steering_angle_rad, double time_s) {
  return command_.set(speed_mps, steering_angle_rad, time_s);
}

bool TricycleController::timedOut(double time_s) const { return command_.timedOut(time_s, params_.command_timeout_s); }

void TricycleController::reset() { command_.reset(); }

double TricycleController::wheelSpeed(double time_s, double current_radps, double dt_s) const {
  const double target = timedOut(time_s) ? 0.0 : command_.first / (params_.actuated_wheel_diameter_m / 2.0);
  if (params_.wheel_acceleration_radps2 <= 0.0) return target;
  const double diff = target - current_radps;
  if (std::abs(diff) < params_.wheel_speed_tolerance_radps) return target;
  // Speeding up: the magnitude grows (same sign, or from a standstill); otherwise slowing down.
  const bool speeding_up = std::abs(target) > std::abs(current_radps) && target * current_radps >= 0.0;
  const double rate = speeding_up ? params_.wheel_acceleration_radps2 : params_.wheel_deceleration_radps2;
  if (rate <= 0.0) return target;
  return current_radps + std::clamp(diff, -rate * dt_s, rate * dt_s);
}

double TricycleController::steeringTarget() const { return std::clamp(command_.second, -M_PI / 2.0, M_PI / 2.0); }

double TricycleController::steeringSpeed(double current_rad) const {
  const double diff = steeringTarget() - current_rad;
  if (std::abs(diff) < params_.steering_angle_tolerance_rad) return 0.0;
  return diff > 0.0 ? params_.steering_speed_radps : -params_.steering_speed_radps;
}

}  // namespace conde_sim
