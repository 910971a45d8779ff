// The simulator's step: what runs before the physics step, the step, what runs after it. The
// node, the in-process tests and the benchmarks all step the world through StepLoop::update(),
// so plugins see the same order everywhere.
//
//   StepLoop loop(sim);
//   loop.add(diff_drive_plugin);   // StepHooks, called in the order added
//   loop.add(clock_publisher);
//   loop.run(1000);                // 1000 physics steps
//
// Hooks read sim.stepCount() to know where they are: before the step it counts the steps done so
// far, after it the step just done. Rate-limited work asks an UpdateTimer (update_timer.h).
#pragma once

#include <cstdint>
#include <vector>

#include "conde_sim/simulation.h"

namespace conde_sim {

class StepHooks {
 public:
  virtual ~StepHooks() = default;
  virtual void beforeStep() {}  // commands, efforts
  virtual void afterStep() {}   // sensors, odometry, clock
};

// Calls beforeStep() and afterStep() of an object that is not a StepHooks (the ROS-free drives
// of the tests and benchmarks): `HooksOf<DiffDrive> hooks(drive); loop.add(hooks);`.
template <class T>
class HooksOf : public StepHooks {
 public:
  explicit HooksOf(T& target) : target_(target) {}
  void beforeStep() override { target_.beforeStep(); }
  void afterStep() override { target_.afterStep(); }

 private:
  T& target_;
};

class StepLoop {
 public:
  explicit StepLoop(Simulation& sim) : sim_(sim) {}
  StepLoop(const StepLoop&) = delete;
  StepLoop& operator=(const StepLoop&) = delete;

  // The hooks must outlive the loop (or be removed by clear()).
  void add(StepHooks& hooks) { hooks_.push_back(&hooks); }
  void clear() { hooks_.clear(); }

  // One physics step with every hook around it.
  void update() {
    for (StepHooks* h : hooks_) h->beforeStep();
    sim_.step();
    for (StepHooks* h : hooks_) h->afterStep();
  }
  void run(std::uint64_t steps) {
    for (std::uint64_t i = 0; i < steps; ++i) update();
  }

  Simulation& simulation() { return sim_; }

 private:
  Simulation& sim_;
  std::vector<StepHooks*> hooks_;
};

}  // namespace conde_sim
