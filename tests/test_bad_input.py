"""Bad input stops conde_sim_node at start-up with a message naming the file and the field, and
a non-zero exit. Each case runs the real node against a real roscore on a free loopback port."""
import os
import subprocess

import pytest
import rosgraph
from conde_testing.ros_harness import fatal_error


HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURES = os.path.join(HERE, "fixtures")
FLAT_WORLD = os.path.join(FIXTURES, "flat.world.yaml")

GOOD_URDF = """<robot name="box_bot">
<link name="base"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
</inertial><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link>
</robot>"""


def run_node(env, urdf=GOOD_URDF, **params):
    """Starts conde_sim_node with the given private parameters; returns (exit code, stderr)."""
    master_api = rosgraph.Master("/bad_input_test", master_uri=env["ROS_MASTER_URI"])
    # Private parameters from an earlier case stay on the master: start from none.
    if master_api.hasParam("/conde_sim"):
        master_api.deleteParam("/conde_sim")
    master_api.setParam("/robot_description", urdf)  # (rosparam set would fold the newlines)
    args = ["rosrun", "conde_sim", "conde_sim_node"] + [f"_{k}:={v}" for k, v in params.items()]
    proc = subprocess.run(args, env=env, capture_output=True, text=True, timeout=60)
    return proc.returncode, proc.stderr


def startup_error(env, urdf=GOOD_URDF, **params):
    """The message of a start of conde_sim_node that must fail."""
    return fatal_error(*run_node(env, urdf, **params), "conde_sim")


def test_unknown_engine(master):
    assert startup_error(master, world_file=FLAT_WORLD, physics_engine="havok", max_sim_time_s=0.1) == (
        "parameter /conde_sim/physics_engine: unknown physics engine 'havok' "
        "(expected one of: ode, bullet)")


def test_model_poses_rate_must_be_positive(master):
    assert startup_error(master, world_file=FLAT_WORLD, model_poses_rate_hz=0) == (
        "parameter /conde_sim/model_poses_rate_hz must be > 0 (got 0)")


def test_missing_world_file_parameter(master):
    assert startup_error(master) == "parameter /conde_sim/world_file is required (path of a *.world.yaml)"


def test_unknown_world_key(master):
    path = os.path.join(FIXTURES, "unknown_key.world.yaml")
    assert startup_error(master, world_file=path) == (
        f"{path}:5: ground: unknown key 'gravity' "
        "(expected one of: texture, x_range_m, y_range_m, color_rgb, friction)")


def test_missing_texture(master):
    path = os.path.join(FIXTURES, "missing_texture.world.yaml")
    assert startup_error(master, world_file=path) == (
        f"{path}:4: ground.texture: cannot load image "
        f"'{os.path.join(FIXTURES, 'no_such_track.png')}': No such file or directory")


def test_malformed_urdf(master):
    assert startup_error(master, urdf="<robot name='r'>\n<link name='a'>\n</robot>", world_file=FLAT_WORLD) == (
        "/robot_description: malformed URDF: XML error at line 2: XML_ERROR_MISMATCHED_ELEMENT")


def test_unknown_plugin(master):
    urdf = GOOD_URDF.replace("</robot>",
                             '<gazebo>\n<plugin name="p" filename="libgazebo_ros_teleport.so"/>\n</gazebo>\n</robot>')
    assert startup_error(master, urdf=urdf, world_file=FLAT_WORLD).startswith(
        "/robot_description:5: plugin 'p' (libgazebo_ros_teleport.so): "
        "unknown plugin 'libgazebo_ros_teleport.so' (known: ")


def test_unknown_plugin_parameter(master):
    urdf = GOOD_URDF.replace("</robot>", '<gazebo>\n<plugin name="gt" filename="libgazebo_ros_p3d.so">'
                             "<bodyName>base</bodyName><topicName>gt</topicName>\n<bodyname>base</bodyname>"
                             "</plugin>\n</gazebo>\n</robot>")
    assert startup_error(master, urdf=urdf, world_file=FLAT_WORLD) == (
        "/robot_description:6: plugin 'gt' (libgazebo_ros_p3d.so): unknown parameter <bodyname>")


