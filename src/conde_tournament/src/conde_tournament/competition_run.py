"""Runs the competition (conde_tournament.competition's options), `--jobs` challenges at a time
(default 2: on two cores the lock-step runs leave each other idle time; each run's result stays
the same), each an isolated tournament job of the reference Conde stack (conde_tournament.job: own
master, lock-step, referee; the long challenges started first), with a progress line per challenge;
then prints the table, where the wall time went (start-up, run, stop per challenge), with --profile
where the CPU time went, and writes the summary page. Exit status: 0
when the referee judged every challenge (whatever the robot did), 1 when some run has no referee
report or the run was interrupted (Ctrl-C, SIGTERM: the running challenges are stopped, the finished
ones keep their folders, no table or summary), 2 on bad options."""
import contextlib
import os
import resource
import shutil
import sys
import time

from conde_tournament import competition, cpu_profile
from conde_tournament.job import run_job
from conde_tournament.pools import run_each, interrupting_signals
from conde_tournament.progress import Progress
from conde_tournament.tournament_file import Job, Team

# What a challenge asks (conde_referee rules scoring.laps; the twelve V1 signs of conde_worlds).
LAPS_REQUIRED = 2


def signs_total() -> int:
    from conde_worlds.sign_names import SIGNS
    return len(SIGNS)


def start_order(challenges, time_limits_s: dict) -> list:
    """The order the challenges start in (pure): the longest first by their time limit [s] (equal
    ones as given), so that with two at a time a long run does not end alone after the short ones
    (D1-D4 and V1 take about 170 simulated seconds, P and B about 20). The table keeps the given order."""
    return sorted(challenges, key=lambda name: -time_limits_s.get(name, 0.0))


def challenge_time_limits_s() -> dict:
    from conde_worlds.challenges import load_challenges
    return {name: ch.time_limit_s for name, ch in load_challenges().challenges.items()}


def runner_cpu_s() -> float:
    """CPU seconds of this runner itself (its threads poll the jobs; the jobs' process trees are
    reaped with their own rusage, not counted here)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def run(options: competition.Options) -> int:
    out_dir = os.path.abspath(options.output_dir)
    os.makedirs(out_dir, exist_ok=True)
    team = Team("reference")
    total_signs = signs_total()
    print("competition: %s (%s), lock-step, %s; output %s"
          % (" ".join(options.challenges), competition.heading(options),
             "paced with rviz" if options.rviz else "headless", out_dir), flush=True)
    progress = Progress(len(options.challenges), unit="challenge")
    started = time.monotonic()

    def run_challenge(name):
        job_dir = os.path.join(out_dir, name)
        shutil.rmtree(job_dir, ignore_errors=True)  # no report or plot of an earlier run stays
        result = run_job(Job(team, name, "", 0, options.engine, 0), job_dir, options.sim_limit_s,
                         options.wall_limit_s, options.launch_args())
        result["folder"] = name
        return competition.row(result, LAPS_REQUIRED, total_signs)

    by_name = {}
    try:
        order = start_order(options.challenges, challenge_time_limits_s())
        with contextlib.closing(run_each(run_challenge, order, options.jobs, on_start=progress.start)) as finished:
            for name, row in finished:
                by_name[name] = row
                progress.done("%-3s %s  time %s s  penalties %g  score %.1f  (%.0f s wall, %.0f s in all)"
                              % (name, row["result"], "-" if row["time_s"] is None else "%.1f" % row["time_s"],
                                 row["penalties"], row["score"], row["wall_s"], time.monotonic() - started))
    except KeyboardInterrupt:
        progress.close()
        print("\ncompetition: interrupted after %.0f s; %d of %d challenges finished, their folders are in %s "
              "(no table or summary written)"
              % (time.monotonic() - started, len(by_name), len(options.challenges), out_dir), flush=True)
        return 1
    finally:
        progress.close()
    rows = [by_name[name] for name in options.challenges]
    elapsed_s = time.monotonic() - started
    print()
    print(competition.table_text(rows), end="")
    print()
    print(competition.timing_text(rows, elapsed_s, options.jobs), end="")
    if options.profile:
        print()
        print(cpu_profile.profile_text([(r["challenge"], r["cpu"]) for r in rows], runner_cpu_s=runner_cpu_s()), end="")
    paths = competition.write_summary(out_dir, rows, options)
    print("competition: %.0f s wall; summary %s, %s" % (elapsed_s, paths["md"], paths["html"]), flush=True)
    judged = all(os.path.isfile(os.path.join(out_dir, r["folder"], "challenge", "referee.json")) for r in rows)
    return 0 if judged else 1


def command_main(parse_options, run_options, name: str, argv=None) -> int:
    """A command's main: options parsed (a bad one: "<name>: <message>" on stderr, exit 2), then run.
    SIGTERM and SIGHUP are taken as Ctrl-C while it runs (pools.interrupting_signals); an interruption that
    run_options does not report itself ends it with "<name>: interrupted" on stderr, exit 130."""
    with interrupting_signals():
        try:
            try:
                options = parse_options(sys.argv[1:] if argv is None else argv)
            except competition.OptionError as error:
                print("%s: %s" % (name, error), file=sys.stderr)
                return 2
            return run_options(options)
        except KeyboardInterrupt:
            print("\n%s: interrupted" % name, file=sys.stderr, flush=True)
            return 130


def main(argv=None) -> int:
    return command_main(competition.parse_options, run, "run_demo", argv)
