"""conde_decision on a car (Major Alvega), against a real roscore: the robot's manoeuvre file
(~manoeuvres) laid over the state machine, and every arc checked against the car's minimum turning
radius read from /robot_description through its wheel file (~ackermann_wheel_file); an arc tighter
than the car turns stops the node with one line naming the parameter, the state and both radii."""

import os
import subprocess

import pytest

from conde_testing.ros_harness import Roscore, fatal_error

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.dirname(os.path.dirname(HERE))
STATES = os.path.join(SRC, "conde_decision", "config", "conde_states.yaml")
MAJOR = os.path.join(SRC, "conde_major", "config")
WHEELS = os.path.join(MAJOR, "major_ackermann_controller.yaml")
XACRO = os.path.join(os.path.dirname(SRC), "urdf", "robots", "major_alvega.urdf.xacro")
TURNING = ("0.445 m (/robot_description: wheelbase 0.320 m, hinges 0.250 m apart, steering limit 0.7854 rad)")


@pytest.fixture(scope="module")
def core():
    with Roscore("conde_decision_car") as core:
        urdf = subprocess.run(["xacro", XACRO, "cameras:=false"], env=core.env, capture_output=True, text=True,
                              check=True).stdout
        core.set_params({"/robot_description": urdf})
        yield core


def startup_error(core, **params):
    core.set_params({}, clear=["/conde_decision"])
    args = ["rosrun", "conde_decision", "conde_decision"] + ["_%s:=%s" % kv for kv in params.items()]
    proc = subprocess.run(args, env=core.env, capture_output=True, text=True, timeout=120)
    return fatal_error(proc.returncode, proc.stderr, "conde_decision")


def test_condes_parking_arcs_are_refused_on_major_alvega(core):
    assert startup_error(core, ackermann_wheel_file=WHEELS) == (
        "parameter /conde_decision/state_machine (%s): states.park_swing_out.command.radius_m: 0.400 m is tighter "
        "than the robot's minimum turning radius %s; give the state a radius >= 0.445 m in the robot's manoeuvre "
        "file" % (STATES, TURNING))


def test_a_manoeuvre_file_radius_tighter_than_the_car_names_the_parameter(core, tmp_path):
    path = tmp_path / "tight.yaml"
    path.write_text("park_swing_out: {radius_m: 0.5}\npark_swing_in: {radius_m: 0.44, distance_m: 0.7}\n")
    assert startup_error(core, ackermann_wheel_file=WHEELS, manoeuvres=str(path)) == (
        "parameter /conde_decision/manoeuvres (%s): park_swing_in.radius_m: 0.440 m is tighter than the robot's "
        "minimum turning radius %s; give the state a radius >= 0.445 m in the robot's manoeuvre file"
        % (path, TURNING))
