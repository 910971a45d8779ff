"""One tournament job, isolated: its own ROS master on a free port, ROS_HOME and ROS_LOG_DIR in its
own folder, its own process group (roslaunch, the master and every node), ended when the run is
over or over its wall-clock limit. The simulated-time limit is the simulator's own
(~max_sim_time_s): it stops there and roslaunch ends the job.

Files of a job folder:
    job.json        what ran (team, challenge, ..., port, command) while it runs
    roslaunch.log   roslaunch's output
    challenge/      generated world and the referee's referee.{json,md,png}
    ros/log/        ROS logs
    result.json     the outcome (written last: its presence marks the job finished; resume skips it)

An interruption (STOP set, by conde_tournament.pools when its consumer stops early) ends every
running job of the process at once: its roslaunch group is stopped as at any end, no result.json is
written and run_job raises JobInterrupted, so a resumed campaign runs the job again. A job whose
referee had already written its report keeps its result (without waiting for the path plot).
"""
import json
import os
import shlex
import signal
import socket
import subprocess
import threading
import time

from conde_common.files import replaced_whole
from conde_eval import launch_log

from conde_tournament import cpu_profile
from conde_tournament.tournament_file import REFERENCE_NODES, Job, team_problem

RESULT_FILE = "result.json"
# The process whose death ends the run as the simulator's (not the team's) failure.
SIMULATOR_NODES = ("conde_sim", "roscore", "rosmaster", "master")
# The simulator's executable (/proc/PID/comm): frozen (SIGSTOP) once the referee has decided, so that
# the lock-step loop (and every node waiting on it) stops using the CPU while the referee draws its
# plot and the job is shut down; the run after the decision is not judged.
SIMULATOR_PROGRAM = "conde_sim_node"
# roslaunch's message when the master it started did not answer in time, and how often a job is
# started in all when that happens.
MASTER_START_FAILURE = "ERROR: could not contact master"
MASTER_START_ATTEMPTS = 3
# conde_eval start_when_ready's line when it unpauses the simulation: the end of the job's start-up.
RUNNING_MARK = b"every node is up; the simulation runs"
# A job whose simulation is not running this long [s of wall time] after its launch is stopped and
# started again (status "start_stalled", within MASTER_START_ATTEMPTS): seen twice in the competition,
# a simulator that stopped in the lock-step pre-roll at t = 0.01 s and never answered (cause not
# found). Start-ups measured 24-51 s on a quiet machine, up to 258 s at load 43.
STARTUP_LIMIT_S = 420.0
START_STALLED = "start_stalled"
# Set to stop every running job of this process at once (an interruption): each job's poll loop
# leaves within its 0.2 s period, its roslaunch group and leftovers are stopped as at any end, and
# run_job raises JobInterrupted instead of returning a result. Cleared by pools.run_each as it starts.
STOP = threading.Event()
# How long the job waits for the referee's path plot once its report is there [s]. The referee
# draws it in 3-5 s on this machine, more on a busy one; the job's result does not depend on it.
PLOT_WAIT_S = 60.0
# How long roslaunch lets a node end on SIGINT when it shuts the job down itself (the simulator
# stopped at limits.sim_s) before SIGTERM and SIGKILL; its default, 15 s, is shorter than the
# referee needs on a busy machine to write its report and draw the plot as it shuts down (seen: a
# tournament job's plot lost at a load of about 12 on 2 cores). A job stopped by this module is
# bounded by its own grace (_stop), not by this.
ROSLAUNCH_SIGINT_TIMEOUT_S = PLOT_WAIT_S
# How long an interrupted job's nodes get to end on SIGINT before SIGKILL: the referee's report is
# written already or the job keeps no result, so nothing is lost, and the person who pressed
# Ctrl-C is not kept waiting for a slow shutdown (a referee stopped early in a run was seen still
# working after 15 s on a loaded machine).
INTERRUPTED_GRACE_S = 3.0


class JobInterrupted(Exception):
    """A job ended by STOP: it has no result (none is written, so a resumed campaign runs it again)."""


class _LogWatch:
    """When a mark first shows up in a growing log file (read in increments, never twice)."""

    def __init__(self, path: str, mark: bytes):
        self.path, self.mark, self.offset, self.tail, self.seen_at = path, mark, 0, b"", None

    def poll(self, now: float):
        if self.seen_at is not None:
            return
        try:
            with open(self.path, "rb") as f:
                f.seek(self.offset)
                data = f.read()
        except OSError:
            return
        self.offset += len(data)
        seen = self.tail + data
        if self.mark in seen:
            self.seen_at = now
        self.tail = seen[-len(self.mark):]


