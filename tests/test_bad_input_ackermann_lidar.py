"""Bad configuration of the Ackermann drive, the ros_control controllers and the LiDAR stops
conde_sim_node at start-up with an exact message naming the file, line, plugin and key, and a
non-zero exit. Each case runs the real node against a real roscore on a free loopback port, with
the test car of fixtures/ackermann_car.urdf.xacro changed in one place."""
import os
import subprocess

import pytest
import rosgraph
from conde_testing.ros_harness import fatal_error

from test_bad_input import FLAT_WORLD

HERE = os.path.dirname(os.path.abspath(__file__))
CAR_XACRO = os.path.join(HERE, "fixtures", "ackermann_car.urdf.xacro")

# The controller YAML the good ros_control car needs (the same as fixtures/ackermann_car_controllers.yaml).
PID = {"p": 100.0, "i": 100.0, "d": 0.2, "i_clamp": 0.1}
CONTROLLERS = {
    "joint_state_ctrlr": {"type": "joint_state_controller/JointStateController", "publish_rate": 30},
    "left_steering_ctrlr": {"type": "effort_controllers/JointPositionController", "joint": "left_steering_joint",
                            "pid": PID},
}


def car_urdf(drive="ackermann"):
    return subprocess.run(["xacro", CAR_XACRO, f"drive:={drive}"], check=True, capture_output=True,
                          text=True).stdout


def changed(urdf, old, new):
    assert urdf.count(old) == 1, f"expected '{old}' once in the car's URDF"
    return urdf.replace(old, new)


def line_of(urdf, text):
    """1-based line of the first line of `urdf` that contains `text`."""
    for number, line in enumerate(urdf.splitlines(), start=1):
        if text in line:
            return number
    raise AssertionError(f"'{text}' not in the URDF")


_controllers_set = set()


def run_node(env, urdf, controllers=None, **params):
    """Starts conde_sim_node on the flat world; returns (exit code, stderr)."""
    master_api = rosgraph.Master("/bad_input_test", master_uri=env["ROS_MASTER_URI"])
    # Parameters of earlier cases stay on the master: start from none.
    for name in ["/conde_sim"] + sorted(_controllers_set):
        if master_api.hasParam(name):
            master_api.deleteParam(name)
    master_api.setParam("/robot_description", urdf)
    for name, config in (controllers or {}).items():
        master_api.setParam("/" + name, config)
        _controllers_set.add("/" + name)
    args = ["rosrun", "conde_sim", "conde_sim_node", f"_world_file:={FLAT_WORLD}", "_real_time_factor:=0",
            "_max_sim_time_s:=0.2"] + [f"_{k}:={v}" for k, v in params.items()]
    proc = subprocess.run(args, env=env, capture_output=True, text=True, timeout=60)
    return proc.returncode, proc.stderr


def startup_error(env, urdf, controllers=None):
    """The error line of a start of conde_sim_node that must fail."""
    return fatal_error(*run_node(env, urdf, controllers), "conde_sim")


# ---------------------------------------------------------------- Ackermann drive

ACKERMANN = "plugin 'ackermann_drive' (libconde_ackermann_drive.so)"


@pytest.mark.parametrize("old, new, detail", [
    ("<rightSteeringJoint>right_steering_joint</rightSteeringJoint>", "",
     "<rightSteeringJoint>: required parameter is missing"),
    ("<leftSteeringJoint>left_steering_joint<", "<leftSteeringJoint>left_steer<",
     "<leftSteeringJoint>: robot 'ackermann_car' has no movable joint named 'left_steer'"),
    # A wheel joint (about y) named as the steering joint.
    ("<rightSteeringJoint>right_steering_joint<", "<rightSteeringJoint>right_front_wheel_joint<",
     "<rightSteeringJoint>: joint 'right_front_wheel_joint' must turn about the vertical (z) axis of 'base_footprint'"),
    ("<driveWheels>rear</driveWheels>", "<driveWheels>4wd</driveWheels>",
     "<driveWheels>: expected 'rear', 'front' or 'all', got '4wd'"),
], ids=["steering_joint_missing", "steering_joint_unknown", "steering_joint_about_the_wrong_axis",
        "unknown_drive_wheels"])
def test_bad_ackermann_drive(master, old, new, detail):
    urdf = changed(car_urdf(), old, new)
    line = line_of(urdf, 'filename="libconde_ackermann_drive.so"')
    assert startup_error(master, urdf) == f"/robot_description:{line}: {ACKERMANN}: {detail}"


# ---------------------------------------------------------------- ros_control controllers

ROS_CONTROL = "plugin 'gazebo_ros_control' (libgazebo_ros_control.so)"


def ros_control_error(master, urdf, controllers):
    """The start-up error of the ros_control car with `controllers`, and the URDF line it must name."""
    return startup_error(master, urdf, controllers), line_of(urdf, 'filename="libgazebo_ros_control.so"')


def test_controller_with_unknown_joint(master):
    controllers = dict(CONTROLLERS)
    controllers["left_steering_ctrlr"] = dict(CONTROLLERS["left_steering_ctrlr"], joint="left_steer")
    error, line = ros_control_error(master, car_urdf("ros_control"), controllers)
    assert error == (f"/robot_description:{line}: {ROS_CONTROL}: controller 'left_steering_ctrlr': "
                     "parameter /left_steering_ctrlr/joint: robot 'ackermann_car' has no movable joint "
                     "named 'left_steer'")


