"""The leaderboard of a tournament from its job results (pure Python): Markdown, CSV, static HTML.

A team's total is the sum of the referee's scores over its jobs. A job counts as the referee
judged it when it ended normally, by the team's code failing or over the wall-clock limit (scored as
it ended); a job without a score (the team's launch file missing, the simulator died) scores 0 and
counts as "without score". Rank: total score (higher first), then runs without score (fewer first),
then total penalties (fewer first), then the team's name.
"""
import csv
import html
import io
import os
from typing import Dict, List

RUN_COLUMNS = ("team", "challenge", "variant", "seed", "engine", "repeat", "score", "penalties", "end", "status",
               "reason", "wall_s")


# Job statuses (conde_tournament.job.classify) whose referee report counts.
SCORED_STATUSES = ("ok", "team_failed", "wall_limit")


def scored(result: dict) -> bool:
    return result["status"] in SCORED_STATUSES and bool(result.get("report"))


def run_row(result: dict) -> dict:
    report = result["report"] if scored(result) else {}
    return {"team": result["team"], "challenge": result["challenge"], "variant": result["variant"] or "-",
            "seed": result["seed"], "engine": result["engine"], "repeat": result["repeat"],
            "score": report.get("score", 0.0), "penalties": report.get("penalty_total", 0.0),
            "end": report.get("end", "-"), "status": result["status"], "reason": result["reason"],
            "wall_s": result.get("wall_s", 0.0), "job_id": result["job_id"]}


def standings(results: List[dict]) -> List[dict]:
    """One row per team, ranked: rank, team, score, penalties, runs, failed."""
    teams: Dict[str, dict] = {}
    for result in results:
        row = run_row(result)
        team = teams.setdefault(row["team"], {"team": row["team"], "score": 0.0, "penalties": 0.0, "runs": 0,
                                              "failed": 0})
        team["score"] = round(team["score"] + row["score"], 3)
        team["penalties"] += row["penalties"]
        team["runs"] += 1
        team["failed"] += not scored(result)
    ranked = sorted(teams.values(), key=lambda t: (-t["score"], t["failed"], t["penalties"], t["team"]))
    for rank, team in enumerate(ranked, 1):
        team["rank"] = rank
    return ranked


def markdown(title: str, results: List[dict]) -> str:
    lines = ["# %s" % title, "", "| rank | team | score | penalties | runs | without score |",
             "|---|---|---|---|---|---|"]
    for t in standings(results):
        cells = (t["rank"], t["team"], t["score"], t["penalties"], t["runs"], t["failed"])
        lines.append("| %d | %s | %.3f | %g | %d | %d |" % cells)
    lines += ["", "## Runs", "", "| " + " | ".join(RUN_COLUMNS) + " |", "|" + "---|" * len(RUN_COLUMNS)]
    for row in sorted((run_row(r) for r in results), key=lambda r: r["job_id"]):
        lines.append("| " + " | ".join(str(row[c]).replace("|", "/") for c in RUN_COLUMNS) + " |")
    return "\n".join(lines) + "\n"


def runs_csv(results: List[dict]) -> str:
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=("rank",) + RUN_COLUMNS + ("job_id",), lineterminator="\n")
    writer.writeheader()
    ranks = {t["team"]: t["rank"] for t in standings(results)}
    for row in sorted((run_row(r) for r in results), key=lambda r: (ranks[r["team"]], r["job_id"])):
        writer.writerow(dict(row, rank=ranks[row["team"]]))
    return out.getvalue()


# Click a header to sort by that column (numbers as numbers); click again to reverse.
_SORT_JS = """
document.querySelectorAll("table.sortable th").forEach(function (th, col) {
  th.addEventListener("click", function () {
    var body = th.closest("table").tBodies[0], rows = Array.from(body.rows);
    var dir = th.dataset.dir = th.dataset.dir === "asc" ? "desc" : "asc";
    rows.sort(function (a, b) {
      var x = a.cells[col].textContent, y = b.cells[col].textContent;
      var c = (isNaN(x) || isNaN(y)) ? x.localeCompare(y) : x - y;
      return dir === "asc" ? c : -c;
    });
    rows.forEach(function (r) { body.appendChild(r); });
  });
});
"""


def _table(columns, rows) -> List[str]:
    out = ['<table class="sortable"><thead><tr>' + "".join("<th>%s</th>" % html.escape(c) for c in columns)
           + "</tr></thead><tbody>"]
    for row in rows:
        out.append("<tr>" + "".join("<td>%s</td>" % cell for cell in row) + "</tr>")
    out.append("</tbody></table>")
    return out


def html_page(title: str, results: List[dict], jobs_dir: str = "jobs") -> str:
    """A static page: the standings and every run, with its path plot and referee report linked."""
    esc = html.escape
    lines = ["<!DOCTYPE html>", '<html><head><meta charset="utf-8"><title>%s</title>' % esc(title),
             "<style>body{font-family:sans-serif}table{border-collapse:collapse;margin:1em 0}"
             "td,th{border:1px solid #999;padding:2px 6px}th{cursor:pointer;background:#eee}</style></head><body>",
             "<h1>%s</h1>" % esc(title), "<h2>Standings</h2>"]
    lines += _table(("rank", "team", "score", "penalties", "runs", "without score"),
                    [(t["rank"], esc(t["team"]), "%.3f" % t["score"], "%g" % t["penalties"], t["runs"], t["failed"])
                     for t in standings(results)])
    lines.append("<h2>Runs</h2>")
    rows = []
    for row in sorted((run_row(r) for r in results), key=lambda r: r["job_id"]):
        folder = "%s/%s" % (jobs_dir, row["job_id"])
        links = ['<a href="%s/roslaunch.log">log</a>' % esc(folder)]
        if row["end"] != "-":
            links[:0] = ['<a href="%s/challenge/referee.png">path</a>' % esc(folder),
                         '<a href="%s/challenge/referee.md">report</a>' % esc(folder)]
        rows.append([esc(str(row[c])) for c in RUN_COLUMNS] + [" ".join(links)])
    lines += _table(RUN_COLUMNS + ("files",), rows)
    lines += ["<script>%s</script>" % _SORT_JS, "</body></html>"]
    return "\n".join(lines) + "\n"


def write_leaderboard(out_dir: str, title: str, results: List[dict]) -> Dict[str, str]:
    """leaderboard.md, leaderboard.csv and index.html in out_dir; returns their paths."""
    paths = {"md": os.path.join(out_dir, "leaderboard.md"), "csv": os.path.join(out_dir, "leaderboard.csv"),
             "html": os.path.join(out_dir, "index.html")}
    for kind, text in (("md", markdown(title, results)), ("csv", runs_csv(results)),
                       ("html", html_page(title, results))):
        with open(paths[kind], "w") as f:
            f.write(text)
    return paths
