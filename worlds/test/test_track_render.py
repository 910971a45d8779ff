"""Measured facts checked on the rendered texture, and the committed files."""

import os

import cv2
import numpy as np
import pytest
import yaml

from conde_worlds import track_geometry as tg
from conde_worlds import track_render as tr
from conde_worlds.track_files import TEXTURE_FILE

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RES = tr.RESOLUTION_PX_PER_M
PX = 1.0 / RES
X0, X1 = tr.X_RANGE_M
Y0, Y1 = tr.Y_RANGE_M


@pytest.fixture(scope="module")
def track():
    return tg.build_track()


@pytest.fixture(scope="module")
def image(track):
    return tr.render_track(track)


@pytest.fixture(scope="module")
def grey(image):
    return image[:, :, 0]


def row_index(y):
    """Row whose pixel covers world y."""
    return int(np.floor((Y1 - y) * RES))


def col_index(x):
    return int(np.floor((x - X0) * RES))


def white_runs(values):
    """(first, last) indices of the runs of pixels >= 128."""
    w = np.concatenate([[False], np.asarray(values) >= 128, [False]])
    d = np.diff(w.astype(int))
    return list(zip(np.nonzero(d == 1)[0], np.nonzero(d == -1)[0] - 1))


def runs_along_row(grey, y, x_lo, x_hi):
    """White runs of the row at y as world x intervals (pixel edges), within [x_lo, x_hi]."""
    c0, c1 = col_index(x_lo), col_index(x_hi)
    return [(X0 + (c0 + a) * PX, X0 + (c0 + b + 1) * PX) for a, b in white_runs(grey[row_index(y), c0:c1])]


def runs_along_column(grey, x, y_lo, y_hi):
    """White runs of the column at x as world y intervals (pixel edges), within [y_lo, y_hi]."""
    r0, r1 = row_index(y_hi), row_index(y_lo)
    return sorted((Y1 - (r0 + b + 1) * PX, Y1 - (r0 + a) * PX) for a, b in white_runs(grey[r0:r1, col_index(x)]))


# --- image format ----------------------------------------------------------------------------

def test_image_format(image):
    assert image.shape == (3340, 1490, 3)
    assert image.dtype == np.uint8
    assert (image[:, :, 0] == image[:, :, 1]).all() and (image[:, :, 0] == image[:, :, 2]).all()
    # White on black, anti-aliased: mostly black, some intermediate values.
    assert np.mean(image[:, :, 0] == 0) > 0.9
    assert image.max() == 255
    assert np.any((image > 0) & (image < 255))


def test_pixel_mapping():
    assert tr.image_size() == (1490, 3340)
    x, y = tr.pixel_centre(0, 0)
    assert (x, y) == pytest.approx((X0 + PX / 2, Y1 - PX / 2))
    c, r = tr.world_to_pixel(x, y)
    assert (c, r) == pytest.approx((0.5, 0.5))


# --- the straight ----------------------------------------------------------------------------

def test_row_at_minus_two_metres_shows_the_three_lines(grey):
    runs = runs_along_row(grey, -2.0, 0.3, 2.8)
    expected = [(0.929, 1.014), (1.760, 1.796), (2.542, 2.626)]
    assert len(runs) == 3, runs
    for (a, b), (ea, eb) in zip(runs, expected):
        assert a == pytest.approx(ea, abs=PX) and b == pytest.approx(eb, abs=PX)


def test_lane_width(grey):
    runs = runs_along_row(grey, -2.0, 0.3, 2.8)
    assert runs[1][0] - runs[0][1] == pytest.approx(0.746, abs=PX)
    assert runs[2][0] - runs[1][1] == pytest.approx(0.746, abs=PX)


def test_solid_lines_north_of_the_crosswalk(grey):
    runs = runs_along_row(grey, 0.3, 0.3, 2.8)  # between the crosswalk and the first dash
    assert len(runs) == 2
    assert runs[0] == pytest.approx((0.929, 1.014), abs=PX)
    assert runs[1] == pytest.approx((2.542, 2.626), abs=PX)


def dashes(grey, x, y_lo, y_hi):
    runs = runs_along_column(grey, x, y_lo, y_hi)
    return [r for r in runs if r[0] > y_lo + 2 * PX and r[1] < y_hi - 2 * PX]  # complete dashes


