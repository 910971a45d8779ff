"""conde_tournament end to end: a small tournament (fixtures/tournament/two_teams.yaml: the reference
Conde stack, a weak team whose control drives straight, a team whose launch file does not exist;
D1 with two seeds, ODE, 15 s of simulated time) run on this machine and on a two-node Ray cluster
that the test starts on loopback; the same leaderboard both times, the weak team below the
reference, the missing team's jobs failed with the reason and nobody else's. A job whose simulator
is killed (SIGKILL) is reported with that reason while the other job finishes. A Ray run stopped
by SIGTERM stops its jobs on the cluster (no node left running). A malformed
tournament file stops the run with an error naming the file and the key.
About 5 minutes on a busy 2-core machine (the Ray part needs scripts/install_dependencies.sh
tournament: Ray in its virtualenv; the test says so and fails without it)."""
import csv
import glob
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time

import pytest

from conde_testing.ros_harness import WORKSPACE, free_port, wait_until, workspace_env
from conde_tournament.job import job_processes

FIXTURES = os.path.join(WORKSPACE, "tests", "fixtures", "tournament")
TIMEOUT_S = 900


def run_tournament(env, tournament, out_dir, *extra):
    return subprocess.run(["rosrun", "conde_tournament", "run", os.path.join(FIXTURES, tournament), "--output",
                           str(out_dir), "--no-progress", *extra],
                          env=env, capture_output=True, text=True, timeout=TIMEOUT_S)


def standings(out_dir):
    """[(rank, team, score, penalties, runs, without score)] of leaderboard.md."""
    rows = []
    with open(os.path.join(out_dir, "leaderboard.md")) as f:
        for line in f:
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) == 6 and cells[0].isdigit():
                rows.append((int(cells[0]), cells[1], float(cells[2]), float(cells[3]), int(cells[4]), int(cells[5])))
            if line.startswith("## Runs"):
                break
    return rows


def runs(out_dir):
    """{job_id: csv row} of leaderboard.csv."""
    with open(os.path.join(out_dir, "leaderboard.csv")) as f:
        return {row["job_id"]: row for row in csv.DictReader(f)}


@pytest.fixture(scope="module")
def env():
    return workspace_env("conde_tournament")


@pytest.fixture(scope="module")
def local_run(env, tmp_path_factory):
    out_dir = tmp_path_factory.mktemp("local")
    run = run_tournament(env, "two_teams.yaml", out_dir, "--jobs", "2")
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-4000:]
    return out_dir


def test_local_leaderboard(local_run):
    table = standings(local_run)
    assert [team for _, team, *_ in table] == ["reference", "straight", "ghost"], table
    reference, straight, ghost = table
    assert reference[5] == 0 and straight[5] == 0, table  # every run of both teams judged
    assert straight[3] > reference[3], "the straight driver leaves the road: %s" % table
    assert ghost[4] == 2 and ghost[5] == 2, table
    for job_id, row in runs(local_run).items():
        if job_id.startswith("ghost"):
            assert row["status"] == "team_failed" and "launch file" in row["reason"] \
                and "does not exist" in row["reason"], row
        else:
            assert row["status"] == "ok", row
            folder = os.path.join(local_run, "jobs", job_id, "challenge")
            for name in ("referee.json", "referee.md", "referee.png"):
                assert os.path.isfile(os.path.join(folder, name)), (job_id, name)
    page = open(os.path.join(local_run, "index.html")).read()
    assert 'href="jobs/reference__D1_v1_seed0__ode__r0/challenge/referee.png"' in page
    assert "<script>" in page and "sortable" in page


def test_resume_keeps_finished_jobs(env, local_run):
    run = run_tournament(env, "two_teams.yaml", local_run)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    assert "6 kept from an earlier run, 0 to run" in run.stdout, run.stdout


