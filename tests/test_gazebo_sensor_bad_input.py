"""Bad configuration of the range, block laser and model-form IMU plugins stops conde_sim_node at
start-up with an exact message naming the file, line, plugin and key, and a non-zero exit. Each
case runs the real node against a real roscore on a free loopback port, with the robot of
fixtures/ray_imu_bot.urdf changed in one place."""
import os

import pytest

from test_bad_input import FLAT_WORLD, startup_error

HERE = os.path.dirname(os.path.abspath(__file__))
with open(os.path.join(HERE, "fixtures", "ray_imu_bot.urdf"), encoding="utf-8") as f:
    BOT_URDF = f.read()


def line_of(urdf, text):
    """1-based number of the first line of `urdf` holding `text`."""
    return next(n for n, line in enumerate(urdf.splitlines(), start=1) if text in line)


@pytest.mark.parametrize("old, new, at, detail", [
    ("<radiation>ultrasound</radiation>", "<radiation>laser</radiation>", 'name="sonar_plugin"',
     "plugin 'sonar_plugin' (libgazebo_ros_range.so): <radiation>: expected ultrasound or infrared, got 'laser'"),
    ("<fov>0.2</fov>", "<fov>0.2</fov><fieldOfView>0.2</fieldOfView>", "<fieldOfView>",
     "plugin 'sonar_plugin' (libgazebo_ros_range.so): unknown parameter <fieldOfView>"),
    ("<bodyName>imu_link</bodyName>", "", 'name="imu_plugin"',
     "plugin 'imu_plugin' (libgazebo_ros_imu.so): <bodyName>: required parameter is missing"),
    ("<bodyName>imu_link</bodyName>", "<bodyName>imu</bodyName>", 'name="imu_plugin"',
     "plugin 'imu_plugin' (libgazebo_ros_imu.so): <bodyName>: robot 'ray_imu_bot' has no link 'imu'"),
    ("<min_angle>-0.1</min_angle><max_angle>0.1</max_angle></vertical>\n        </scan>\n        "
     "<range><min>0.05</min>", "<min_angle>0.1</min_angle><max_angle>-0.1</max_angle></vertical>\n        "
     "</scan>\n        <range><min>0.05</min>", "<max_angle>-0.1</max_angle></vertical>",
     "sensor 'block' (ray): <ray><scan><vertical><max_angle>: must be greater than <min_angle> (0.1), got -0.1"),
], ids=["unknown_radiation", "unknown_range_key", "imu_body_missing", "imu_body_unknown", "block_rows_reversed"])
def test_bad_gazebo_sensor(master, old, new, at, detail):
    assert BOT_URDF.count(old) == 1, f"expected '{old}' once in the fixture"
    urdf = BOT_URDF.replace(old, new)
    message = startup_error(master, urdf, world_file=FLAT_WORLD, max_sim_time_s=0.1)
    assert message == f"/robot_description:{line_of(urdf, at)}: {detail}"
