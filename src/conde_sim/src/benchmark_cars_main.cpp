// Speed of many Ackermann cars with a LiDAR each, physics only (no ROS), per engine, side by side:
//   conde_sim_benchmark_cars CAR.urdf [cars=1,4,16,50] [sim_seconds=10] [engines=ode,bullet] [solver_iterations=10]
//                            [extra_world]
// extra_world: a world file (e.g. the mesh rocks of conde_physics/benchmark/make_mesh_world.py)
// whose objects join the arena, so that the scans meet its shapes.
// Every car runs the Ackermann drive (four driven wheels, PIDs at every 1 ms physics step) on a
// circle and casts its LiDAR (the URDF's `laser` link: 1081 beams over 270 degrees, 10 m, noise
// 0.01 m) at 40 Hz, whether or not anyone would listen. The solver runs 10 iterations per step
// by default, as in the racetrack world and the Ackermann tests (there the turning radius is
// within 0.2 % of L / tan(delta) on both engines; SDF's default is 50). Cars stand 3 m apart on
// a grid inside a walled arena. Prints a Markdown table: real-time factor by this thread's CPU
// time (what one core delivers; the wall clock of a shared machine also counts other processes)
// and by the wall clock, and the CPU time per physics step (with the PIDs) and per scan. Run it
// on one core: `taskset -c 0 conde_sim_benchmark_cars ...`.
#include <sys/resource.h>

#include <time.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "benchmark_support.h"
#include "conde_physics/world_file.h"
#include "conde_sim/ackermann_drive.h"
#include "conde_sim/laser_scanner.h"
#include "conde_sim/simulation.h"
#include "conde_sim/step_loop.h"
#include "conde_sim/update_timer.h"

namespace cp = conde_physics;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kSpacing_m = 3.0;
constexpr double kLidarRate_hz = 40.0;

int gridSide(int cars) { return static_cast<int>(std::ceil(std::sqrt(static_cast<double>(cars)))); }

// Four walls around the grid of cars, 2 m beyond the outermost car.
cp::WorldDescription arena(int cars, int solver_iterations, const cp::WorldDescription* extra) {
  const double half = (gridSide(cars) - 1) * kSpacing_m / 2.0 + 2.0;
  cp::WorldDescription w;
  w.name = "arena";
  w.physics.solver_iterations = solver_iterations;
  auto wall = [&](const std::string& name, double x, double y, double sx, double sy) {
    cp::WorldObject o;
    o.name = name;
    o.shape = cp::ObjectShape::kBox;
    o.size_m = cp::Vec3(sx, sy, 0.5);
    o.pose = cp::Pose(cp::Vec3(x, y, 0.25), cp::Quat());
    w.objects.push_back(o);
  };
  wall("north", 0, half + 0.05, 2 * half + 0.2, 0.1);
  wall("south", 0, -half - 0.05, 2 * half + 0.2, 0.1);
  wall("east", half + 0.05, 0, 0.1, 2 * half);
  wall("west", -half - 0.05, 0, 0.1, 2 * half);
  if (extra) w.objects.insert(w.objects.end(), extra->objects.begin(), extra->objects.end());
  return w;
}

// CPU time of this thread [s]: on a shared machine the wall clock also counts other people's work.
double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

struct Result {
  double sim_s = 0, wall_s = 0, cpu_s = 0, physics_s = 0, lidar_s = 0;
  long steps = 0, scans = 0;
};