class RayCluster:
    """A head node and a second node on loopback, one CPU each, small object stores; the processes
    of each `ray start --block` in their own process group, ended at close()."""

    def __init__(self, env, temp_dir):
        self.ray = os.path.join(os.path.dirname(self.python()), "ray")
        # A cluster of this test only, on loopback: no token (a ~/.ray/auth_token left by another Ray
        # session would switch token authentication on for the head but not for the second node).
        self.env = dict(env, RAY_USAGE_STATS_ENABLED="0", RAY_AUTH_MODE="disabled")
        self.port = free_port()  # ephemeral range: outside Ray's worker ports (10002-19999)
        self.address = "127.0.0.1:%d" % self.port
        common = ["--block", "--node-ip-address=127.0.0.1", "--num-cpus=1", "--object-store-memory=100000000",
                  "--disable-usage-stats"]
        self.log = open(os.path.join(temp_dir, "ray.log"), "w")
        self.processes = []
        # Ray's sockets live under its temp dir: keep the path short (AF_UNIX paths < 108 bytes).
        self.temp_dir = tempfile.mkdtemp(prefix="ray", dir="/tmp")
        self._start(["start", "--head", "--port=%d" % self.port, "--include-dashboard=false",
                     "--temp-dir=" + self.temp_dir] + common)
        self._start(["start", "--address=" + self.address] + common)
        try:
            wait_until(lambda: self.nodes() == 2, "two Ray nodes", timeout_s=120, poll_s=2.0)
        except AssertionError:
            self.close()
            raise AssertionError("no two Ray nodes: " + open(self.log.name).read()[-3000:])

    @staticmethod
    def python():
        return subprocess.run(["/usr/bin/python3", "-c", "from conde_tournament.pools import ray_venv_python; "
                               "print(ray_venv_python())"], capture_output=True, text=True,
                              env=workspace_env("conde_tournament"), check=True).stdout.strip()

    def _start(self, args):
        self.processes.append(subprocess.Popen([self.ray] + args, env=self.env, stdout=self.log,
                                               stderr=subprocess.STDOUT, start_new_session=True))
        if len(self.processes) == 1:  # the second node needs the head's GCS
            try:
                wait_until(lambda: "Ray runtime started" in open(self.log.name).read(), "the Ray head",
                           timeout_s=120, poll_s=1.0)
            except AssertionError:
                self.close()
                raise AssertionError("the Ray head did not start: " + open(self.log.name).read()[-3000:])

    def nodes(self):
        out = subprocess.run([self.ray, "status", "--address", self.address], env=self.env, capture_output=True,
                             text=True).stdout
        return out.split("Active:")[-1].split("Pending:")[0].count("node_") if "Active:" in out else 0

    def close(self):
        for process in reversed(self.processes):
            for sig, wait_s in ((signal.SIGTERM, 30), (signal.SIGKILL, 10)):
                try:
                    os.killpg(process.pid, sig)
                    process.wait(timeout=wait_s)
                    break
                except ProcessLookupError:
                    break
                except subprocess.TimeoutExpired:
                    continue
            try:  # what the node started and outlived its `ray start`
                os.killpg(process.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        self.log.close()
        shutil.rmtree(self.temp_dir, ignore_errors=True)


def test_ray_run_gives_the_same_leaderboard(env, local_run, tmp_path):
    if not os.access(RayCluster.python(), os.X_OK):
        pytest.fail("no Ray virtualenv at %s: run scripts/install_dependencies.sh tournament" % RayCluster.python())
    cluster = RayCluster(env, str(tmp_path))
    try:
        out_dir = tmp_path / "ray"
        run = run_tournament(cluster.env, "two_teams.yaml", out_dir, "--ray", cluster.address)
    finally:
        cluster.close()
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-4000:]
    assert standings(out_dir) == standings(local_run)
    local, ray = runs(local_run), runs(out_dir)
    assert sorted(ray) == sorted(local)
    for job_id in local:
        for column in ("rank", "score", "penalties", "end", "status"):
            assert ray[job_id][column] == local[job_id][column], (job_id, column, ray[job_id], local[job_id])
    # The jobs ran on the cluster's two nodes (one CPU each): their files came back.
    for job_id in ray:
        if not job_id.startswith("ghost"):
            assert os.path.isfile(os.path.join(out_dir, "jobs", job_id, "challenge", "referee.png")), job_id


