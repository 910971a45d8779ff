"""Gazebo's /gazebo/ services refuse bad requests with exact status messages, on both engines,
against the real node (named gazebo, no robot, as gazebo_ros/empty_world.launch starts it). The
requests go through one rospy client process per engine, which prints each answer as JSON."""
import json
import subprocess
import textwrap
import time

import pytest
import rosgraph

from test_bad_input import FLAT_WORLD, GOOD_URDF

CLIENT = textwrap.dedent("""
    import json, math, sys
    import rospy
    from gazebo_msgs.msg import LinkState, ModelState
    from gazebo_msgs.srv import (ApplyBodyWrench, DeleteModel, GetLinkState, GetModelProperties, GetModelState,
                                 GetWorldProperties, SetLinkState, SetModelState, SpawnModel)
    from geometry_msgs.msg import Pose, Wrench

    urdf = sys.stdin.read()
    rospy.init_node('gazebo_bad_input_client', anonymous=True)
    rospy.wait_for_service('/gazebo/delete_model', timeout=60)

    def srv(name, kind):
        return rospy.ServiceProxy('/gazebo/' + name, kind)

    def answer(response):
        return [bool(response.success), response.status_message]

    spawn = srv('spawn_urdf_model', SpawnModel)
    nan_pose = Pose()
    nan_pose.position.x = math.nan
    results = {
        'spawn': answer(spawn('box_bot', urdf, '', Pose(), '')),
        'spawn_again': answer(spawn('box_bot', urdf, '', Pose(), '')),
        'spawn_bad_urdf': answer(spawn('broken', '<robot name="broken"><link', '', Pose(), '')),
        'spawn_bad_frame': answer(spawn('other', urdf, '', Pose(), 'nowhere')),
        'spawn_sdf': answer(srv('spawn_sdf_model', SpawnModel)('s', '<model name="s"/>', '', Pose(), '')),
        'spawn_sdf_taken': answer(srv('spawn_sdf_model', SpawnModel)(
            'box_bot', '<sdf version="1.6"><model name="m"><static>true</static></model></sdf>', '', Pose(), '')),
        'get_unknown': answer(srv('get_model_state', GetModelState)('nope', '')),
        'get_bad_frame': answer(srv('get_model_state', GetModelState)('box_bot', 'nope::base')),
        'set_unknown': answer(srv('set_model_state', SetModelState)(ModelState(model_name='nope'))),
        'set_nan': answer(srv('set_model_state', SetModelState)(ModelState(model_name='box_bot', pose=nan_pose))),
        'get_link_unknown': answer(srv('get_link_state', GetLinkState)('box_bot::nolink', '')),
        'get_link_unscoped': answer(srv('get_link_state', GetLinkState)('base', '')),
        'set_link_unknown': answer(srv('set_link_state', SetLinkState)(LinkState(link_name='nope::base'))),
        'wrench_unknown': answer(srv('apply_body_wrench', ApplyBodyWrench)(
            'box_bot::nolink', '', None, Wrench(), rospy.Time(), rospy.Duration(-1))),
        'properties_unknown': answer(srv('get_model_properties', GetModelProperties)('nope')),
        'get_link': answer(srv('get_link_state', GetLinkState)('box_bot::base', 'world')),
        'models_before_delete': srv('get_world_properties', GetWorldProperties)().model_names,
        'delete': answer(srv('delete_model', DeleteModel)('box_bot')),
        'delete_again': answer(srv('delete_model', DeleteModel)('box_bot')),
        'models_after_delete': srv('get_world_properties', GetWorldProperties)().model_names,
    }
    print(json.dumps(results))
""")


