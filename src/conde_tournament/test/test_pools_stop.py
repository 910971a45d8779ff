"""An interruption (Ctrl-C, SIGTERM) stops the running jobs within seconds and keeps what finished
(no ROS: the jobs here are `sleep` and `true` in place of roslaunch)."""
import json
import os
import shlex
import signal
import subprocess
import sys
import threading
import time

import pytest

from conde_tournament import job as job_module
from conde_tournament import pools
from conde_tournament.tournament_file import Job, Team

STOP_WAIT_S = 30.0  # how long a running item waits for the stop: far above what the tests allow


@pytest.fixture(autouse=True)
def stop_clear():
    """Each test starts, and leaves the next one, with job.STOP clear."""
    job_module.STOP.clear()
    yield
    job_module.STOP.clear()


def waiting_run(seen, first_done=None):
    """A run_each callable: item 0 returns at once (after first_done() when given); the others wait
    for job.STOP and record whether they saw it, then raise JobInterrupted as an interrupted job does."""
    def run(item):
        if item == 0:
            if first_done is not None:
                first_done()
            return "done"
        seen[item] = job_module.STOP.wait(STOP_WAIT_S)
        raise job_module.JobInterrupted(str(item))
    return run


def test_run_each_closed_early_stops_the_running_items_at_once():
    seen, started = {}, []

    def when_the_others_run():
        while not {1, 2} <= set(started):
            time.sleep(0.01)
    finished = pools.run_each(waiting_run(seen, when_the_others_run), [1, 2, 0, 3], workers=3,
                              on_start=started.append)
    assert next(finished) == (0, "done")
    t0 = time.monotonic()
    finished.close()
    assert time.monotonic() - t0 < 5.0
    assert not job_module.STOP.is_set()  # cleared once the workers ended: a later job in this process runs
    assert seen[1] and seen[2]
    assert seen == {item: True for item in started if item != 0}  # 3 ran (a worker was free) or was dropped


def test_run_each_interrupted_raises_the_interruption_not_the_jobs():
    """Ctrl-C while the consumer waits in run_each (KeyboardInterrupt raised in the generator): the
    running items are stopped, and their JobInterrupted does not take the place of the KeyboardInterrupt."""
    seen, started = {}, []

    def when_the_others_run():
        while not {1, 2} <= set(started):
            time.sleep(0.01)
    finished = pools.run_each(waiting_run(seen, when_the_others_run), [1, 2, 0], workers=3, on_start=started.append)
    assert next(finished) == (0, "done")
    t0 = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        finished.throw(KeyboardInterrupt)
    assert time.monotonic() - t0 < 5.0
    assert seen == {1: True, 2: True}


def test_an_ordinary_end_leaves_stop_clear():
    job_module.STOP.set()  # left by an earlier interruption: cleared as run_each starts
    assert sorted(pools.run_each(lambda i: i * 2, range(5), 2)) == [(i, i * 2) for i in range(5)]
    assert not job_module.STOP.is_set()
    finished = pools.run_each(lambda i: i, [7], 1)
    assert list(next(finished)) == [7, 7]
    finished.close()  # every item done: nothing to stop
    assert not job_module.STOP.is_set()


def sleeping_launch(seconds):
    """A stand-in for job.launch_command: the job's 'roslaunch' sleeps (or ends at once: 0)."""
    def command(job, port, job_dir, sim_limit_s, launch_args=()):
        return ["bash", "-c", "echo launched; exec sleep %g" % seconds] if seconds else ["bash", "-c", "true"]
    return command


