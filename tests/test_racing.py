"""racetrack.launch of conde_racing with 4 F1/10 cars, on each engine, against a real roscore on a
free loopback port: the four namespaced cars come up, each answers only its own command topic,
TF has no two frames of the same name, and the lap timer reports a lap of car0 driven by its
reference driver (gap_follower), in the CSV too. The simulation starts paused and is stepped
one LiDAR period at a time by racing_checks.py, which prints its measurements as JSON."""
import csv
import json
import os
import signal
import subprocess
import sys

import pytest

from conde_testing.ros_harness import Roscore

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "src", "conde_racing", "src"))
from conde_racing import racetrack as rt  # noqa: E402

ENGINES = ["ode", "bullet"]
CARS = ["car0", "car1", "car2", "car3"]
CAR_FRAMES = {"odom", "base_footprint", "base_link", "left_rear_wheel", "right_rear_wheel", "left_steering_link",
              "right_steering_link", "left_front_wheel", "right_front_wheel", "laser", "imu_link", "camera_link",
              "camera_optical"}
MAX_SPEED_MPS = 2.0          # racetrack.launch's default max_speed of the drivers
SIM_TIME_LIMIT_S = 90.0      # for car0's lap (about 15 s at 2 m/s)


@pytest.fixture(scope="module", params=ENGINES)
def run(request, tmp_path_factory):
    engine = request.param
    out_dir = tmp_path_factory.mktemp("racing_" + engine)
    laps_csv = out_dir / "laps.csv"
    log_path = out_dir / "roslaunch.log"
    # A roscore of its own for each engine's run, so that nothing the first run left registered (a
    # node not unregistered yet) can answer the second run's calls.
    with Roscore("conde_racing") as core, open(log_path, "w") as log:
        master = core.env
        launch = subprocess.Popen(
            ["roslaunch", "conde_racing", "racetrack.launch", "cars:=4", "physics_engine:=" + engine, "paused:=true",
             "real_time_factor:=0", "drivers_enabled:=false", "laps_csv:=%s" % laps_csv],
            env=master, stdout=log, stderr=subprocess.STDOUT)
        try:
            probe = subprocess.run([sys.executable, os.path.join(HERE, "racing_checks.py"), "--cars", "4",
                                    "--sim-time-limit", str(SIM_TIME_LIMIT_S)],
                                   env=master, capture_output=True, text=True, timeout=1800)
        finally:
            launch.send_signal(signal.SIGINT)
            launch.wait(timeout=120)
    launch_log = log_path.read_text()
    problems = "\n".join(line for line in launch_log.splitlines() if "died" in line or "rror" in line)
    assert probe.returncode == 0, "%s\n--- roslaunch log (%s), problems ---\n%s\n--- its end ---\n%s" % (
        probe.stderr[-4000:], log_path, problems, launch_log[-3000:])
    results = json.loads(probe.stdout)
    results["csv_rows"] = list(csv.reader(laps_csv.open())) if laps_csv.exists() else None
    results["launch_log"] = launch_log
    print("%s: lap rows %s, %.1f s simulated in %.1f s of wall time, max |lateral| %.3f m" % (
        engine, results["lap_rows"], results["lap_sim_time_s"], results["lap_wall_time_s"],
        results["car0_max_abs_lateral_m"]))
    return results


def test_four_namespaced_cars_come_up(run):
    assert run["cars_with_ground_truth"] == CARS


def test_each_car_answers_only_its_own_command_topic(run):
    moved = run["moved_when_car1_commanded_m"]
    assert moved["car1"] == pytest.approx(0.5, abs=0.1)
    for car in ("car0", "car2", "car3"):
        assert moved[car] < 0.005, moved


def test_tf_frames_do_not_collide(run):
    parents, publishers = {}, {}
    for parent, child, caller, _topic in run["tf_edges"]:
        parents.setdefault(child, set()).add(parent)
        publishers.setdefault(child, set()).add(caller)
    for child in parents:
        assert len(parents[child]) == 1, "%s has parents %s" % (child, parents[child])
        assert len(publishers[child]) == 1, "%s is published by %s" % (child, publishers[child])
    expected = {"%s/%s" % (car, frame) for car in CARS for frame in CAR_FRAMES}
    assert set(parents) == expected
    for child, (parent,) in parents.items():
        car = child.split("/")[0]
        assert parent == "world" if child == car + "/odom" else parent.startswith(car + "/"), (parent, child)


def test_lap_timer_reports_a_lap_of_car0(run):
    rows = [row.split(",") for row in run["lap_rows"]]
    assert rows, "no lap within %g s of simulated time" % SIM_TIME_LIMIT_S
    car, lap, start_s, end_s, lap_s, distance_m, average_mps, top_mps = rows[0]
    assert (car, lap) == ("car0", "1")
    lap_s, distance_m, average_mps, top_mps = float(lap_s), float(distance_m), float(average_mps), float(top_mps)
    assert float(end_s) - float(start_s) == pytest.approx(lap_s, abs=0.002)
    # a lap of the 31 m centre line, shorter on the inside of the turns (4 pi rad of turning)
    assert rt.CentreLine().length_m - 0.55 * 4 * 3.1416 < distance_m < rt.CentreLine().length_m + 2.0
    assert average_mps == pytest.approx(distance_m / lap_s, abs=0.002)
    assert 0.5 < average_mps <= top_mps <= MAX_SPEED_MPS * 1.15
    # it stayed between the walls (base_footprint is the rear-axle centre, 0.155 m from the side)
    assert run["car0_max_abs_lateral_m"] < rt.HALF_WIDTH_M - 0.1
    # the cars parked off the track did not move
    for car, moved in run["parked_cars_moved_m"].items():
        assert moved < 0.005, (car, moved)
    # the same lap in the CSV written at shutdown
    assert run["csv_rows"] is not None, "no CSV"
    assert run["csv_rows"][0] == ["car", "lap", "start_time_s", "end_time_s", "lap_time_s", "distance_m",
                                  "average_speed_mps", "top_speed_mps"]
    assert ",".join(run["csv_rows"][1]) == run["lap_rows"][0]
    assert "lap_timer: 1 lap(s) written to" in run["launch_log"]
