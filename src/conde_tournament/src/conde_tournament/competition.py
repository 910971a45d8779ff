"""The whole competition with the reference Conde stack (scripts/run_demo.sh, rosrun conde_tournament
competition): the options, each challenge's row from its job result and referee report, the
console table and the summary page (Markdown and HTML). Pure Python, no ROS: the runner
(scripts/competition) runs the jobs with conde_tournament.job.

    python3 -m conde_tournament.competition --check [OPTIONS]   # checks the options only (exit 2 on bad ones)
"""
import argparse
import html
import os
import sys
from dataclasses import dataclass
from typing import List, Optional, Tuple

from conde_tournament.leaderboard import scored

CHALLENGES = ("D1", "D2", "D3", "D4", "P1", "P2", "B1", "B2", "V1")
ENGINES = ("ode", "bullet")
#: The robots that drive the stack (team_run.launch robot:=...), each with the challenges it runs
#: by default: Major Alvega (through conde_major's Ackermann adapter) is set up for D1 and D2; the
#: others can still be chosen with --challenge.
ROBOT_CHALLENGES = {"conde": CHALLENGES, "major_alvega": ("D1", "D2")}
ROBOT_NAMES = {"conde": "Conde", "major_alvega": "Major Alvega"}
TABLE_COLUMNS = ("challenge", "result", "time [s]", "penalties", "score", "wall [s]")


class OptionError(ValueError):
    """Options that cannot be used; the message names the option and the value."""


def positive_seconds(text: str, option: str) -> float:
    """float(text) when it is > 0, else OptionError naming the option and the value."""
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not value > 0:
        raise OptionError("%s: expected a number of seconds > 0, got %r" % (option, text))
    return value


def jobs_count(text: str) -> int:
    """int(text) when it is an integer >= 1, else OptionError naming --jobs."""
    if not text.isdigit() or int(text) < 1:
        raise OptionError("--jobs: expected an integer >= 1, got %r" % text)
    return int(text)


@dataclass(frozen=True)
class Options:
    challenges: Tuple[str, ...] = CHALLENGES
    engine: str = "ode"
    track_seed: int = 0
    rviz: bool = False
    output_dir: str = "results/competition"
    wall_limit_s: float = 600.0
    sim_limit_s: float = 0.0   # 0 = each challenge's own end (its time limit)
    jobs: int = 2              # challenges run at a time (lock-step: the same results with 1 or 2)
    robot: str = "conde"       # team_run.launch robot: conde | major_alvega
    profile: bool = False      # print where the CPU time went (conde_tournament.cpu_profile)

    def launch_args(self) -> List[str]:
        """team_run.launch arguments of every job: the track, the robot and, with --rviz, rviz paced
        to the wall clock."""
        args = ["track_seed:=%d" % self.track_seed, "robot:=" + self.robot]
        if self.rviz:
            args += ["rviz:=true", "real_time_factor:=1"]
        return args


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="scripts/run_demo.sh", description="Runs the competition (%s) with the Conde stack, headless in "
        "lock-step, each challenge scored by the referee; prints the table and writes the summary page."
        % " ".join(CHALLENGES))
    parser.add_argument("--challenge", action="append", default=[], metavar="NAME[,NAME...]",
                        help="run only these challenges (repeatable or a comma-separated list; default all)")
    parser.add_argument("--engine", default="ode", help="physics engine: ode (default) or bullet")
    parser.add_argument("--robot", default="conde",
                        help="the robot driving the stack: conde (default) or major_alvega (default challenges: %s)"
                        % ", ".join(ROBOT_CHALLENGES["major_alvega"]))
    parser.add_argument("--track-seed", default="0", metavar="N",
                        help="0 = the nominal track (default), N > 0 = a track varied within the rules' tolerance")
    parser.add_argument("--rviz", action="store_true", help="show each run in rviz, paced to the wall clock")
    parser.add_argument("--output-dir", default="results/competition", help="where the reports and the summary go")
    parser.add_argument("--wall-limit", default="600", metavar="S",
                        help="wall-clock limit of one challenge [s] (default 600); the run is scored as it ended")
    parser.add_argument("--sim-limit", default="0", metavar="S",
                        help="stop each run at this simulated time [s] (default 0: the challenge's own time limit)")
    parser.add_argument("--jobs", default="2", metavar="N",
                        help="challenges run at a time (default 2; lock-step keeps each run's result the same)")
    parser.add_argument("--profile", action="store_true",
                        help="also print the CPU time [s] per challenge and phase and per node per simulated second")
    parser.add_argument("--check", action="store_true", help=argparse.SUPPRESS)
    return parser


