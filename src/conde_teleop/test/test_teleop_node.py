"""The conde_teleop node against a real roscore on a free loopback port, on a real
pseudo-terminal: keys typed into the terminal, geometry_msgs/Twist received on cmd_vel; the
current command republished; a zero Twist and the terminal restored on every way out (q, Ctrl-C,
SIGTERM, roslaunch stopping); the namespace and the launch file; bad parameters and a stdin that
is not a terminal, with the exact message and exit status 1.

The nodes are started with rosrun/roslaunch: the workspace must be built (scripts/build.sh); its
devel/setup.bash is sourced for them if the current environment does not find conde_teleop."""

import signal

import pytest

try:
    from geometry_msgs.msg import Twist
except ImportError as error:
    raise ImportError("%s: run the tests with /usr/bin/python3 (the Python that has rospy)" % error) from None

from conde_testing.pseudo_terminal import Terminal
from conde_testing.ros_harness import LoggedProcess, Roscore, TopicLog, joined_as_node, wait_until

TIMEOUT_S = 60.0  # generous: the machine may be busy
HELP_FIRST_LINE = b"Conde keyboard teleop: one key at a time, no Enter."
UP, DOWN, RIGHT, LEFT = b"\x1b[A", b"\x1b[B", b"\x1b[C", b"\x1b[D"


@pytest.fixture(scope="module")
def master():
    """A roscore on a free port (ours: not another test run's); this test process joins it as a
    ROS node.  Yields the Roscore; its `env` is the environment the nodes under test run in."""
    with Roscore("conde_teleop") as core, joined_as_node(core.uri, "teleop_test"):
        yield core


def command_of(message):
    return (message.linear.x, message.angular.z)


class Commands(TopicLog):
    """Every Twist received on a topic, and waiting for one that matches."""

    def __init__(self, topic):
        super().__init__(topic, Twist, queue_size=1000)

    def wait_for_command(self, command, since=0, count=1, timeout_s=TIMEOUT_S):
        """Waits until `count` messages with `command` (linear [m/s], angular [rad/s]) have
        arrived from the since-th message on."""
        self.wait_for(lambda m: command_of(m) == pytest.approx(command), "%d x %s" % (count, command), since=since,
                      count=count, timeout_s=timeout_s)

    def distinct(self):
        """The commands received, consecutive repeats dropped."""
        commands = [command_of(m) for m in self.snapshot()]
        return [c for i, c in enumerate(commands) if i == 0 or c != commands[i - 1]]

    def received(self):  # what a time-out shows
        return self.distinct()


def start_teleop(master, tmp_path, terminal, args=(), controlling_terminal=False, namespace=None):
    # Private parameters of an earlier case stay on the master: delete them.
    master.set_params({}, clear=["/%s/conde_teleop" % namespace if namespace else "/conde_teleop"])
    command = ["rosrun", "conde_teleop", "conde_teleop"] + list(args)
    if controlling_terminal:  # the terminal on stdin becomes the node's: Ctrl-C there sends SIGINT
        command = ["setsid", "-w", "-c"] + command
    env = dict(master.env, ROS_NAMESPACE=namespace) if namespace else master.env
    return LoggedProcess(command, env, tmp_path, stdin=terminal.slave_fd, stdout=terminal.slave_fd)


def wait_until_ready(commands, terminal):
    """The node publishes (the initial zero reached this subscriber) and reads keys."""
    commands.wait_for_command((0.0, 0.0))
    wait_until(terminal.in_cbreak_mode, "the terminal in cbreak mode")
    wait_until(lambda: HELP_FIRST_LINE in terminal.output, "the help text")


