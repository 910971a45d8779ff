"""What the node tests of the Python packages share to run real nodes against a real ROS master:
a roscore of their own on a free loopback port, the environment in which the built workspace's
nodes run, waiting on the wall clock (generous timeouts: the machine may be busy), processes
under test with their output kept, this test process joining the master as a node, and the
messages of a topic.

Importing this module needs no ROS: rospy, rosgraph and xacro are imported where they are used,
so that the pure tests of a package run without a built workspace."""

import contextlib
import os
import signal
import socket
import subprocess
import sys
import threading
import time

# src/conde_testing/src/conde_testing/ros_harness.py -> the repository (the catkin source space)
WORKSPACE = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", ".."))
PYTHON = "/usr/bin/python3"  # the Python that has rospy
TIMEOUT_S = 60.0  # default wall-clock patience
ROSCORE_PARAMS = ("/rosdistro", "/rosversion", "/run_id", "/roslaunch")  # what roscore itself sets


def fatal_error(code, stderr, node):
    """The message of a node that had to stop: asserts a non-zero exit `code` and returns the
    <message> of the last "<node>: error: <message>" line of `stderr`."""
    prefix = node + ": error: "
    lines = [line for line in stderr.splitlines() if line.startswith(prefix)]
    assert code != 0, f"{node} exited 0:\n{stderr}"
    assert lines, f"no '{prefix}' line in:\n{stderr}"
    return lines[-1][len(prefix):]


def free_port():
    """A TCP port of 127.0.0.1 that is free now (another process may take it before it is used)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_until(condition, what, timeout_s=TIMEOUT_S, poll_s=0.05):
    """Polls condition() on the wall clock until it holds; AssertionError "timed out waiting for
    <what>" after timeout_s."""
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, "timed out waiting for " + what
        time.sleep(poll_s)


def wait_or_exit(probe, condition, what, timeout_s=TIMEOUT_S, poll_s=0.005):
    """For a probe (a ROS node that a test runs as a child process and judges by its exit status
    and stderr): waits until condition() holds; on a time-out or a ROS shutdown writes
    "<probe>: timed out waiting for <what>" on stderr and exits with status 2."""
    import rospy  # here: the pure tests must not need ROS

    deadline = time.monotonic() + timeout_s
    while not condition():
        if time.monotonic() > deadline or rospy.is_shutdown():
            sys.stderr.write("%s: timed out waiting for %s\n" % (probe, what))
            sys.exit(2)
        time.sleep(poll_s)


def workspace_env(package):
    """The environment in which the built workspace's nodes run: the current one (with /usr/bin
    first on PATH) if rospack finds `package` in it, else the one of the workspace's
    devel/setup.bash."""
    env = dict(os.environ, PATH="/usr/bin:" + os.environ.get("PATH", ""))
    if subprocess.run(["rospack", "find", package], env=env, capture_output=True).returncode == 0:
        return env
    setup = os.path.join(WORKSPACE, "devel", "setup.bash")
    assert os.path.isfile(setup), "build the workspace first (scripts/build.sh): no %s" % setup
    out = subprocess.run(["bash", "-c", "set +u; source '%s' && env -0" % setup], env=env, capture_output=True,
                         check=True).stdout
    return dict(item.split("=", 1) for item in out.decode().split("\0") if "=" in item)


def stop_process(process, timeout_s=30.0, group=False):
    """SIGINT (what Ctrl-C and roslaunch send), then SIGKILL if it has not exited within
    timeout_s. group=True: to the process group the process leads (started with
    start_new_session=True), so that its children stop too. Returns the exit status."""
    def send(sig):
        try:
            if group:
                os.killpg(process.pid, sig)
            elif process.poll() is None:
                process.send_signal(sig)
        except ProcessLookupError:  # the group has ended already
            pass

    if group or process.poll() is None:
        send(signal.SIGINT)
        try:
            process.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            send(signal.SIGKILL)
            process.wait()
    return process.returncode


def _master_parent_pid(uri):
    """The parent process of the master answering at uri (the roscore that started it), or None."""
    import rosgraph  # here: the pure tests must not need ROS

    try:
        pid = rosgraph.Master("/conde_testing", master_uri=uri).getPid()
        with open("/proc/%d/stat" % pid) as stat:
            return int(stat.read().rsplit(")", 1)[1].split()[1])
    except Exception:  # no master (yet) at uri, or it is not on this machine
        return None


