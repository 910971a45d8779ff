// When something periodic runs in simulated time: plugins publishing at their update rate, the
// camera's frames, /clock, controllers. One mechanism for all of them.
//
//   UpdateTimer timer(50.0, sim.stepS());       // 50 Hz at a 1 ms step: every 20th step
//   if (timer.due(sim.stepCount())) publish();
//
// Update k falls on step round(k * steps_per_update), so a rate that is not a whole number of
// steps keeps its exact mean (30 Hz at 1 ms: 33, 33, 34 steps apart, 30 updates per simulated
// second); a whole number of steps gives every n-th step, counted from step 0. A rate <= 0, or one
// faster than the step, updates at every step. due() depends only on the step number, so a hook
// before and one after the physics step can ask the same timer.
#pragma once

#include <cstdint>

namespace conde_sim {

class UpdateTimer {
 public:
  UpdateTimer() = default;  // every step
  UpdateTimer(double rate_hz, double step_s);
  // Every `steps` steps (at least 1).
  static UpdateTimer everySteps(std::uint64_t steps);

  bool due(std::uint64_t step) const;
  // Steps between updates (not a whole number for rates that are not); their duration [s] is
  // stepsPerUpdate() * step_s.
  double stepsPerUpdate() const { return steps_per_update_; }
  // Update rate in updates per simulated second for a step of step_s.
  double rateHz(double step_s) const { return 1.0 / (steps_per_update_ * step_s); }

 private:
  std::uint64_t updateStep(std::uint64_t k) const;

  double steps_per_update_ = 1.0;
};

}  // namespace conde_sim
