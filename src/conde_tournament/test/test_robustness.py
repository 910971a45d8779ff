"""The robustness benchmark's options, runs, results file (resume) and table (no ROS run here)."""
import json
import os
import subprocess

import pytest

from conde_tournament import robustness
from conde_tournament.robustness import OptionError, Run, parse_options, parse_seeds


def report(**fields):
    base = {"challenge": "D1", "kind": "driving", "score": 0.0, "penalty_total": 0.0, "disqualified": False,
            "end": "end of trial", "laps": 2, "parked": None, "signs_right": 0, "driving_time_s": 100.0,
            "events": []}
    base.update(fields)
    return base


def result(rep, status="ok", wall_s=60.0):
    return {"status": status, "reason": "referee", "report": rep, "wall_s": wall_s}


@pytest.mark.parametrize("text, seeds", [("3", (1, 2, 3)), ("0", (0,)), ("0,3,7-9", (0, 3, 7, 8, 9)),
                                         ("2-4,3", (2, 3, 4)), (" 5 ", (1, 2, 3, 4, 5))])
def test_seeds_are_a_count_or_a_list(text, seeds):
    assert parse_seeds(text, "--track-seeds") == seeds


@pytest.mark.parametrize("text", ["-1", "x", "3-1", "1,,2", "1-"])
def test_bad_seeds_name_the_option(text):
    with pytest.raises(OptionError) as error:
        parse_seeds(text, "--placement-seeds")
    assert str(error.value) == ("--placement-seeds: expected a count N (seeds 1..N), 0, or a list such as "
                                "0,3,7-9, got %r" % text)


def test_every_combination_in_a_stable_order():
    options = parse_options(["--challenges", "p1,D1", "--engines", "bullet,ode", "--track-seeds", "2",
                             "--placement-seeds", "0,5"])
    assert (options.challenges, options.engines) == (("D1", "P1"), ("ode", "bullet"))
    keys = [r.key for r in options.runs()]
    assert len(keys) == 2 * 2 * 2 * 2 == len(set(keys))
    # seed pair by seed pair over every challenge and engine: a stopped campaign has runs of each
    assert keys[:5] == ["D1_ode_track1_place0", "D1_bullet_track1_place0", "P1_ode_track1_place0",
                        "P1_bullet_track1_place0", "D1_ode_track1_place5"]
    assert keys[-1] == "P1_bullet_track2_place5"


def test_paired_seeds_run_side_by_side():
    options = parse_options(["--challenges", "D1", "--engines", "ode", "--track-seeds", "3",
                             "--placement-seeds", "4-6", "--paired"])
    assert [(r.track_seed, r.placement_seed) for r in options.runs()] == [(1, 4), (2, 5), (3, 6)]
    with pytest.raises(OptionError) as error:
        parse_options(["--track-seeds", "3", "--placement-seeds", "2", "--paired"])
    assert str(error.value) == "--paired: 3 track seeds and 2 placement seeds (expected as many of each)"


def test_another_robot_runs_its_own_challenges_under_keys_of_its_own():
    """--robot major_alvega: D1 and D2 by default (the challenges Major is set up for), the run keys
    (job folders, records) name the robot; Conde's keep the names of earlier campaigns."""
    options = parse_options(["--robot", "major_alvega", "--engines", "ode", "--track-seeds", "6",
                             "--placement-seeds", "6", "--paired"])
    assert options.challenges == ("D1", "D2") and options.robot == "major_alvega"
    runs = options.runs()
    assert [r.key for r in runs[:2]] == ["major_alvega_D1_ode_track1_place1", "major_alvega_D2_ode_track1_place1"]
    assert all(r.robot == "major_alvega" for r in runs)
    assert parse_options(["--track-seeds", "0", "--placement-seeds", "0"]).runs()[0].key == "D1_ode_track0_place0"
    assert parse_options(["--robot", "major_alvega", "--challenges", "P1"]).challenges == ("P1",)
    report = robustness.report_markdown(options, runs, {})
    assert "robot Major Alvega; challenges D1 D2; engines ode;" in report


@pytest.mark.parametrize("argv, message", [
    (["--robot", "marvin"], "--robot: unknown robot 'marvin' (expected conde or major_alvega)"),
    (["--challenges", "D9"], "--challenges: unknown 'D9' (expected D1, D2, D3, D4, P1, P2, B1, B2, V1)"),
    (["--engines", "physx"], "--engines: unknown 'physx' (expected ode, bullet)"),
    (["--jobs", "0"], "--jobs: expected an integer >= 1, got '0'"),
    (["--wall-limit", "x"], "--wall-limit: expected a number of seconds > 0, got 'x'"),
])
def test_bad_options_name_the_option(argv, message):
    with pytest.raises(OptionError) as error:
        parse_options(argv)
    assert str(error.value) == message