def stop_a_running_job(job_dir, ready=None, settle_s=0.0):
    """Runs a P1 job (its launch command patched by the caller) in a thread; once ready() (default:
    the job's processes run) and settle_s later, sets job.STOP and waits for run_job to end.
    Returns ({"result": ...} or {"interrupted": JobInterrupted}, seconds from STOP to the end)."""
    outcome = {}

    def run():
        try:
            outcome["result"] = job_module.run_job(Job(Team("a"), "P1", "", 0, "ode", 0), job_dir, 0.0, 600.0)
        except job_module.JobInterrupted as error:
            outcome["interrupted"] = error
    ready = ready or (lambda: job_module.job_processes(job_dir))
    thread = threading.Thread(target=run)
    thread.start()
    try:
        deadline = time.monotonic() + 10.0
        while not ready() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert ready(), "the job did not start"
        time.sleep(settle_s)
        t0 = time.monotonic()
        job_module.STOP.set()
        thread.join(STOP_WAIT_S + 5.0)
        return outcome, time.monotonic() - t0
    finally:
        job_module.STOP.set()  # whatever failed above: the job ends, the thread with it
        thread.join()


def test_a_running_job_is_stopped_and_leaves_no_result(tmp_path, monkeypatch):
    monkeypatch.setattr(job_module, "launch_command", sleeping_launch(STOP_WAIT_S))
    job_dir = str(tmp_path / "job")
    outcome, took_s = stop_a_running_job(job_dir)
    assert took_s < 5.0
    assert "interrupted" in outcome
    assert job_module.job_processes(job_dir) == []  # its process group is gone
    assert job_module.load_result(job_dir) is None


def test_an_interrupted_job_that_ignores_sigint_is_killed_after_the_short_grace(tmp_path, monkeypatch):
    """A node slow to end on SIGINT (here: it ignores it) keeps an interrupted job for
    INTERRUPTED_GRACE_S, not for the 15 s an ordinary end grants."""
    def command(job, port, job_dir, sim_limit_s, launch_args=()):
        return ["bash", "-c", "trap '' INT; echo launched; exec sleep %g" % STOP_WAIT_S]
    monkeypatch.setattr(job_module, "launch_command", command)
    job_dir = str(tmp_path / "job")
    outcome, took_s = stop_a_running_job(job_dir)
    assert job_module.INTERRUPTED_GRACE_S <= took_s < 10.0, took_s
    assert "interrupted" in outcome
    assert job_module.job_processes(job_dir) == []


def test_a_job_judged_before_the_interruption_keeps_its_result(tmp_path, monkeypatch):
    """The referee's report is there, its plot not yet, when the command is interrupted: the job
    does not wait for the plot and keeps its result (a resumed campaign does not run it again)."""
    report = {"challenge": "P1", "kind": "parking", "score": 60.0, "penalty_total": 0.0, "disqualified": False,
              "end": "parked", "laps": 0, "parked": "parallel", "signs_right": 0, "driving_time_s": 20.0,
              "events": []}

    def command(job, port, job_dir, sim_limit_s, launch_args=()):
        return ["bash", "-c", "mkdir -p challenge && echo %s > challenge/referee.json && echo launched && exec sleep %g"
                % (shlex.quote(json.dumps(report)), STOP_WAIT_S)]
    monkeypatch.setattr(job_module, "launch_command", command)
    job_dir = str(tmp_path / "job")
    # settle_s: the job has seen the report and waits for the plot
    outcome, took_s = stop_a_running_job(
        job_dir, ready=lambda: os.path.exists(os.path.join(job_dir, "challenge", "referee.json")), settle_s=0.5)
    assert took_s < 10.0
    assert "interrupted" not in outcome, outcome
    assert outcome["result"]["report"]["end"] == "parked"
    assert job_module.load_result(job_dir)["report"]["score"] == 60.0
    assert job_module.job_processes(job_dir) == []


def test_run_job_starts_no_other_attempt_once_stopped(tmp_path, monkeypatch):
    calls = []

    def once(job, job_dir, sim_limit_s, wall_limit_s, launch_args=()):
        calls.append(job.job_id)
        with open(job_dir + "/roslaunch.log", "w") as f:
            f.write("ran\n")
        job_module.STOP.set()  # stopped while the first attempt stalled
        return {"status": job_module.START_STALLED, "report": None}
    monkeypatch.setattr(job_module, "_run_job_once", once)
    with pytest.raises(job_module.JobInterrupted):  # (the autouse fixture clears STOP afterwards)
        job_module.run_job(Job(Team("a"), "D1", "", 0, "ode", 0), str(tmp_path), 0.0, 600.0)
    assert len(calls) == 1
    assert job_module.load_result(str(tmp_path)) is None