def test_every_key_on_the_terminal_within_the_limits(master, tmp_path):
    """Non-default steps and limits, so that the parameters are seen to be read; the limits are
    not whole numbers of steps."""
    with (Terminal() as terminal, Commands("/cmd_vel") as commands,
          start_teleop(master, tmp_path, terminal, ["_linear_step_mps:=0.2", "_max_linear_mps:=0.3",
                                                    "_angular_step_radps:=0.5", "_max_angular_radps:=0.75"]) as node):
        wait_until_ready(commands, terminal)
        steps = [  # (keys typed at once, the command after them [m/s, rad/s])
            (b"i", (0.2, 0.0)),
            (UP, (0.3, 0.0)),  # the limit
            (b"ix,", (0.2, 0.0)),  # i: already at the limit; x ignored; one step back
            (DOWN, (0.0, 0.0)),
            (b",", (-0.2, 0.0)),
            (b"j", (-0.2, 0.5)),
            (LEFT, (-0.2, 0.75)),
            (RIGHT, (-0.2, 0.5)),
            (b"l", (-0.2, 0.0)),
            (b"l", (-0.2, -0.5)),
            (b"l", (-0.2, -0.75)),
            (b"k", (0.0, 0.0)),
            (b"ij", (0.2, 0.5)),  # two keys in one read
            (b" ", (0.0, 0.0)),
            (b"\x1bOA", (0.2, 0.0)),  # Up in application cursor mode
        ]
        for keys, command in steps:
            count = len(commands.messages)
            terminal.type(keys)
            commands.wait_for_command(command, since=count)
        # Republished without keys, so the diff drive's command timeout does not brake.
        count = len(commands.messages)
        commands.wait_for_command((0.2, 0.0), since=count, count=5)
        assert node.process.poll() is None

        count = len(commands.messages)
        terminal.type(b"q")
        assert node.wait() == 0, node.stderr()
        commands.wait_for_command((0.0, 0.0), since=count)
        assert terminal.restored()
        expected = [(0.0, 0.0), (0.2, 0.0), (0.3, 0.0), (0.2, 0.0), (0.0, 0.0), (-0.2, 0.0), (-0.2, 0.5),
                    (-0.2, 0.75), (-0.2, 0.5), (-0.2, 0.0), (-0.2, -0.5), (-0.2, -0.75), (0.0, 0.0), (0.2, 0.0),
                    (0.2, 0.5), (0.0, 0.0), (0.2, 0.0), (0.0, 0.0)]
        assert commands.distinct() == pytest.approx(expected)
        for message in commands.messages:  # a planar robot: only linear.x and angular.z are used
            assert (message.linear.y, message.linear.z, message.angular.x, message.angular.y) == (0, 0, 0, 0)
        text = terminal.output.decode()
        assert "  i or Up      faster forward    linear  +0.2 m/s (up to 0.3 m/s)" in text
        assert "linear -0.20 m/s, angular +0.75 rad/s" in text
        assert "conde_teleop: quit key 'q': stopping the robot and quitting" in text


def test_ctrl_c_stops_the_robot_and_restores_the_terminal(master, tmp_path):
    with (Terminal() as terminal, Commands("/cmd_vel") as commands,
          start_teleop(master, tmp_path, terminal, controlling_terminal=True) as node):
        wait_until_ready(commands, terminal)
        assert "  j or Left    turn left         angular +0.25 rad/s (up to 1.5 rad/s)" in terminal.output.decode()
        count = len(commands.messages)
        terminal.type(b"i" + LEFT)  # the defaults: 0.1 m/s and 0.25 rad/s per key
        commands.wait_for_command((0.1, 0.25), since=count)
        count = len(commands.messages)
        terminal.type(b"\x03")  # Ctrl-C: the terminal sends SIGINT to the node
        assert node.wait() == 0, node.stderr()
        commands.wait_for_command((0.0, 0.0), since=count)
        assert command_of(commands.messages[-1]) == (0.0, 0.0)
        assert terminal.restored()
        assert "conde_teleop: signal SIGINT: stopping the robot and quitting" in terminal.output.decode()


