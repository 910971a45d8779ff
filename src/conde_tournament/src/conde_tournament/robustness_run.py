"""Runs a robustness campaign (conde_tournament.robustness's options): the runs without a record in
OUT/runs.jsonl, `--jobs` at a time, each an isolated tournament job (conde_tournament.job) of the
reference Conde stack on the challenge's world with `track_seed:=T placement_seed:=P robot:=R`; each finished
run is appended to runs.jsonl at once (an interrupted campaign resumes), its job folder kept in
OUT/jobs/<key>/. Prints the table per challenge and engine and writes OUT/robustness.md (--report:
only that, of the runs already recorded, while a campaign runs or after it was stopped). Exit
status: 0 when every run of the campaign has a record, 1 otherwise (e.g. interrupted: Ctrl-C or
SIGTERM stop the running jobs, which are run again on resume), 2 on bad options."""
import contextlib
import os
import shutil
import sys
import time

from conde_tournament import robustness
from conde_tournament.competition_run import LAPS_REQUIRED, command_main, signs_total
from conde_tournament.job import load_result, run_job
from conde_tournament.pools import run_each
from conde_tournament.progress import Progress
from conde_tournament.tournament_file import Job, Team


def run(options: robustness.Options) -> int:
    out_dir = os.path.abspath(options.out_dir)
    results_path = os.path.join(out_dir, robustness.RESULTS_FILE)
    if options.report_only and not os.path.exists(results_path):
        print("robustness: --report: no campaign in %s (%s not found)" % (out_dir, results_path), file=sys.stderr)
        return 2
    os.makedirs(os.path.join(out_dir, "jobs"), exist_ok=True)
    runs = options.runs()
    records = robustness.load_records(results_path)
    todo = robustness.pending(runs, records)
    if options.report_only:
        print("robustness: %d runs, %d of them recorded in %s (--report: none is run)"
              % (len(runs), len(runs) - len(todo), results_path), flush=True)
        print(robustness.table_text(robustness.table_rows(runs, records)), end="")
        return _write_report(out_dir, options, runs, records, todo)
    stack = robustness.stack_version(os.path.dirname(os.path.abspath(__file__)))
    print("robustness: %d runs (%d done before, %d to run, %d at a time) with the stack %s; results %s"
          % (len(runs), len(runs) - len(todo), len(todo), options.jobs, stack, results_path), flush=True)
    others = [(version, n) for version, n in robustness.stacks(runs, records) if version != stack]
    if others:
        print("robustness: warning: %d recorded runs come from another version of the stack (%s); the table "
              "mixes them" % (sum(n for _, n in others), ", ".join("%s: %d" % pair for pair in others)), flush=True)
    team, total_signs = Team("reference"), signs_total()
    progress = Progress(len(todo), unit="run")
    started = time.monotonic()

    def one(run_: robustness.Run):
        job_dir = os.path.join(out_dir, "jobs", run_.key)
        # A job that finished as the campaign was interrupted, before runs.jsonl had its line, keeps
        # its result and the stack version that drove it (maybe not this campaign's); what an
        # interrupted job left (no result.json) is removed and run again.
        result = load_result(job_dir)
        if result is not None:
            return robustness.run_record(run_, result, LAPS_REQUIRED, total_signs, robustness.job_stack(job_dir))
        shutil.rmtree(job_dir, ignore_errors=True)
        robustness.write_job_stack(job_dir, stack)
        result = run_job(Job(team, run_.challenge, "", 0, run_.engine, 0), job_dir, 0.0, options.wall_limit_s,
                         ["track_seed:=%d" % run_.track_seed, "placement_seed:=%d" % run_.placement_seed,
                          "robot:=" + run_.robot])
        return robustness.run_record(run_, result, LAPS_REQUIRED, total_signs, stack)

    try:
        with contextlib.closing(run_each(one, todo, options.jobs, on_start=lambda r: progress.start(r.key))) as done:
            for run_, record in done:
                robustness.append_record(results_path, record)
                records[run_.key] = record
                progress.done("%s: %s, penalties %g (%.0f s wall, %.0f s in all)"
                              % (run_.key, record["result"], record["penalties"], record["wall_s"],
                                 time.monotonic() - started))
    except KeyboardInterrupt:
        print("\nrobustness: interrupted; the finished runs are in %s (run the same command to resume)"
              % results_path, flush=True)
    finally:
        progress.close()
    print()
    print(robustness.table_text(robustness.table_rows(runs, records)), end="")
    print("robustness: %.0f s wall" % (time.monotonic() - started), flush=True)
    return _write_report(out_dir, options, runs, records, robustness.pending(runs, records))


def _write_report(out_dir, options, runs, records, pending) -> int:
    """Writes OUT/robustness.md; the exit status: 0 when every run has a record, else 1."""
    report_path = os.path.join(out_dir, robustness.REPORT_FILE)
    with open(report_path, "w") as f:
        f.write(robustness.report_markdown(options, runs, records))
    print("robustness: report %s" % report_path, flush=True)
    return 0 if not pending else 1


def main(argv=None) -> int:
    return command_main(robustness.parse_options, run, "robustness", argv)
