"""The leaderboard from job results: ranking, Markdown, CSV and the HTML page."""
import csv
import io

from conde_tournament.leaderboard import html_page, markdown, runs_csv, standings, write_leaderboard


def result(team, seed, score=None, penalties=0.0, status="ok", end="stopped"):
    report = None if score is None else {"score": score, "penalty_total": penalties, "end": end}
    return {"job_id": "%s__D1_v1_seed%d__ode__r0" % (team, seed), "team": team, "challenge": "D1", "variant": "v1",
            "seed": seed, "engine": "ode", "repeat": 0, "status": status, "reason": "why", "report": report,
            "wall_s": 12.5}


RESULTS = [result("a", 0, 100.0, 10), result("a", 1, 50.0, 0), result("b", 0, 150.0, 40), result("b", 1, 0.0, 0),
           result("c", 0, 150.0, 0), result("c", 1, None, status="team_failed"),
           result("d", 0, 400.0, 0, status="sim_failed"), result("d", 1, 0.0, 0)]


def test_rank_by_score_then_runs_without_score_then_penalties():
    table = standings(RESULTS)
    assert [(t["rank"], t["team"], t["score"], t["penalties"], t["failed"]) for t in table] == [
        (1, "a", 150.0, 10.0, 0), (2, "b", 150.0, 40.0, 0), (3, "c", 150.0, 0.0, 1), (4, "d", 0.0, 0.0, 1)]


def test_a_simulator_failure_is_not_scored():
    rows = list(csv.DictReader(io.StringIO(runs_csv(RESULTS))))
    d0 = next(r for r in rows if r["job_id"] == "d__D1_v1_seed0__ode__r0")
    assert (d0["score"], d0["status"], d0["rank"]) == ("0.0", "sim_failed", "4")


def test_markdown_and_html(tmp_path):
    text = markdown("Class", RESULTS)
    assert text.startswith("# Class\n") and "| 1 | a | 150.000 | 10 | 2 | 0 |" in text
    page = html_page("Class <1>", RESULTS)
    assert "<title>Class &lt;1&gt;</title>" in page
    assert 'href="jobs/a__D1_v1_seed0__ode__r0/challenge/referee.png"' in page
    assert 'href="jobs/c__D1_v1_seed1__ode__r0/challenge/referee.md"' not in page  # no report, no link
    assert page.count("<table") == 2 and "addEventListener" in page
    paths = write_leaderboard(str(tmp_path), "Class", RESULTS)
    assert sorted(p.rsplit("/", 1)[1] for p in paths.values()) == ["index.html", "leaderboard.csv", "leaderboard.md"]