def alive(pid):
    """Whether the process runs (a zombie does not)."""
    try:
        with open("/proc/%d/stat" % pid) as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def test_interrupted_ray_run_stops_its_jobs_on_the_cluster(env, tmp_path):
    """SIGTERM to a Ray run while both jobs run on the cluster: the driver cancels the tasks, each
    task stops its job's roslaunch group, and no node of the jobs is left running on the nodes (they
    run in sessions of their own, which a killed Ray worker would leave behind)."""
    if not os.access(RayCluster.python(), os.X_OK):
        pytest.fail("no Ray virtualenv at %s: run scripts/install_dependencies.sh tournament" % RayCluster.python())
    tournament = tmp_path / "long.yaml"
    tournament.write_text("name: interrupted\nteams: [{name: reference}]\nchallenges: [{name: D1, seeds: [0, 1]}]\n"
                          "limits: {sim_s: 0, wall_s: 600}\n")
    cluster = RayCluster(env, str(tmp_path))
    log_path = tmp_path / "run.log"
    process = None
    try:
        with open(log_path, "w") as log:
            process = subprocess.Popen(["rosrun", "conde_tournament", "run", str(tournament), "--output",
                                        str(tmp_path / "out"), "--no-progress", "--ray", cluster.address],
                                       env=cluster.env, stdout=log, stderr=subprocess.STDOUT, text=True)
        job_ids = ["reference__D1_v1_seed%d__ode__r0" % seed for seed in (0, 1)]

        def job_dirs():  # each task runs its job in a temporary folder of its node
            return [d for job_id in job_ids for d in glob.glob("/tmp/conde_tournament_*/" + job_id)]

        def both_simulators_up():
            if process.poll() is not None:
                raise AssertionError("the run ended (exit %s):\n%s"
                                     % (process.returncode, log_path.read_text()[-4000:]))
            dirs = job_dirs()
            return len(dirs) == 2 and all(simulator_of(d) is not None for d in dirs)

        wait_until(both_simulators_up, "both jobs' simulators on the cluster", timeout_s=400, poll_s=0.5)
        pids = [pid for d in job_dirs() for pid in job_processes(d)]
        assert len(pids) >= 8, pids  # master, simulator, the stack's nodes, of two jobs
        process.send_signal(signal.SIGTERM)
        process.wait(timeout=180)
        out = log_path.read_text()
        assert process.returncode == 1, out[-4000:]
        assert "conde_tournament: interrupted; 0 of 2 jobs have a result" in out, out[-4000:]
        left = [pid for pid in pids if alive(pid)]
        assert left == [], "processes of the interrupted jobs still run: %s" % left
        assert job_dirs() == []  # the tasks removed their folders
    finally:
        if process is not None and process.poll() is None:
            process.kill()
        cluster.close()


def simulator_of(job_dir):
    """The pid of the job's conde_sim node, or None."""
    for pid in job_processes(str(job_dir)):
        try:
            with open("/proc/%d/cmdline" % pid, "rb") as f:
                if b"conde_sim_node" in f.read():
                    return pid
        except OSError:
            continue
    return None


def test_killed_simulator_fails_only_its_job(env, tmp_path):
    out_dir = tmp_path / "kill"
    # The run's output goes to a file, not a pipe: a pipe nobody reads while the test waits would stop the
    # run once its buffer is full.
    log_path = tmp_path / "run.log"
    with open(log_path, "w") as log:
        process = subprocess.Popen(["rosrun", "conde_tournament", "run", os.path.join(FIXTURES, "kill.yaml"),
                                    "--output", str(out_dir), "--no-progress", "--jobs", "2"],
                                   env=env, stdout=log, stderr=subprocess.STDOUT, text=True)
    victim = os.path.join(out_dir, "jobs", "reference__D1_v1_seed1__ode__r0")
    try:
        found = []

        def simulator_up():
            found.append(simulator_of(victim))
            if found[-1] is None and process.poll() is not None:  # the run ended without it: say how
                raise AssertionError("the tournament ended (exit %s) before the job's simulator was seen:\n%s"
                                     % (process.returncode, log_path.read_text()[-4000:]))
            return found[-1] is not None

        # Wall-clock bound for a slow, busy machine (one CI run took more than 120 s here).
        wait_until(simulator_up, "the job's simulator", timeout_s=300, poll_s=0.2)
        time.sleep(3.0)  # into the run
        os.kill(found[-1], signal.SIGKILL)
        process.wait(timeout=TIMEOUT_S)
    finally:
        if process.poll() is None:
            process.kill()
    out = log_path.read_text()
    assert process.returncode == 0, out[-4000:]
    with open(os.path.join(victim, "result.json")) as f:
        killed = json.load(f)
    assert killed["status"] == "sim_failed", killed
    assert "conde_sim" in killed["reason"] and "SIGKILL" in killed["reason"], killed["reason"]
    with open(os.path.join(out_dir, "jobs", "reference__D1_v1_seed0__ode__r0", "result.json")) as f:
        other = json.load(f)
    assert other["status"] == "ok" and other["report"]["end"] == "stopped", other
    assert standings(out_dir) == [(1, "reference", other["report"]["score"], other["report"]["penalty_total"], 2, 1)]


def test_malformed_tournament_file_is_named(env, tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("teams: [{name: a}]\nchallenges: [{name: D1}]\nengine: [ode]\n")
    run = subprocess.run(["rosrun", "conde_tournament", "run", str(bad), "--output", str(tmp_path / "out")], env=env,
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2, run.stdout + run.stderr
    assert "%s: unknown key 'engine'" % bad in run.stderr, run.stderr
    assert not (tmp_path / "out").exists()
