"""The competition's options, result of a referee report, table and summary page (no ROS run here)."""
import os
import subprocess

import pytest

from conde_tournament import competition
from conde_tournament.competition import OptionError, Options, outcome, parse_options, row, table_text

PACKAGE_SRC = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "src")


def report(**fields):
    base = {"challenge": "D1", "kind": "driving", "score": 0.0, "penalty_total": 0.0, "disqualified": False,
            "end": "end of trial", "laps": 0, "parked": None, "signs_right": 0, "driving_time_s": None, "events": []}
    base.update(fields)
    return base


def result(challenge, rep, status="ok", wall_s=30.0):
    return {"job_id": challenge, "challenge": challenge, "status": status, "reason": "referee", "report": rep,
            "wall_s": wall_s}


def test_default_options_run_every_challenge_on_ode():
    options = parse_options([])
    assert options.challenges == ("D1", "D2", "D3", "D4", "P1", "P2", "B1", "B2", "V1")
    assert (options.engine, options.track_seed, options.rviz) == ("ode", 0, False)
    assert options.robot == "conde"
    assert options.launch_args() == ["track_seed:=0", "robot:=conde"]


def test_challenges_repeatable_or_listed_in_competition_order():
    options = parse_options(["--challenge", "p1", "--challenge", "D3,B2", "--engine", "bullet", "--track-seed", "7",
                             "--rviz"])
    assert options.challenges == ("D3", "P1", "B2")
    assert options.engine == "bullet"
    assert options.launch_args() == ["track_seed:=7", "robot:=conde", "rviz:=true", "real_time_factor:=1"]


def test_robot_major_alvega_runs_its_challenges_and_reaches_every_job():
    options = parse_options(["--robot", "major_alvega"])
    assert options.robot == "major_alvega"
    assert options.challenges == ("D1", "D2")  # what Major Alvega is set up for
    assert "robot:=major_alvega" in options.launch_args()
    chosen = parse_options(["--robot", "major_alvega", "--challenge", "P1", "--engine", "bullet"])
    assert chosen.challenges == ("P1",) and chosen.launch_args() == ["track_seed:=0", "robot:=major_alvega"]
    # the launch arguments reach each job's roslaunch command
    from conde_tournament.job import launch_command
    from conde_tournament.tournament_file import Job, Team
    command = launch_command(Job(Team("reference"), "D2", "", 0, "bullet", 0), 11311, "/tmp/j", 0.0,
                             options.launch_args())
    assert "robot:=major_alvega" in command[-1].split()


@pytest.mark.parametrize("argv, message", [
    (["--challenge", "D5"], "--challenge: unknown challenge 'D5' (expected D1, D2, D3, D4, P1, P2, B1, B2, V1)"),
    (["--engine", "physx"], "--engine: unknown engine 'physx' (expected ode or bullet)"),
    (["--robot", "nao"], "--robot: unknown robot 'nao' (expected conde or major_alvega)"),
    (["--track-seed", "-1"], "--track-seed: expected an integer >= 0, got '-1'"),
    (["--track-seed", "x"], "--track-seed: expected an integer >= 0, got 'x'"),
    (["--wall-limit", "0"], "--wall-limit: expected a number of seconds > 0, got '0'"),
    (["--sim-limit", "nan"], "--sim-limit: expected a number of seconds >= 0, got 'nan'"),
])
def test_bad_options_name_the_option(argv, message):
    with pytest.raises(OptionError) as error:
        parse_options(argv)
    assert str(error.value) == message


