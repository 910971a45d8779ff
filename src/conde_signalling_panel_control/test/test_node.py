"""The signalling_panel_controller node against a real roscore on a free loopback port: the
service and the topic, latched pictures on both monitor topics, schedule mode on a simulated
clock published by the test, the menu on a real pseudo-terminal, and bad configuration.

Needs the built workspace: `source devel/setup.bash` (the node is started with rosrun)."""
import signal
import subprocess
import termios
from contextlib import closing

import numpy as np
import pytest

try:
    import rospy
    from conde_msgs.msg import PanelSignal
    from conde_msgs.srv import SetPanelSignal
    from rosgraph_msgs.msg import Clock
    from sensor_msgs.msg import Image
except ImportError as error:
    raise ImportError("%s: build the workspace and source devel/setup.bash first" % error) from None

from conde_signalling_panel_control.panel_images import draw_signal
from conde_testing.pseudo_terminal import Terminal
from conde_testing.ros_harness import LoggedProcess, Roscore, TopicLog, joined_as_node, wait_until

NODE = "/signalling_panel_controller"
MONITOR_TOPICS = ("/monitor1/image1", "/monitor2/image2")
SIGNAL_TOPIC = "/signalling_panel/signal"
TIMEOUT_S = 60.0  # generous: the machine may be busy
VALID_NAMES = "none, left, right, forward, stop, end_of_trial, parking"


@pytest.fixture(scope="module")
def master():
    """A roscore on a free port; this test process joins it as a ROS node (wall-clock time)."""
    with Roscore("conde_signalling_panel_control") as core, joined_as_node(core.uri, "signalling_panel_test"):
        yield core


def topic_log(topic, message_type):
    """Every message received on a topic, and waiting for one that matches."""
    return TopicLog(topic, message_type, describe=describe)


def describe(message):
    if isinstance(message, PanelSignal):
        return "signal %d at %.3f s" % (message.signal, message.header.stamp.to_sec())
    return "%dx%d %s at %.3f s" % (message.width, message.height, message.encoding, message.header.stamp.to_sec())


def pixels(image):
    assert image.encoding == "rgb8" and image.step == 3 * image.width
    return np.frombuffer(image.data, np.uint8).reshape(image.height, image.width, 3)


def start_node(master, tmp_path, params, stdin=subprocess.DEVNULL, stdout=None, sim_time=False,
               controlling_terminal=False):
    """The node under test, started with rosrun and private parameters `_name:=value`."""
    # Private parameters of an earlier case stay on the master: delete them.
    master.set_params({"/use_sim_time": True} if sim_time else {},
                      clear=[NODE] if sim_time else [NODE, "/use_sim_time"])
    command = ["rosrun", "conde_signalling_panel_control", "signalling_panel_controller"]
    command += ["_%s:=%s" % item for item in params.items()]
    if controlling_terminal:  # stdin's terminal becomes the controlling one: Ctrl-C sends SIGINT
        command = ["setsid", "-c"] + command
    return LoggedProcess(command, master.env, tmp_path, stdin=stdin, stdout=stdout)


def set_signal(name):
    rospy.wait_for_service(NODE + "/set_signal", timeout=TIMEOUT_S)
    return rospy.ServiceProxy(NODE + "/set_signal", SetPanelSignal)(name)


def test_service_sets_latched_pictures_and_ground_truth(master, tmp_path):
    # No ~mode: the default (menu) with stdin not a terminal falls back to service mode.
    node = start_node(master, tmp_path, {})
    try:
        response = set_signal("stop")
        assert response.success, response.message
        # Subscribing only now: latched topics still deliver the current picture.
        monitors = [topic_log(topic, Image) for topic in MONITOR_TOPICS]
        truth = topic_log(SIGNAL_TOPIC, PanelSignal)
        expected = draw_signal("stop")
        for monitor in monitors:
            image = monitor.wait_for(lambda m: m.width == 1022 and m.height == 757 and pixels(m)[385, 511, 0] == 255,
                                     "the stop picture")
            picture = pixels(image)
            assert image.encoding == "rgb8"
            assert tuple(picture[385, 511]) == (255, 0, 0)  # where the bars of the X cross
            assert np.count_nonzero(np.all(picture == (255, 0, 0), axis=2)) > 100000
            assert not picture[..., 1].any()  # nothing green
            assert np.array_equal(picture, expected)
        message = truth.wait_for(lambda m: m.signal == PanelSignal.STOP, "STOP")
        assert message.confidence == 1.0

        response = set_signal("stp")
        assert not response.success
        assert response.message == "unknown signal 'stp' (expected one of: %s)" % VALID_NAMES
        # A command on the topic switches too.
        command_pub = rospy.Publisher(NODE + "/signal_command", PanelSignal, queue_size=1, latch=True)
        command_pub.publish(PanelSignal(signal=PanelSignal.LEFT))
        truth.wait_for(lambda m: m.signal == PanelSignal.LEFT, "LEFT from the command topic")
        left = draw_signal("left")
        for monitor in monitors:
            monitor.wait_for(lambda m: np.array_equal(pixels(m), left), "the left picture")
        # The unknown name changed nothing in between: STOP, then LEFT.
        codes = [m.signal for m in truth.messages]
        assert codes == [PanelSignal.STOP, PanelSignal.LEFT], codes
        command_pub.unregister()
        for collector in monitors + [truth]:
            collector.close()
        assert "mode menu needs a terminal on stdin" in node.output()
    finally:
        node.stop()