def parse_options(argv) -> Options:
    """Options of the command line; OptionError names the bad option (argparse's own errors exit 2)."""
    args = _parser().parse_args(argv)
    challenges = []
    for entry in args.challenge:
        for name in entry.split(","):
            name = name.strip().upper()
            if name not in CHALLENGES:
                raise OptionError("--challenge: unknown challenge %r (expected %s)" % (name, ", ".join(CHALLENGES)))
            if name not in challenges:
                challenges.append(name)
    if args.robot not in ROBOT_CHALLENGES:
        raise OptionError("--robot: unknown robot %r (expected %s)" % (args.robot, " or ".join(ROBOT_CHALLENGES)))
    if args.engine not in ENGINES:
        raise OptionError("--engine: unknown engine %r (expected %s)" % (args.engine, " or ".join(ENGINES)))
    try:
        track_seed = int(args.track_seed)
    except ValueError:
        track_seed = -1
    if track_seed < 0:
        raise OptionError("--track-seed: expected an integer >= 0, got %r" % args.track_seed)
    wall_limit_s = positive_seconds(args.wall_limit, "--wall-limit")
    try:
        sim_limit_s = float(args.sim_limit)
    except ValueError:
        sim_limit_s = -1.0
    if not sim_limit_s >= 0:
        raise OptionError("--sim-limit: expected a number of seconds >= 0, got %r" % args.sim_limit)
    jobs = jobs_count(args.jobs)
    ordered = tuple(c for c in CHALLENGES if c in challenges) or ROBOT_CHALLENGES[args.robot]
    # With rviz each run is shown paced, one window at a time.
    jobs = 1 if args.rviz else jobs
    return Options(ordered, args.engine, track_seed, args.rviz, args.output_dir, wall_limit_s, sim_limit_s, jobs,
                   args.robot, profile=args.profile)


def outcome(report: Optional[dict], laps_required: int, signs_total: int) -> Tuple[bool, str]:
    """(passed, result text) of a referee report: the challenge's task done without disqualification
    (two laps; parked in a free bay; every sign recognised). Penalties are a column of their own."""
    if not report:
        return False, "FAIL (no referee report)"
    end = report.get("end") or "not ended"
    if report.get("disqualified"):
        return False, "FAIL (disqualified: %s)" % end
    kind = report.get("kind")
    if kind == "parking":
        done = bool(report.get("parked"))
        what = "parked %s" % report["parked"] if done else "not parked"
    elif kind == "signs":
        right = int(report.get("signs_right", 0))
        done, what = right >= signs_total, "%d/%d signs" % (right, signs_total)
    else:
        laps = int(report.get("laps", 0))
        done, what = laps >= laps_required, "%d/%d laps" % (laps, laps_required)
    return done, "%s (%s, %s)" % ("PASS" if done else "FAIL", what, end)


def row(result: dict, laps_required: int = 2, signs_total: int = 12) -> dict:
    """One table row of a job result (conde_tournament.job.run_job); the report only counts when the
    referee judged the run (leaderboard.scored)."""
    report = result.get("report") if scored(result) else None
    passed, text = outcome(report, laps_required, signs_total)
    if result.get("status") not in (None, "ok"):
        text += " [%s: %s]" % (result["status"], result.get("reason", ""))
    report = report or {}
    return {"challenge": result["challenge"], "passed": passed, "result": text,
            "time_s": report.get("driving_time_s"), "penalties": float(report.get("penalty_total", 0.0)),
            "score": float(report.get("score", 0.0)), "wall_s": float(result.get("wall_s", 0.0)),
            "events": [e.get("kind", "?") for e in report.get("events", []) if e.get("penalty")],
            "folder": result.get("folder", result["challenge"]), "timing": result.get("timing") or {},
            "cpu": result.get("cpu")}


def totals(rows: List[dict]) -> dict:
    return {"passed": sum(r["passed"] for r in rows), "runs": len(rows),
            "penalties": sum(r["penalties"] for r in rows), "score": round(sum(r["score"] for r in rows), 3),
            "wall_s": round(sum(r["wall_s"] for r in rows), 1)}


def _cells(r: dict):
    return (r["challenge"], r["result"], "-" if r["time_s"] is None else "%.1f" % r["time_s"],
            "%g" % r["penalties"], "%.1f" % r["score"], "%.0f" % r["wall_s"])


def _total_cells(rows: List[dict]):
    t = totals(rows)
    return ("total", "%d/%d passed" % (t["passed"], t["runs"]), "", "%g" % t["penalties"], "%.1f" % t["score"],
            "%.0f" % t["wall_s"])


def table_text(rows: List[dict]) -> str:
    """The console table: a row per challenge and the total."""
    lines = [_cells(r) for r in rows] + [_total_cells(rows)]
    widths = [max(len(str(line[i])) for line in lines + [TABLE_COLUMNS]) for i in range(len(TABLE_COLUMNS))]

    def fmt(cells):
        return "  ".join(str(c).ljust(w) if i < 2 else str(c).rjust(w) for i, (c, w) in enumerate(zip(cells, widths)))
    rule = "-" * len(fmt(TABLE_COLUMNS))
    return "\n".join([fmt(TABLE_COLUMNS), rule] + [fmt(c) for c in lines[:-1]] + [rule, fmt(lines[-1])]) + "\n"


TIMING_COLUMNS = ("challenge", "start-up [s]", "run [s]", "stop [s]", "wall [s]")


