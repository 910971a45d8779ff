#include "conde_sim/update_timer.h"

#include <algorithm>
#include <cmath>

namespace conde_sim {

UpdateTimer::UpdateTimer(double rate_hz, double step_s) {
  if (rate_hz <= 0.0 || step_s <= 0.0) return;
  const double steps = 1.0 / (rate_hz * step_s);
  // A whole number of steps up to rounding error (1 / (50 Hz * 0.001 s) = 20.000000000000004).
  steps_per_update_ = std::max(1.0, std::abs(steps - std::round(steps)) < 1e-9 ? std::round(steps) : steps);
}

UpdateTimer UpdateTimer::everySteps(std::uint64_t steps) {
  UpdateTimer timer;
  timer.steps_per_update_ = static_cast<double>(std::max<std::uint64_t>(1, steps));
  return timer;
}

std::uint64_t UpdateTimer::updateStep(std::uint64_t k) const {
  return static_cast<std::uint64_t>(std::llround(static_cast<double>(k) * steps_per_update_));
}

bool UpdateTimer::due(std::uint64_t step) const {
  // The update whose step is nearest: k = floor(step / steps_per_update) or the next one.
  const auto k = static_cast<std::uint64_t>(std::floor(static_cast<double>(step) / steps_per_update_));
  return updateStep(k) == step || updateStep(k + 1) == step;
}

}  // namespace conde_sim
