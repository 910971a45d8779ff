"""The pure part of start_when_ready: roslaunch process names and the master's system state."""
import pytest
from conde_eval import startup


def test_process_names_map_to_node_names():
    assert startup.node_name_of_process("conde_tracking-12") == "/conde_tracking"
    assert startup.node_name_of_process("robot1/conde_tracking-3") == "/robot1/conde_tracking"
    assert startup.node_name_of_process("signalling-panel-controller-7") == "/signalling-panel-controller"


@pytest.mark.parametrize("bad", ["conde_tracking", "conde_tracking-", "-4", "conde_tracking-x1"])
def test_a_name_roslaunch_does_not_make_is_refused_by_name(bad):
    with pytest.raises(ValueError, match=f"'{bad}' is not a roslaunch process name"):
        startup.node_name_of_process(bad)


# getSystemState(): [publishers, subscribers, services], each [[topic, [nodes]], ...]
JUST_INITIALISED = [[["/rosout", ["/tracking", "/decision"]]], [["/clock", ["/tracking", "/decision"]]], []]


def test_a_node_with_only_rosout_and_clock_is_not_up():
    assert startup.nodes_not_up({"/tracking", "/decision"}, JUST_INITIALISED) == ["/decision", "/tracking"]


def test_a_node_is_up_with_one_topic_of_its_own_published_or_subscribed():
    state = [[["/rosout", ["/tracking", "/decision", "/recorder"]], ["/conde_lane", ["/tracking"]]],
             [["/clock", ["/tracking"]], ["/conde_lane", ["/decision"]]], []]
    assert startup.nodes_not_up({"/tracking", "/decision", "/recorder", "/absent"}, state) == ["/absent", "/recorder"]


def test_the_graph_changes_when_a_node_adds_a_topic():
    before = [[["/conde_lane", ["/tracking"]]], [], []]
    after = [[["/conde_lane", ["/tracking"]]], [["/image", ["/tracking"]]], []]
    expected = {"/tracking"}
    assert startup.graph_of(expected, before) == startup.graph_of(expected, [[["/conde_lane", ["/tracking"]]], [], []])
    assert startup.graph_of(expected, before) != startup.graph_of(expected, after)
    assert startup.graph_of(expected, after) == {"/tracking": frozenset({"/conde_lane", "/image"})}


LOCKSTEP_CONFIG = {"rules": [{"answer": "conde_lane", "inputs": ["camera/image_raw"]},
                             {"answer": "cmd_vel", "inputs": ["conde_lane", "/clock"]}]}
SIM = "/conde_sim"


def graph(image_subscribers=("/tracking",)):
    publishers = [["/camera/image_raw", [SIM]], ["/conde_lane", ["/tracking"]], ["/cmd_vel", ["/control"]],
                  ["/clock", [SIM]]]
    subscribers = [["/camera/image_raw", list(image_subscribers)], ["/conde_lane", [SIM, "/control"]],
                   ["/cmd_vel", [SIM]]]
    return publishers, subscribers, []


def links(*rows):
    return [[i, "peer", direction, "TCPROS", topic, True] for i, (direction, topic) in enumerate(rows)]


def test_lockstep_links_complete_when_every_answer_and_input_is_connected():
    bus = links(("o", "/camera/image_raw"), ("i", "/conde_lane"), ("i", "/cmd_vel"))
    assert startup.lockstep_links_missing(LOCKSTEP_CONFIG, SIM, graph(), bus) == []


def test_lockstep_links_name_a_camera_nobody_subscribes_to_yet_and_an_answer_not_connected():
    bus = links(("i", "/conde_lane"))
    assert startup.lockstep_links_missing(LOCKSTEP_CONFIG, SIM, graph(image_subscribers=()), bus) == [
        "/camera/image_raw: no subscriber yet", "/cmd_vel: not connected to its publisher yet"]


def test_lockstep_links_wait_for_the_connection_to_a_registered_subscriber():
    bus = links(("i", "/conde_lane"), ("i", "/cmd_vel"))
    assert startup.lockstep_links_missing(LOCKSTEP_CONFIG, SIM, graph(), bus) == [
        "/camera/image_raw: not connected to its subscribers yet"]


def test_a_rule_owing_nothing_before_its_first_answer_holds_no_start_without_its_node():
    # V1's sign node: its rule is in the stack's config, but only V1 starts the node
    signs = {"answer": "signs/detections", "inputs": ["camera/image_raw"], "wait_for_first_answer": False}
    config = {"rules": LOCKSTEP_CONFIG["rules"] + [signs]}
    bus = links(("o", "/camera/image_raw"), ("i", "/conde_lane"), ("i", "/cmd_vel"))
    assert startup.lockstep_links_missing(config, SIM, graph(), bus) == []
    publishers, subscribers, services = graph()
    with_node = (publishers + [["/signs/detections", ["/signs"]]], subscribers, services)
    assert startup.lockstep_links_missing(config, SIM, with_node, bus) == [
        "/signs/detections: not connected to its publisher yet"]
    owed = dict(signs, wait_for_first_answer=True)
    assert startup.lockstep_links_missing({"rules": [owed]}, SIM, graph(), bus) == [
        "/signs/detections: no publisher yet"]


def test_an_input_nobody_publishes_or_listens_to_holds_no_start():
    # V1's detections rule lists the sign camera too; a robot built without it has no such topic
    signs = {"answer": "signs/detections", "inputs": ["camera/image_raw", "rear_camera/image_raw"]}
    config = {"rules": LOCKSTEP_CONFIG["rules"] + [signs]}
    publishers, subscribers, services = graph()
    with_node = (publishers + [["/signs/detections", ["/signs"]]], subscribers, services)
    bus = links(("o", "/camera/image_raw"), ("i", "/conde_lane"), ("i", "/cmd_vel"), ("i", "/signs/detections"))
    assert startup.lockstep_links_missing(config, SIM, with_node, bus) == []
    # a node that subscribes to it while nobody publishes it yet still holds the start
    listened = (with_node[0], subscribers + [["/rear_camera/image_raw", ["/signs"]]], services)
    assert startup.lockstep_links_missing(config, SIM, listened, bus) == ["/rear_camera/image_raw: no publisher yet"]


def test_static_transforms_are_out_once_every_tf_static_publisher_has_sent():
    state = ([["/tf_static", ["/robot_state_publisher", "/map_static", "/conde_sim"]], ["/clock", ["/conde_sim"]]],
             [], [])
    assert not startup.static_transforms_out(state, set(), "/conde_sim")
    assert not startup.static_transforms_out(state, {"/map_static"}, "/conde_sim")  # the robot's not yet
    # the simulator advertises /tf_static even when it has no optical frame to send: not waited for
    assert startup.static_transforms_out(state, {"/map_static", "/robot_state_publisher"}, "/conde_sim")


def test_static_transforms_are_not_out_without_a_publisher():
    # nobody publishes /tf_static (yet): the pre-roll goes on to its ~preroll_s
    assert not startup.static_transforms_out(([["/clock", ["/conde_sim"]]], [], []), {"/someone"}, "/conde_sim")
    assert not startup.static_transforms_out(([["/tf_static", ["/conde_sim"]]], [], []), set(), "/conde_sim")
