"""How a job's end is classified, and the command a job runs (no ROS run here)."""
from conde_eval.launch_log import DeadNode

from conde_tournament.job import classify, launch_command
from conde_tournament.tournament_file import Job, Team

REPORT = {"end": "stopped", "score": 0.0}


def test_a_judged_run_is_ok():
    assert classify(REPORT, [], False, 0) == ("ok", "referee: stopped")


def test_the_simulator_stopping_at_its_time_limit_is_no_failure():
    assert classify(REPORT, [DeadNode("conde_sim", 10, 0)], False, 0)[0] == "ok"


def test_a_killed_simulator_is_not_the_teams_fault():
    status, reason = classify(REPORT, [DeadNode("conde_sim", 10, -9)], False, 0)
    assert status == "sim_failed" and reason == "conde_sim (pid 10) died: killed by SIGKILL"


def test_a_team_node_that_dies_is_scored_as_it_ended():
    dead = [DeadNode("conde_control", 11, 1), DeadNode("conde_sim", 10, 0)]
    assert classify(REPORT, dead, False, 0) == ("team_failed", "conde_control (pid 11) died: exit status 1")
    # The simulator going down after the team's node (roslaunch ends the run) stays the team's failure.
    assert classify(REPORT, [DeadNode("conde_control", 11, 1), DeadNode("conde_sim", 10, -15)], False, 0)[0] \
        == "team_failed"


def test_wall_limit_and_missing_report():
    assert classify(REPORT, [], True, 0)[0] == "wall_limit"
    assert classify(None, [], False, 3) == ("no_report", "the referee wrote no report (roslaunch exit status 3)")


def test_launch_command_switches_off_what_the_team_replaces():
    team = Team("a", launch="/t/a.launch", replaces=("control", "tracking"))
    command = launch_command(Job(team, "D1", "v1", 4, "bullet", 0), 12345, "/out/job", 30.0)
    assert command[:2] == ["bash", "-c"]
    text = command[2]
    assert text.startswith("roslaunch -p 12345 --sigint-timeout=60 conde_tournament team_run.launch challenge:=D1 "
                           "variant:=v1 seed:=4 ")
    for arg in ("physics_engine:=bullet", "max_sim_time:=30", "output_dir:=/out/job/challenge", "tracking:=false",
                "control:=false", "team_launch:=/t/a.launch"):
        assert " " + arg in text
    assert "decision:=false" not in text and "semaphore:=false" not in text


def test_an_overlay_is_sourced_first():
    team = Team("b", overlay="/ws b/devel/setup.bash")
    text = launch_command(Job(team, "D1", "v1", 0, "ode", 0), 1, "/o", 0.0)[2]
    assert text.startswith("source '/ws b/devel/setup.bash' && exec roslaunch ")


def test_timing_splits_the_wall_time():
    from conde_tournament.job import timing
    assert timing(100.0, 112.0, 180.5, 186.0) == {"startup_s": 12.0, "run_s": 68.5, "stop_s": 5.5}
    # never running (start-up failed): no run; no decision: the run lasts until the job ended
    assert timing(100.0, None, None, 130.0) == {"startup_s": None, "run_s": None, "stop_s": None}
    assert timing(100.0, 110.0, None, 130.0) == {"startup_s": 10.0, "run_s": 20.0, "stop_s": None}


def test_the_log_watch_sees_a_mark_split_across_reads(tmp_path):
    from conde_tournament.job import RUNNING_MARK, _LogWatch
    path = tmp_path / "roslaunch.log"
    watch = _LogWatch(str(path), RUNNING_MARK)
    watch.poll(1.0)  # no file yet
    path.write_bytes(b"[INFO] start_when_ready: every node is ")
    watch.poll(2.0)
    assert watch.seen_at is None
    with open(path, "ab") as f:
        f.write(b"up; the simulation runs\n")
    watch.poll(3.0)
    watch.poll(4.0)
    assert watch.seen_at == 3.0


def test_only_the_jobs_simulator_is_frozen(tmp_path):
    """A stand-in process named like the simulator, one in another job and another program of the
    job: only the first gets the signal."""
    import os
    import shutil
    import signal
    import subprocess
    import time
    from conde_tournament.job import SIMULATOR_PROGRAM, _signal_simulator
    program = tmp_path / SIMULATOR_PROGRAM
    shutil.copy("/bin/sleep", program)
    job_dir, other_dir = str(tmp_path / "job"), str(tmp_path / "other")

    def start(path, folder):
        return subprocess.Popen([str(path), "60"], env=dict(os.environ, ROS_HOME=os.path.join(folder, "ros")))
    sim, other_sim, node = start(program, job_dir), start(program, other_dir), start("/bin/sleep", job_dir)

    def state(p):
        with open("/proc/%d/stat" % p.pid) as f:
            return f.read().rsplit(")", 1)[1].split()[0]

    def wait_for(condition):
        deadline = time.monotonic() + 10.0
        while not condition() and time.monotonic() < deadline:
            time.sleep(0.02)

    def comm(p):
        with open("/proc/%d/comm" % p.pid) as f:
            return f.read().strip()
    try:
        wait_for(lambda: comm(sim) == comm(other_sim) == SIMULATOR_PROGRAM and comm(node) == "sleep")  # exec done
        assert _signal_simulator(job_dir, signal.SIGSTOP) == [sim.pid]
        wait_for(lambda: state(sim) == "T")
        # the others are not stopped (sleeping, or still running right after their start)
        assert state(sim) == "T" and state(other_sim) != "T" and state(node) != "T"
        assert _signal_simulator(job_dir, signal.SIGCONT) == [sim.pid]
    finally:
        for p in (sim, other_sim, node):
            p.kill()
            p.wait()