def test_record_of_a_run():
    run = Run("D1", "ode", 3, 2)
    rec = robustness.run_record(run, result(report(penalty_total=5.0, events=[
        {"kind": "line_touch", "penalty": 5.0}, {"kind": "trial_end", "penalty": 0.0}])), 2, 12)
    assert rec["key"] == "D1_ode_track3_place2" and rec["track_seed"] == 3 and rec["placement_seed"] == 2
    assert rec["passed"] and rec["penalties"] == 5.0 and rec["penalty_events"] == ["line_touch"]
    assert rec["time_s"] == 100.0 and rec["wall_s"] == 60.0
    failed = robustness.run_record(run, result(None, status="sim_failed"), 2, 12)
    assert not failed["passed"] and not failed["judged"] and "sim_failed" in failed["result"]


def test_results_file_resumes_and_skips_a_torn_last_line(tmp_path):
    path = str(tmp_path / robustness.RESULTS_FILE)
    runs = [Run("P1", "ode", t, 0) for t in (1, 2, 3)]
    assert robustness.load_records(path) == {}
    robustness.append_record(path, robustness.run_record(runs[0], result(report(kind="parking", parked="p")), 2, 12))
    robustness.append_record(path, robustness.run_record(runs[1], result(report()), 2, 12))
    with open(path, "a") as f:
        f.write('{"key": "P1_ode_track3_place0", "pas')  # interrupted while writing
    records = robustness.load_records(path)
    assert sorted(records) == ["P1_ode_track1_place0", "P1_ode_track2_place0"]
    assert robustness.pending(runs, records) == [runs[2]]
    # the run again (after resume) appends a whole line after the torn one: its record counts
    robustness.append_record(path, robustness.run_record(runs[2], result(report(kind="parking")), 2, 12))
    with open(path) as f:
        lines = f.read().splitlines()
    assert len(lines) == 4 and json.loads(lines[3])["key"] == "P1_ode_track3_place0"
    assert robustness.pending(runs, robustness.load_records(path)) == []


def test_table_per_challenge_and_engine():
    runs = [Run("D1", e, t, 0) for e in ("ode", "bullet") for t in (1, 2, 3, 4)]
    reports = {"D1_ode_track1_place0": report(), "D1_ode_track2_place0": report(penalty_total=5.0, driving_time_s=120),
               "D1_ode_track3_place0": report(laps=1, disqualified=True, end="left the road", penalty_total=0.0),
               "D1_ode_track4_place0": report(driving_time_s=110.0),
               "D1_bullet_track1_place0": report()}  # the other bullet runs are not done yet
    records = {r.key: robustness.run_record(r, result(reports[r.key]), 2, 12) for r in runs if r.key in reports}
    rows = robustness.table_rows(runs, records)
    assert [(r["challenge"], r["engine"]) for r in rows] == [("D1", "ode"), ("D1", "bullet")]
    ode, bullet = rows
    assert (ode["runs"], ode["passed"], ode["clean"]) == (4, 3, 2)
    assert ode["success_pct"] == 75.0 and ode["clean_pct"] == 50.0
    assert ode["mean_penalties"] == pytest.approx(5.0 / 4)
    assert ode["mean_time_s"] == pytest.approx((100 + 120 + 110) / 3)
    assert (bullet["runs"], bullet["passed"], bullet["success_pct"]) == (1, 1, 100.0)
    text = robustness.table_text(rows)
    assert text.splitlines()[2].split() == ["D1", "ode", "4", "3", "75", "2", "50", "1.25", "110.0", "0"]
    options = parse_options(["--challenges", "D1", "--track-seeds", "4", "--placement-seeds", "0"])
    md = robustness.report_markdown(options, runs, records)
    assert "| D1 | ode | 4 | 3 | 75 | 2 | 50 | 1.25 | 110.0 | 0 |" in md
    assert "5 of 8 runs done" in md and "track seeds 1-4; placement seeds 0" in md
    assert "| D1_ode_track3_place0 | FAIL (disqualified: left the road) | 0 | - |" in md
    assert "D1_ode_track1_place0 |" not in md


def test_an_empty_campaign_has_empty_rows():
    rows = robustness.table_rows([Run("B1", "ode", 1, 1)], {})
    assert rows[0]["runs"] == 0 and rows[0]["success_pct"] is None
    assert robustness.table_text(rows).splitlines()[2].split() == ["B1", "ode", "0", "0", "-", "0", "-", "-", "-", "0"]


