"""The robustness benchmark of the reference Conde stack (rosrun conde_tournament robustness): every
chosen challenge on every chosen engine over track seeds x placement seeds, each run a tournament
job scored by the referee. Pure Python, no ROS: the options, the runs of a campaign, the results
file (one JSON line per finished run, appended, so an interrupted campaign resumes where it
stopped), the table per challenge and engine and the Markdown report. The runner is
robustness_run.py.

    rosrun conde_tournament robustness --challenges D1,P1 --engines ode,bullet --track-seeds 20 \\
        --placement-seeds 20 [--paired] [--jobs 2] [--out results/robustness] [--robot major_alvega]

Seeds: a count N means seeds 1..N (varied tracks / placements), 0 the nominal one only; a list
such as 0,3,5 or a range 1-20 names them. By default every track seed is run with every placement
seed; --paired runs track seed i with placement seed i (the lists must then be equally long).
--robot major_alvega drives the stack with Major Alvega (default challenges: its own, D1 and D2).
"""
import argparse
import collections
import json
import os
import subprocess
from dataclasses import asdict, dataclass
from typing import Dict, Iterable, List, Optional, Tuple

from conde_tournament.competition import (CHALLENGES, ENGINES, ROBOT_CHALLENGES, ROBOT_NAMES, OptionError,
                                          jobs_count, outcome, positive_seconds)
from conde_tournament.leaderboard import scored

RESULTS_FILE = "runs.jsonl"
REPORT_FILE = "robustness.md"
#: the stack version where none can be told: outside a git checkout, without git, a record or job
#: folder from before versions were noted
UNKNOWN_STACK = "unknown"
#: in a run's job folder: the stack version that runs it, written before the job starts, so that a job
#: recorded only on resume (it finished as the campaign was interrupted) keeps the version that drove it
JOB_STACK_FILE = "stack.txt"
TABLE_COLUMNS = ("challenge", "engine", "runs", "passed", "success [%]", "no penalty", "no penalty [%]",
                 "mean penalties", "mean time [s]", "not judged")


@dataclass(frozen=True)
class Run:
    """One run of a campaign; its key names it in the results file and its job folder."""
    challenge: str
    engine: str
    track_seed: int
    placement_seed: int
    robot: str = "conde"  # team_run.launch robot:=

    @property
    def key(self) -> str:
        """e.g. D2_ode_track6_place6; another robot than Conde leads: major_alvega_D2_ode_track6_place6."""
        key = "%s_%s_track%d_place%d" % (self.challenge, self.engine, self.track_seed, self.placement_seed)
        return key if self.robot == "conde" else self.robot + "_" + key


@dataclass(frozen=True)
class Options:
    challenges: Tuple[str, ...]
    engines: Tuple[str, ...]
    track_seeds: Tuple[int, ...]
    placement_seeds: Tuple[int, ...]
    paired: bool = False
    jobs: int = 1
    out_dir: str = "results/robustness"
    wall_limit_s: float = 900.0
    robot: str = "conde"
    report_only: bool = False  # --report: the table and report of what OUT/runs.jsonl holds, no run

    def runs(self) -> List[Run]:
        """Every run of the campaign in a stable order: seed pair by seed pair, each over every
        challenge and engine, so that a campaign stopped part-way has runs of every group."""
        if self.paired:
            seeds = list(zip(self.track_seeds, self.placement_seeds))
        else:
            seeds = [(t, p) for t in self.track_seeds for p in self.placement_seeds]
        return [Run(c, e, t, p, self.robot) for t, p in seeds for c in self.challenges for e in self.engines]


def parse_seeds(text: str, option: str) -> Tuple[int, ...]:
    """A count N (seeds 1..N; 0 = only the nominal seed 0), or a comma-separated list of seeds and
    ranges A-B. OptionError names the option."""
    bad = OptionError("%s: expected a count N (seeds 1..N), 0, or a list such as 0,3,7-9, got %r" % (option, text))
    text = text.strip()
    if text.isdigit():
        count = int(text)
        return (0,) if count == 0 else tuple(range(1, count + 1))
    seeds = []
    for part in text.split(","):
        lo, dash, hi = part.strip().partition("-")
        if not lo.isdigit() or (dash and not hi.isdigit()):
            raise bad
        first, last = int(lo), int(hi) if dash else int(lo)
        if last < first:
            raise bad
        seeds += [s for s in range(first, last + 1) if s not in seeds]
    return tuple(seeds)


