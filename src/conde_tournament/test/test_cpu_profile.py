"""The CPU accounting of a job (conde_tournament.cpu_profile) and the job's reaping with rusage."""
import os
import signal
import subprocess
import sys
import time

import pytest

from conde_tournament import cpu_profile
from conde_tournament.cpu_profile import JobCpu, ProcessCpu, parse_stat, per_node_s, process_name, profile_text
from conde_tournament.job import _reap, _stop, _wait

TICK = cpu_profile.CLOCK_TICKS_PER_S


def stat_line(name, utime, stime, cutime, cstime):
    """A /proc/PID/stat line with these times [clock ticks]."""
    return "4242 (%s) S 1 4242 4242 0 -1 4194560 100 0 0 0 %d %d %d %d 20 0 1 0 100 1000 50\n" % (
        name, utime, stime, cutime, cstime)


def test_parse_stat_counts_fields_after_the_last_parenthesis():
    own, children = parse_stat(stat_line("a (b) c", 3 * TICK, TICK, 2 * TICK, TICK))
    assert own == pytest.approx(4.0) and children == pytest.approx(3.0)


def test_parse_stat_of_this_process():
    with open("/proc/self/stat") as f:
        own, children = parse_stat(f.read())
    assert own >= 0.0 and children >= 0.0


def test_process_names():
    assert process_name(["/usr/bin/python3", "/ws/devel/lib/conde_tracking/conde_tracking", "__name:=conde_tracking",
                         "__log:=/x.log"]) == "conde_tracking"
    assert process_name(["/usr/bin/python3", "/usr/bin/roslaunch", "-p", "1234", "x.launch"]) == "roslaunch"
    assert process_name(["/usr/bin/python3", "-u", "/usr/bin/rosmaster", "--core"]) == "rosmaster"
    assert process_name(["/ws/devel/lib/conde_sim/conde_sim_node", "__name:=conde_sim"]) == "conde_sim"
    assert process_name(["bash", "-c", "roslaunch x"]) == "roslaunch x"
    assert process_name([]) == "?"


def test_per_node_counts_from_the_first_snapshot_and_adds_same_names():
    before = {1: ProcessCpu("sim", 10.0, 0.0), 2: ProcessCpu("roslaunch", 1.0, 2.0)}
    after = {1: ProcessCpu("sim", 25.0, 0.0), 2: ProcessCpu("roslaunch", 1.5, 2.0), 3: ProcessCpu("sim", 1.0, 0.0),
             4: ProcessCpu("rosout", 0.25, 0.0)}
    assert per_node_s(before, after) == {"sim": 16.0, "roslaunch": 0.5, "rosout": 0.25}
    # A pid reused by another process counts from zero.
    assert per_node_s({5: ProcessCpu("old", 9.0, 0.0)}, {5: ProcessCpu("new", 1.0, 0.0)}) == {"new": 1.0}
    # Own time only: the children roslaunch reaped (nodes that ended) are not counted twice.
    assert per_node_s(before, after, own_only=True)["roslaunch"] == 0.5
    assert per_node_s({}, {2: ProcessCpu("roslaunch", 1.0, 7.0)}, own_only=True) == {"roslaunch": 1.0}


def test_a_node_that_ended_before_the_decision_keeps_its_last_reading():
    running = {1: ProcessCpu("roslaunch", 2.0, 0.0), 2: ProcessCpu("conde_sim", 1.0, 0.0)}
    sampled = {1: ProcessCpu("roslaunch", 2.0, 0.0), 2: ProcessCpu("conde_sim", 9.0, 0.0)}
    decided = {1: ProcessCpu("roslaunch", 2.5, 9.5)}  # the simulator ended and was reaped
    cpu = FakeTree([running, sampled, decided])
    cpu.mark("nodes", 2.0)
    cpu.sample(10.0)
    cpu.mark("run", 11.0)
    cpu.finish(12.5)
    result = cpu.result(sim_s=10.0)
    assert result["nodes_run_s"] == {"conde_sim": 8.0, "roslaunch": 0.5}
    assert result["phases_s"]["run"] == 9.0 and result["phases_s"]["stop"] == 0.5


class FakeTree(JobCpu):
    """A JobCpu that reads prepared snapshots instead of /proc."""

    def __init__(self, shots):
        super().__init__(list_pids=lambda: [])
        self.shots = list(shots)

    def _read(self):
        shot = self.shots.pop(0)
        self._remember(shot)
        return shot