def test_good_input_runs_to_max_sim_time(master):
    code, err = run_node(master, world_file=FLAT_WORLD, real_time_factor=0, max_sim_time_s=0.5)
    assert code == 0, err


def camera_urdf(camera_xml, plugin_xml="", sensor_type="camera"):
    """GOOD_URDF with a camera on its link: <sensor> on line 5, the camera on 6, <plugin> on 7."""
    return GOOD_URDF.replace("</robot>", f'<gazebo reference="base">\n<sensor type="{sensor_type}" name="cam">\n'
                             f"{camera_xml}\n"
                             f'<plugin name="cam_controller" filename="libgazebo_ros_camera.so">{plugin_xml}</plugin>\n'
                             "</sensor>\n</gazebo>\n</robot>")


@pytest.mark.parametrize("camera_xml, message", [
    ("<camera><image><width>0</width><height>120</height></image></camera>",
     "<camera><image>: image size must be a positive whole number of pixels (got 0x120)"),
    ("<camera><image><width>160</width><height>-4</height></image></camera>",
     "<camera><image>: image size must be a positive whole number of pixels (got 160x-4)"),
    ("<camera><horizontal_fov>3.1416</horizontal_fov></camera>",
     "<camera><horizontal_fov>: must be in (0, pi) rad (got 3.1416)"),
    ("<camera><image><format>R16G16B16</format></image></camera>",
     "<camera><image><format>: unknown image format 'R16G16B16' (expected R8G8B8, B8G8R8 or L8)"),
    ("<camera><clip><near>0.5</near><far>0.1</far></clip></camera>",
     "<camera><clip>: needs 0 < near < far (got near 0.5, far 0.1)"),
])
def test_bad_camera(master, camera_xml, message):
    assert startup_error(master, urdf=camera_urdf(camera_xml), world_file=FLAT_WORLD) == (
        f"/robot_description:6: sensor 'cam' (camera): {message}")


def test_unknown_camera_element(master):
    urdf = camera_urdf("<camera><lense>fisheye</lense></camera>")
    assert startup_error(master, urdf=urdf, world_file=FLAT_WORLD) == (
        "/robot_description:6: sensor 'cam' (camera): unknown element <camera><lense>")


@pytest.mark.parametrize("sensor_type, camera_xml, message", [
    ("wideanglecamera", "<camera><lens><type>fisheye</type></lens></camera>",
     "<camera><lens>: unknown lens type 'fisheye' (expected gnomonical, stereographic, equidistant, "
     "equisolid_angle, orthographic or custom)"),
    ("wideanglecamera", "<camera><lens><type>custom</type></lens></camera>",
     "<camera><lens><type>: lens type 'custom' needs a <custom_function>"),
    ("wideanglecamera", "<camera><lens><type>custom</type><custom_function><fun>cos</fun></custom_function></lens>"
     "</camera>",
     "<camera><lens>: unknown lens function 'cos' (expected tan, sin or id)"),
    ("wideanglecamera", "<camera><horizontal_fov>7</horizontal_fov></camera>",
     "<camera><horizontal_fov>: must be in (0, 2 pi] rad (got 7)"),
    ("wideanglecamera", "<camera><horizontal_fov>3.2</horizontal_fov><lens><type>gnomonical</type></lens></camera>",
     "<camera><lens>: lens cannot show half the horizontal_fov (1.6 rad) at the image edge: its radius there is 0"),
    ("camera", "<camera><lens><type>stereographic</type></lens></camera>",
     "<camera><lens><type>: lens 'stereographic' needs <sensor type=\"wideanglecamera\"> (a \"camera\" sensor "
     "is a pinhole, i.e. gnomonical)"),
    ("camera", "<camera><distortion><k1>-0.1</k1><center>0.5</center></distortion></camera>",
     "<camera><distortion><center>: expected two fractions of the image size in (0, 1), e.g. '0.5 0.5' "
     "(got '0.5')"),
])
def test_bad_wide_angle_camera(master, sensor_type, camera_xml, message):
    assert startup_error(master, urdf=camera_urdf(camera_xml, sensor_type=sensor_type), world_file=FLAT_WORLD) == (
        f"/robot_description:6: sensor 'cam' ({sensor_type}): {message}")