def test_check_exits_2_with_the_message_before_anything_is_installed():
    env = dict(os.environ, PYTHONPATH=PACKAGE_SRC)
    run = subprocess.run(["/usr/bin/python3", "-m", "conde_tournament.competition", "--check", "--engine", "x"],
                         env=env, capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and "run_demo: --engine: unknown engine 'x'" in run.stderr, run.stderr
    run = subprocess.run(["/usr/bin/python3", "-m", "conde_tournament.competition", "--check", "--no-such"],
                         env=env, capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and "unrecognized arguments: --no-such" in run.stderr, run.stderr
    ok = subprocess.run(["/usr/bin/python3", "-m", "conde_tournament.competition", "--check", "--challenge", "P1"],
                        env=env, capture_output=True, text=True, timeout=60)
    assert ok.returncode == 0, ok.stderr


def test_outcome_per_kind():
    assert outcome(report(laps=2, end="end of trial"), 2, 12) == (True, "PASS (2/2 laps, end of trial)")
    assert outcome(report(laps=1, end="time limit"), 2, 12) == (False, "FAIL (1/2 laps, time limit)")
    assert outcome(report(disqualified=True, end="left the road"), 2, 12) == \
        (False, "FAIL (disqualified: left the road)")
    assert outcome(report(kind="parking", parked="parallel", end="parked"), 2, 12) == \
        (True, "PASS (parked parallel, parked)")
    assert outcome(report(kind="parking", end="parking failed"), 2, 12) == \
        (False, "FAIL (not parked, parking failed)")
    assert outcome(report(kind="signs", signs_right=11, end="time limit"), 2, 12) == \
        (False, "FAIL (11/12 signs, time limit)")
    assert outcome(None, 2, 12) == (False, "FAIL (no referee report)")


def test_table_rows_and_total_come_from_the_reports():
    rows = [row(result("D1", report(laps=2, score=190.5, penalty_total=10.0, driving_time_s=139.5,
                                    events=[{"kind": "line_touch", "penalty": 10.0}]))),
            row(result("P1", report(kind="parking", end="time limit", score=0.0), wall_s=20.0)),
            row(result("V1", None, status="sim_failed"))]
    assert [r["passed"] for r in rows] == [True, False, False]
    assert rows[2]["result"].startswith("FAIL (no referee report) [sim_failed")
    text = table_text(rows)
    lines = text.splitlines()
    assert lines[0].split() == ["challenge", "result", "time", "[s]", "penalties", "score", "wall", "[s]"]
    assert lines[2].split()[:2] == ["D1", "PASS"] and lines[2].split()[-4:] == ["139.5", "10", "190.5", "30"]
    assert lines[3].split()[-4:] == ["-", "0", "0.0", "20"]
    assert lines[-1].split() == ["total", "1/3", "passed", "10", "190.5", "80"]


def test_summary_pages_embed_each_plot_and_link_each_report(tmp_path):
    rows = [row(dict(result("D3", report(challenge="D3", end="left the road", disqualified=True)), folder="D3"))]
    paths = competition.write_summary(str(tmp_path), rows, Options(challenges=("D3",), track_seed=3))
    md = open(paths["md"]).read()
    page = open(paths["html"]).read()
    assert "| D3 | FAIL (disqualified: left the road) | - | 0 | 0.0 | 30 |" in md
    assert "![D3 path](D3/challenge/referee.png)" in md and "(D3/challenge/referee.md)" in md
    assert '<img src="D3/challenge/referee.png" alt="D3 path">' in page
    assert '<a href="D3/challenge/referee.json">JSON</a>' in page
    assert "robot Conde, engine ode, track seed 3" in page and '<tr class="fail">' in page
    assert "robot Conde, engine ode, track seed 3" in md


def test_summary_records_the_robot(tmp_path):
    rows = [row(dict(result("D2", report(challenge="D2", laps=2)), folder="D2"))]
    paths = competition.write_summary(str(tmp_path), rows, parse_options(["--robot", "major_alvega"]))
    assert "robot Major Alvega, engine ode, track seed 0" in open(paths["md"]).read()
    assert "robot Major Alvega, engine ode, track seed 0" in open(paths["html"]).read()


def test_two_challenges_at_a_time_by_default_one_with_rviz():
    assert parse_options([]).jobs == 2
    assert parse_options(["--jobs", "1"]).jobs == 1
    assert parse_options(["--jobs", "3", "--rviz"]).jobs == 1  # paced runs are shown one at a time
    with pytest.raises(OptionError) as error:
        parse_options(["--jobs", "0"])
    assert str(error.value) == "--jobs: expected an integer >= 1, got '0'"


def test_timing_table_sums_the_parts_and_names_the_elapsed_time():
    rows = [row(dict(result("D1", report(laps=2), wall_s=80.0),
                     timing={"startup_s": 12.0, "run_s": 60.5, "stop_s": 7.5})),
            row(dict(result("P1", report(kind="parking"), wall_s=70.0),
                     timing={"startup_s": 10.0, "run_s": None, "stop_s": 5.0})),
            row(result("V1", None, status="sim_failed", wall_s=3.0))]
    lines = competition.timing_text(rows, 95.4, 2).splitlines()
    assert lines[0].split() == ["challenge", "start-up", "[s]", "run", "[s]", "stop", "[s]", "wall", "[s]"]
    assert lines[2].split() == ["D1", "12.0", "60.5", "7.5", "80.0"]
    assert lines[3].split() == ["P1", "10.0", "-", "5.0", "70.0"]
    assert lines[4].split() == ["V1", "-", "-", "-", "3.0"]
    assert lines[6].split() == ["sum", "22.0", "60.5", "12.5", "153.0"]
    assert lines[7] == "elapsed 95 s with 2 challenges at a time"
