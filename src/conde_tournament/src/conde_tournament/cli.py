"""rosrun conde_tournament run TOURNAMENT.yaml [--ray auto|ADDRESS] [--jobs N] [--output DIR]

Runs every (team, challenge, variant, seed, engine, repeat) of the tournament file as an isolated
lock-step job (conde_tournament.job), on this machine (as many jobs at once as there are cores
per cpus_per_job, or --jobs) or on a Ray cluster (--ray), and writes the leaderboard:
DIR/leaderboard.md, DIR/leaderboard.csv, DIR/index.html; each job's files in DIR/jobs/<job>/.
Finished jobs are kept: run the same command again to resume an interrupted tournament (Ctrl-C or
SIGTERM: the running jobs are stopped, without a result, and the leaderboard of the finished ones is
written). Exit status: 0 when every job has a result (whatever the teams scored), 1 when some job
could not be run or the run was interrupted, 2 when the tournament file or the arguments cannot be used.
"""
import argparse
import contextlib
import os
import sys

from conde_tournament import pools
from conde_tournament.job import load_result
from conde_tournament.leaderboard import standings, write_leaderboard
from conde_tournament.tournament_file import TournamentError, load_tournament


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="rosrun conde_tournament run", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("tournament", help="tournament file (YAML, docs/tournament.md)")
    parser.add_argument("--ray", metavar="auto|ADDRESS", default=None,
                        help="run on a Ray cluster: 'auto' (the one this machine belongs to, `ray start`) or HOST:PORT")
    parser.add_argument("--jobs", type=int, default=None,
                        help="local pool: jobs at once (default: cores / cpus_per_job, at least 1)")
    parser.add_argument("--output", default=None, help="output folder (default: ./<tournament file name>_results)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar (one line per finished job)")
    args = parser.parse_args(argv)
    if args.jobs is not None and args.jobs < 1:
        parser.error("--jobs: expected at least 1, got %d" % args.jobs)
    return args


def reexec_with_ray_venv(argv):
    """--ray needs the ray module: run again with the Python of install_dependencies.sh's Ray venv."""
    python = pools.ray_venv_python()
    venv = os.path.dirname(os.path.dirname(python))
    if os.path.abspath(sys.prefix) == os.path.abspath(venv) or not os.access(python, os.X_OK):
        sys.exit("conde_tournament: --ray: the ray module (ray==%s) is not installed: run "
                 "scripts/install_dependencies.sh tournament (it makes %s)" % (pools.RAY_VERSION, python))
    os.execv(python, [python, "-m", "conde_tournament.cli"] + argv)


def main(argv=None):
    """The command (run): SIGTERM and SIGHUP are taken as Ctrl-C while it runs (pools.interrupting_signals)."""
    with pools.interrupting_signals():
        try:
            return _main(argv)
        except KeyboardInterrupt:  # outside the jobs' loop (e.g. while loading or writing)
            print("\nconde_tournament: interrupted", file=sys.stderr, flush=True)
            return 130


def _main(argv):
    argv = sys.argv[1:] if argv is None else argv
    args = parse_args(argv)
    try:
        tournament = load_tournament(args.tournament)
    except TournamentError as error:
        print("conde_tournament: %s" % error, file=sys.stderr)
        return 2
    if args.ray is not None:
        try:
            import ray  # noqa: F401
        except ImportError:
            reexec_with_ray_venv(argv)
    out_dir = os.path.abspath(args.output or os.path.splitext(os.path.basename(args.tournament))[0] + "_results")
    jobs_dir = os.path.join(out_dir, "jobs")
    os.makedirs(jobs_dir, exist_ok=True)
    jobs = tournament.jobs()
    results = {}
    for job in jobs:
        result = load_result(os.path.join(jobs_dir, job.job_id))
        if result is not None:
            results[job.job_id] = result
    todo = [job for job in jobs if job.job_id not in results]
    where = "Ray (%s)" % args.ray if args.ray else "this machine"
    print("conde_tournament: %s: %d jobs (%d teams), %d kept from an earlier run, %d to run on %s; output %s"
          % (tournament.name, len(jobs), len(tournament.teams), len(results), len(todo), where, out_dir), flush=True)
    if args.ray:
        finished = pools.run_ray(todo, jobs_dir, tournament.sim_limit_s, tournament.wall_limit_s,
                                 tournament.cpus_per_job, args.ray)
    else:
        workers = args.jobs or max(1, (os.cpu_count() or 1) // tournament.cpus_per_job)
        finished = pools.run_local(todo, jobs_dir, tournament.sim_limit_s, tournament.wall_limit_s, workers)
    progress = None
    if not args.no_progress and todo:
        from tqdm import tqdm
        progress = tqdm(total=len(jobs), initial=len(results), unit="job", dynamic_ncols=True)
    interrupted = False
    try:
        with contextlib.closing(finished):  # closed early: the running jobs are stopped
            for result in finished:
                results[result["job_id"]] = result
                line = "%s: %s (%s)" % (result["job_id"], result["status"], result["reason"])
                if progress is not None:
                    progress.write(line)
                    progress.update(1)
                else:
                    print(line, flush=True)
    except KeyboardInterrupt:
        interrupted = True
        if progress is not None:
            progress.close()
        for job in todo:  # the jobs that ended while the running ones were being stopped
            if job.job_id not in results:
                result = load_result(os.path.join(jobs_dir, job.job_id))
                if result is not None:
                    results[job.job_id] = result
        print("\nconde_tournament: interrupted; %d of %d jobs have a result in %s (run the same command to resume)"
              % (len(results), len(jobs), jobs_dir), flush=True)
    if progress is not None:
        progress.close()
    ordered = [results[job.job_id] for job in jobs if job.job_id in results]
    paths = write_leaderboard(out_dir, tournament.name, ordered)
    for team in standings(ordered):
        print("%2d. %-20s score %9.3f  penalties %g  runs %d  without score %d"
              % (team["rank"], team["team"], team["score"], team["penalties"], team["runs"], team["failed"]))
    print("conde_tournament: leaderboard %s, %s, %s" % (paths["md"], paths["csv"], paths["html"]), flush=True)
    return 0 if len(ordered) == len(jobs) and not interrupted else 1


if __name__ == "__main__":
    sys.exit(main())
