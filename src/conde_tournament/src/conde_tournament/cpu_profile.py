"""Where a job's CPU time goes: user + system CPU seconds of the job's whole process tree per phase
and per node (the competition's --profile table). On a machine shared with other work the wall
time says little; CPU seconds do not depend on the load, and their sum over the jobs divided by
the cores is the lower bound of the wall time alone.

A job's processes (roslaunch, the master, every node) are read from /proc at each phase boundary
and every few seconds in between. A process's own CPU time plus the CPU time of the children it
has reaped (/proc/PID/stat utime + stime + cutime + cstime) counts each CPU second of the tree
exactly once while the process lives: roslaunch reaps the commands it runs while reading the
launch files (xacro, generate_challenge) and the nodes it started, so their time moves into
roslaunch's. The end of the job is roslaunch's own rusage (os.wait4), which holds everything it
reaped.

Phases (the boundaries are lines of roslaunch's output or moments of the job):
    parse   launch until roslaunch printed its SUMMARY (launch files read, `command=` run)
    nodes   until the simulation runs (master and nodes started, the lock-step pre-roll)
    run     until the referee decided (or the simulation's own end)
    stop    until every process is gone (the referee's plot, shut-down)

Pure parsing and arithmetic apart from the /proc reads (read_stat, read_cmdline).
"""
import os
from dataclasses import dataclass, field
from typing import Callable, Dict, Iterable, List, Optional, Tuple

PHASES = ("parse", "nodes", "run", "stop")
# roslaunch prints this once it has read every launch file, before it starts any process.
PARSED_MARK = b"SUMMARY\n========"
CLOCK_TICKS_PER_S = os.sysconf("SC_CLK_TCK")


@dataclass(frozen=True)
class ProcessCpu:
    """One process's CPU time [s]: its own and that of the children it has reaped."""
    name: str
    own_s: float
    children_s: float

    @property
    def total_s(self) -> float:
        return self.own_s + self.children_s


def parse_stat(text: str) -> Tuple[float, float]:
    """(own, reaped children) CPU seconds of a /proc/PID/stat line. The command name (field 2) is
    in parentheses and may hold spaces and parentheses itself: fields are counted after the last ')'."""
    fields = text[text.rindex(")") + 2:].split()
    # After the name: state(3) ppid(4) ... utime(14) stime(15) cutime(16) cstime(17).
    utime, stime, cutime, cstime = (int(v) for v in fields[11:15])
    return (utime + stime) / CLOCK_TICKS_PER_S, (cutime + cstime) / CLOCK_TICKS_PER_S


def process_name(argv: List[str]) -> str:
    """A readable name of a process from its command line: the ROS node name (__name:=X), else the
    script run by an interpreter, else the program (roslaunch, rosmaster, xacro, ...)."""
    for arg in argv:
        if arg.startswith("__name:="):
            return arg[len("__name:="):]
    if not argv:
        return "?"
    program = os.path.basename(argv[0])
    if program.startswith(("python", "bash", "sh")) and len(argv) > 1:
        script = next((a for a in argv[1:] if not a.startswith("-")), None)
        if script:
            return os.path.basename(script)
    return program


def read_stat(pid: int) -> Optional[Tuple[float, float]]:
    try:
        with open("/proc/%d/stat" % pid) as f:
            return parse_stat(f.read())
    except (OSError, ValueError, IndexError):
        return None  # gone meanwhile


def read_cmdline(pid: int) -> List[str]:
    try:
        with open("/proc/%d/cmdline" % pid, "rb") as f:
            return [a.decode(errors="replace") for a in f.read().split(b"\0") if a]
    except OSError:
        return []


def snapshot(pids: Iterable[int], names: Optional[Dict[int, str]] = None) -> Dict[int, ProcessCpu]:
    """{pid: ProcessCpu} of the live processes among pids; names caches each pid's name."""
    names = {} if names is None else names
    shot = {}
    for pid in pids:
        times = read_stat(pid)
        if times is None:
            continue
        if pid not in names:
            names[pid] = process_name(read_cmdline(pid))
        shot[pid] = ProcessCpu(names[pid], times[0], times[1])
    return shot


def tree_total_s(shot: Dict[int, ProcessCpu]) -> float:
    """CPU seconds the job's process tree has used so far (each second counted once)."""
    return sum(p.total_s for p in shot.values())