Result run(const std::string& engine, const std::string& urdf, int cars, double sim_seconds, int solver_iterations,
           const cp::WorldDescription* extra) {
  conde_sim::Simulation sim(arena(cars, solver_iterations, extra), engine, nullptr);
  const int side = gridSide(cars);
  for (int i = 0; i < cars; ++i) {
    conde_sim::RobotSpec spec;
    spec.name = "car" + std::to_string(i);
    spec.source = "car";
    spec.urdf_xml = urdf;
    const double x = (i % side - (side - 1) / 2.0) * kSpacing_m, y = (i / side - (side - 1) / 2.0) * kSpacing_m;
    spec.spawn_pose = cp::Pose(cp::Vec3(x - 0.5, y - 1.0, 0.0), cp::Quat());  // circle of R 1.07 m around (x, y)
    sim.addRobot(spec);
  }
  std::vector<std::unique_ptr<conde_sim::AckermannDrive>> drives;
  std::vector<std::unique_ptr<conde_sim::LaserScanner>> lidars;
  for (int i = 0; i < cars; ++i) {
    conde_sim::AckermannDrive::Config c = conde_sim::AckermannDrive::Config::placeNamedJoints();
    c.drive_front = true;
    c.command_timeout_s = 0.0;
    drives.push_back(std::make_unique<conde_sim::AckermannDrive>(sim, i, c));
    drives.back()->commandDrive(1.0, 0.3);
    conde_sim::LaserScanConfig l;
    l.link = "laser";
    l.beam_count = 1081;
    l.min_angle_rad = -0.75 * M_PI;
    l.max_angle_rad = 0.75 * M_PI;
    l.min_range_m = 0.06;
    l.max_range_m = 10.0;
    l.noise_stddev_m = 0.01;
    l.noise_seed = static_cast<std::uint32_t>(i);
    lidars.push_back(std::make_unique<conde_sim::LaserScanner>(sim, i, l));
  }
  const conde_sim::UpdateTimer scan_timer(kLidarRate_hz, sim.stepS());
  Result r;
  r.steps = std::lround(sim_seconds / sim.stepS());
  const auto start = Clock::now();
  const double cpu_start = cpuSeconds();
  conde_sim::StepLoop loop(sim);
  std::vector<conde_sim::HooksOf<conde_sim::AckermannDrive>> hooks;
  hooks.reserve(drives.size());
  for (auto& d : drives) loop.add(hooks.emplace_back(*d));
  for (long s = 0; s < r.steps; ++s) {
    loop.update();
    if (scan_timer.due(sim.stepCount())) {
      const double t0 = cpuSeconds();  // (a system call: only around the scans, not every step)
      for (auto& l : lidars) l->scan();
      r.scans += cars;
      r.lidar_s += cpuSeconds() - t0;
    }
  }
  r.cpu_s = cpuSeconds() - cpu_start;
  r.physics_s = r.cpu_s - r.lidar_s;
  r.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  r.sim_s = sim.timeS();
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: %s CAR.urdf [cars=1,4,16,50] [sim_seconds=10] [engines=ode,bullet] [solver_iterations=10] "
                 "[extra_world]\n",
                 argv[0]);
    return 2;
  }
  const std::optional<std::string> urdf = conde_sim::benchmark::readFile(argv[1], "URDF");
  if (!urdf) return 2;
  const std::vector<std::string> car_counts = conde_sim::benchmark::splitList(argc > 2 ? argv[2] : "1,4,16,50");
  const double sim_seconds = argc > 3 ? std::atof(argv[3]) : 10.0;
  const std::vector<std::string> engines = conde_sim::benchmark::splitList(argc > 4 ? argv[4] : "ode,bullet");
  const int solver_iterations = argc > 5 ? std::atoi(argv[5]) : 10;
  try {
    std::optional<cp::WorldDescription> extra;
    if (argc > 6) {
      extra = cp::loadWorldFile(argv[6], nullptr);
      size_t triangles = 0;
      for (const cp::WorldObject& o : extra->objects) {
        if (o.collision && o.mesh) triangles += o.mesh->triangles.size() / 3;
      }
      std::printf("extra world %s: %zu objects, %zu collision triangles\n", argv[6], extra->objects.size(), triangles);
    }
    std::printf("physics at %.0f Hz, %d solver iterations; LiDAR 1081 beams over 270 degrees at %.0f Hz per car\n\n",
                1.0 / cp::PhysicsSettings().step_s, solver_iterations, kLidarRate_hz);
    std::printf(
        "| engine | cars | simulated [s] | CPU [s] | real-time factor (CPU) | real-time factor (wall) | "
        "physics + PIDs per step [us] | per scan of 1081 beams [us] |\n|---|---|---|---|---|---|---|---|\n");
    for (const std::string& cars : car_counts) {
      for (const std::string& engine : engines) {
        const Result r = run(engine, *urdf, std::stoi(cars), sim_seconds, solver_iterations, extra ? &*extra : nullptr);
        std::printf("| %s | %s | %.1f | %.2f | %.2f | %.2f | %.1f | %.0f |\n", engine.c_str(), cars.c_str(), r.sim_s,
                    r.cpu_s, r.sim_s / r.cpu_s, r.sim_s / r.wall_s, 1e6 * r.physics_s / r.steps,
                    r.scans > 0 ? 1e6 * r.lidar_s / r.scans : 0.0);
        std::fflush(stdout);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "conde_sim_benchmark_cars: error: %s\n", e.what());
    return 1;
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("\npeak RSS %.1f MB\n", usage.ru_maxrss / 1024.0);
  return 0;
}