def test_a_master_that_did_not_come_up_in_time_is_started_again():
    from conde_tournament.job import master_start_failed
    log = "RLException: ERROR: could not contact master [http://127.0.0.1:59559/]\n"
    assert master_start_failed({"status": "no_report"}, log)
    assert not master_start_failed({"status": "no_report"}, "conde_sim died\n")
    assert not master_start_failed({"status": "ok"}, log)  # judged: never run twice


def test_a_simulation_that_does_not_start_running_in_time_has_stalled():
    from conde_tournament.job import STARTUP_LIMIT_S, start_stalled
    assert not start_stalled(100.0 + STARTUP_LIMIT_S - 1, 100.0, None)
    assert start_stalled(100.0 + STARTUP_LIMIT_S + 1, 100.0, None)
    assert not start_stalled(100.0 + STARTUP_LIMIT_S + 1, 100.0, 150.0)  # it ran: the wall limit decides


def test_run_job_tries_again_after_a_stalled_start(tmp_path, monkeypatch):
    from conde_tournament import job as job_module
    outcomes = [job_module.START_STALLED, "ok"]

    def once(job, job_dir, sim_limit_s, wall_limit_s, launch_args=()):
        status = outcomes.pop(0)
        with open(job_dir + "/roslaunch.log", "w") as f:
            f.write("ran\n")
        return {"status": status, "report": None if status == job_module.START_STALLED else REPORT}
    monkeypatch.setattr(job_module, "_run_job_once", once)
    result = job_module.run_job(Job(Team("a"), "D1", "", 0, "ode", 0), str(tmp_path), 0.0, 600.0)
    assert (result["status"], result["attempts"]) == ("ok", 2)
    assert "roslaunch.attempt1.log" in [p.name for p in tmp_path.iterdir()]


def test_run_job_tries_again_after_a_master_start_failure(tmp_path, monkeypatch):
    """The attempts of run_job with a stand-in for one launch: the master fails twice, then the run is judged."""
    from conde_tournament import job as job_module
    outcomes = ["no_report", "no_report", "ok"]

    def once(job, job_dir, sim_limit_s, wall_limit_s, launch_args=()):
        status = outcomes.pop(0)
        with open(job_dir + "/roslaunch.log", "w") as f:
            f.write("RLException: ERROR: could not contact master [x]\n" if status == "no_report" else "ran\n")
        return {"status": status, "report": None if status == "no_report" else REPORT}
    monkeypatch.setattr(job_module, "_run_job_once", once)
    result = job_module.run_job(Job(Team("a"), "D1", "", 0, "ode", 0), str(tmp_path), 0.0, 60.0)
    assert (result["status"], result["attempts"]) == ("ok", 3)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["result.json", "roslaunch.attempt1.log",
                                                          "roslaunch.attempt2.log", "roslaunch.log"]
    outcomes[:] = ["no_report"] * 3
    assert job_module.run_job(Job(Team("a"), "D1", "", 0, "ode", 0), str(tmp_path), 0.0, 60.0)["attempts"] == 3


def test_job_environment_points_at_its_own_master_and_folder_with_unbuffered_python():
    """A job's roslaunch talks to its own master, keeps ROS_HOME and the logs in the job folder,
    drops ROS_HOSTNAME (127.0.0.1 is the job's address) and gets unbuffered Python output: without
    it, where stdout is a file, roslaunch's SUMMARY reached roslaunch.log only after the nodes' lines
    (the CPU profile's parse phase was then never seen)."""
    from conde_tournament.job import job_environment
    env = job_environment({"ROS_HOSTNAME": "somehost", "PATH": "/usr/bin", "PYTHONUNBUFFERED": ""}, 11411, "/tmp/job")
    assert env["ROS_MASTER_URI"] == "http://127.0.0.1:11411" and env["ROS_IP"] == "127.0.0.1"
    assert env["ROS_HOME"] == "/tmp/job/ros" and env["ROS_LOG_DIR"] == "/tmp/job/ros/log"
    assert env["PYTHONUNBUFFERED"] == "1" and env["PATH"] == "/usr/bin" and "ROS_HOSTNAME" not in env
