// Physics-only speed of a robot in a world, for each engine in one process (side by side):
//   conde_sim_benchmark WORLD.world.yaml ROBOT.urdf [sim_seconds=20] [engines=ode,bullet]
// The robot is spawned at the world's first spawn pose and its diff drive (if it has one named
// left_wheel_joint/right_wheel_joint) is commanded along a gentle curve. Prints a Markdown table.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "benchmark_support.h"
#include "conde_physics/world_file.h"
#include "conde_sim/diff_drive_controller.h"
#include "conde_sim/simulation.h"
#include "conde_sim/step_loop.h"

namespace cp = conde_physics;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s WORLD.world.yaml ROBOT.urdf [sim_seconds] [engines]\n", argv[0]);
    return 2;
  }
  const double sim_seconds = argc > 3 ? std::atof(argv[3]) : 20.0;
  const std::vector<std::string> engines = conde_sim::benchmark::splitList(argc > 4 ? argv[4] : "ode,bullet");
  const std::optional<std::string> urdf = conde_sim::benchmark::readFile(argv[2], "URDF");
  if (!urdf) return 2;
  try {
    const cp::WorldDescription world = cp::loadWorldFile(argv[1], nullptr);
    std::printf("| engine | simulated [s] | wall [s] | real-time factor | step [us] |\n|---|---|---|---|---|\n");
    for (const std::string& engine : engines) {
      conde_sim::Simulation sim(world, engine, nullptr);
      conde_sim::RobotSpec spec;
      spec.name = "robot";
      spec.source = argv[2];
      spec.urdf_xml = *urdf;
      spec.spawn_pose = world.spawns.empty() ? cp::Pose() : world.spawns.front().pose;
      sim.addRobot(spec);
      conde_sim::DiffDrive::Config c;
      c.left_joint = "left_wheel_joint";
      c.right_joint = "right_wheel_joint";
      c.params.wheel_separation_m = 0.33;
      c.params.wheel_diameter_m = 0.064;
      c.params.command_timeout_s = 0.0;
      conde_sim::DiffDrive drive(sim, 0, c);
      drive.command(0.3, 0.2);
      const long steps = std::lround(sim_seconds / sim.stepS());
      conde_sim::HooksOf<conde_sim::DiffDrive> hooks(drive);
      conde_sim::StepLoop loop(sim);
      loop.add(hooks);
      const auto start = std::chrono::steady_clock::now();
      loop.run(steps);
      const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("| %s | %.1f | %.3f | %.1f | %.2f |\n", engine.c_str(), sim.timeS(), wall_s, sim.timeS() / wall_s,
                  1e6 * wall_s / steps);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "conde_sim_benchmark: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