def _names(text: str, option: str, allowed: Tuple[str, ...], upper: bool) -> Tuple[str, ...]:
    names = []
    for name in text.split(","):
        name = name.strip().upper() if upper else name.strip().lower()
        if name not in allowed:
            raise OptionError("%s: unknown %r (expected %s)" % (option, name, ", ".join(allowed)))
        if name not in names:
            names.append(name)
    return tuple(n for n in allowed if n in names)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="rosrun conde_tournament robustness",
        description="Robustness benchmark of the Conde stack: challenges x engines x track seeds x placement "
        "seeds, each run scored by the referee; resumable; writes a table and a Markdown report.")
    parser.add_argument("--challenges", default=None,
                        help="comma-separated (default: all; with --robot major_alvega: D1,D2)")
    parser.add_argument("--engines", default=",".join(ENGINES), help="comma-separated (default: ode,bullet)")
    parser.add_argument("--track-seeds", default="20", metavar="N|LIST",
                        help="count N = seeds 1..N, 0 = the nominal track only, or a list 0,3,7-9 (default 20)")
    parser.add_argument("--placement-seeds", default="20", metavar="N|LIST",
                        help="as --track-seeds, for the start pose within the start area (default 20)")
    parser.add_argument("--paired", action="store_true",
                        help="run track seed i with placement seed i instead of every combination")
    parser.add_argument("--jobs", default="1", metavar="N", help="runs at a time (default 1)")
    parser.add_argument("--out", default="results/robustness", metavar="DIR",
                        help="results, job folders and the report (default results/robustness); an existing "
                        "campaign there is resumed")
    parser.add_argument("--wall-limit", default="900", metavar="S", help="wall-clock limit of one run [s]")
    parser.add_argument("--robot", default="conde",
                        help="the robot driving the stack: conde (default) or major_alvega")
    parser.add_argument("--report", action="store_true",
                        help="run nothing: print the table of the runs recorded in OUT and write OUT's report "
                        "(the campaign's other options name the runs it counts)")
    return parser


def parse_options(argv) -> Options:
    args = _parser().parse_args(argv)
    if args.robot not in ROBOT_CHALLENGES:
        raise OptionError("--robot: unknown robot %r (expected %s)" % (args.robot, " or ".join(ROBOT_CHALLENGES)))
    challenges = (_names(args.challenges, "--challenges", CHALLENGES, upper=True) if args.challenges is not None
                  else ROBOT_CHALLENGES[args.robot])
    engines = _names(args.engines, "--engines", ENGINES, upper=False)
    tracks = parse_seeds(args.track_seeds, "--track-seeds")
    placements = parse_seeds(args.placement_seeds, "--placement-seeds")
    if args.paired and len(tracks) != len(placements):
        raise OptionError("--paired: %d track seeds and %d placement seeds (expected as many of each)"
                          % (len(tracks), len(placements)))
    jobs = jobs_count(args.jobs)
    wall_limit_s = positive_seconds(args.wall_limit, "--wall-limit")
    return Options(challenges, engines, tracks, placements, args.paired, jobs, args.out, wall_limit_s, args.robot,
                   args.report)


# --- results ---------------------------------------------------------------------------------------

#: the workspace's folders whose files make the stack a campaign runs (docs, scripts, docker do not)
STACK_PATHS = ("src", "launch", "urdf", "worlds", "CMakeLists.txt")


def stack_version(path: str) -> str:
    """The version of the stack a campaign runs, for its records: the last commit that changed the
    stack's folders (STACK_PATHS) in the git checkout that holds path, e.g. 2fac12d, with "-dirty"
    when tracked files there differ from it (a commit of docs or records alone changes nothing);
    "unknown" outside a git checkout (an install space, the Docker images) or without git."""
    def git(*args):
        return subprocess.run(["git", "-C", path] + list(args), stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                              universal_newlines=True, timeout=60)
    try:
        top = git("rev-parse", "--show-toplevel")
        if top.returncode != 0 or not top.stdout.strip():
            return UNKNOWN_STACK
        path = top.stdout.strip()
        paths = [p for p in STACK_PATHS if os.path.exists(os.path.join(path, p))]
        last = git("log", "-1", "--format=%h", "--abbrev=7", "--", *paths)
        if last.returncode != 0 or not last.stdout.strip():
            return UNKNOWN_STACK
        changed = git("diff", "--quiet", "HEAD", "--", *paths).returncode != 0
    except (OSError, subprocess.TimeoutExpired):
        return UNKNOWN_STACK
    return last.stdout.strip() + ("-dirty" if changed else "")