def test_a_run_the_referee_did_not_judge_is_left_out_of_the_rates_and_run_again():
    """A job that failed before the referee's report (simulator died, wall limit) says nothing of the
    stack: its own column, not a failure in the success rate, and pending on resume."""
    runs = [Run("D1", "ode", t, 0) for t in (1, 2)]
    records = {runs[0].key: robustness.run_record(runs[0], result(report()), 2, 12),
               runs[1].key: robustness.run_record(runs[1], result(None, status="sim_failed"), 2, 12)}
    row, = robustness.table_rows(runs, records)
    assert (row["runs"], row["passed"], row["success_pct"], row["not_judged"]) == (1, 1, 100.0, 1)
    assert robustness.pending(runs, records) == [runs[1]]
    options = parse_options(["--challenges", "D1", "--track-seeds", "2", "--placement-seeds", "0", "--engines", "ode"])
    md = robustness.report_markdown(options, runs, records)
    assert "1 of 2 runs done" in md and "| D1 | ode | 1 | 1 | 100 | 1 | 100 | 0.00 | 100.0 | 1 |" in md


def test_report_runs_nothing_and_counts_what_is_recorded(tmp_path, monkeypatch, capsys):
    from conde_tournament import robustness_run

    def no_run(*args, **kwargs):
        raise AssertionError("--report started a run")
    monkeypatch.setattr(robustness_run, "run_job", no_run)
    out = str(tmp_path / "campaign")
    argv = ["--challenges", "P1", "--engines", "ode", "--track-seeds", "2", "--placement-seeds", "2", "--paired",
            "--out", out, "--report"]
    assert parse_options(argv).report_only
    assert robustness_run.main(argv) == 2  # no campaign there yet: named, and nothing is created
    assert "no campaign in %s" % out in capsys.readouterr().err
    assert not (tmp_path / "campaign").exists()
    (tmp_path / "campaign").mkdir()
    path = str(tmp_path / "campaign" / robustness.RESULTS_FILE)
    robustness.append_record(path, robustness.run_record(Run("P1", "ode", 1, 1), result(report(
        challenge="P1", kind="parking", parked="parallel", end="parked", penalty_total=0.0)), 2, 12))
    assert robustness_run.main(argv) == 1  # one of the two runs has no record
    printed = capsys.readouterr().out
    assert "2 runs, 1 of them recorded" in printed
    row = [line for line in printed.splitlines() if line.startswith("P1 ")]
    assert len(row) == 1 and row[0].split()[2:4] == ["1", "1"], printed  # runs 1, passed 1
    with open(str(tmp_path / "campaign" / robustness.REPORT_FILE)) as f:
        assert "1 of 2 runs done" in f.read()
    assert robustness.load_records(path).keys() == {"P1_ode_track1_place1"}


def test_a_job_that_finished_unrecorded_is_not_run_again(tmp_path, monkeypatch):
    """Interrupted after a job wrote its result.json but before runs.jsonl had its line: the resumed
    campaign records that result instead of running the job again."""
    from conde_tournament import job as job_module
    from conde_tournament import robustness_run

    def no_run(*args, **kwargs):
        raise AssertionError("the finished job was run again")
    monkeypatch.setattr(robustness_run, "run_job", no_run)
    out = tmp_path / "campaign"
    job_dir = out / "jobs" / "P1_ode_track1_place1"
    job_dir.mkdir(parents=True)
    (job_dir / job_module.RESULT_FILE).write_text(json.dumps(result(report(
        challenge="P1", kind="parking", parked="parallel", end="parked", penalty_total=5.0, events=[
            {"kind": "cone_touch", "penalty": 5.0}]))))
    argv = ["--challenges", "P1", "--engines", "ode", "--track-seeds", "1", "--placement-seeds", "1", "--paired",
            "--out", str(out)]
    assert robustness_run.main(argv) == 0
    records = robustness.load_records(str(out / robustness.RESULTS_FILE))
    assert records["P1_ode_track1_place1"]["penalties"] == 5.0
    assert records["P1_ode_track1_place1"]["penalty_events"] == ["cone_touch"]
    assert (job_dir / job_module.RESULT_FILE).exists()  # its folder kept


