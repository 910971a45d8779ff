"""A simulation started as the README says (the workspace sourced, nothing set by hand) listens on
loopback only: the master, roslaunch, and every node's XML-RPC and TCPROS servers. On a lab
network nobody else can read the camera streams or call a node's XML-RPC API.

The environment is built the way a user's shell is: a clean environment without ROS_IP,
ROS_HOSTNAME or LD_PRELOAD that sources devel/setup.bash (the env hook of conde_bringup sets
ROS_IP=127.0.0.1 and preloads libconde_loopback_bind.so for the roscpp nodes)."""
import ipaddress
import os
import re
import signal
import subprocess

import pytest
import rosgraph

from conde_testing.ros_harness import WORKSPACE, free_port, stop_process, wait_until

SETUP = os.path.join(WORKSPACE, "devel", "setup.bash")
NODES = ("/conde_sim", "/rosout", "/robot_state_publisher")


def user_shell_env():
    """The environment of a fresh login shell: no ROS variables, no preloads."""
    keep = ("HOME", "USER", "LANG", "TERM", "TMPDIR")
    env = {k: os.environ[k] for k in keep if k in os.environ}
    env["PATH"] = "/usr/bin:/usr/local/bin:/bin"
    return env


def listening_sockets():
    """[(address, port, pid, program)] of every listening TCP socket that `ss` attributes to a
    process."""
    out = subprocess.run(["ss", "-ltnpH"], capture_output=True, text=True, check=True).stdout
    sockets = []
    for line in out.splitlines():
        fields = line.split()
        local = fields[3]
        address, port = local.rsplit(":", 1)
        for program, pid in re.findall(r'\("([^"]+)",pid=(\d+),', line):
            sockets.append((address.strip("[]").split("%")[0], int(port), int(pid), program))
    return sockets


def descendant_pids(root_pid):
    """root_pid and every process below it (roslaunch starts each node in a session of its own)."""
    out = subprocess.run(["ps", "-e", "-o", "pid=,ppid="], capture_output=True, text=True, check=True).stdout
    children = {}
    for pid, ppid in (map(int, line.split()) for line in out.splitlines()):
        children.setdefault(ppid, []).append(pid)
    found, todo = set(), [root_pid]
    while todo:
        pid = todo.pop()
        found.add(pid)
        todo.extend(children.get(pid, []))
    return found


def is_loopback(address):
    return address != "*" and ipaddress.ip_address(address).is_loopback


@pytest.fixture
def sourced_simulation(tmp_path):
    if not os.path.isfile(SETUP):
        pytest.fail("build the workspace first (scripts/build.sh): no " + SETUP)
    port = free_port()
    command = (f"source '{SETUP}' && exec roslaunch -p {port} conde_bringup sim.launch "
               "paused:=true real_time_factor:=0")
    log = open(tmp_path / "roslaunch.log", "w")
    process = subprocess.Popen(["bash", "-c", command], env=user_shell_env(), stdout=log, stderr=subprocess.STDOUT,
                               start_new_session=True)
    try:
        master = rosgraph.Master("/loopback_test", master_uri=f"http://127.0.0.1:{port}")

        def nodes_up():
            assert process.poll() is None, "roslaunch exited:\n" + (tmp_path / "roslaunch.log").read_text()
            try:
                return all(master.lookupNode(name) for name in NODES)
            except Exception:
                return False

        wait_until(nodes_up, "the nodes " + ", ".join(NODES), timeout_s=120)
        yield process
    finally:
        stop_process(process, group=True)
        log.close()
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)


def test_every_server_of_a_sourced_simulation_listens_on_loopback(sourced_simulation):
    pids = descendant_pids(sourced_simulation.pid)
    ours = [s for s in listening_sockets() if s[2] in pids]
    programs = {program for _, _, _, program in ours}
    # Each roscpp node has an XML-RPC and a TCPROS server; the master and roslaunch one each.
    for program in ("conde_sim_node", "rosout", "robot_state_pub", "rosmaster", "roslaunch"):
        assert program in programs, f"no listening socket of {program} found in {ours}"
    assert len(ours) >= 8, ours
    exposed = [s for s in ours if not is_loopback(s[0])]
    assert not exposed, "listening beyond loopback: " + ", ".join(f"{p} on {a}:{n}" for a, n, _, p in exposed)


def test_the_preload_changes_nothing_for_processes_without_roscpp(tmp_path):
    """The preloaded library leaves programs that are not roscpp nodes alone: a Python server
    that asks for every interface gets every interface."""
    script = ("import socket; s = socket.socket(); s.bind(('0.0.0.0', 0)); "
              "print(s.getsockname()[0])")
    command = f"source '{SETUP}' && echo \"$LD_PRELOAD\" && /usr/bin/python3 -c \"{script}\""
    out = subprocess.run(["bash", "-c", command], env=user_shell_env(), capture_output=True, text=True,
                         check=True).stdout.split()
    assert out[0].endswith("/libconde_loopback_bind.so"), out
    assert out[1] == "0.0.0.0"


def test_a_user_address_is_kept(tmp_path):
    """Who sets ROS_IP (a lab network) keeps it: the env hook sets ROS_IP only when it is unset."""
    env = dict(user_shell_env(), ROS_IP="192.0.2.7")
    out = subprocess.run(["bash", "-c", f"source '{SETUP}' && echo \"$ROS_IP\""], env=env, capture_output=True,
                         text=True, check=True).stdout.strip()
    assert out == "192.0.2.7"