def per_node_s(before: Dict[int, ProcessCpu], after: Dict[int, ProcessCpu], own_only: bool = False) -> Dict[str, float]:
    """{name: CPU seconds between the two snapshots} of the processes in `after` (a process that
    started in between counts from zero); processes of the same name are added. own_only: without
    the reaped children's time (a node that ended counts once, not again in roslaunch's)."""
    def cpu(proc):
        return proc.own_s if own_only else proc.total_s

    used: Dict[str, float] = {}
    for pid, proc in after.items():
        start = before.get(pid)
        delta = cpu(proc) - (cpu(start) if start is not None and start.name == proc.name else 0.0)
        used[proc.name] = used.get(proc.name, 0.0) + max(0.0, delta)
    return used


@dataclass
class JobCpu:
    """A job's CPU accounting while it runs: mark() at each phase boundary, sample() in between,
    finish() with roslaunch's rusage at the end; result() is what goes into the job's result.json."""
    list_pids: Callable[[], List[int]]
    sample_period_s: float = 1.0
    totals_s: Dict[str, float] = field(default_factory=dict)   # tree total at each phase's end
    names: Dict[int, str] = field(default_factory=dict)
    last: Dict[int, ProcessCpu] = field(default_factory=dict)  # the latest reading of every pid seen
    at_run_start: Optional[Dict[int, ProcessCpu]] = None
    at_run_end: Optional[Dict[int, ProcessCpu]] = None
    sampled_at: float = -1e9
    last_total_s: Optional[float] = None  # the tree's total at the latest reading
    ended_before_run: set = field(default_factory=set)

    def _read(self) -> Dict[int, ProcessCpu]:
        shot = snapshot(self.list_pids(), self.names)
        self._remember(shot)
        return shot

    def _remember(self, shot: Dict[int, ProcessCpu]):
        """Keeps each pid's latest reading and the tree's total; CPU time only grows, so a smaller
        reading (a process in its exit: its times already gone, not yet reaped) is left out."""
        for pid, proc in shot.items():
            seen = self.last.get(pid)
            if seen is None or seen.name != proc.name or proc.total_s >= seen.total_s:
                self.last[pid] = proc
        if shot:
            self.last_total_s = max(self.last_total_s or 0.0, tree_total_s(shot))

    def sample(self, now: float):
        """A reading every sample_period_s (keeps the last CPU time of nodes that end before the job)."""
        if now - self.sampled_at >= self.sample_period_s:
            self.sampled_at = now
            self._read()

    def mark(self, phase: str, now: float):
        """The end of `phase` (PHASES): the tree's total now."""
        if phase in self.totals_s:
            return
        self.sampled_at = now
        shot = self._read()
        self.totals_s[phase] = tree_total_s(shot)
        if phase == "nodes":
            self.at_run_start = shot
            # what ended before the run (xacro, generate_challenge, ...) is not the run's
            self.ended_before_run = set(self.last) - set(shot)
        elif phase == "run":
            self.at_run_end = dict(self.last)  # with the last reading of nodes that ended before

    def finish(self, roslaunch_cpu_s: Optional[float]):
        """The job is over: roslaunch's rusage (everything it reaped) ends the last phase."""
        if roslaunch_cpu_s is not None:
            self.totals_s["stop"] = roslaunch_cpu_s

    def result(self, sim_s: Optional[float]) -> dict:
        """{"phases_s": {phase: CPU s}, "total_s", "sim_s", "nodes_run_s": {node: own CPU s in the run, a
        node that ended before the run did up to its last reading},
        "nodes_startup_s": {node: CPU s until the run started (roslaunch's with what it reaped)}}.
        A phase whose boundary was not seen is None (its CPU goes to the next one seen); a run that
        the simulation ended (no decision) ends at the latest reading, up to sample_period_s early."""
        totals = dict(self.totals_s)
        if "run" not in totals and "nodes" in totals and self.last_total_s is not None:
            totals["run"] = self.last_total_s  # no decision (the simulation's own end): the latest reading
        phases, previous = {}, 0.0
        for phase in PHASES:
            total = totals.get(phase)
            if total is None:
                phases[phase] = None
                continue
            total = max(total, previous)  # an orphan's time may be lost to roslaunch's rusage
            phases[phase] = round(total - previous, 2)
            previous = total
        nodes, startup = {}, {}
        if self.at_run_start is not None:
            startup = {name: round(s, 2) for name, s in sorted(per_node_s({}, self.at_run_start).items())}
            end = self.at_run_end if self.at_run_end is not None else self.last  # each process's last reading
            end = {pid: p for pid, p in end.items() if pid not in self.ended_before_run}
            used = per_node_s(self.at_run_start, end, own_only=True)
            nodes = {name: round(s, 2) for name, s in sorted(used.items())}
        return {"phases_s": phases, "total_s": round(previous, 2), "sim_s": sim_s, "nodes_run_s": nodes,
                "nodes_startup_s": startup}