def write_schedule(tmp_path, text):
    path = tmp_path / "schedule.yaml"
    path.write_text(text)
    return str(path)


class SimClock:
    """Publishes /clock from the test, after the node under test is connected."""

    def __init__(self):
        self._pub = rospy.Publisher("/clock", Clock, queue_size=100)

    def wait_for_subscriber(self):
        wait_until(lambda: self._pub.get_num_connections() >= 1, "the node to subscribe to /clock")

    def publish(self, *times_s):
        for t_s in times_s:
            self._pub.publish(Clock(clock=rospy.Time.from_sec(t_s)))

    def close(self):
        self._pub.unregister()


def stamp_s(message):
    return message.header.stamp.to_sec()


def test_schedule_switches_at_sim_times(master, tmp_path):
    path = write_schedule(tmp_path, """
steps:
  - {at_s: 0.0, signal: stop}
  - {at_s: 5.0, signal: forward}
  - {at_s: 20.0, signal: end_of_trial}
""")
    with (closing(SimClock()) as clock, topic_log(SIGNAL_TOPIC, PanelSignal) as truth,
          start_node(master, tmp_path, {"mode": "schedule", "schedule": path, "image_width_px": 320,
                                        "image_height_px": 240}, sim_time=True)):
        # No /clock yet: ROS time is 0, and the schedule's step at 0 s shows at once.
        assert stamp_s(truth.wait_for(lambda m: m.signal == PanelSignal.STOP, "STOP at t = 0")) == 0.0
        clock.wait_for_subscriber()
        clock.publish(1.0, 4.9, 4.999, 5.0)
        # Stamped with the ROS time of the switch: 5.0 exactly, not one of the earlier clocks.
        assert stamp_s(truth.wait_for(lambda m: m.signal == PanelSignal.FORWARD, "FORWARD")) == 5.0
        monitor = topic_log(MONITOR_TOPICS[1], Image)
        image = monitor.wait_for(lambda m: m.header.stamp.to_sec() == 5.0, "the forward picture")
        assert (image.width, image.height) == (320, 240)
        assert np.array_equal(pixels(image), draw_signal("forward", 320, 240))
        monitor.close()
        clock.publish(10.0, 19.99, 20.0)
        assert stamp_s(truth.wait_for(lambda m: m.signal == PanelSignal.END_OF_TRIAL, "END_OF_TRIAL")) == 20.0
        codes = [m.signal for m in truth.messages if m.signal != PanelSignal.NONE]
        assert codes == [PanelSignal.STOP, PanelSignal.FORWARD, PanelSignal.END_OF_TRIAL], codes
        # The service still works once the schedule is done.
        assert set_signal("parking").success
        truth.wait_for(lambda m: m.signal == PanelSignal.PARKING, "PARKING from the service")


def test_schedule_starting_on_the_first_clock(master, tmp_path):
    path = write_schedule(tmp_path, """
start_on: first_clock
steps:
  - {at_s: 0.0, signal: stop}
  - {at_s: 5.0, signal: right}
""")
    with (closing(SimClock()) as clock, topic_log(SIGNAL_TOPIC, PanelSignal) as truth,
          start_node(master, tmp_path, {"mode": "schedule", "schedule": path, "image_width_px": 64,
                                        "image_height_px": 48}, sim_time=True) as node):
        truth.wait_for(lambda m: m.signal == PanelSignal.NONE, "the initial NONE")
        clock.wait_for_subscriber()
        clock.publish(100.0)
        assert stamp_s(truth.wait_for(lambda m: m.signal == PanelSignal.STOP, "STOP")) == 100.0
        clock.publish(104.0, 104.99, 105.0)
        assert stamp_s(truth.wait_for(lambda m: m.signal == PanelSignal.RIGHT, "RIGHT")) == 105.0
        assert "schedule: 2 steps, t = 0 at ROS time 100.000 s (start_on: first_clock)" in node.output()


def run_to_exit(master, tmp_path, params):
    node = start_node(master, tmp_path, params)
    try:
        code = node.wait()
    finally:
        node.stop()
    return code, node.stderr()


def test_bad_schedule_file_exits_with_its_message(master, tmp_path):
    path = write_schedule(tmp_path, "steps:\n  - {at_s: 0.0, signal: stop}\n  - {at_s: 1.0, signal: left}\n"
                                    "  - {at_s: 2.0, signal: stp}\n")
    code, stderr = run_to_exit(master, tmp_path, {"mode": "schedule", "schedule": path})
    assert code != 0
    assert ("signalling_panel_controller: error: %s: steps[2]: unknown signal 'stp' (expected one of: %s)"
            % (path, VALID_NAMES)) in stderr.splitlines()