@pytest.fixture(scope="module", params=["ode", "bullet"])
def answers(master, request):
    # An empty list cannot be given on the command line (roscpp would read the string "[]").
    rosgraph.Master("/gazebo_bad_input_test", master_uri=master["ROS_MASTER_URI"]).setParam("/gazebo/robots", [])
    node = subprocess.Popen(["rosrun", "conde_sim", "conde_sim_node", "__name:=gazebo", f"_world_file:={FLAT_WORLD}",
                             "_paused:=true", f"_physics_engine:={request.param}"], env=master,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        client = subprocess.run(["/usr/bin/python3", "-c", CLIENT], input=GOOD_URDF, env=master, capture_output=True,
                                text=True, timeout=120)
        assert client.returncode == 0, client.stderr
        yield json.loads(client.stdout.strip().splitlines()[-1])
    finally:
        node.terminate()
        output = node.communicate(timeout=60)[0]  # a process on a slow, busy machine
        time.sleep(0.1)
        assert "Segmentation" not in output, output


def test_spawn_and_delete(answers):
    assert answers["spawn"] == [True, "SpawnModel: Successfully spawned entity"]
    assert answers["models_before_delete"] == ["box_bot"]
    assert answers["delete"] == [True, "DeleteModel: successfully deleted model"]
    assert answers["models_after_delete"] == []
    assert answers["get_link"][0], answers["get_link"]


def test_spawn_refuses_an_existing_name_bad_urdf_and_sdf(answers):
    assert answers["spawn_again"] == [False, "SpawnModel: Failure - entity already exists."]
    assert answers["spawn_sdf_taken"] == [False, "SpawnModel: Failure - entity already exists."]
    ok, message = answers["spawn_bad_urdf"]
    assert not ok and message.startswith("SpawnModel: Failure - spawn_urdf_model 'broken'"), message
    assert answers["spawn_bad_frame"] == [False, "SpawnModel: Failure - reference_frame [nowhere] does not exist"]
    assert answers["spawn_sdf"] == [
        False, "SpawnModel: Failure - spawn_sdf_model 's': the XML's root element is <model>, not <sdf>"]


def test_delete_of_an_unknown_model(answers):
    assert answers["delete_again"] == [False, "DeleteModel: model [box_bot] does not exist"]


def test_unknown_models_links_and_frames(answers):
    assert answers["get_unknown"] == [False, "GetModelState: model [nope] does not exist"]
    assert answers["get_bad_frame"] == [
        False, "GetModelState: reference relative_entity_name [nope::base] not found, did you forget to scope the "
        "link by model name?"]
    assert answers["set_unknown"] == [False, "SetModelState: model [nope] does not exist"]
    assert answers["set_nan"] == [False, "SetModelState: pose and twist must be finite"]
    assert answers["get_link_unknown"] == [
        False, "GetLinkState: link [box_bot::nolink] does not exist (name it model::link)"]
    assert answers["get_link_unscoped"] == [False, "GetLinkState: link [base] does not exist (name it model::link)"]
    assert answers["set_link_unknown"] == [
        False, "SetLinkState: link [nope::base] does not exist (name it model::link)"]
    assert answers["wrench_unknown"] == [
        False, "ApplyBodyWrench: body [box_bot::nolink] does not exist (name it model::link)"]
    assert answers["properties_unknown"] == [False, "GetModelProperties: model [nope] does not exist"]


def spawn_model(env, *args):
    out = subprocess.run(["rosrun", "gazebo_ros", "spawn_model", *args], env=env, capture_output=True, text=True,
                         timeout=60)
    return out.returncode, out.stdout + out.stderr


def test_spawn_model_script_names_what_is_wrong(master):
    code, output = spawn_model(master, "-urdf", "-param", "no_such_param", "-model", "x")
    assert code == 1 and "spawn_model: parameter /no_such_param is not set" in output, output
    code, output = spawn_model(master, "-urdf", "-file", "/no/such.urdf", "-model", "x")
    assert code == 1 and "spawn_model: cannot read /no/such.urdf: No such file or directory" in output, output
    code, output = spawn_model(master, "-urdf", "-database", "table", "-model", "x")
    assert code == 2 and "-database: the model path holds SDF models" in output, output
    code, output = spawn_model(master, "-urdf", "-model", "x")
    assert code == 2 and "one of -param, -file or -database is required" in output, output
    rosgraph.Master("/gazebo_bad_input_test", master_uri=master["ROS_MASTER_URI"]).setParam("/some_urdf", GOOD_URDF)
    code, output = spawn_model(master, "-urdf", "-param", "some_urdf", "-model", "x", "-gazebo_namespace", "/nowhere",
                               "-timeout", "0.5")
    assert code == 1 and "spawn_model: /nowhere/spawn_urdf_model did not appear within 0.5 s" in output, output
