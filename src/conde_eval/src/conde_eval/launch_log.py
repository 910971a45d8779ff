"""What roslaunch's output says about nodes that died (pure Python).

roslaunch writes, for a node process that ends on its own:
    [conde_tracking-7] process has died [pid 4300, exit code 1, cmd /.../conde_tracking ...].
and for a required one (then it shuts everything down and exits 0 itself):
    ==== (a line of them) ====REQUIRED process [conde_sim-2] has died!
    process has died [pid 4242, exit code -9, cmd /.../conde_sim_node __name:=conde_sim ...].
A run that ends early reports these instead of "roslaunch stopped (exit 0)"."""
import re
import signal
from dataclasses import dataclass
from typing import List

_DIED = re.compile(r"(?:\[(?P<label>[^\]\s]+)-\d+\] |REQUIRED process \[(?P<required>[^\]\s]+)-\d+\] has died!\s*)"
                   r"process has died \[pid (?P<pid>\d+), exit code (?P<code>-?\d+)")


@dataclass
class DeadNode:
    name: str
    pid: int
    exit_code: int  # negative: killed by signal -exit_code (Popen's convention)

    def how(self) -> str:
        if self.exit_code < 0:
            try:
                sig = signal.Signals(-self.exit_code).name
            except ValueError:
                sig = "signal %d" % -self.exit_code
            return "killed by %s" % sig
        return "exit status %d" % self.exit_code

    def describe(self) -> str:
        return "%s (pid %d) died: %s" % (self.name, self.pid, self.how())


def dead_nodes(log_text: str) -> List[DeadNode]:
    """Every node that roslaunch reports dead, in the order of the log."""
    return [DeadNode(m.group("label") or m.group("required"), int(m.group("pid")), int(m.group("code")))
            for m in _DIED.finditer(log_text)]


def stop_reason(log_text: str, roslaunch_status: int) -> str:
    """Why a launch ended before the run did: the nodes that died first, else roslaunch's status."""
    dead = dead_nodes(log_text)
    if dead:
        return "; ".join(d.describe() for d in dead)
    return "roslaunch stopped (exit status %d) and no node was reported dead" % roslaunch_status