def test_bad_parameters_exit_with_their_message(master, tmp_path):
    cases = [
        ({"mode": "schedule"}, "parameter /signalling_panel_controller/schedule is required in schedule mode "
                               "(path of a schedule YAML file)"),
        ({"mode": "auto"}, "parameter /signalling_panel_controller/mode: unknown mode 'auto' "
                           "(expected one of: menu, schedule, service)"),
        ({"mode": "service", "image_width_px": 8}, "parameter /signalling_panel_controller/image_width_px: "
                                                   "expected an integer >= 16, got 8"),
        ({"mode": "service", "initial_signal": "go"}, "parameter /signalling_panel_controller/initial_signal: "
                                                      "unknown signal 'go' (expected one of: %s)" % VALID_NAMES),
    ]
    for params, message in cases:
        code, stderr = run_to_exit(master, tmp_path, params)
        assert code != 0, params
        assert "signalling_panel_controller: error: " + message in stderr.splitlines(), stderr


def test_menu_keys_on_a_terminal(master, tmp_path):
    with (Terminal() as terminal, topic_log(SIGNAL_TOPIC, PanelSignal) as truth,
          start_node(master, tmp_path, {"mode": "menu", "image_width_px": 64, "image_height_px": 48},
                     stdin=terminal.slave_fd, stdout=terminal.slave_fd) as node):
        # As in the original, the menu starts on stop.
        truth.wait_for(lambda m: m.signal == PanelSignal.STOP, "the initial STOP")
        wait_until(lambda: b"Choose the semaphore [Press <Esc> to exit]" in terminal.output, "the menu")
        wait_until(terminal.in_cbreak_mode, "the terminal in cbreak mode")
        for key, code in ((b"0", PanelSignal.LEFT), (b"1", PanelSignal.RIGHT), (b"2", PanelSignal.FORWARD),
                          (b"4", PanelSignal.PARKING), (b"5", PanelSignal.END_OF_TRIAL), (b"n", PanelSignal.NONE),
                          (b"3", PanelSignal.STOP)):
            count = len(truth.messages)
            terminal.type(key)
            truth.wait_for(lambda m, c=code: m.signal == c, "signal %d after key %r" % (code, key), since=count)
        # Any other key, an arrow key included, publishes the current picture again.
        for key in (b"x", b"\x1b[A"):
            count = len(truth.messages)
            terminal.type(key)
            wait_until(lambda n=count: len(truth.messages) > n, "a republish after key %r" % key)
            assert truth.messages[-1].signal == PanelSignal.STOP
        wait_until(lambda: b"Current signal: stop" in terminal.output.rsplit(b"Choose the semaphore", 1)[-1],
                   "the menu to show the current signal")
        assert node.process.poll() is None
        terminal.type(b"\x1b")
        assert node.wait() == 0
        assert termios.tcgetattr(terminal.slave_fd) == terminal.saved  # terminal restored


def test_menu_restores_the_terminal_on_ctrl_c(master, tmp_path):
    with (Terminal() as terminal, topic_log(SIGNAL_TOPIC, PanelSignal) as truth,
          start_node(master, tmp_path, {"mode": "menu", "image_width_px": 64, "image_height_px": 48},
                     stdin=terminal.slave_fd, stdout=terminal.slave_fd, controlling_terminal=True) as node):
        truth.wait_for(lambda m: m.signal == PanelSignal.STOP, "the initial STOP")
        wait_until(terminal.in_cbreak_mode, "the terminal in cbreak mode")
        terminal.type(b"\x03")  # Ctrl-C: the terminal sends SIGINT to the node
        node.wait()
        assert termios.tcgetattr(terminal.slave_fd) == terminal.saved


@pytest.mark.parametrize("mode", ["service", "schedule"])
def test_node_stops_on_sigterm(master, tmp_path, mode):
    """roslaunch stops nodes with SIGINT, then SIGTERM; rospy turns both into a shutdown request
    without an exception, so every wait of the node must check for shutdown (here a schedule
    step an hour ahead on the wall clock)."""
    path = write_schedule(tmp_path, "steps:\n  - {at_s: 0.0, signal: stop}\n  - {at_s: 3600.0, signal: left}\n")
    with (topic_log(SIGNAL_TOPIC, PanelSignal) as truth,
          start_node(master, tmp_path, {"mode": mode, "schedule": path, "initial_signal": "stop",
                                        "image_width_px": 64, "image_height_px": 48}) as node):
        truth.wait_for(lambda m: m.signal == PanelSignal.STOP, "STOP")
        rospy.wait_for_service(NODE + "/set_signal", timeout=TIMEOUT_S)
        node.process.send_signal(signal.SIGTERM)
        assert node.wait(timeout_s=30) == 0
