"""The racetrack's geometry (conde_racing.racetrack) and its generated files: the world file, the
floor texture and the lap-timing lines are what racetrack_world.py makes from the geometry, the
walls follow the centre line, the grid fits on the main straight."""

import math
import os

import cv2
import numpy as np
import pytest
import yaml

from conde_racing import racetrack as rt
from conde_racing import racetrack_world as rw

RACING_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WORLDS_DIR = os.path.normpath(os.path.join(RACING_DIR, "..", "..", "worlds"))
LINE = rt.CentreLine()


def test_centre_line_closes_smoothly():
    assert LINE.end.x_m == pytest.approx(0.0, abs=1e-9) and LINE.end.y_m == pytest.approx(0.0, abs=1e-9)
    assert LINE.end.yaw_rad == pytest.approx(2 * math.pi)   # one counter-clockwise turn
    assert LINE.length_m == pytest.approx(12.8 + 2 * math.pi * 1.6 + 2 * math.pi * 1.3)
    # positions are continuous at every segment boundary
    for s in LINE.start_s[1:]:
        a, b = LINE.pose_at(s - 1e-7), LINE.pose_at(s + 1e-7)
        assert math.hypot(a.x_m - b.x_m, a.y_m - b.y_m) < 1e-6
        assert a.yaw_rad == pytest.approx(b.yaw_rad, abs=1e-6)


def test_curvature_and_turning():
    assert LINE.curvature_at(3.0) == 0.0
    assert LINE.curvature_at(8.0) == pytest.approx(1 / 1.6)
    assert LINE.curvature_at(17.5) == pytest.approx(-1 / 1.3)   # the right-hand bend of the dip
    turning = sum(seg.angle_rad for seg in LINE.segments if isinstance(seg, rt.Arc))
    assert turning == pytest.approx(2 * math.pi)


def test_projection():
    for s in (0.3, 8.1, 17.2, 25.0, 30.9):
        for lateral in (-0.5, 0.0, 0.4):
            x, y = LINE.point_at(s, lateral)
            s2, lateral2 = LINE.project(x, y)
            assert s2 == pytest.approx(s, abs=0.01) and lateral2 == pytest.approx(lateral, abs=0.005)


def test_no_two_parts_of_the_track_overlap():
    # every point of the corridor is nearer to its own stretch of centre line than to any other
    samples = LINE.sample(0.05)
    for s, x, y, yaw in samples[::4]:
        for lateral in (-rt.HALF_WIDTH_M - rt.WALL_THICKNESS_M, rt.HALF_WIDTH_M + rt.WALL_THICKNESS_M):
            px, py = LINE.point_at(s, lateral)
            d = np.hypot(samples[:, 1] - px, samples[:, 2] - py)
            gap = np.abs((samples[:, 0] - s + LINE.length_m / 2) % LINE.length_m - LINE.length_m / 2)
            assert d[gap > 3.0].min() > rt.HALF_WIDTH_M + rt.WALL_THICKNESS_M + 0.1, (s, lateral)


def test_walls_follow_the_track_edges():
    boxes = rt.wall_boxes(LINE)
    assert len({b.name for b in boxes}) == len(boxes)
    for box in boxes:
        c, s = math.cos(box.yaw_rad), math.sin(box.yaw_rad)
        core = box.length_m - rt.WALL_THICKNESS_M          # the chord, without the overlap
        for t in np.linspace(-core / 2, core / 2, 5):
            x, y = box.centre_xy_m[0] + t * c, box.centre_xy_m[1] + t * s
            _, lateral = LINE.project(x, y)
            # the box's centre line lies half a wall thickness outside the corridor, to the sagitta
            assert abs(lateral) == pytest.approx(rt.HALF_WIDTH_M + rt.WALL_THICKNESS_M / 2,
                                                 abs=rt.WALL_MAX_SAGITTA_M + 0.006), box
    # every stretch of both edges has a wall: no gap the LiDAR could see through
    for s in np.arange(0.0, LINE.length_m, 0.05):
        for lateral in (-1, 1):
            x, y = LINE.point_at(s, lateral * (rt.HALF_WIDTH_M + rt.WALL_THICKNESS_M / 2))
            covered = False
            for box in boxes:
                dx, dy = x - box.centre_xy_m[0], y - box.centre_xy_m[1]
                along = dx * math.cos(box.yaw_rad) + dy * math.sin(box.yaw_rad)
                across = -dx * math.sin(box.yaw_rad) + dy * math.cos(box.yaw_rad)
                if abs(along) <= box.length_m / 2 and abs(across) <= rt.WALL_THICKNESS_M / 2 + rt.WALL_MAX_SAGITTA_M:
                    covered = True
                    break
            assert covered, (s, lateral)