# A command in a subprocess, its jobs' launch replaced: challenge P1 ends at once (no report), the
# others sleep until they are stopped.
COMMAND = """
import sys
from conde_tournament import job
import test_pools_stop
job.launch_command = test_pools_stop.command_of_challenge
from conde_tournament import {module}
sys.exit({module}.main({argv!r}))
"""


def command_of_challenge(job, port, job_dir, sim_limit_s, launch_args=()):
    return sleeping_launch(0 if job.challenge == "P1" else STOP_WAIT_S)(job, port, job_dir, sim_limit_s)


def job_dirs(out):
    return [os.path.join(root, d) for root, dirs, _ in os.walk(out) for d in dirs
            if os.path.exists(os.path.join(root, d, "job.json"))]


def commands(out):
    tournament = os.path.join(out, "class.yaml")
    return {
        "robustness": ("robustness_run", ["--challenges", "P1,P2", "--engines", "ode", "--track-seeds", "0",
                                          "--placement-seeds", "0", "--jobs", "2", "--out", out],
                       "robustness: interrupted; the finished runs are in"),
        "competition": ("competition_run", ["--challenge", "P1,P2", "--output-dir", out],
                        "competition: interrupted after"),
        "run": ("cli", [tournament, "--jobs", "2", "--no-progress", "--output", out],
                "conde_tournament: interrupted; 1 of 2 jobs have a result in"),
    }


@pytest.mark.parametrize("command, sig", [("robustness", signal.SIGTERM), ("competition", signal.SIGTERM),
                                          ("run", signal.SIGTERM), ("robustness", signal.SIGHUP)])
def test_sigterm_stops_the_command_like_ctrl_c(tmp_path, command, sig):
    """SIGTERM (or SIGHUP) to the command once one job has finished and another runs: it stops the running one
    within seconds (no process of it left), keeps the finished one, says it was interrupted (no
    traceback) and exits 1."""
    out = str(tmp_path)
    with open(os.path.join(out, "class.yaml"), "w") as f:
        f.write("teams: [{name: reference}]\nchallenges: [{name: P1}, {name: P2}]\n")
    module, argv, message = commands(out)[command]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([os.path.dirname(__file__)] + sys.path))
    process = subprocess.Popen([sys.executable, "-c", COMMAND.format(module=module, argv=argv)], env=env,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 30.0
        while time.monotonic() < deadline:  # until P1 has its result and P2 runs
            dirs = job_dirs(out)
            results = [d for d in dirs if job_module.load_result(d) is not None]
            running = [d for d in dirs if d not in results and job_module.job_processes(d)]
            if results and running:
                break
            assert process.poll() is None, process.communicate()
            time.sleep(0.1)
        else:
            pytest.fail("the jobs did not start: %s" % (job_dirs(out),))
        time.sleep(0.5)  # the consumer has taken P1's result
        t0 = time.monotonic()
        process.send_signal(sig)
        stdout, stderr = process.communicate(timeout=STOP_WAIT_S)
        assert time.monotonic() - t0 < 10.0
        assert process.returncode == 1, (stdout, stderr)
        assert message in stdout
        assert "Traceback" not in stderr, stderr
        assert [job_module.job_processes(d) for d in running] == [[]]
        assert [job_module.load_result(d) for d in running] == [None]  # run again on resume
        assert job_module.load_result(results[0])["challenge"] == "P1"
        if command == "robustness":
            with open(os.path.join(out, "runs.jsonl")) as f:
                assert [json.loads(line)["key"] for line in f] == ["P1_ode_track0_place0"]
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
        for d in job_dirs(out):  # what the old behaviour left running
            for pid in job_module.job_processes(d):
                os.kill(pid, signal.SIGKILL)
