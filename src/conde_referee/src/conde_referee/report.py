"""The referee's report files: JSON (everything, with the path), Markdown (score and events) and a
PNG of the path over the track with a numbered marker where each event happened. Pure Python
(matplotlib), no ROS."""
import json
import os

import numpy as np
from conde_common.files import replaced_whole

#: The competition texture's extent in the world [m]: x0, x1, y0, y1 (worlds/competition.world.yaml).
TRACK_EXTENT_M = (-3.475, 3.975, -8.35, 8.35)
#: Resolution of a varied track drawn under the path [px/m].
PLOT_TEXTURE_PX_PER_M = 40.0
#: The path in the JSON file: one pose every this many seconds at most.
PATH_PERIOD_S = 0.1
#: Spacing of the numbered event markers in the PNG [m].
MARKER_M = 0.3


def default_texture() -> str:
    """conde_worlds' textures/competition_track.png (source tree or devel space, else via rospkg)."""
    import conde_worlds
    here = os.path.dirname(os.path.abspath(conde_worlds.__file__))
    beside = os.path.normpath(os.path.join(here, "..", "..", "textures", "competition_track.png"))
    if os.path.isfile(beside):
        return beside
    import rospkg
    return os.path.join(rospkg.RosPack().get_path("conde_worlds"), "textures", "competition_track.png")


def thin_path(path, period_s=PATH_PERIOD_S):
    """[(t, x, y)] of the path [(t, x, y, yaw)], at most one every period_s, with the last one."""
    out, last = [], None
    for t, x, y, _ in path:
        if last is None or t - last >= period_s - 1e-9:
            out.append((round(t, 3), round(x, 3), round(y, 3)))
            last = t
    if path and (not out or out[-1][0] != round(path[-1][0], 3)):
        out.append(tuple(round(v, 3) for v in path[-1][:3]))
    return out


def seeds_text(report) -> str:
    """"seed 0" on the nominal track, "seed 0, track seed 6" on a varied one (reports written before
    the track seed was recorded have none: nominal)."""
    track_seed = report.get("track_seed", 0)
    return "seed %d" % report["seed"] + (", track seed %d" % track_seed if track_seed else "")


def markdown(report) -> str:
    lines = ["## Referee: %s (%s)" % (report["challenge"], seeds_text(report)), "",
             "| result | value |", "|---|---|",
             "| score (%s) | %.1f |" % (report["kind"], report["score"]),
             "| penalties | %.1f |" % report["penalty_total"],
             "| end | %s%s |" % (report["end"], ", disqualified" if report["disqualified"] else ""),
             "| laps (half laps) | %d (%d) |" % (report["laps"], report["half_laps"]),
             "| driving time | %s |" % ("-" if report["driving_time_s"] is None
                                        else "%.1f s" % report["driving_time_s"]),
             "| rules | %s |" % report["rules"], "",
             "| # | t [s] | event | penalty | x, y [m] | detail |", "|---|---|---|---|---|---|"]
    lines += ["| %d | %.1f | %s | %g | %.2f, %.2f | %s |"
              % (e["n"], e["t_s"], e["kind"], e["penalty"], e["x_m"], e["y_m"], e["detail"])
              for e in report["events"]]
    if not report["events"]:
        lines.append("| - | | no event | | | |")
    return "\n".join(lines) + "\n"


def plot(report, path, course, out_png, texture_path=None):
    """The PNG: path, objects and numbered event markers over the track texture (default: the
    competition track's)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 10), dpi=120)
    if texture_path is None and course.track_seed:
        # A varied track: drawn from the course's own geometry (its texture is not in the package).
        from conde_worlds.track_render import render_track, texture_ranges
        (x0, x1), (y0, y1) = texture_ranges(course.dims)
        ax.imshow(render_track(course.track, PLOT_TEXTURE_PX_PER_M), extent=(x0, x1, y0, y1), origin="upper")
        texture_path = ""
    texture_path = texture_path if texture_path is not None else default_texture()
    if os.path.isfile(texture_path):
        import matplotlib.image as mpimg
        ax.imshow(mpimg.imread(texture_path), extent=TRACK_EXTENT_M, origin="upper")
    for ob in course.obstacles:
        poly = np.vstack([ob.polygon, ob.polygon[:1]])
        ax.fill(poly[:, 0], poly[:, 1], color="tab:green", alpha=0.7)
    xy = np.array([(x, y) for _, x, y, _ in path]).reshape(-1, 2)
    if len(xy):
        ax.plot(xy[:, 0], xy[:, 1], color="tab:orange", linewidth=1.2, label="path (ground truth)")
        ax.plot(xy[0, 0], xy[0, 1], "o", color="tab:green", label="start")
    placed = []  # markers of events at (nearly) the same place go side by side, joined to the place
    for e in report["events"]:
        colour = "tab:red" if e["penalty"] > 0 else "tab:blue"
        k = sum(1 for x, y in placed if abs(x - e["x_m"]) < MARKER_M and abs(y - e["y_m"]) < MARKER_M)
        placed.append((e["x_m"], e["y_m"]))
        mx = e["x_m"] + k * MARKER_M
        if k:
            ax.plot([e["x_m"], mx], [e["y_m"], e["y_m"]], color=colour, linewidth=0.6)
        ax.plot(mx, e["y_m"], "o", markersize=11, markerfacecolor="white", markeredgecolor=colour)
        ax.annotate(str(e["n"]), (mx, e["y_m"]), ha="center", va="center", fontsize=7, color=colour)
    ax.set_xlim(TRACK_EXTENT_M[0], TRACK_EXTENT_M[1])
    ax.set_ylim(TRACK_EXTENT_M[2], TRACK_EXTENT_M[3])
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("%s (%s): score %.1f, penalties %g (%s)\nred = penalty, blue = no penalty" % (
        report["challenge"], seeds_text(report), report["score"], report["penalty_total"], report["end"]), fontsize=8)
    ax.legend(loc="lower left", fontsize=7)
    fig.tight_layout()
    fig.savefig(out_png)
    plt.close(fig)


def write_report(report, path, course, out_dir, stem="referee", texture_path=None):
    """Writes <stem>.json, <stem>.md and <stem>.png into out_dir; returns their paths."""
    os.makedirs(out_dir, exist_ok=True)
    paths = {ext: os.path.join(out_dir, stem + "." + ext) for ext in ("json", "md", "png")}
    data = dict(report, path_t_x_y=thin_path(path))
    # Each file appears whole (a watcher reads them as soon as they exist); the plot comes last.
    with replaced_whole(paths["json"]) as tmp:
        with open(tmp, "w") as f:
            json.dump(data, f, indent=1, sort_keys=True)
            f.write("\n")
    with replaced_whole(paths["md"]) as tmp:
        with open(tmp, "w") as f:
            f.write(markdown(report))
    with replaced_whole(paths["png"]) as tmp:
        plot(report, path, course, tmp, texture_path)
    return paths