def sim_seconds(report: Optional[dict]) -> Optional[float]:
    """Simulated seconds of a run from the referee's report (its path's last time), or None."""
    path = (report or {}).get("path_t_x_y") or []
    return float(path[-1][0]) if path else None


def _fmt(value, digits=1) -> str:
    return "-" if value is None else "%.*f" % (digits, value)


def profile_text(rows: List[Tuple[str, Optional[dict]]], cores: int = 2, runner_cpu_s: float = 0.0) -> str:
    """The --profile tables of [(challenge, JobCpu.result() or None)]: CPU seconds per challenge and
    phase, the run's CPU per simulated second, then each process's CPU per simulated second of the
    run; the last line: the whole competition's wall time alone, at least the CPU (the jobs' and the
    runner's own, runner_cpu_s) spread over the cores and at least the longest job (a lock-step job's
    nodes wait for each other: about one core at a time)."""
    head = "%-9s" + " %7s" * (len(PHASES) + 4) + "\n"
    out = ["CPU time [s] (user + system, the job's whole process tree)\n",
           head % (("challenge",) + PHASES + ("total", "sim [s]", "run/sim", "all/sim"))]
    sums = {p: 0.0 for p in PHASES + ("total",)}
    for name, cpu in rows:
        if not cpu:
            out.append("%-9s (not measured)\n" % name)
            continue
        phases, sim_s = cpu["phases_s"], cpu.get("sim_s")
        for p in PHASES:
            sums[p] += phases.get(p) or 0.0
        sums["total"] += cpu["total_s"]
        per_sim = (phases.get("run") or 0.0) / sim_s if sim_s else None
        all_per_sim = cpu["total_s"] / sim_s if sim_s else None
        out.append(head % ((name,) + tuple(_fmt(phases.get(p)) for p in PHASES)
                           + (_fmt(cpu["total_s"]), _fmt(sim_s), _fmt(per_sim, 2), _fmt(all_per_sim, 2))))
    out.append(head % (("total",) + tuple(_fmt(sums[p]) for p in PHASES) + (_fmt(sums["total"]), "", "", "")))
    measured = [(name, cpu) for name, cpu in rows if cpu and cpu.get("sim_s") and cpu.get("nodes_run_s")]
    if measured:
        nodes = sorted({n for _, cpu in measured for n in cpu["nodes_run_s"]},
                       key=lambda n: -sum(cpu["nodes_run_s"].get(n, 0.0) / cpu["sim_s"] for _, cpu in measured))
        out.append("\nCPU per simulated second of the run [ms/s], by process\n")
        line = "%-30s" + " %6s" * len(measured) + "\n"
        out.append(line % (("process",) + tuple(name for name, _ in measured)))
        for node in nodes:
            out.append(line % ((node,) + tuple(_fmt(1e3 * cpu["nodes_run_s"].get(node, 0.0) / cpu["sim_s"], 0)
                                               for _, cpu in measured)))
    started = [(name, cpu) for name, cpu in rows if cpu and cpu.get("nodes_startup_s")]
    if started:
        out.append("\nCPU until the run started [s], by process (parse and node start-up)\n")
        line = "%-30s" + " %6s" * len(started) + "\n"
        out.append(line % (("process",) + tuple(name for name, _ in started)))
        nodes = sorted({n for _, cpu in started for n in cpu["nodes_startup_s"]},
                       key=lambda n: -sum(cpu["nodes_startup_s"].get(n, 0.0) for _, cpu in started))
        for node in nodes:
            out.append(line % ((node,) + tuple(_fmt(cpu["nodes_startup_s"].get(node, 0.0), 2) for _, cpu in started)))
    longest = max((cpu["total_s"] for _, cpu in rows if cpu), default=0.0)
    alone_s = max((sums["total"] + runner_cpu_s) / cores, longest)
    out.append("\nwhole run alone, estimated: max((%.0f + runner %.0f) CPU s / %d cores, longest job %.0f CPU s)"
               " = %.0f s (%.1f min)\n" % (sums["total"], runner_cpu_s, cores, longest, alone_s, alone_s / 60.0))
    return "".join(out)