def timing_text(rows: List[dict], elapsed_s: float, jobs: int) -> str:
    """Where the wall time went, per challenge (job.timing: start-up until the simulation runs,
    the run until the referee decided, the stop), their sums and the elapsed time with `jobs` at a time."""
    def cell(value):
        return "-" if value is None else "%.1f" % value

    def total(key):
        return sum(r["timing"].get(key) or 0.0 for r in rows)
    lines = [TIMING_COLUMNS] + [(r["challenge"], cell(r["timing"].get("startup_s")), cell(r["timing"].get("run_s")),
                                 cell(r["timing"].get("stop_s")), cell(r["wall_s"])) for r in rows]
    lines.append(("sum", cell(total("startup_s")), cell(total("run_s")), cell(total("stop_s")),
                  cell(sum(r["wall_s"] for r in rows))))
    widths = [max(len(line[i]) for line in lines) for i in range(len(TIMING_COLUMNS))]
    out = ["  ".join(c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(line, widths)))
           for line in lines]
    out.insert(1, "-" * len(out[0]))
    out.insert(len(out) - 1, "-" * len(out[0]))
    out.append("elapsed %.0f s with %d challenge%s at a time" % (elapsed_s, jobs, "s" if jobs > 1 else ""))
    return "\n".join(out) + "\n"


def heading(options: Options) -> str:
    return "robot %s, engine %s, track seed %d%s" % (ROBOT_NAMES[options.robot], options.engine, options.track_seed,
                                                     ", rviz (paced)" if options.rviz else "")


def summary_markdown(rows: List[dict], options: Options, title: str = "Conde competition") -> str:
    """The summary page in Markdown: the table, then each challenge's path plot and report (relative links)."""
    lines = ["# %s" % title, "", heading(options), "",
             "| " + " | ".join(TABLE_COLUMNS) + " |", "|" + "---|" * len(TABLE_COLUMNS)]
    lines += ["| " + " | ".join(str(c).replace("|", "/") for c in cells) + " |"
              for cells in [_cells(r) for r in rows] + [_total_cells(rows)]]
    for r in rows:
        folder = r["folder"] + "/challenge"
        penalties = "; penalties: " + ", ".join(r["events"]) if r["events"] else ""
        lines += ["", "## %s" % r["challenge"], "", r["result"] + penalties,
                  "", "![%s path](%s/referee.png)" % (r["challenge"], folder), "",
                  "[referee report](%s/referee.md) · [JSON](%s/referee.json)" % (folder, folder)]
    return "\n".join(lines) + "\n"


def summary_html(rows: List[dict], options: Options, title: str = "Conde competition") -> str:
    """The summary page in HTML: the table and each challenge's path plot (linked files beside it)."""
    e = html.escape
    head = "".join("<th>%s</th>" % e(c) for c in TABLE_COLUMNS)
    body = []
    for r in rows:
        cells = "".join("<td>%s</td>" % e(str(c)) for c in _cells(r))
        body.append('<tr class="%s">%s</tr>' % ("pass" if r["passed"] else "fail", cells))
    body.append('<tr class="total">%s</tr>' % "".join("<td>%s</td>" % e(str(c)) for c in _total_cells(rows)))
    plots = []
    for r in rows:
        folder = e(r["folder"] + "/challenge")
        plots.append('<figure><a href="{f}/referee.png"><img src="{f}/referee.png" alt="{c} path"></a>'
                     '<figcaption><b>{c}</b>: {res}{ev} &middot; <a href="{f}/referee.md">report</a> &middot; '
                     '<a href="{f}/referee.json">JSON</a></figcaption></figure>'
                     .format(f=folder, c=e(r["challenge"]), res=e(r["result"]),
                             ev=e("; penalties: " + ", ".join(r["events"])) if r["events"] else ""))
    return """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>{title}</title><style>
body {{ font-family: sans-serif; margin: 1.5em; }}
table {{ border-collapse: collapse; }} td, th {{ border: 1px solid #999; padding: 0.2em 0.6em; }}
tr.pass td:nth-child(2) {{ color: #060; }} tr.fail td:nth-child(2) {{ color: #a00; }} tr.total {{ font-weight: bold; }}
figure {{ display: inline-block; width: 30em; margin: 0.5em; vertical-align: top; }} img {{ width: 100%; }}
</style></head><body>
<h1>{title}</h1><p>{heading}</p>
<table><thead><tr>{head}</tr></thead><tbody>
{body}
</tbody></table>
{plots}
</body></html>
""".format(title=e(title), heading=e(heading(options)), head=head, body="\n".join(body), plots="\n".join(plots))


def write_summary(out_dir: str, rows: List[dict], options: Options) -> dict:
    """Writes summary.md and summary.html into out_dir; returns their paths."""
    paths = {"md": os.path.join(out_dir, "summary.md"), "html": os.path.join(out_dir, "summary.html")}
    with open(paths["md"], "w") as f:
        f.write(summary_markdown(rows, options))
    with open(paths["html"], "w") as f:
        f.write(summary_html(rows, options))
    return paths


def check_main(argv=None) -> int:
    """`--check OPTIONS`: 0 when the options can be used, 2 with the message otherwise (run_demo.sh
    checks them before it installs and builds)."""
    try:
        parse_options(sys.argv[1:] if argv is None else argv)
    except OptionError as error:
        print("run_demo: %s" % error, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(check_main())
