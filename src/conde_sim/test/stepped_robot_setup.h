// Set-up shared by the tests that build a world in-process with one of this repository's robots
// and step it, once per physics engine (diff drive, Ackermann drive, joint controllers, LiDAR).
// Needs CONDE_REPO_ROOT, the repository root (CMakeLists.txt defines it for these tests).
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "conde_sim/simulation.h"
#include "conde_sim/step_loop.h"

namespace conde_sim_test {

// A xacro file of this repository (`path` from the repository root) expanded with `args`, as the
// launch files load it; $(find ...) finds this repository's packages. Throws std::runtime_error
// with xacro's message when xacro fails (or cannot be run).
inline std::string xacroUrdf(const std::string& path, const std::string& args = "") {
  const std::string cmd = std::string("ROS_PACKAGE_PATH=") + CONDE_REPO_ROOT + " xacro " + CONDE_REPO_ROOT + "/" +
                          path + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run: " + cmd);
  std::string out;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
  const int status = pclose(pipe);
  if (status != 0)
    throw std::runtime_error("xacro " + path + " " + args + " failed (status " + std::to_string(status) + "): " + out);
  return out;
}

// The test car (tests/fixtures/ackermann_car.urdf.xacro) with its Ackermann drive plugin,
// expanded once.
inline const std::string& testCarUrdf() {
  static const std::string urdf = xacroUrdf("tests/fixtures/ackermann_car.urdf.xacro");
  return urdf;
}

// Conde (urdf/robots/conde.urdf.xacro) with its default arguments, expanded once.
inline const std::string& condeUrdf() {
  static const std::string urdf = xacroUrdf("urdf/robots/conde.urdf.xacro");
  return urdf;
}

// A world of flat ground only, named `name`, with the default physics (1 ms step, friction 1).
inline conde_physics::WorldDescription flatGround(const std::string& name) {
  conde_physics::WorldDescription w;
  w.name = name;
  return w;
}

// Adds the robot `name` from `urdf` at `spawn_pose`; `source` names the description in messages.
inline int addRobot(conde_sim::Simulation& sim, const std::string& name, const std::string& source,
                    const std::string& urdf, const conde_physics::Pose& spawn_pose = conde_physics::Pose()) {
  conde_sim::RobotSpec spec;
  spec.name = name;
  spec.source = source;
  spec.urdf_xml = urdf;
  spec.spawn_pose = spawn_pose;
  return sim.addRobot(spec);
}

// A new simulation of `world` on `engine` with robot 0 `name` from `urdf`.
inline std::unique_ptr<conde_sim::Simulation> simulationWithRobot(const conde_physics::WorldDescription& world,
                                                                  const std::string& engine, const std::string& name,
                                                                  const std::string& source, const std::string& urdf) {
  auto sim = std::make_unique<conde_sim::Simulation>(world, engine, nullptr);
  addRobot(*sim, name, source, urdf);
  return sim;
}

// A gtest fixture run once per engine (GetParam(): "ode" or "bullet") around one simulation
// with a robot; SetUp (or the test) calls ASSERT_NO_FATAL_FAILURE(buildWorld(...)) first.
class SteppedRobotTest : public ::testing::TestWithParam<std::string> {
 protected:
  // `world` on this test's engine with robot 0 `name` from `urdf` (`source` names it in messages).
  void buildWorld(const conde_physics::WorldDescription& world, const std::string& name, const std::string& source,
                  const std::string& urdf) {
    ASSERT_NE(urdf.find("<robot"), std::string::npos) << "xacro failed: " << urdf;
    sim_ = simulationWithRobot(world, GetParam(), name, source, urdf);
  }

  std::unique_ptr<conde_sim::Simulation> sim_;
};

// One physics step with a drive's hooks around it, through the simulator's own step loop.
template <class Drive>
void stepWithDrive(conde_sim::Simulation& sim, Drive& drive) {
  conde_sim::HooksOf<Drive> hooks(drive);
  conde_sim::StepLoop loop(sim);
  loop.add(hooks);
  loop.update();
}

// x, y of robot 0's base_footprint after each of `steps` steps of `drive`; `command(step)` runs
// every 50th step (20 Hz at the 1 ms step, like a driver node).
template <class Drive, class Command>
std::vector<double> baseTrajectory(conde_sim::Simulation& sim, Drive& drive, int steps, Command command) {
  conde_sim::HooksOf<Drive> hooks(drive);
  conde_sim::StepLoop loop(sim);
  loop.add(hooks);
  std::vector<double> xy;
  for (int i = 0; i < steps; ++i) {
    if (i % 50 == 0) command(i);
    loop.update();
    const conde_physics::Pose p = sim.linkPose(0, "base_footprint");
    xy.push_back(p.position.x);
    xy.push_back(p.position.y);
  }
  return xy;
}

// Every physics behaviour is tested on both engines:
//   INSTANTIATE_TEST_SUITE_P(BothEngines, Suite, bothEngines(), engineName);
inline auto bothEngines() { return ::testing::Values("ode", "bullet"); }
inline std::string engineName(const ::testing::TestParamInfo<std::string>& info) { return info.param; }

}  // namespace conde_sim_test
