"""Where jobs run: a local process pool (default) or a Ray cluster (--ray).

Both hand back each job's result as it finishes. Locally a job writes into its folder under the
output directory. On Ray a job runs in a temporary folder on whichever node Ray picks and its task
returns the result and the folder (tar.gz), which the driver unpacks into the output directory:
the nodes need the workspace at the same path and no shared file system.

Locally, a consumer that stops early (Ctrl-C, or SIGTERM or SIGHUP through interrupting_signals)
sets job.STOP: the running jobs stop their roslaunch groups within seconds and leave no result
(those the referee had judged keep theirs); the jobs not started are dropped. On Ray the driver
cancels its tasks (_cancel_ray_tasks)."""
import contextlib
import io
import os
import shutil
import signal
import tarfile
import tempfile
import threading
from concurrent.futures import ThreadPoolExecutor, as_completed

from conde_tournament.job import STOP, failed_result, run_job

# The Ray release that scripts/install_dependencies.sh tournament installs (it names the same
# version; test_ray_version.py checks), in a virtualenv that sees Debian's Python packages.
RAY_VERSION = "2.60.0"
# A task whose worker process or node died is run again this often; an exception is not retried
# (run_job returns the team's failures as results, it does not raise them).
RAY_MAX_RETRIES = 2


# How long an interrupted Ray run waits for its cancelled tasks to stop their jobs [s]: a job's
# stop takes up to 15 s of SIGINT grace and 10 s after SIGKILL.
RAY_CANCEL_WAIT_S = 40.0


def ray_venv_python() -> str:
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(cache, "conde_sim", "venv-ray-%s" % RAY_VERSION, "bin", "python")


def run_local(jobs, out_dir, sim_limit_s, wall_limit_s, workers):
    """Yields each job's result as it finishes, `workers` jobs at a time on this machine (run_each:
    stopped early, the running jobs are stopped and the others dropped)."""
    def one(job):
        return run_job(job, os.path.join(out_dir, job.job_id), sim_limit_s, wall_limit_s)

    with contextlib.closing(run_each(one, jobs, workers)) as finished:
        for _, result in finished:
            yield result


def run_each(run, items, workers, on_start=None):
    """Yields (item, run(item)) as each finishes, `workers` at a time on this machine, started in
    the order of `items`; on_start(item) is called as each one starts (from its worker thread).
    Stopped early (the generator closed, or an exception such as KeyboardInterrupt unwinding through
    it) while items still run: job.STOP is set, so that running jobs end within seconds (a `run` that
    is no job may wait on it too), the items not started are dropped, and it returns once the running
    ones have ended; what they raise then (job.JobInterrupted) is not raised again. STOP is cleared as
    it starts and again once its workers have ended."""
    def call(item):
        if on_start is not None:
            on_start(item)
        return run(item)

    STOP.clear()
    pool = ThreadPoolExecutor(max_workers=workers)
    futures = {}  # filled one by one: an interruption while submitting still sees the ones submitted
    try:
        for item in items:
            futures[pool.submit(call, item)] = item
        for future in as_completed(futures):
            yield futures[future], future.result()
    finally:
        if not all(future.done() for future in futures):
            STOP.set()
        pool.shutdown(wait=True, cancel_futures=True)
        STOP.clear()  # every worker has ended: a later run_each or run_job in this process runs


INTERRUPTING_SIGNALS = (signal.SIGTERM, signal.SIGHUP)


@contextlib.contextmanager
def interrupting_signals():
    """Within the block, SIGTERM and SIGHUP (the terminal closed, the ssh session lost) raise
    KeyboardInterrupt in the main thread, as Ctrl-C does: the command reports the interruption, keeps
    the finished results and stops the running jobs (their roslaunch groups are sessions of their
    own: with the default action they would outlive it). The previous handlers are restored after
    the block. Outside the main thread it does nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum, frame):
        raise KeyboardInterrupt(signal.Signals(signum).name)

    previous = {sig: signal.signal(sig, interrupt) for sig in INTERRUPTING_SIGNALS}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler if handler is not None else signal.SIG_DFL)


def run_job_packed(job, sim_limit_s, wall_limit_s):
    """Runs `job` in a temporary folder; returns (result, the folder as tar.gz bytes)."""
    # ray.cancel interrupts a running task with SIGINT (KeyboardInterrupt): a worker whose cluster
    # was started with SIGINT ignored (from nohup or a shell's background job) would not see it,
    # and its job would run on after the driver stopped.
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.default_int_handler)
    work = tempfile.mkdtemp(prefix="conde_tournament_")
    try:
        job_dir = os.path.join(work, job.job_id)
        result = run_job(job, job_dir, sim_limit_s, wall_limit_s)
        buffer = io.BytesIO()
        with tarfile.open(fileobj=buffer, mode="w:gz") as tar:
            # Files and folders only (ROS's log/latest is a link).
            tar.add(job_dir, arcname=job.job_id, filter=lambda info: info if info.isfile() or info.isdir() else None)
        return result, buffer.getvalue()
    finally:
        shutil.rmtree(work, ignore_errors=True)


def run_ray(jobs, out_dir, sim_limit_s, wall_limit_s, cpus_per_job, address):
    """Yields each job's result as it finishes, one Ray task per job with `cpus_per_job` CPUs."""
    import ray

    handlers = {sig: signal.getsignal(sig) for sig in INTERRUPTING_SIGNALS}
    ray.init(address=address, log_to_driver=False)
    # ray.init installs its own SIGTERM handler (it aborts the driver, which leaves the jobs running
    # on the cluster); the command's own handlers (interrupting_signals) are put back.
    if threading.current_thread() is threading.main_thread():
        for sig, handler in handlers.items():
            if handler is not None:
                signal.signal(sig, handler)
    pending = []
    try:
        task = ray.remote(num_cpus=cpus_per_job, max_retries=RAY_MAX_RETRIES, retry_exceptions=False)(run_job_packed)
        job_of = {task.remote(job, sim_limit_s, wall_limit_s): job for job in jobs}
        pending = list(job_of)
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            job = job_of[done[0]]
            job_dir = os.path.join(out_dir, job.job_id)
            try:
                result, packed = ray.get(done[0])
            except ray.exceptions.RayError as error:  # its worker died more often than retried
                yield failed_result(job, job_dir, "ray: %s" % str(error).splitlines()[0])
                continue
            shutil.rmtree(job_dir, ignore_errors=True)
            with tarfile.open(fileobj=io.BytesIO(packed), mode="r:gz") as tar:
                for member in tar.getmembers():  # only the job's own folder, no links out of it
                    if not (member.isfile() or member.isdir()) or member.name.split("/")[0] != job.job_id \
                            or ".." in member.name.split("/"):
                        raise ValueError("ray: unexpected member %r in the files of job %s" % (member.name, job.job_id))
                tar.extractall(out_dir)
            yield result
    finally:
        if pending:  # stopped early (Ctrl-C, SIGTERM): the running tasks stop their jobs, the others are dropped
            _cancel_ray_tasks(ray, pending)
        ray.shutdown()


def _cancel_ray_tasks(ray, refs):
    """Cancels Ray tasks and waits until they have ended (at most RAY_CANCEL_WAIT_S). A running task
    gets KeyboardInterrupt (ray.cancel without force), so its job stops its roslaunch group as at
    any end (job._stop, _kill_leftovers): the nodes run in sessions of their own, which a killed
    Ray worker would leave behind."""
    for ref in refs:
        ray.cancel(ref)
    ray.wait(refs, num_returns=len(refs), timeout=RAY_CANCEL_WAIT_S)
