"""A real roscore on a free loopback port for the node tests, and the environment in which the
built workspace's nodes run (the current one if it already finds conde_racing, else the one of
the workspace's devel/setup.bash)."""

import os
import socket
import subprocess
import time

WORKSPACE = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", ".."))


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def workspace_env():
    env = dict(os.environ)
    env["PATH"] = "/usr/bin:" + env.get("PATH", "")
    if subprocess.run(["rospack", "find", "conde_racing"], env=env, capture_output=True).returncode == 0:
        return env
    setup = os.path.join(WORKSPACE, "devel", "setup.bash")
    assert os.path.isfile(setup), "build the workspace first (scripts/build.sh): no %s" % setup
    out = subprocess.run(["bash", "-c", "set +u; source '%s' && env -0" % setup], env=env, capture_output=True,
                         check=True).stdout
    return dict(item.split("=", 1) for item in out.decode().split("\0") if "=" in item)


class Roscore:
    """roscore on a free port; `env` runs processes against it."""

    def __init__(self):
        port = free_port()
        self.env = dict(workspace_env(), ROS_MASTER_URI="http://127.0.0.1:%d" % port, ROS_IP="127.0.0.1")
        self.env.pop("ROS_HOSTNAME", None)
        self.proc = subprocess.Popen(["roscore", "-p", str(port)], env=self.env, stdout=subprocess.DEVNULL,
                                     stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 60
        while subprocess.run(["rosparam", "list"], env=self.env, capture_output=True).returncode != 0:
            assert self.proc.poll() is None, "roscore exited"
            assert time.monotonic() < deadline, "roscore did not come up"
            time.sleep(0.2)

    def set_params(self, params, clear=()):
        """Sets parameters on the master (deleting the namespaces in `clear` first)."""
        import rosgraph  # here: the pure tests must not need ROS

        master = rosgraph.Master("/test_setup", master_uri=self.env["ROS_MASTER_URI"])
        for ns in clear:
            if master.hasParam(ns):
                master.deleteParam(ns)
        for name, value in params.items():
            master.setParam(name, value)

    def stop(self):
        self.proc.terminate()
        self.proc.wait(timeout=30)