def test_controller_of_an_unsupported_type(master):
    controllers = dict(CONTROLLERS)
    controllers["base_ctrlr"] = {"type": "diff_drive_controller/DiffDriveController"}
    error, line = ros_control_error(master, car_urdf("ros_control"), controllers)
    assert error == (
        f"/robot_description:{line}: {ROS_CONTROL}: controller 'base_ctrlr': parameter /base_ctrlr/type: "
        "unsupported controller type 'diff_drive_controller/DiffDriveController' (supported: "
        "effort_controllers/JointPositionController, effort_controllers/JointVelocityController, "
        "effort_controllers/JointEffortController, velocity_controllers/JointVelocityController, "
        "position_controllers/JointPositionController, position_controllers/JointTrajectoryController, "
        "joint_state_controller/JointStateController)")


@pytest.mark.parametrize("controller, detail", [
    ({"type": "position_controllers/JointPositionController", "joint": "right_steering_joint",
      "mimic_joints": ["left_steer"]},
     "parameter /right_steering_ctrlr/mimic_joints: robot 'ackermann_car' has no movable joint named 'left_steer'"),
    ({"type": "position_controllers/JointPositionController", "joint": "right_steering_joint",
      "mimic_joints": ["left_steering_joint"]},
     "parameter /right_steering_ctrlr/mimic_joints: joint 'left_steering_joint' is already controlled by "
     "'left_steering_ctrlr'"),
    ({"type": "position_controllers/JointPositionController", "joint": "right_steering_joint",
      "mimic_joints": "left_front_wheel_joint"},
     "parameter /right_steering_ctrlr/mimic_joints: expected a list of joint names, got a string"),
    ({"type": "position_controllers/JointTrajectoryController", "joints": ["right_steering_joint"],
      "mimic_joints": {"left_front_wheel_joint": "right_front_wheel_joint"}},
     "parameter /right_steering_ctrlr/mimic_joints/left_front_wheel_joint: the master must be one of `joints`"),
    ({"type": "position_controllers/JointTrajectoryController"},
     "parameter /right_steering_ctrlr/joints: required: a list of joint names"),
], ids=["mimic_joint_unknown", "mimic_joint_already_controlled", "mimic_joints_not_a_list",
        "trajectory_mimic_master_not_a_joint", "trajectory_without_joints"])
def test_bad_coupled_or_trajectory_controller(master, controller, detail):
    controllers = dict(CONTROLLERS, right_steering_ctrlr=controller)
    error, line = ros_control_error(master, car_urdf("ros_control"), controllers)
    assert error == f"/robot_description:{line}: {ROS_CONTROL}: controller 'right_steering_ctrlr': {detail}"


def test_controller_with_an_unknown_pid_key(master):
    controllers = dict(CONTROLLERS)
    controllers["left_steering_ctrlr"] = dict(CONTROLLERS["left_steering_ctrlr"], pid={"p": 1.0, "I": 0.5})
    error, line = ros_control_error(master, car_urdf("ros_control"), controllers)
    assert error == (f"/robot_description:{line}: {ROS_CONTROL}: controller 'left_steering_ctrlr': "
                     "parameter /left_steering_ctrlr/pid/I: unknown key (expected one of: p, i, d, "
                     "i_clamp, i_clamp_min, i_clamp_max, antiwindup, publish_state)")


def test_listed_controller_without_yaml(master):
    urdf = changed(car_urdf("ros_control"), "<legacyModeNS>true</legacyModeNS>",
                   "<legacyModeNS>true</legacyModeNS><controllers>joint_state_ctrlr steer_ctrlr</controllers>")
    error, line = ros_control_error(master, urdf, CONTROLLERS)
    assert error == (f"/robot_description:{line}: {ROS_CONTROL}: controller 'steer_ctrlr': parameter "
                     "/steer_ctrlr/type: not set: load the controller YAML before the simulator starts")


# ---------------------------------------------------------------- LiDAR

LIDAR = "sensor 'lidar' (ray)"


@pytest.mark.parametrize("edits, named_line, detail", [
    ([("<samples>1081</samples>", "<samples>0</samples>")], "<samples>0</samples>",
     "<ray><scan><horizontal><samples>: must be at least 1, got 0"),
    ([("<min_angle>-2.35619449</min_angle>", "<min_angle>1.0</min_angle>"),
      ("<max_angle>2.35619449</max_angle>", "<max_angle>0.5</max_angle>")], "<max_angle>0.5</max_angle>",
     "<ray><scan><horizontal><max_angle>: must be greater than <min_angle> (1), got 0.5"),
    ([("<min>0.06</min>", "<min>5</min>"), ("<max>10.0</max>", "<max>2</max>")], "<max>2</max>",
     "<ray><range><max>: must be greater than <min> (5), got 2"),
    ([("<resolution>0.01</resolution>", "<resolution>0.01</resolution><step>0.1</step>")], "<step>0.1</step>",
     "unknown element <ray><range><step>"),
], ids=["zero_samples", "min_angle_not_below_max_angle", "min_range_not_below_max_range", "unknown_element"])
def test_bad_lidar(master, edits, named_line, detail):
    urdf = car_urdf()
    for old, new in edits:
        urdf = changed(urdf, old, new)
    line = line_of(urdf, named_line)
    assert startup_error(master, urdf) == f"/robot_description:{line}: {LIDAR}: {detail}"


# ---------------------------------------------------------------- good input

@pytest.mark.parametrize("engine", ["ode", "bullet"])
@pytest.mark.parametrize("drive", ["ackermann", "ros_control"])
def test_good_car_runs_to_max_sim_time(master, engine, drive):
    code, err = run_node(master, car_urdf(drive), CONTROLLERS if drive == "ros_control" else None,
                         physics_engine=engine)
    assert code == 0, err