class Roscore:
    """A roscore on a free loopback port, the test's own: up once the master answering at its
    address is the one this roscore started (another test run may take the port between the check
    and roscore's start: that roscore then exits, and another port is tried). `env` runs processes
    against it: the built workspace's environment (see workspace_env(package)), with
    ROS_MASTER_URI and ROS_IP set, no ROS_HOSTNAME and no ROS_NAMESPACE. Also a context manager
    that stops it at the end."""

    def __init__(self, package, timeout_s=TIMEOUT_S, tries=5):
        env = dict(workspace_env(package), ROS_IP="127.0.0.1")
        env.pop("ROS_HOSTNAME", None)
        env.pop("ROS_NAMESPACE", None)
        for _ in range(tries):
            port = free_port()
            uri = "http://127.0.0.1:%d" % port
            self.env = dict(env, ROS_MASTER_URI=uri)
            self.proc = subprocess.Popen(["roscore", "-p", str(port)], env=self.env, stdout=subprocess.DEVNULL,
                                         stderr=subprocess.DEVNULL, start_new_session=True)
            deadline = time.monotonic() + timeout_s
            while self.proc.poll() is None and _master_parent_pid(uri) != self.proc.pid:
                if time.monotonic() > deadline:
                    self.stop()
                    raise AssertionError("timed out waiting for roscore to come up at " + uri)
                time.sleep(0.2)
            if self.proc.poll() is None:
                return
        raise AssertionError("roscore did not start on any of %d free ports" % tries)

    @property
    def uri(self):
        return self.env["ROS_MASTER_URI"]

    def _master(self):
        import rosgraph  # here: the pure tests must not need ROS

        return rosgraph.Master("/conde_testing_setup", master_uri=self.uri)

    def set_params(self, params, clear=()):
        """Sets parameters on the master ({name: value}; newlines kept, unlike `rosparam set`),
        after deleting the namespaces in `clear` (private parameters of an earlier case stay on
        the master)."""
        master = self._master()
        for ns in clear:
            if master.hasParam(ns):
                master.deleteParam(ns)
        for name, value in params.items():
            master.setParam(name, value)

    def param_namespaces(self):
        """The top-level namespaces on the parameter server, roscore's own left out (for
        set_params(..., clear=...) to start from what roscore set)."""
        names = {"/" + name.split("/")[1] for name in self._master().getParamNames()}
        return sorted(names - set(ROSCORE_PARAMS))

    def stop(self):
        """SIGINT to roscore and its children (the master, rosout); SIGKILL after 30 s."""
        stop_process(self.proc, group=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.stop()


@contextlib.contextmanager
def joined_as_node(master_uri, name):
    """This test process as an anonymous ROS node `name` of the master at master_uri (wall-clock
    time unless /use_sim_time is set), with os.environ pointing to that master while it lasts
    (rospy reads the master's address at init_node, but some of its calls, wait_for_service and
    service proxies, look it up in the environment each time); rospy is shut down at the end.
    rospy joins one master per process, once: each module that joins needs a pytest process of
    its own (as tests/run_all_tests.sh runs one per test directory)."""
    import rospy  # here: the pure tests must not need ROS

    saved = {k: os.environ.get(k) for k in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOSTNAME")}
    os.environ.update(ROS_MASTER_URI=master_uri, ROS_IP="127.0.0.1")
    os.environ.pop("ROS_HOSTNAME", None)
    try:
        rospy.init_node(name, anonymous=True, disable_signals=True)
        yield
    finally:
        if rospy.core.is_initialized():
            rospy.signal_shutdown("tests done")
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def publishes_to(node, topic, subscriber):
    """Whether the node `node` publishes `topic` to the node `subscriber` already, as the
    publisher's own connection list says (getBusInfo). A subscriber's get_num_connections() counts
    a connection once the publisher has answered the handshake, but rospy's publisher adds it to
    the connections it publishes on only after answering: a message published in between is lost.
    A test that expects one message per input waits for this first."""
    import xmlrpc.client

    import rosgraph  # here: the pure tests must not need ROS

    try:
        uri = rosgraph.Master(subscriber).lookupNode(node)
        code, _, connections = xmlrpc.client.ServerProxy(uri).getBusInfo(subscriber)
    except (rosgraph.MasterError, OSError):  # not registered (yet), or gone
        return False
    # (connection id, the other node, direction "o" for outbound, transport, topic, ...)
    return code == 1 and any(c[1] == subscriber and c[2] == "o" and c[4] == topic for c in connections)


def run_probe(probe_path, node_command, env, timeout_s=300.0):
    """Runs the probe script probe_path (a ROS node of its own: rospy allows one node per process)
    with PYTHON to its end while node_command (the node under test) runs, then stops the node with
    SIGINT. The probe must exit with status 0 (else AssertionError with its stderr and the node's
    output). Returns (the probe's stdout, the node's stdout and stderr together)."""
    node = subprocess.Popen(node_command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        probe = subprocess.run([PYTHON, probe_path], env=env, capture_output=True, text=True, timeout=timeout_s)
    finally:
        node.send_signal(signal.SIGINT)
        log = node.communicate(timeout=60)[0]
    assert probe.returncode == 0, probe.stderr + "\nnode log:\n" + log
    return probe.stdout, log


class LoggedProcess:
    """A command under test: stdin and stdout as given; what it writes to stdout (unless given)
    and to stderr is kept in log_dir/stdout.txt and log_dir/stderr.txt. Python processes write
    unbuffered (PYTHONUNBUFFERED=1), so a test reads their log lines while they run. A `with`
    block stops it on the way out."""

    def __init__(self, command, env, log_dir, stdin=subprocess.DEVNULL, stdout=None):
        env = dict(env, PYTHONUNBUFFERED="1")
        self.stdout_path = os.path.join(str(log_dir), "stdout.txt")
        self.stderr_path = os.path.join(str(log_dir), "stderr.txt")
        with open(self.stdout_path, "w") as out, open(self.stderr_path, "w") as err:
            self.process = subprocess.Popen(command, env=env, stdin=stdin, stdout=out if stdout is None else stdout,
                                            stderr=err)

    def stderr(self):
        with open(self.stderr_path) as f:
            return f.read()

    def output(self):
        """stdout (where it went to the file) and then stderr."""
        with open(self.stdout_path) as f:
            return f.read() + self.stderr()

    def wait(self, timeout_s=TIMEOUT_S):
        return self.process.wait(timeout=timeout_s)

    def stop(self):
        """SIGINT if it still runs, SIGKILL after 30 s."""
        stop_process(self.process)

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.stop()


class TopicLog:
    """Every message received on a topic (this process must have joined the master), and waiting
    for the ones that match. describe(message) shows a message in a time-out's message. A `with`
    block unsubscribes on the way out."""

    def __init__(self, topic, message_type, describe=str, queue_size=100):
        import rospy  # here: the pure tests must not need ROS

        self.topic = topic
        self.messages = []
        self._describe = describe
        self._changed = threading.Condition()
        self.subscriber = rospy.Subscriber(topic, message_type, self._on_message, queue_size=queue_size)

    def _on_message(self, message):
        with self._changed:
            self.messages.append(message)
            self._changed.notify_all()

    def snapshot(self):
        """The messages received so far."""
        with self._changed:
            return list(self.messages)

    def received(self):
        """What a time-out's message shows of the messages received."""
        return [self._describe(m) for m in self.snapshot()]

    def wait_for(self, predicate, what, since=0, count=1, timeout_s=TIMEOUT_S):
        """The count-th message (from the since-th message on, received so far or later) for which
        predicate holds; AssertionError "<topic>: timed out waiting for <what>; received <...>"
        after timeout_s."""
        deadline = time.monotonic() + timeout_s
        with self._changed:
            while True:
                matching = [m for m in self.messages[since:] if predicate(m)]
                if len(matching) >= count:
                    return matching[count - 1]
                remaining = deadline - time.monotonic()
                assert remaining > 0, "%s: timed out waiting for %s; received %s" % (
                    self.topic, what, self.received())
                self._changed.wait(remaining)

    def close(self):
        self.subscriber.unregister()

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()


def xacro_finding(package_dir):
    """The xacro module, with package_dir first on ROS_PACKAGE_PATH (in os.environ) so that
    $(find <that package>) in a robot file resolves to this checkout, not to another workspace's
    copy; roslaunch's cached RosPack (made on first use, maybe with another path) is dropped."""
    os.environ["ROS_PACKAGE_PATH"] = os.pathsep.join(
        p for p in [package_dir, os.environ.get("ROS_PACKAGE_PATH", "")] if p)
    import xacro  # here: after ROS_PACKAGE_PATH is set

    try:
        from roslaunch import substitution_args
        substitution_args._rospack = None
    except ImportError:  # pragma: no cover
        pass
    return xacro


#: Lines of a run's roslaunch log that tell what a failed referee-judged run did and whether the
#: machine kept it deterministic: the decision's transitions (with their simulated time), the
#: simulator's lock-step totals and the nodes' bounded waits that gave up (conde_common.sim_clock).
DIGEST_MARKERS = ("-->", "conde_sim: lock-step: ", " frames waited for answers", "waits for owed",
                  "had not come after", "timed out", "ERROR", "Traceback")


def run_digest(log_text, max_lines=80):
    """The lines of a run's log that DIGEST_MARKERS name (the last max_lines of them), without the
    lock-step rule listing of the start-up, for a failed run's assertion message."""
    lines = [line for line in log_text.splitlines()
             if any(m in line for m in DIGEST_MARKERS) and " answers " not in line]
    return "run digest (transitions, lock-step totals, given-up waits):\n" + "\n".join(lines[-max_lines:])