def test_stack_version_names_the_last_commit_of_the_stack_and_local_changes(tmp_path, monkeypatch):
    monkeypatch.setenv("GIT_CEILING_DIRECTORIES", str(tmp_path.parent))  # not a checkout above tmp_path
    monkeypatch.delenv("GIT_DIR", raising=False)

    def git(*args):
        return subprocess.run(["git", "-C", str(tmp_path), "-c", "user.name=t", "-c", "user.email=t@t", *args],
                              check=True, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                              universal_newlines=True).stdout.strip()
    assert robustness.stack_version(str(tmp_path)) == "unknown"  # not a git checkout
    git("init", "-q")
    (tmp_path / "src").mkdir()
    (tmp_path / "src" / "node.py").write_text("speed = 0.5\n")
    git("add", "src")
    git("commit", "-q", "-m", "the stack")
    stack = git("rev-parse", "--short=7", "HEAD")
    assert robustness.stack_version(str(tmp_path / "src")) == stack  # from any folder of the checkout
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "results.md").write_text("a campaign's records\n")
    git("add", "docs")
    git("commit", "-q", "-m", "docs only")
    assert git("rev-parse", "--short=7", "HEAD") != stack
    assert robustness.stack_version(str(tmp_path)) == stack  # docs change no stack
    (tmp_path / "docs" / "results.md").write_text("edited\n")
    (tmp_path / "src" / "build.log").write_text("untracked files do not count\n")
    assert robustness.stack_version(str(tmp_path)) == stack
    (tmp_path / "src" / "node.py").write_text("speed = 0.6\n")
    assert robustness.stack_version(str(tmp_path)) == stack + "-dirty"


def test_records_name_their_stack_and_a_report_flags_a_mixture():
    runs = [Run("B1", "ode", t, t) for t in (1, 2, 3)]
    records = {runs[0].key: robustness.run_record(runs[0], result(report()), 2, 12, "abc1234"),
               runs[1].key: robustness.run_record(runs[1], result(report()), 2, 12, "abc1234")}
    assert records[runs[0].key]["stack"] == "abc1234"
    options = parse_options(["--challenges", "B1", "--engines", "ode", "--track-seeds", "3", "--placement-seeds", "3",
                             "--paired"])
    assert "Stack: abc1234 (2 runs)." in robustness.report_markdown(options, runs, records)
    old = robustness.run_record(runs[2], result(report()), 2, 12)
    del old["stack"]  # a line written before records named their stack
    records[runs[2].key] = old
    assert robustness.stacks(runs, records) == [("abc1234", 2), ("unknown", 1)]
    md = robustness.report_markdown(options, runs, records)
    assert "**The records come from 2 versions of the stack**: abc1234 (2 runs), unknown (1 runs)" in md
    assert "Stack: no run recorded yet." in robustness.report_markdown(options, runs, {})


def test_a_resumed_campaign_records_its_stack_and_warns_of_records_from_another(tmp_path, monkeypatch, capsys):
    from conde_tournament import job as job_module
    from conde_tournament import robustness_run

    here = robustness.stack_version(robustness_run.__file__.rsplit("/", 1)[0])
    bay = dict(challenge="B1", kind="parking", parked="bay", end="parked")
    ran = []

    def finished_job(job, job_dir, *args, **kwargs):
        """Seed 4 runs now: its folder names the stack before the job starts."""
        with open(os.path.join(job_dir, robustness.JOB_STACK_FILE)) as f:
            ran.append((job.challenge, f.read().strip()))
        return result(report(**bay))
    monkeypatch.setattr(robustness_run, "run_job", finished_job)
    out = tmp_path / "campaign"
    # seed 1 recorded by an older stack; seeds 2 and 3 finished but unrecorded (the campaign was
    # interrupted): seed 2 by an older stack that noted itself in the job folder, seed 3 before
    # job folders noted their stack
    for seed in (1, 2, 3):
        job_dir = out / "jobs" / ("B1_ode_track%d_place%d" % (seed, seed))
        job_dir.mkdir(parents=True)
        (job_dir / job_module.RESULT_FILE).write_text(json.dumps(result(report(**bay))))
    robustness.write_job_stack(str(out / "jobs" / "B1_ode_track2_place2"), "n0tth1s")
    (out / robustness.RESULTS_FILE).write_text(json.dumps(robustness.run_record(
        Run("B1", "ode", 1, 1), result(report(**bay)), 2, 12, "0ld0ld0")) + "\n")
    argv = ["--challenges", "B1", "--engines", "ode", "--track-seeds", "1-4", "--placement-seeds", "1-4", "--paired",
            "--out", str(out)]
    assert robustness_run.main(argv) == 0
    printed = capsys.readouterr().out
    assert "with the stack %s;" % here in printed
    assert "warning: 1 recorded runs come from another version of the stack (0ld0ld0: 1)" in printed
    assert ran == [("B1", here)]  # only seed 4 ran
    records = robustness.load_records(str(out / robustness.RESULTS_FILE))
    assert records["B1_ode_track1_place1"]["stack"] == "0ld0ld0"
    assert records["B1_ode_track2_place2"]["stack"] == "n0tth1s"  # the stack that drove it, not this one
    assert records["B1_ode_track3_place3"]["stack"] == "unknown"
    assert records["B1_ode_track4_place4"]["stack"] == here