def test_phases_from_the_tree_totals_and_roslaunchs_rusage():
    parsed = {1: ProcessCpu("roslaunch", 1.0, 2.0)}
    running = {1: ProcessCpu("roslaunch", 2.0, 2.0), 2: ProcessCpu("conde_sim", 1.0, 0.0)}
    decided = {1: ProcessCpu("roslaunch", 2.5, 2.0), 2: ProcessCpu("conde_sim", 31.0, 0.0)}
    cpu = FakeTree([parsed, running, decided])
    cpu.mark("parse", 1.0)
    cpu.mark("parse", 1.2)  # a boundary counts once
    cpu.mark("nodes", 2.0)
    cpu.mark("run", 50.0)
    cpu.finish(40.0)
    result = cpu.result(sim_s=20.0)
    assert result["phases_s"] == {"parse": 3.0, "nodes": 2.0, "run": 30.5, "stop": 4.5}
    assert result["total_s"] == 40.0 and result["sim_s"] == 20.0
    assert result["nodes_run_s"] == {"conde_sim": 30.0, "roslaunch": 0.5}  # own CPU only
    assert result["nodes_startup_s"] == {"conde_sim": 1.0, "roslaunch": 4.0}


def test_processes_that_ended_before_the_run_are_not_the_runs():
    parsing = {1: ProcessCpu("roslaunch", 1.0, 0.0), 7: ProcessCpu("xacro", 0.25, 0.0)}
    running = {1: ProcessCpu("roslaunch", 1.0, 0.5), 2: ProcessCpu("conde_sim", 1.0, 0.0)}
    decided = {1: ProcessCpu("roslaunch", 1.5, 0.5), 2: ProcessCpu("conde_sim", 3.0, 0.0),
               8: ProcessCpu("conde_traffic_sign", 0.5, 0.0)}
    cpu = FakeTree([parsing, running, decided])
    cpu.mark("parse", 1.0)
    cpu.mark("nodes", 2.0)
    cpu.mark("run", 9.0)
    assert cpu.result(sim_s=4.0)["nodes_run_s"] == {"conde_sim": 2.0, "conde_traffic_sign": 0.5, "roslaunch": 0.5}


def test_a_run_ended_by_the_simulation_ends_at_the_latest_reading():
    running = {1: ProcessCpu("roslaunch", 2.0, 0.0), 2: ProcessCpu("conde_sim", 1.0, 0.0)}
    sampled = {1: ProcessCpu("roslaunch", 2.0, 0.0), 2: ProcessCpu("conde_sim", 11.0, 0.0)}
    cpu = FakeTree([running, sampled])
    cpu.mark("nodes", 2.0)
    cpu.sample(10.0)
    cpu.finish(14.0)
    result = cpu.result(sim_s=None)
    assert result["phases_s"] == {"parse": None, "nodes": 3.0, "run": 10.0, "stop": 1.0}
    assert result["nodes_run_s"] == {"conde_sim": 10.0, "roslaunch": 0.0}


def test_a_process_in_its_exit_keeps_its_last_reading():
    running = {1: ProcessCpu("roslaunch", 2.0, 0.0), 2: ProcessCpu("conde_sim", 1.0, 0.0)}
    sampled = {1: ProcessCpu("roslaunch", 2.0, 0.0), 2: ProcessCpu("conde_sim", 11.0, 0.0)}
    exiting = {1: ProcessCpu("roslaunch", 2.0, 0.0), 2: ProcessCpu("conde_sim", 0.0, 0.0)}
    cpu = FakeTree([running, sampled, exiting])
    cpu.mark("nodes", 2.0)
    cpu.sample(10.0)
    cpu.sample(20.0)
    assert cpu.last[2].total_s == 11.0 and cpu.last_total_s == 13.0
    assert cpu.result(sim_s=None)["nodes_run_s"]["conde_sim"] == 10.0


def test_samples_are_rate_limited():
    cpu = FakeTree([{1: ProcessCpu("a", 1.0, 0.0)}])
    cpu.sample(100.0)
    cpu.sample(100.5)  # within sample_period_s: no reading (FakeTree would run out of snapshots)
    assert cpu.last_total_s == 1.0


