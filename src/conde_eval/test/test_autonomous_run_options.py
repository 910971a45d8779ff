"""autonomous_run refuses options that contradict each other before it starts anything."""
import os
import subprocess
import sys

AUTONOMOUS_RUN = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts", "autonomous_run")


def run_autonomous_run(*args, cwd):
    return subprocess.run([sys.executable, AUTONOMOUS_RUN, *args], capture_output=True, text=True, cwd=cwd,
                          timeout=60)


def test_a_real_time_factor_without_pacing_is_refused(tmp_path):
    # Lock-step is the default: a real-time factor would be silently ignored.
    for args in (["--real-time-factor", "2"], ["--lockstep", "--real-time-factor", "1"]):
        proc = run_autonomous_run(*args, "--output-dir", str(tmp_path / "out"), cwd=tmp_path)
        assert proc.returncode == 2, proc.stdout + proc.stderr
        assert "autonomous_run: error: --real-time-factor paces a run to the wall clock: add --paced or --rviz" \
            in proc.stderr, proc.stderr
        assert not (tmp_path / "out").exists()


def test_paced_and_lockstep_are_refused_together(tmp_path):
    proc = run_autonomous_run("--paced", "--lockstep", "--real-time-factor", "1", cwd=tmp_path)
    assert proc.returncode == 2
    assert "autonomous_run: error: --paced and --lockstep exclude each other" in proc.stderr, proc.stderr
