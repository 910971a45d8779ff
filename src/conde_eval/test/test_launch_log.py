"""conde_eval.launch_log: which node died and how, from roslaunch's output."""
from conde_eval.launch_log import dead_nodes, stop_reason

LOG = """[conde_sim-2] process started with pid [4242]
\x1b[31m""" + "=" * 80 + """REQUIRED process [conde_sim-2] has died!
process has died [pid 4242, exit code -9, cmd /ws/devel/lib/conde_sim/conde_sim_node __name:=conde_sim].
log file: /root/.ros/log/x/conde_sim-2*.log
Initiating shutdown!
[conde_tracking-7] process has died [pid 4300, exit code 1, cmd /ws/src/conde_tracking/scripts/conde_tracking].
"""


def test_dead_nodes_with_signal_and_status():
    dead = dead_nodes(LOG)
    assert [(d.name, d.pid, d.exit_code) for d in dead] == [("conde_sim", 4242, -9), ("conde_tracking", 4300, 1)]
    assert dead[0].describe() == "conde_sim (pid 4242) died: killed by SIGKILL"
    assert dead[1].describe() == "conde_tracking (pid 4300) died: exit status 1"


def test_stop_reason():
    assert stop_reason(LOG, 0) == ("conde_sim (pid 4242) died: killed by SIGKILL; "
                                   "conde_tracking (pid 4300) died: exit status 1")
    assert stop_reason("nothing\n", 0) == "roslaunch stopped (exit status 0) and no node was reported dead"