def test_sigterm_in_a_namespace(master, tmp_path):
    """cmd_vel is a relative name: in namespace robot1 the node publishes /robot1/cmd_vel and
    reads its parameters from /robot1/conde_teleop."""
    with (Terminal() as terminal, Commands("/robot1/cmd_vel") as commands,
          start_teleop(master, tmp_path, terminal, ["_max_angular_radps:=0.25"], namespace="robot1") as node):
        wait_until_ready(commands, terminal)
        count = len(commands.messages)
        terminal.type(b"lll")
        commands.wait_for_command((0.0, -0.25), since=count)
        count = len(commands.messages)
        node.process.send_signal(signal.SIGTERM)
        assert node.wait() == 0, node.stderr()
        commands.wait_for_command((0.0, 0.0), since=count)
        assert command_of(commands.messages[-1]) == (0.0, 0.0)
        assert commands.distinct() == [(0.0, 0.0), (0.0, -0.25), (0.0, 0.0)]
        assert terminal.restored()
        assert "publishing on /robot1/cmd_vel at 10 Hz" in terminal.output.decode()


def test_launch_file(master, tmp_path):
    """roslaunch with a limit and a remapped topic; stopping roslaunch stops the robot."""
    master.set_params({}, clear=["/conde_teleop"])
    with (Terminal() as terminal, Commands("/teleop/cmd_vel") as commands,
          LoggedProcess(["roslaunch", "conde_teleop", "conde_teleop.launch", "max_linear_mps:=0.15",
                         "cmd_vel:=/teleop/cmd_vel"], master.env, tmp_path, stdin=terminal.slave_fd,
                        stdout=terminal.slave_fd) as launch):
        wait_until_ready(commands, terminal)
        for keys, command in ((b"i", (0.1, 0.0)), (b"ii", (0.15, 0.0)), (b"j", (0.15, 0.25))):
            count = len(commands.messages)
            terminal.type(keys)
            commands.wait_for_command(command, since=count)
        count = len(commands.messages)
        launch.process.send_signal(signal.SIGINT)  # as Ctrl-C in roslaunch's terminal does
        assert launch.wait() == 0, launch.stderr()
        commands.wait_for_command((0.0, 0.0), since=count)
        assert commands.distinct() == pytest.approx([(0.0, 0.0), (0.1, 0.0), (0.15, 0.0), (0.15, 0.25), (0.0, 0.0)])
        assert terminal.restored()


@pytest.mark.parametrize("arg, message", [
    ("_linear_step_mps:=-0.1", "parameter /conde_teleop/linear_step_mps: expected a number > 0, got -0.1"),
    ("_angular_step_radps:=0", "parameter /conde_teleop/angular_step_radps: expected a number > 0, got 0"),
    ("_max_linear_mps:=fast", "parameter /conde_teleop/max_linear_mps: expected a number > 0, got 'fast'"),
    ("_max_angular_radps:=.inf", "parameter /conde_teleop/max_angular_radps: expected a number > 0, got inf"),
    ("_linear_step_mps:=0.6", "parameter /conde_teleop/linear_step_mps: must not exceed max_linear_mps (0.5), "
                              "got 0.6"),
    ("_rate_hz:=0", "parameter /conde_teleop/rate_hz: expected a number > 0, got 0"),
    ("_rate_hz:=true", "parameter /conde_teleop/rate_hz: expected a number > 0, got True"),
])
def test_bad_parameter_exits_with_its_message(master, tmp_path, arg, message):
    # A terminal, so that the parameter is the only thing wrong.
    with Terminal() as terminal, start_teleop(master, tmp_path, terminal, [arg]) as node:
        assert node.wait() == 1, node.stderr()
        errors = [line for line in node.stderr().splitlines() if line.startswith("conde_teleop: error: ")]
        assert errors == ["conde_teleop: error: " + message], node.stderr()
        assert terminal.restored()


def test_stdin_not_a_terminal_exits_with_its_message(master, tmp_path):
    master.set_params({}, clear=["/conde_teleop"])
    with LoggedProcess(["rosrun", "conde_teleop", "conde_teleop"], master.env, tmp_path) as node:  # stdin: /dev/null
        assert node.wait() == 1, node.stderr()
        errors = [line for line in node.stderr().splitlines() if line.startswith("conde_teleop: error: ")]
        assert errors == ["conde_teleop: error: stdin is not a terminal, and the keys are read from it: run the "
                          "node in a terminal (rosrun conde_teleop conde_teleop, or roslaunch with "
                          "launch_prefix:='xterm -e')"], node.stderr()
