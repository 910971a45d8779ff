// The step loop and its timer, without ROS: hooks in order around each physics step, and update
// schedules in whole steps at exact mean rates.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "conde_sim/step_loop.h"
#include "conde_sim/update_timer.h"

namespace cs = conde_sim;
namespace cp = conde_physics;

namespace {

std::vector<std::uint64_t> dueSteps(const cs::UpdateTimer& timer, std::uint64_t steps) {
  std::vector<std::uint64_t> due;
  for (std::uint64_t s = 1; s <= steps; ++s)
    if (timer.due(s)) due.push_back(s);
  return due;
}

}  // namespace

TEST(UpdateTimer, WholeNumberOfStepsIsEveryNthStep) {
  const cs::UpdateTimer timer(50.0, 0.001);  // 1 / (50 * 0.001) = 20.000000000000004
  EXPECT_EQ(timer.stepsPerUpdate(), 20.0);
  for (std::uint64_t s = 0; s < 5000; ++s) EXPECT_EQ(timer.due(s), s % 20 == 0) << s;
}

TEST(UpdateTimer, FractionalPeriodKeepsTheExactRate) {
  const cs::UpdateTimer timer(30.0, 0.001);  // 33.33 steps per update
  const std::vector<std::uint64_t> due = dueSteps(timer, 10000);
  EXPECT_EQ(due.size(), 300u);  // 30 per simulated second, exactly
  EXPECT_EQ(due.front(), 33u);
  for (size_t k = 0; k < due.size(); ++k) {  // update k + 1 on step round((k + 1) * 33.33...)
    EXPECT_EQ(due[k], static_cast<std::uint64_t>(std::llround((k + 1) * (1.0 / 0.03)))) << k;
  }
  for (size_t k = 1; k < due.size(); ++k) {
    const auto gap = due[k] - due[k - 1];
    EXPECT_TRUE(gap == 33 || gap == 34) << gap;
  }
}

TEST(UpdateTimer, NoRateOrTooFastIsEveryStep) {
  for (const cs::UpdateTimer& timer : {cs::UpdateTimer(), cs::UpdateTimer(0.0, 0.001), cs::UpdateTimer(5000.0, 0.001),
                                       cs::UpdateTimer::everySteps(0)}) {
    EXPECT_EQ(timer.stepsPerUpdate(), 1.0);
    EXPECT_EQ(dueSteps(timer, 100).size(), 100u);
  }
  EXPECT_EQ(dueSteps(cs::UpdateTimer::everySteps(7), 70),
            (std::vector<std::uint64_t>{7, 14, 21, 28, 35, 42, 49, 56, 63, 70}));
}

TEST(UpdateTimer, RateOfTheTimer) { EXPECT_NEAR(cs::UpdateTimer(40.0, 0.001).rateHz(0.001), 40.0, 1e-9); }

namespace {

struct Recorder : cs::StepHooks {
  Recorder(std::string name, cs::Simulation& sim, std::vector<std::string>& log) : name(name), sim(sim), log(log) {}
  void beforeStep() override { log.push_back(name + " before " + std::to_string(sim.stepCount())); }
  void afterStep() override { log.push_back(name + " after " + std::to_string(sim.stepCount())); }
  std::string name;
  cs::Simulation& sim;
  std::vector<std::string>& log;
};

cp::WorldDescription flatWorld() {
  cp::WorldDescription world;
  world.name = "flat";
  return world;
}

}  // namespace

TEST(StepLoop, HooksRunInOrderAroundEachPhysicsStep) {
  cs::Simulation sim(flatWorld(), "ode", nullptr);
  std::vector<std::string> log;
  Recorder a("a", sim, log), b("b", sim, log);
  cs::StepLoop loop(sim);
  loop.add(a);
  loop.add(b);
  loop.run(2);
  EXPECT_EQ(log, (std::vector<std::string>{"a before 0", "b before 0", "a after 1", "b after 1", "a before 1",
                                           "b before 1", "a after 2", "b after 2"}));
  EXPECT_EQ(sim.stepCount(), 2u);
}