@pytest.mark.parametrize("y_lo, y_hi", [(0.3, 1.99), (-1.99, -0.3)])
def test_dashed_centre_line(grey, y_lo, y_hi):
    d = dashes(grey, tg.X_REF, y_lo, y_hi)
    assert len(d) >= 4
    for a, b in d:
        assert b - a == pytest.approx(0.20, abs=PX)
    starts = np.array([a for a, _ in d])
    np.testing.assert_allclose(np.diff(starts), 0.348, atol=PX)


def test_dashes_start_one_gap_after_the_crosswalk(grey):
    north = dashes(grey, tg.X_REF, 0.3, 1.0)[0]
    south = dashes(grey, tg.X_REF, -1.0, -0.35)[-1]
    assert north[0] == pytest.approx(0.252 + 0.148, abs=PX)
    assert south[1] == pytest.approx(-0.340 - 0.148, abs=PX)


# --- crosswalk -------------------------------------------------------------------------------

def test_crosswalk_stripes(grey):
    runs = runs_along_row(grey, -0.044, 1.10, 2.45)
    assert len(runs) == 7
    centres = np.array([(a + b) / 2 for a, b in runs])
    np.testing.assert_allclose(centres, tg.CROSSWALK_STRIPE_X, atol=PX)
    for a, b in runs:
        assert 0.092 - PX <= b - a <= 0.099 + PX
    assert np.mean(np.diff(centres)) == pytest.approx(0.19, abs=0.002)
    np.testing.assert_allclose(np.diff(centres), 0.19, atol=0.003 + PX)  # measured 0.187 .. 0.190


def test_crosswalk_stripe_length_and_bars(grey):
    stripe = runs_along_column(grey, tg.CROSSWALK_STRIPE_X[2], -0.5, 0.5)
    bar_col = runs_along_column(grey, 1.49, -0.5, 0.5)  # between stripes 1 and 2
    assert len(bar_col) == 2
    assert bar_col[0] == pytest.approx((-0.340, -0.252), abs=PX)
    assert bar_col[1] == pytest.approx((0.155, 0.252), abs=PX)
    assert (-0.192, 0.104) in [pytest.approx(r, abs=PX) for r in stripe]
    # The bars span x 1.169 .. 2.387.
    bars = runs_along_row(grey, 0.2, 1.05, 2.5)
    assert bars == [pytest.approx((1.169, 2.387), abs=PX)]


# --- parking ---------------------------------------------------------------------------------

def test_parallel_parking(grey):
    # Along the bay: the east line is dashed, the outer line solid at x 3.373 .. 3.429.
    runs = runs_along_row(grey, 2.5, 2.3, 3.6)
    assert runs[-1] == pytest.approx((3.373, 3.429), abs=PX)
    d = dashes(grey, 2.5845, 0.6, 4.9)
    assert len(d) >= 10
    np.testing.assert_allclose(np.diff([a for a, _ in d]), 0.348, atol=PX)
    for a, b in d:
        assert b - a == pytest.approx(0.20, abs=PX)
    # South of the bulge the east line is solid again and nothing lies east of it.
    assert runs_along_row(grey, 0.2, 2.45, X1 - PX) == [pytest.approx((2.542, 2.626), abs=PX)]


def test_bay_parking_picture(grey):
    # Between the north border and the P: only the west and east borders.
    runs = runs_along_row(grey, -1.6, 2.7, X1 - PX)
    assert runs == [pytest.approx((2.875, 2.967), abs=PX), pytest.approx((3.848, 3.925), abs=PX)]
    # Along the middle: north border, P stem/bowl, divider, P, south border.
    col = runs_along_column(grey, 3.4, -3.2, -1.4)
    assert col[0] == pytest.approx((-3.1, -3.04), abs=PX)
    assert col[-1] == pytest.approx((-1.548, -1.5), abs=PX)
    assert pytest.approx((-2.321, -2.273), abs=PX) in col
    # Each bay has some paint (the P) inside it.
    for bay, ((xa, xb), (ya, yb)) in ((b, v) for b, v in [("north", ((2.967, 3.848), (-2.273, -1.548))),
                                                          ("south", ((2.967, 3.848), (-3.04, -2.321)))]):
        sub = grey[row_index(yb) + 2:row_index(ya) - 2, col_index(xa) + 2:col_index(xb) - 2]
        assert 0.1 < np.mean(sub > 128) < 0.3, bay


# --- loops -----------------------------------------------------------------------------------