def job_environment(environ, port: int, job_dir: str) -> dict:
    """The environment of a job's roslaunch (pure): its own master on 127.0.0.1:port, ROS_HOME and
    the logs in the job folder, and Python's output unbuffered, so that roslaunch.log holds each
    line as it is printed (the phase marks, e.g. roslaunch's SUMMARY, come when they happen, also
    where stdout is not a terminal)."""
    env = dict(environ, ROS_MASTER_URI="http://127.0.0.1:%d" % port, ROS_IP="127.0.0.1",
               ROS_HOME=os.path.join(job_dir, "ros"), ROS_LOG_DIR=os.path.join(job_dir, "ros", "log"),
               PYTHONUNBUFFERED="1")
    env.pop("ROS_HOSTNAME", None)
    return env


def timing(started: float, running_at, decided_at, ended: float) -> dict:
    """Where a job's wall time went [s] (pure): start-up (launch until the simulation runs), run
    (until the referee decided, or the job ended), stop (from the decision until every process is
    gone). None where a moment was not seen."""
    run_end = decided_at if decided_at is not None else ended
    return {"startup_s": None if running_at is None else round(running_at - started, 1),
            "run_s": None if running_at is None else round(run_end - running_at, 1),
            "stop_s": None if decided_at is None else round(ended - decided_at, 1)}


