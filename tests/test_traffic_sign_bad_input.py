"""Bad camera lists stop the conde_traffic_sign node at start-up with a message naming the parameter,
and a non-zero exit: the real node against a real roscore on a free loopback port."""
import subprocess

import pytest
import rosgraph
from conde_testing.ros_harness import fatal_error


def startup_error(env, extra_cameras):
    master_api = rosgraph.Master("/traffic_sign_bad_input_test", master_uri=env["ROS_MASTER_URI"])
    master_api.setParam("/conde_traffic_sign/extra_cameras", extra_cameras)
    proc = subprocess.run(["rosrun", "conde_traffic_sign", "conde_traffic_sign"], env=env, capture_output=True,
                          text=True, timeout=60)
    return fatal_error(proc.returncode, proc.stderr, "conde_traffic_sign")


REAR = {"image_topic": "/conde_camera_signs_rear/image_raw",
        "camera_info_topic": "/conde_camera_signs_rear/camera_info"}


@pytest.mark.parametrize("extra_cameras, message", [
    ([REAR, dict(REAR, lens="wide")], "parameter /conde_traffic_sign/extra_cameras[1]: expected {image_topic"),
    ([dict(REAR, image_topic="/conde_camera_signalling_panel/image_raw")],
     "parameter /conde_traffic_sign/extra_cameras: an image topic is listed twice"),
])
def test_a_bad_camera_list_stops_the_node_naming_the_entry(master, extra_cameras, message):
    assert startup_error(master, extra_cameras).startswith(message)