def test_loop_west_side(grey):
    runs = runs_along_row(grey, tg.LOOP_CENTRE_Y, X0, 0.5)
    # outer line -3.429..-3.338, dashed -2.598..-2.556 (if a dash is there), island -1.817..-1.725
    assert runs[0] == pytest.approx((-3.429, -3.338), abs=0.01)
    assert runs[-1] == pytest.approx((-1.817, -1.725), abs=0.01)


def test_figure_eight_extent(grey):
    paint = grey >= 128
    rows = np.nonzero(paint.any(axis=1))[0]
    cols = np.nonzero(paint[:, :col_index(2.8)].any(axis=0))[0]  # without the parking areas
    top, bottom = Y1 - rows[0] * PX, Y1 - (rows[-1] + 1) * PX
    assert top == pytest.approx(8.3, abs=0.03) and bottom == pytest.approx(-8.3, abs=0.03)
    assert X0 + cols[0] * PX == pytest.approx(-3.429, abs=0.01)


def test_lane_centres_run_on_black_except_the_crosswalk(grey, track):
    for name, lc in track.lane_centres(0.01).items():
        c, r = tr.world_to_pixel(lc["xy"][:, 0], lc["xy"][:, 1])
        v = grey[r.astype(int), c.astype(int)]
        sec = np.array(lc["section"])
        y = lc["xy"][:, 1]
        near = (y > tg.CROSSWALK_Y[0] - 2 * PX) & (y < tg.CROSSWALK_Y[1] + 2 * PX)  # anti-aliased edge
        assert v[~near].max() == 0, name
        assert v[sec == "crosswalk"].max() == 255, name


def test_strokes_are_painted_without_seams(grey, track):
    """Every visible part of every stroke is fully white along its centre (joins between
    primitives included)."""
    for st in track.strokes:
        for a, b in st.intervals:
            if b - a < 4 * PX:
                continue
            s = np.arange(a + 1.5 * PX, b - 1.5 * PX, PX / 2)
            pts = st.prim.point(s)
            c, r = tr.world_to_pixel(pts[:, 0], pts[:, 1])
            assert grey[r.astype(int), c.astype(int)].min() == 255, st.name
        if st.join_end:  # across the join into the next stroke
            pts = st.prim.point(np.array([st.prim.length]))
            c, r = tr.world_to_pixel(pts[:, 0], pts[:, 1])
            if st.intervals[-1][1] >= st.prim.length - 1e-9:
                assert grey[int(r[0]), int(c[0])] == 255, st.name


# --- determinism and the committed texture ---------------------------------------------------

def test_render_is_deterministic(image, track):
    assert np.array_equal(image, tr.render_track(track))


def test_committed_texture_equals_a_fresh_render(image):
    path = os.path.join(PACKAGE_DIR, TEXTURE_FILE)
    committed = cv2.imread(path, cv2.IMREAD_COLOR)
    assert committed is not None, path
    assert committed.shape == image.shape
    assert np.array_equal(committed, image), "run scripts/generate_track and commit the result"
    assert os.path.getsize(path) < 400_000


def test_world_file_matches_the_texture():
    with open(os.path.join(PACKAGE_DIR, "worlds", "competition.world.yaml")) as f:
        world = yaml.safe_load(f)
    g = world["ground"]
    assert tuple(g["x_range_m"]) == tr.X_RANGE_M and tuple(g["y_range_m"]) == tr.Y_RANGE_M
    tex = os.path.normpath(os.path.join(PACKAGE_DIR, "worlds", g["texture"]))
    assert tex == os.path.join(PACKAGE_DIR, TEXTURE_FILE)
    assert g["friction"] == {"mu": 100, "mu2": 50}
    objects = {o["name"]: o for o in world["objects"]}
    assert objects["monitor_lcd1"]["pose"] == {"xyz": [1.4, 0.0, 1.0], "rpy": [2.006, 0.0, 3.1415]}
    assert objects["monitor_lcd2"]["pose"] == {"xyz": [2.2, 0.0, 1.0], "rpy": [2.006, 0.0, 0.0]}
    assert objects["monitor_lcd1"]["display_topic"] == "/monitor1/image1"
    assert objects["monitor_lcd2"]["display_topic"] == "/monitor2/image2"
    # Every other object stands off the road (or is above it, out of reach of the robots).
    track = tg.build_track()
    for name, o in objects.items():
        x, y, z = o["pose"]["xyz"]
        if not name.startswith("monitor") and z < 1.0:
            assert not track.on_road([[x, y]])[0], name
    for name, (x, y, z, yaw) in tg.SPAWNS.items():
        assert world["spawn"][name] == {"xyz": [x, y, z], "yaw": yaw}