def free_port() -> int:
    """A TCP port on loopback that nothing listens on now (the master binds it right after)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def launch_command(job: Job, port: int, job_dir: str, sim_limit_s: float, launch_args=()):
    """The shell command of the job: the team's overlay (if any) sourced, then roslaunch (with
    ROSLAUNCH_SIGINT_TIMEOUT_S). launch_args: more team_run.launch arguments ("name:=value"), e.g.
    track_seed:=3 rviz:=true."""
    args = ["roslaunch", "-p", str(port), "--sigint-timeout=%g" % ROSLAUNCH_SIGINT_TIMEOUT_S,
            "conde_tournament", "team_run.launch",
            "challenge:=" + job.challenge, "variant:=" + job.variant, "seed:=%d" % job.seed,
            "physics_engine:=" + job.engine, "max_sim_time:=%g" % sim_limit_s,
            "output_dir:=" + os.path.join(job_dir, "challenge")]
    args += ["%s:=false" % node for node in REFERENCE_NODES if node in job.team.replaces]
    if job.team.launch:
        args.append("team_launch:=" + job.team.launch)
    if job.team.lockstep_config:
        args.append("lockstep_config:=" + job.team.lockstep_config)
    args += list(launch_args)
    command = " ".join(shlex.quote(a) for a in args)
    if job.team.overlay:
        command = "source %s && exec %s" % (shlex.quote(job.team.overlay), command)
    return ["bash", "-c", command]


def classify(report, dead, over_wall_limit: bool, roslaunch_status: int):
    """(status, reason) of a job from what is known when it ended (pure).

    report: the referee's report (dict) or None; dead: launch_log.DeadNode list (first = first to
    die). Statuses: "ok" (the referee judged the run), "team_failed" (a team or reference node
    died: scored as it ended), "wall_limit" (scored as it ended), "sim_failed" (the simulator or
    master died: not the team's fault, no score), "no_report"."""
    dead = [d for d in dead if d.exit_code != 0]  # the simulator ends with 0 at its simulated-time limit
    first_sim = next((d for d in dead if d.name in SIMULATOR_NODES), None)
    if first_sim is not None and (not dead or dead[0] is first_sim or report is None):
        return "sim_failed", first_sim.describe()
    if over_wall_limit:
        return "wall_limit", "over the wall-clock limit; stopped"
    if dead:
        return "team_failed", "; ".join(d.describe() for d in dead)
    if report is None:
        return "no_report", "the referee wrote no report (roslaunch exit status %d)" % roslaunch_status
    return "ok", "referee: %s" % report.get("end", "?")


def _default_signals():
    """In the job's roslaunch before exec: SIGINT and SIGTERM handled by default and not blocked. A
    Ray worker ignores SIGINT and its threads block signals; both survive exec, and roslaunch and
    its nodes would then not shut down on SIGINT (the referee's report would be cut short)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT, signal.SIGTERM})


def job_processes(job_dir: str):
    """Pids of the processes that run with this job's ROS_HOME: roslaunch starts each node in a
    session of its own, so the job's process group does not hold them all."""
    marker = ("ROS_HOME=" + os.path.join(job_dir, "ros")).encode()
    pids = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            with open("/proc/%s/environ" % entry, "rb") as f:
                if marker in f.read().split(b"\0"):
                    pids.append(int(entry))
        except OSError:  # gone, or not ours
            continue
    return pids


def _signal_simulator(job_dir: str, sig) -> list:
    """Sends `sig` to the job's simulator processes (SIMULATOR_PROGRAM); returns their pids."""
    pids = []
    for pid in job_processes(job_dir):
        try:
            with open("/proc/%d/comm" % pid) as f:
                if f.read().strip() != SIMULATOR_PROGRAM:
                    continue
            os.kill(pid, sig)
            pids.append(pid)
        except (OSError, ProcessLookupError):
            continue
    return pids


def _kill_leftovers(job_dir: str):
    """SIGKILL to whatever of the job outlived roslaunch (e.g. roslaunch killed before its nodes)."""
    for pid in job_processes(job_dir):
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def _reap(process):
    """process.poll() through os.wait4, which also gives the CPU time [s] of the process and of every
    child it reaped (process.cpu_s; roslaunch reaps its nodes): the job's whole process tree."""
    if process.returncode is not None:
        return process.returncode
    try:
        pid, status, usage = os.wait4(process.pid, os.WNOHANG)
    except ChildProcessError:  # reaped elsewhere: no rusage
        return process.poll()
    if pid == 0:
        return None
    process.returncode = os.waitstatus_to_exitcode(status)
    process.cpu_s = usage.ru_utime + usage.ru_stime
    return process.returncode


def _wait(process, timeout_s: float) -> bool:
    """Whether the process ended (and was reaped by _reap) within timeout_s."""
    deadline = time.monotonic() + timeout_s
    while _reap(process) is None:
        if time.monotonic() > deadline:
            return False
        time.sleep(0.1)
    return True


def _stop(process, grace_s: float):
    """SIGINT to the job's process group (the referee writes its report on shutdown), then SIGKILL."""
    for sig, wait_s in ((signal.SIGINT, grace_s), (signal.SIGKILL, 10.0)):
        try:
            os.killpg(process.pid, sig)
        except ProcessLookupError:
            return
        if _wait(process, wait_s) and sig == signal.SIGKILL:
            return
    # roslaunch may have gone while nodes of its group linger: end them too.
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


def _wait_for_file(path: str, timeout_s: float, poll_s: float = 0.05):
    """Until `path` exists (the referee writes each file whole: conde_common.files), timeout_s has
    passed, or STOP is set."""
    deadline = time.monotonic() + timeout_s
    while not os.path.exists(path) and time.monotonic() < deadline and not STOP.is_set():
        time.sleep(poll_s)


def start_stalled(now: float, started: float, running_at, limit_s: float = STARTUP_LIMIT_S) -> bool:
    """Whether a job's simulation has not started running within limit_s of its launch (pure)."""
    return running_at is None and now - started > limit_s


def master_start_failed(result: dict, log_text: str) -> bool:
    """Whether a job ended before anything ran because roslaunch could not reach the master it had
    just started (a busy machine: roslaunch gives the master a fixed time): run again, not scored."""
    return result.get("status") == "no_report" and MASTER_START_FAILURE in log_text


def run_job(job: Job, job_dir: str, sim_limit_s: float, wall_limit_s: float, launch_args=()) -> dict:
    """Runs one job into job_dir and returns its result (also written to job_dir/result.json);
    a job whose master did not come up in time, or whose simulation did not start running within
    STARTUP_LIMIT_S, is started again (up to MASTER_START_ATTEMPTS times; result "attempts").
    launch_args: more team_run.launch arguments (launch_command). JobInterrupted when STOP is set
    (no attempt is started then, and a running one is stopped): no result is written."""
    for attempt in range(1, MASTER_START_ATTEMPTS + 1):
        if STOP.is_set():
            raise JobInterrupted(job.job_id)
        result = _run_job_once(job, job_dir, sim_limit_s, wall_limit_s, launch_args)
        try:
            with open(os.path.join(job_dir, "roslaunch.log"), errors="replace") as f:
                log_text = f.read()
        except OSError:
            log_text = ""
        again = master_start_failed(result, log_text) or result.get("status") == START_STALLED
        if not again or attempt == MASTER_START_ATTEMPTS:
            break
        os.replace(os.path.join(job_dir, "roslaunch.log"), os.path.join(job_dir, "roslaunch.attempt%d.log" % attempt))
    result["attempts"] = attempt
    return _write_result(job_dir, result)


def _run_job_once(job: Job, job_dir: str, sim_limit_s: float, wall_limit_s: float, launch_args=()) -> dict:
    os.makedirs(job_dir, exist_ok=True)
    result = {"job_id": job.job_id, "team": job.team.name, "challenge": job.challenge, "variant": job.variant,
              "seed": job.seed, "engine": job.engine, "repeat": job.repeat, "host": socket.gethostname()}
    problem = team_problem(job.team)
    started = time.monotonic()
    if problem:
        return failed_result(job, job_dir, problem, status="team_failed")
    port = free_port()
    env = job_environment(os.environ, port, job_dir)
    command = launch_command(job, port, job_dir, sim_limit_s, launch_args)
    with open(os.path.join(job_dir, "job.json"), "w") as f:
        json.dump(dict(result, port=port, command=command), f, indent=1)
    report_path = os.path.join(job_dir, "challenge", "referee.json")
    plot_path = report_path[:-len(".json")] + ".png"
    for old in (report_path, plot_path):  # a report of an interrupted earlier attempt
        if os.path.exists(old):
            os.remove(old)
    log_path = os.path.join(job_dir, "roslaunch.log")
    over_wall_limit = False
    log_bytes = None  # what roslaunch wrote before the job was stopped (then nodes die on purpose)
    running, decided_at, frozen = _LogWatch(log_path, RUNNING_MARK), None, []
    parsed = _LogWatch(log_path, cpu_profile.PARSED_MARK)
    cpu = cpu_profile.JobCpu(lambda: job_processes(job_dir))
    stalled = False  # the simulation did not start running within STARTUP_LIMIT_S
    interrupted = False  # STOP was set while the job ran
    with open(log_path, "w") as log:
        process = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, env=env, cwd=job_dir,
                                   start_new_session=True, preexec_fn=_default_signals)
        try:
            while _reap(process) is None:
                now = time.monotonic()
                for watch, phase in ((parsed, "parse"), (running, "nodes")):
                    watch.poll(now)
                    if watch.seen_at is not None:
                        cpu.mark(phase, now)
                cpu.sample(now)
                if os.path.exists(report_path):
                    decided_at = time.monotonic()
                    frozen = _signal_simulator(job_dir, signal.SIGSTOP)
                    cpu.mark("run", decided_at)
                    # The referee ended the run (end of trial, parked, disqualified, time limit);
                    # its path plot is written last. Interrupted (STOP) from here on, the job keeps
                    # its result without waiting for the plot (_wait_for_file returns at once).
                    _wait_for_file(plot_path, timeout_s=PLOT_WAIT_S)
                    break
                if STOP.is_set():
                    interrupted = True
                    break
                if time.monotonic() - started > wall_limit_s:
                    over_wall_limit = True
                    break
                if start_stalled(time.monotonic(), started, running.seen_at):
                    stalled = True
                    break
                time.sleep(0.2)
        finally:
            log.flush()
            log_bytes = os.path.getsize(log_path) if _reap(process) is None else None
            for pid in frozen:  # a stopped process would not act on SIGINT
                try:
                    os.kill(pid, signal.SIGCONT)
                except ProcessLookupError:
                    pass
            _stop(process, grace_s=INTERRUPTED_GRACE_S if STOP.is_set() else 15.0)
            _kill_leftovers(job_dir)
            cpu.finish(getattr(process, "cpu_s", None))
    if interrupted:
        raise JobInterrupted(job.job_id)
    with open(log_path, "rb") as f:
        dead = launch_log.dead_nodes(f.read(log_bytes if log_bytes is not None else -1).decode(errors="replace"))
    report = None
    if os.path.exists(report_path):
        with open(report_path) as f:
            report = json.load(f)
    status, reason = classify(report, dead, over_wall_limit, process.returncode)
    if stalled:  # the referee's report at the shutdown judges no run
        report, status = None, START_STALLED
        reason = "the simulation did not start running within %.0f s of wall time; stopped" % STARTUP_LIMIT_S
    ended = time.monotonic()
    if decided_at is None and report is not None:
        decided_at = ended  # the report came with roslaunch's own end (the simulator's time limit)
    result.update(status=status, reason=reason, report=report, wall_s=round(ended - started, 1), port=port,
                  timing=timing(started, running.seen_at, decided_at, ended),
                  cpu=cpu.result(cpu_profile.sim_seconds(report)))
    return result  # run_job writes it once no attempt is left


def failed_result(job: Job, job_dir: str, reason: str, status: str = "sim_failed") -> dict:
    """The result of a job that did not run (written to job_dir/result.json)."""
    os.makedirs(job_dir, exist_ok=True)
    return _write_result(job_dir, {"job_id": job.job_id, "team": job.team.name, "challenge": job.challenge,
                                   "variant": job.variant, "seed": job.seed, "engine": job.engine,
                                   "repeat": job.repeat, "host": socket.gethostname(), "status": status,
                                   "reason": reason, "report": None, "wall_s": 0.0})


def _write_result(job_dir: str, result: dict) -> dict:
    with replaced_whole(os.path.join(job_dir, RESULT_FILE)) as tmp:
        with open(tmp, "w") as f:
            json.dump(result, f, indent=1, sort_keys=True)
    return result


def load_result(job_dir: str):
    """The result of a finished job, or None (not run, or interrupted)."""
    try:
        with open(os.path.join(job_dir, RESULT_FILE)) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None