def write_job_stack(job_dir: str, stack: str) -> None:
    """Notes in a run's job folder the stack version about to drive it (JOB_STACK_FILE)."""
    os.makedirs(job_dir, exist_ok=True)
    with open(os.path.join(job_dir, JOB_STACK_FILE), "w") as f:
        f.write(stack + "\n")


def job_stack(job_dir: str) -> str:
    """The stack version noted in a run's job folder; "unknown" for a folder without the note (a job
    started before campaigns noted it)."""
    try:
        with open(os.path.join(job_dir, JOB_STACK_FILE)) as f:
            return f.read().strip() or UNKNOWN_STACK
    except OSError:
        return UNKNOWN_STACK


def stacks(runs: Iterable[Run], records: Dict[str, dict]) -> List[Tuple[str, int]]:
    """[(stack version, recorded runs)] of the campaign's records, the most frequent first (records
    written before the field existed count as "unknown")."""
    counts = collections.Counter(records[r.key].get("stack", UNKNOWN_STACK) for r in runs if r.key in records)
    return counts.most_common()


def run_record(run: Run, result: dict, laps_required: int, signs_total: int, stack: str = UNKNOWN_STACK) -> dict:
    """The results-file line of a finished run: its key and seeds, whether the referee's report
    counts as the task done, the penalties, the run's status and wall time, and the version of the
    stack that drove it (stack_version)."""
    report = result.get("report") if scored(result) else None
    passed, text = outcome(report, laps_required, signs_total)
    report = report or {}
    if result.get("status") not in (None, "ok"):
        text += " [%s: %s]" % (result["status"], result.get("reason", ""))
    return dict(asdict(run), key=run.key, passed=passed, result=text, status=result.get("status", "?"),
                judged=bool(report), penalties=float(report.get("penalty_total", 0.0)),
                penalty_events=[e.get("kind", "?") for e in report.get("events", []) if e.get("penalty")],
                time_s=report.get("driving_time_s"), wall_s=float(result.get("wall_s", 0.0)), stack=stack)


def append_record(path: str, record: dict) -> None:
    """Appends one line and flushes it to disk (what an interruption leaves is a whole line or a
    torn last line, which load_records skips; the next record starts on a line of its own)."""
    torn = False
    if os.path.exists(path) and os.path.getsize(path) > 0:
        with open(path, "rb") as f:
            f.seek(-1, os.SEEK_END)
            torn = f.read(1) != b"\n"
    with open(path, "a") as f:
        f.write(("\n" if torn else "") + json.dumps(record, sort_keys=True) + "\n")
        f.flush()
        os.fsync(f.fileno())


def load_records(path: str) -> Dict[str, dict]:
    """{run key: record} of a results file (the last line of a key wins; torn lines are skipped);
    {} when there is no file yet."""
    records = {}
    try:
        with open(path) as f:
            lines = f.readlines()
    except FileNotFoundError:
        return records
    for line in lines:
        try:
            record = json.loads(line)
        except ValueError:
            continue
        if isinstance(record, dict) and "key" in record:
            records[record["key"]] = record
    return records


def judged(record: dict) -> bool:
    """The referee judged the run (False: the job failed before a report: simulator, launch, wall limit)."""
    return bool(record.get("judged", True))


def pending(runs: Iterable[Run], records: Dict[str, dict]) -> List[Run]:
    """The runs of the campaign to run (resume): without a record, or whose job ended without the
    referee's report (a failure of the machinery, not of the stack: run again)."""
    return [r for r in runs if r.key not in records or not judged(records[r.key])]


# --- table and report ------------------------------------------------------------------------------

def _mean(values) -> Optional[float]:
    values = [v for v in values if v is not None]
    return sum(values) / len(values) if values else None