def test_a_real_process_tree_is_read_from_proc():
    child = subprocess.Popen([sys.executable, "-c", "import sys; sum(range(3000000)); print(1, flush=True); "
                              "sys.stdin.read()"], stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    try:
        assert child.stdout.readline() == b"1\n"  # running the script
        cpu = JobCpu(list_pids=lambda: [child.pid])
        cpu.mark("parse", 0.0)
        assert cpu.names[child.pid].startswith("import sys")  # the script an interpreter runs
        assert cpu.totals_s["parse"] == cpu.last[child.pid].total_s >= 0.0
    finally:
        child.stdin.close()
        assert _wait(child, 30.0)
    assert child.returncode == 0 and child.cpu_s > 0.0


def test_reap_gives_the_cpu_of_the_whole_tree():
    # The shell reaps a grandchild that burns CPU; its time reaches the shell's rusage.
    burn = "%s -c 'sum(range(20000000))'" % sys.executable
    process = subprocess.Popen(["bash", "-c", burn + "; exit 3"])
    assert _wait(process, 60.0)
    assert process.returncode == 3 and process.cpu_s > 0.1
    assert _reap(process) == 3  # reaped once, asked again


def test_stop_ends_the_process_group_and_reaps_with_rusage():
    # SIGINT as a terminal would deliver it, whatever this test inherited (a run started in the
    # background of a script inherits SIGINT ignored: the foreground sleep would then wait for the kill)
    process = subprocess.Popen(["bash", "-c", "sleep 60 & sleep 60; wait"], start_new_session=True,
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    started = time.monotonic()
    _stop(process, grace_s=20.0)
    assert time.monotonic() - started < 15.0
    assert process.returncode is not None and process.cpu_s >= 0.0
    # Nothing of the group is left (the background sleep, which ignores SIGINT, got SIGKILL; init
    # reaps it).
    deadline = time.monotonic() + 10.0
    while time.monotonic() < deadline:
        try:
            os.killpg(process.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        pytest.fail("the process group still exists")


def test_profile_text_tables_and_estimate():
    d1 = {"phases_s": {"parse": 2.0, "nodes": 8.0, "run": 100.0, "stop": 2.0}, "total_s": 112.0, "sim_s": 50.0,
          "nodes_run_s": {"conde_sim": 60.0, "conde_tracking": 30.0},
          "nodes_startup_s": {"roslaunch": 3.5, "conde_tracking": 1.25}}
    p1 = {"phases_s": {"parse": 2.0, "nodes": 8.0, "run": 20.0, "stop": 2.0}, "total_s": 32.0, "sim_s": 20.0,
          "nodes_run_s": {"conde_sim": 12.0, "conde_tracking": 6.0}}
    text = profile_text([("D1", d1), ("P1", p1), ("D2", None)], cores=2, runner_cpu_s=4.0)
    lines = text.splitlines()
    assert lines[1].split() == ["challenge", "parse", "nodes", "run", "stop", "total", "sim", "[s]", "run/sim",
                                "all/sim"]
    assert lines[2].split() == ["D1", "2.0", "8.0", "100.0", "2.0", "112.0", "50.0", "2.00", "2.24"]
    assert lines[4].split() == ["D2", "(not", "measured)"]
    assert lines[5].split() == ["total", "4.0", "16.0", "120.0", "4.0", "144.0"]
    assert "conde_sim                        1200    600" in text
    assert text.index("conde_sim ") < text.index("conde_tracking ")
    assert "roslaunch                        3.50\n" in text and "conde_tracking                   1.25\n" in text
    assert lines[-1] == ("whole run alone, estimated: max((144 + runner 4) CPU s / 2 cores, longest job 112 CPU s)"
                         " = 112 s (1.9 min)")


def test_sim_seconds_from_the_referee_path():
    assert cpu_profile.sim_seconds({"path_t_x_y": [[0.0, 1, 2], [29.9, 1, 2]]}) == 29.9
    assert cpu_profile.sim_seconds(None) is None and cpu_profile.sim_seconds({}) is None


@pytest.mark.parametrize("pid", [os.getpid()])
def test_snapshot_skips_processes_that_are_gone(pid):
    shot = cpu_profile.snapshot([pid, 2 ** 22 + 12345])
    assert list(shot) == [pid]