def test_wide_angle_camera_runs_with_good_parameters(master):
    urdf = camera_urdf("<update_rate>30</update_rate><camera><horizontal_fov>2.6</horizontal_fov>"
                       "<image><width>64</width><height>48</height></image>"
                       "<distortion><k1>-0.2673</k1><k2>0.0629</k2><center>0.502 0.4586</center></distortion>"
                       "<lens><type>stereographic</type><scale_to_hfov>true</scale_to_hfov>"
                       "<cutoff_angle>1.5707</cutoff_angle><env_texture_size>256</env_texture_size></lens></camera>",
                       "<cameraName>cam</cameraName>", sensor_type="wideanglecamera")
    code, err = run_node(master, urdf=urdf, world_file=FLAT_WORLD, real_time_factor=0, max_sim_time_s=0.2)
    assert code == 0, err


def test_camera_runs_with_good_parameters(master):
    urdf = camera_urdf("<update_rate>30</update_rate><camera><horizontal_fov>1.0</horizontal_fov>"
                       "<image><width>64</width><height>48</height></image></camera>",
                       "<cameraName>cam</cameraName><frameName>base_optical</frameName>")
    code, err = run_node(master, urdf=urdf, world_file=FLAT_WORLD, real_time_factor=0, max_sim_time_s=0.2)
    assert code == 0, err


def optical_link_urdf(rpy):
    """GOOD_URDF with a camera whose frameName is a URDF link `base_optical` at `rpy` from the
    camera link (line 5: the optical joint, line 9: the camera plugin)."""
    return GOOD_URDF.replace("</robot>", f'<link name="base_optical"/>\n'
                             f'<joint name="optical" type="fixed"><parent link="base"/><child link="base_optical"/>'
                             f'<origin xyz="0 0 0" rpy="{rpy}"/></joint>\n'
                             '<gazebo reference="base">\n<sensor type="camera" name="cam">\n'
                             "<camera><image><width>64</width><height>48</height></image></camera>\n"
                             '<plugin name="cam_controller" filename="libgazebo_ros_camera.so">'
                             "<frameName>base_optical</frameName></plugin>\n"
                             "</sensor>\n</gazebo>\n</robot>")


@pytest.mark.parametrize("rpy", ["-1.5707963 0 -1.5707963", "-1.57 0 -1.57", "-1.571 0 -1.5708"])
def test_optical_link_written_with_rounded_pi_over_2_is_accepted(master, rpy):
    """Almost every public URDF writes the optical frame as rpy="-1.57 0 -1.57" (0.05 degrees
    from the exact rotation): that is the optical frame."""
    code, err = run_node(master, urdf=optical_link_urdf(rpy), world_file=FLAT_WORLD, real_time_factor=0,
                         max_sim_time_s=0.1)
    assert code == 0, err


def test_a_link_that_is_not_the_optical_frame_is_refused(master):
    assert startup_error(master, urdf=optical_link_urdf("0 0 -1.5707963"), world_file=FLAT_WORLD) == (
        "/robot_description:9: plugin 'cam_controller' (libgazebo_ros_camera.so): "
        "<frameName>: link 'base_optical' is not the optical frame of the camera on link 'base' "
        "(REP 103: z forward, x right, y down; expected rpy -pi/2 0 -pi/2 from the camera link, "
        "within 0.5 degrees)")