def table_rows(runs: List[Run], records: Dict[str, dict]) -> List[dict]:
    """A row per (challenge, engine) over the campaign's runs the referee judged: runs, passed
    (task done), success rate, runs without penalty (passed with zero penalties), their rate, mean
    penalties per run, mean driving time of the passed runs; and the runs whose job ended without a
    referee's report (not judged: left out of the rates, run again on resume)."""
    rows = []
    groups = []
    for run in runs:
        if (run.challenge, run.engine) not in groups:
            groups.append((run.challenge, run.engine))
    for challenge, engine in groups:
        recorded = [records[r.key] for r in runs if (r.challenge, r.engine) == (challenge, engine) and r.key in records]
        done = [d for d in recorded if judged(d)]
        n = len(done)
        passed = sum(1 for d in done if d["passed"])
        clean = sum(1 for d in done if d["passed"] and d["penalties"] == 0)
        rows.append({"challenge": challenge, "engine": engine, "runs": n, "passed": passed, "clean": clean,
                     "success_pct": 100.0 * passed / n if n else None,
                     "clean_pct": 100.0 * clean / n if n else None,
                     "mean_penalties": _mean([d["penalties"] for d in done]),
                     "mean_time_s": _mean([d["time_s"] for d in done if d["passed"]]),
                     "not_judged": len(recorded) - n})
    return rows


def _fmt(value, pattern="%.1f") -> str:
    return "-" if value is None else pattern % value


def _cells(row: dict) -> Tuple[str, ...]:
    return (row["challenge"], row["engine"], str(row["runs"]), str(row["passed"]), _fmt(row["success_pct"], "%.0f"),
            str(row["clean"]), _fmt(row["clean_pct"], "%.0f"), _fmt(row["mean_penalties"], "%.2f"),
            _fmt(row["mean_time_s"]), str(row["not_judged"]))


def table_text(rows: List[dict]) -> str:
    lines = [TABLE_COLUMNS] + [_cells(r) for r in rows]
    widths = [max(len(line[i]) for line in lines) for i in range(len(TABLE_COLUMNS))]
    out = ["  ".join(c.ljust(w) if i < 2 else c.rjust(w) for i, (c, w) in enumerate(zip(line, widths)))
           for line in lines]
    out.insert(1, "-" * len(out[0]))
    return "\n".join(out) + "\n"


def report_markdown(options: Options, runs: List[Run], records: Dict[str, dict]) -> str:
    """The campaign's report: what ran, the table, and the runs that did not pass cleanly."""
    rows = table_rows(runs, records)
    done = sum(1 for r in runs if r.key in records and judged(records[r.key]))
    lines = ["# Robustness benchmark of the Conde stack", "",
             "robot %s; challenges %s; engines %s; track seeds %s; placement seeds %s (%s); %d of %d runs done."
             % (ROBOT_NAMES[options.robot], " ".join(options.challenges), " ".join(options.engines),
                _seed_text(options.track_seeds),
                _seed_text(options.placement_seeds), "paired" if options.paired else "every combination",
                done, len(runs)),
             "", "A run passes when the referee judges the task done (two laps, parked in a free bay, every "
             "sign) without disqualification; *no penalty* counts the passed runs without any penalty.", "",
             _stacks_text(stacks(runs, records)), "",
             "| " + " | ".join(TABLE_COLUMNS) + " |", "|" + "---|" * len(TABLE_COLUMNS)]
    lines += ["| " + " | ".join(_cells(r)) + " |" for r in rows]
    failed = [records[r.key] for r in runs if r.key in records
              and not (records[r.key]["passed"] and records[r.key]["penalties"] == 0)]
    lines += ["", "## Runs with a failure or a penalty", ""]
    if failed:
        lines += ["| run | result | penalties | events |", "|---|---|---|---|"]
        lines += ["| %s | %s | %g | %s |" % (d["key"], d["result"].replace("|", "/"), d["penalties"],
                                             ", ".join(d["penalty_events"]) or "-") for d in failed]
    else:
        lines.append("none")
    return "\n".join(lines) + "\n"


def _stacks_text(counted: List[Tuple[str, int]]) -> str:
    if not counted:
        return "Stack: no run recorded yet."
    text = ", ".join("%s (%d runs)" % pair for pair in counted)
    if len(counted) == 1:
        return "Stack: " + text + "."
    return "**The records come from %d versions of the stack**: %s; the table mixes them." % (len(counted), text)


def _seed_text(seeds: Tuple[int, ...]) -> str:
    if len(seeds) > 2 and list(seeds) == list(range(seeds[0], seeds[-1] + 1)):
        return "%d-%d" % (seeds[0], seeds[-1])
    return ",".join(str(s) for s in seeds)
