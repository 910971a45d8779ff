"""SDF worlds and mesh files at the node: bad ones stop conde_sim_node at start-up with the
file (and line) in the message and a non-zero exit; the fixture world runs. Fixtures are
conde_physics' (test/data/sdf)."""
import os

import rospkg

from test_bad_input import run_node, startup_error

SDF_DIR = os.path.join(rospkg.RosPack().get_path("conde_physics"), "test", "data", "sdf")

MESH_URDF = """<robot name="mesh_bot">
<link name="base"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
</inertial><collision><geometry><mesh filename="{mesh}"/></geometry></collision></link>
</robot>"""


def test_sdf_syntax_error_names_file_and_line(master):
    path = os.path.join(SDF_DIR, "bad_syntax.world")
    assert startup_error(master, world_file=path) == (
        f"{path}:7: XML error: Error=XML_ERROR_MISMATCHED_ELEMENT ErrorID=14 (0xe) "
        "Line number=7: XMLElement name=collision")


def test_sdf_missing_include(master):
    path = os.path.join(SDF_DIR, "missing_include.world")
    assert startup_error(master, world_file=path) == f"{path}:4: Unable to find uri[model://no_such_model]"


def test_sdf_mesh_that_does_not_load(master):
    path = os.path.join(SDF_DIR, "bad_mesh.world")
    mesh = os.path.join(SDF_DIR, "models", "mesh_block", "meshes", "broken.stl")
    assert startup_error(master, world_file=path).startswith(
        f"{path}: link 'broken::link' collision 'collision': mesh file '{mesh}': ")


def test_urdf_mesh_that_does_not_load(master):
    mesh = os.path.join(SDF_DIR, "models", "mesh_block", "meshes", "broken.stl")
    world = os.path.join(SDF_DIR, "shapes.world")
    assert f"mesh file '{mesh}': " in startup_error(master, urdf=MESH_URDF.format(mesh=mesh), world_file=world)


def test_sdf_world_and_collada_robot_run(master):
    mesh = os.path.join(SDF_DIR, "models", "mesh_block", "meshes", "tall_red.dae")
    world = os.path.join(SDF_DIR, "shapes.world")
    code, err = run_node(master, urdf=MESH_URDF.format(mesh=mesh), world_file=world, real_time_factor=0,
                         max_sim_time_s=0.2, spawn="0 -1.5 0")
    assert code == 0, err
