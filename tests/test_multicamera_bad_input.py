"""Bad configuration of libgazebo_ros_multicamera.so stops conde_sim_node at start-up with an exact
message naming the file, line, plugin (or sensor and camera) and key, and a non-zero exit. Each case
runs the real node against a real roscore on a free loopback port, with the robot of
fixtures/stereo_camera_bot.urdf changed in one place."""
import os

import pytest

from test_bad_input import FLAT_WORLD, startup_error
from test_gazebo_sensor_bad_input import line_of

HERE = os.path.dirname(os.path.abspath(__file__))
with open(os.path.join(HERE, "fixtures", "stereo_camera_bot.urdf"), encoding="utf-8") as f:
    BOT_URDF = f.read()

RIGHT_CLIP = '<camera name="right">\n        <pose>0 -0.05 0 0 0 0</pose>\n        <horizontal_fov>1.0</horizontal_fov>'


@pytest.mark.parametrize("old, new, at, detail", [
    ("<hackBaseline>0.1</hackBaseline>", "<hackBaseline>0.1</hackBaseline><baseLine>0.1</baseLine>", "<baseLine>",
     "plugin 'stereo_camera_controller' (libgazebo_ros_multicamera.so): unknown parameter <baseLine>"),
    (RIGHT_CLIP, RIGHT_CLIP + "<fov>1.0</fov>", "<fov>",
     "sensor 'stereo_camera' (multicamera): unknown element <camera><fov>"),
    ('<camera name="right">', '<camera name="centre">', '<camera name="centre">',
     "sensor 'stereo_camera' (multicamera): <camera name=\"centre\">: a camera of libgazebo_ros_multicamera.so "
     "needs a name that contains 'left' or 'right' (got 'centre')"),
    ('<camera name="right">', '<camera name="left2">', '<camera name="left2">',
     "sensor 'stereo_camera' (multicamera): <camera name=\"left2\">: a second left camera"),
    ("<image><width>160</width><height>120</height><format>R8G8B8</format></image>\n        "
     "<clip><near>0.02</near><far>30</far></clip>\n        <noise>",
     "<image><width>160</width><height>-1</height><format>R8G8B8</format></image>\n        "
     "<clip><near>0.02</near><far>30</far></clip>\n        <noise>", "<height>-1</height>",
     "sensor 'stereo_camera' (multicamera): <camera name=\"right\"><image>: image size must be a positive whole "
     "number of pixels (got 160x-1)"),
    ('<origin xyz="0 0.05 0" rpy="-1.57 0 -1.57"/>', '<origin xyz="0 -0.05 0" rpy="-1.57 0 -1.57"/>',
     'name="stereo_camera_controller"',
     "plugin 'stereo_camera_controller' (libgazebo_ros_multicamera.so): <frameName>: link 'stereo_left_optical' is "
     "not the optical frame of the camera on link 'stereo_link' (REP 103: z forward, x right, y down; expected rpy "
     "-pi/2 0 -pi/2 from the camera link, within 0.5 degrees)"),
], ids=["unknown_plugin_key", "unknown_camera_element", "camera_neither_left_nor_right", "second_left_camera",
        "right_image_size", "frame_not_the_left_optical_frame"])
def test_bad_multicamera(master, old, new, at, detail):
    assert BOT_URDF.count(old) == 1, f"expected '{old}' once in the fixture"
    urdf = BOT_URDF.replace(old, new)
    message = startup_error(master, urdf, world_file=FLAT_WORLD, max_sim_time_s=0.1)
    assert message == f"/robot_description:{line_of(urdf, at)}: {detail}"