def test_grid_fits_behind_the_start_line_on_the_main_straight():
    poses = rt.grid_poses(LINE)
    assert len(poses) == 16
    for k, p in enumerate(poses):
        s, lateral = LINE.project(p.x_m, p.y_m)
        assert 0.5 < s and s + rt.CAR_NOSE_M < rt.START_LINE_S_M, k  # on the straight, behind the line
        assert p.yaw_rad == 0.0 and abs(lateral) + 0.155 < rt.HALF_WIDTH_M - 0.2
    for a, b in zip(poses, poses[2:]):                                 # same column: 0.15 m between cars
        assert a.x_m - b.x_m - (rt.CAR_NOSE_M + 0.11) == pytest.approx(0.15, abs=1e-9)


def generated(path, fresh):
    """The committed file at `path`, parsed, once it is checked to be what the generator writes now."""
    with open(path) as f:
        text = f.read()
    assert text == fresh, "stale: run `rosrun conde_racing generate_racetrack`"
    return yaml.safe_load(text)


def test_world_file_is_generated_from_the_geometry():
    world = generated(os.path.join(WORLDS_DIR, rw.WORLD_FILE), rw.world_yaml(LINE))
    assert world["format"] == "conde_world/1" and world["name"] == "racetrack"
    assert set(world["spawn"]) == {"grid%d" % k for k in range(16)}
    walls = [o for o in world["objects"] if o["name"].startswith("wall_")]
    assert len(walls) == len(rt.wall_boxes(LINE)) and all(o["shape"] == "box" for o in walls)
    assert world["ground"]["texture"] == "../textures/racetrack.png"


def test_timing_file_is_generated_from_the_geometry():
    timing = generated(os.path.join(RACING_DIR, rw.TIMING_FILE), rw.timing_yaml(LINE))
    right, left = timing["start_line_m"]
    assert right == [rt.START_LINE_S_M, -rt.HALF_WIDTH_M] and left == [rt.START_LINE_S_M, rt.HALF_WIDTH_M]
    assert len(timing["checkpoints_m"]) == len(rt.CHECKPOINT_S_M)


def test_texture_is_the_rendering_and_shows_the_track():
    path = os.path.join(WORLDS_DIR, rw.TEXTURE_FILE)
    committed = cv2.imread(path, cv2.IMREAD_COLOR)
    fresh = rw.render_texture(LINE)
    assert committed is not None and committed.shape == fresh.shape == (400, 650, 3)
    # equal up to anti-aliasing differences between OpenCV builds
    assert np.mean(np.abs(committed.astype(int) - fresh.astype(int))) < 0.5, "stale: run generate_racetrack"

    def colour_at(x, y):
        col = int((x - rw.X_RANGE_M[0]) * rw.RESOLUTION_PX_PER_M)
        row = int((rw.Y_RANGE_M[1] - y) * rw.RESOLUTION_PX_PER_M)
        return tuple(int(v) for v in committed[row, col][::-1])     # RGB

    def expected(rgb):
        return tuple(int(round(255 * c)) for c in rgb)

    assert colour_at(3.1, 0.3) == expected(rw.ASPHALT_RGB)          # on the main straight
    assert colour_at(3.1, 1.2) == expected(rw.GRASS_RGB)            # infield
    assert colour_at(3.1, -1.0) == expected(rw.GRASS_RGB)           # outside
    assert colour_at(0.1, 0.0) == expected(rw.PAINT_RGB)            # a centre-line dash (0 .. 0.25 m)
    assert colour_at(0.4, 0.0) == expected(rw.ASPHALT_RGB)          # the gap after it
    squares = {colour_at(rt.START_LINE_S_M - 0.05, y) for y in (-0.65, -0.55)}
    assert squares == {expected(rw.PAINT_RGB), expected(rw.CHEQUER_DARK_RGB)}
