"""Runs the competition (conde_tournament.competition's options) one challenge after the other,
each an isolated tournament job of the reference Conde stack (conde_tournament.job: own master,
lock-step, referee), with a progress line per challenge; then prints the table and writes the
summary page. Exit status: 0 when the referee judged every challenge (whatever the robot did),
1 when some run has no referee report, 2 on bad options."""
import os
import shutil
import sys
import time

from conde_tournament import competition
from conde_tournament.job import run_job
from conde_tournament.tournament_file import Job, Team

# What a challenge asks (conde_referee rules scoring.laps; the twelve V1 signs of conde_worlds).
LAPS_REQUIRED = 2


def _signs_total() -> int:
    from conde_worlds.traffic_signs import SIGNS
    return len(SIGNS)


class _Progress:
    """A line per finished challenge; on a terminal also a live bar with the elapsed time."""

    def __init__(self, total: int):
        self.bar = None
        if sys.stdout.isatty():
            from tqdm import tqdm
            self.bar = tqdm(total=total, unit="challenge", dynamic_ncols=True,
                            bar_format="{desc} {n_fmt}/{total_fmt} [{elapsed}]")

    def start(self, index: int, total: int, challenge: str):
        if self.bar is not None:
            self.bar.set_description("running %s" % challenge)
        else:
            print("[%d/%d] %s running ..." % (index, total, challenge), flush=True)

    def done(self, line: str):
        if self.bar is not None:
            self.bar.write(line)
            self.bar.update(1)
        else:
            print(line, flush=True)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def run(options: competition.Options) -> int:
    out_dir = os.path.abspath(options.output_dir)
    os.makedirs(out_dir, exist_ok=True)
    team = Team("reference")
    signs_total = _signs_total()
    print("competition: %s with Conde (%s), lock-step, %s; output %s"
          % (" ".join(options.challenges), competition.heading(options),
             "paced with rviz" if options.rviz else "headless", out_dir), flush=True)
    progress = _Progress(len(options.challenges))
    rows, started = [], time.monotonic()
    try:
        for index, name in enumerate(options.challenges, 1):
            progress.start(index, len(options.challenges), name)
            job_dir = os.path.join(out_dir, name)
            shutil.rmtree(job_dir, ignore_errors=True)  # no report or plot of an earlier run stays
            result = run_job(Job(team, name, "", 0, options.engine, 0), job_dir, options.sim_limit_s,
                             options.wall_limit_s, options.launch_args())
            result["folder"] = name
            row = competition.row(result, LAPS_REQUIRED, signs_total)
            rows.append(row)
            progress.done("%-3s %s  time %s s  penalties %g  score %.1f  (%.0f s wall, %.0f s in all)"
                          % (name, row["result"], "-" if row["time_s"] is None else "%.1f" % row["time_s"],
                             row["penalties"], row["score"], row["wall_s"], time.monotonic() - started))
    finally:
        progress.close()
    print()
    print(competition.table_text(rows), end="")
    paths = competition.write_summary(out_dir, rows, options)
    print("competition: %.0f s wall; summary %s, %s" % (time.monotonic() - started, paths["md"], paths["html"]),
          flush=True)
    judged = all(os.path.isfile(os.path.join(out_dir, r["folder"], "challenge", "referee.json")) for r in rows)
    return 0 if judged else 1


def main(argv=None) -> int:
    try:
        options = competition.parse_options(sys.argv[1:] if argv is None else argv)
    except competition.OptionError as error:
        print("run_demo: %s" % error, file=sys.stderr)
        return 2
    return run(options)
