"""The referee's course on a varied track (conde_worlds track seed > 0): its lines are where the
generated texture has paint, its lanes where it has mat, its loops where the objects are."""
import os

import cv2
import numpy as np
import pytest
import yaml

from conde_referee.course import Course
from conde_worlds import track_render as tr
from conde_worlds.challenge_world import write_challenge
from conde_worlds.track_variation import track_dimensions


@pytest.mark.parametrize("seed", [4, 11])
def test_referee_course_matches_the_rendered_lines(tmp_path, seed):
    paths = write_challenge("D4", "v1", 0, str(tmp_path), track_seed=seed)
    with open(paths["summary"]) as f:
        summary = yaml.safe_load(f)
    with open(paths["world"]) as f:
        world = yaml.safe_load(f)
    d = track_dimensions(seed)
    assert summary["track_seed"] == seed and summary["track"] == d.summary()
    assert world["name"].endswith("_track%d" % seed)
    ground = world["ground"]
    texture = cv2.imread(os.path.join(paths["dir"], ground["texture"]), cv2.IMREAD_GRAYSCALE)
    (x0, x1), (y0, y1) = ground["x_range_m"], ground["y_range_m"]
    res = texture.shape[1] / (x1 - x0)
    assert res == pytest.approx(tr.RESOLUTION_PX_PER_M) and texture.shape[0] / (y1 - y0) == pytest.approx(res)

    def grey_at(points):
        p = np.asarray(points, float)
        cols = np.floor((p[:, 0] - x0) * res).astype(int)
        rows = np.floor((y1 - p[:, 1]) * res).astype(int)
        return texture[rows, cols].astype(float)

    course = Course.from_summary(summary)
    assert course.dims == d
    mid = 0.5 * (d.mat_grey + d.line_grey)
    # The centres of the referee's boundary lines, where painted, are paint in the texture...
    for stroke in course.boundary_lines:
        for a, b in stroke.intervals:
            if b - a < 0.05:
                continue
            s = np.linspace(a + 0.01, b - 0.01, 20)
            pts = stroke.prim.point(s)
            assert np.all(grey_at(pts) > mid), (seed, stroke.name)
            assert course.touches(pts[:1], [stroke]) == [stroke.name]
    # ... and its lane centres (away from the crosswalk and the dashes' ends) are mat.
    for route, lc in course.track.lane_centres(0.05).items():
        pts = lc["xy"][np.array(lc["section"]) != "crosswalk"]
        assert np.mean(grey_at(pts) < mid) > 0.99, (seed, route)
        assert not course.touches(pts, course.boundary_lines), (seed, route)
    # Its loop model (angles, divider radius) agrees with the objects the world file holds.
    for obj in (o for o in world["objects"] if o["name"].startswith("cone_")):
        loop, angle, radius = course.loop_position(*obj["pose"]["xyz"][:2])
        assert loop == "north" and 0.0 <= angle <= 270.0
    # The generated texture is the track's rendering, and a second generation reuses it.
    mtime = os.path.getmtime(os.path.join(paths["dir"], ground["texture"]))
    write_challenge("D4", "v1", 0, str(tmp_path), track_seed=seed)
    assert os.path.getmtime(os.path.join(paths["dir"], ground["texture"])) == mtime


@pytest.mark.parametrize("seed", [0, 4])
def test_touches_skipping_far_strokes_names_what_every_stroke_names(seed):
    """Course.touches skips the strokes whose painted box is away from the points: footprints all
    over the course name the same lines as a check that projects on every stroke."""
    course = Course.from_layout("D4", track_seed=seed)
    strokes = course.boundary_lines + course.parking_lines
    rng = np.random.default_rng(seed)
    named = 0
    for _ in range(300):
        centre = rng.uniform((-4.0, -9.0), (4.0, 9.0))
        pts = centre + rng.uniform(-0.25, 0.25, size=(80, 2))
        every = []
        for stroke in strokes:
            s, lat = stroke.prim.project(pts)
            on = (np.abs(lat) <= stroke.width / 2.0) & np.any(
                [(s >= a) & (s <= b) for a, b in stroke.intervals], axis=0)
            if on.any():
                every.append(stroke.name)
        assert course.touches(pts, strokes) == every
        named += bool(every)
    assert named > 30  # many footprints do lie on lines
