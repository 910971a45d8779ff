"""The generated gazebo_msgs types are ROS 1's: a message's MD5 sum is computed from its field
types, names and constants, so equal sums mean a node built against ROS 1's gazebo_msgs talks to
ours. The expected sums are those of ROS 1's gazebo_msgs 2.9 (Noetic)."""
import os

import pytest

import gazebo_msgs.msg as msg  # generated: build the workspace and source devel/setup.bash
import gazebo_msgs.srv as srv

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

ROS1_MD5 = {
    "ModelStates": "48c080191eb15c41858319b4d8a609c2",
    "LinkStates": "48c080191eb15c41858319b4d8a609c2",
    "ModelState": "9330fd35f2fcd82d457e54bd54e10593",
    "ContactsState": "acbcb1601a8e525bf72509f18e6f668d",
}


@pytest.mark.parametrize("name", sorted(ROS1_MD5))
def test_md5_sum_is_ros1s(name):
    assert getattr(msg, name)._md5sum == ROS1_MD5[name]


@pytest.mark.parametrize("kind", ["msg", "srv"])
def test_every_definition_is_generated(kind):
    module = msg if kind == "msg" else srv
    names = sorted(f[:-4] for f in os.listdir(os.path.join(PACKAGE_DIR, kind)) if f.endswith("." + kind))
    assert len(names) == {"msg": 11, "srv": 23}[kind]
    for name in names:
        generated = getattr(module, name)
        assert generated._type == "gazebo_msgs/" + name


def test_spawn_model_fields():
    request = srv.SpawnModelRequest()
    assert request.__slots__ == ["model_name", "model_xml", "robot_namespace", "initial_pose", "reference_frame"]
    assert srv.SpawnModelResponse().__slots__ == ["success", "status_message"]
