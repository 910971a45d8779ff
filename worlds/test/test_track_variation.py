"""Varied tracks (track_variation.py): every measure within the rules' tolerance, seed 0 the nominal
track byte for byte, the same seed the same track, the rendered lines as wide as drawn, and every
challenge object, the start poses and the referee's course on the varied lines."""

import math
import os

import numpy as np
import pytest

from conde_worlds import challenge_objects as co
from conde_worlds import track_geometry as tg
from conde_worlds import track_render as tr
from conde_worlds.challenge_world import challenge_world
from conde_worlds.challenges import ChallengeError, load_challenges
from conde_worlds.track_files import GEOMETRY_FILE, TEXTURE_FILE, geometry_yaml, write_track_files
from conde_worlds.track_variation import (NOMINAL, SOLID_WIDTH_RANGE_M, TOLERANCE, TrackDimensions, shading,
                                          track_dimensions)

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SEEDS = range(1, 201)
#: Seeds whose tracks are built (0.1 s each) and whose objects are checked on the lines.
BUILT_SEEDS = (1, 2, 3, 7, 13, 42, 99, 123, 150, 200)


def within(value, nominal, tol=TOLERANCE):
    return nominal * (1.0 - tol) - 1e-12 <= value <= nominal * (1.0 + tol) + 1e-12


@pytest.fixture(scope="module")
def challenges():
    return load_challenges()


@pytest.fixture(scope="module")
def tracks():
    return {s: tg.build_track(track_dimensions(s)) for s in BUILT_SEEDS}


# --- the measures ----------------------------------------------------------------------------------

def test_each_drawn_measure_stays_within_its_tolerance_over_200_seeds():
    for seed in SEEDS:
        d = track_dimensions(seed)
        what = "track seed %d: %s" % (seed, d.summary())
        assert SOLID_WIDTH_RANGE_M[0] <= d.solid_width_m <= SOLID_WIDTH_RANGE_M[1], what
        assert within(d.dashed_width_m, tg.DASHED_WIDTH), what
        assert within(d.lane_width_m, tg.LANE_WIDTH), what
        assert within(d.loop_radius_m, tg.LOOP_RADIUS), what
        assert within(d.fork_radius_m, tg.FORK_RADIUS), what
        assert within(2 * d.loop_centre_y_m, 2 * tg.LOOP_CENTRE_Y), what  # the straight's length
        assert within(d.dash_on_m, tg.DASH_ON) and within(d.dash_off_m, tg.DASH_OFF), what
        assert within(d.stretch_x, 1.0) and within(d.stretch_y, 1.0), what
        assert within(d.stretch_x / d.stretch_y, 1.0), what  # the anisotropy
        assert within(d.x_ref_m, tg.X_REF), what
        # The crosswalk stays between the straight's lines.
        inner = d.line_spacing_m - d.solid_width_m / 2.0
        assert d.x_ref_m - inner < d.crosswalk_x_m[0] and d.crosswalk_x_m[1] < d.x_ref_m + inner, what
        # The bay-parking area keeps its size within the tolerance, and its borders.
        assert within(d.bay_area_x_m[1] - d.bay_area_x_m[0], tg.BAY_AREA_X[1] - tg.BAY_AREA_X[0]), what
        assert within(d.bay_area_y_m[1] - d.bay_area_y_m[0], tg.BAY_AREA_Y[1] - tg.BAY_AREA_Y[0]), what
        # Slight grey levels: a dark mat, light paint, a few grey levels of noise.
        assert 0 <= d.mat_grey <= 30 and 215 <= d.line_grey <= 255 and 2 <= d.noise_grey <= 6, what
        assert 2 <= d.shading_grey <= 8 and len(d.shading_waves) == 3, what
        for kx, ky, _ in d.shading_waves:  # wavelengths 0.8 .. 4 m
            assert 0.8 - 1e-9 <= 2 * math.pi / math.hypot(kx, ky) <= 4.0 + 1e-9, what


def test_the_draws_cover_their_ranges():
    ds = [track_dimensions(s) for s in SEEDS]
    for name, nominal in (("lane_width_m", tg.LANE_WIDTH), ("loop_radius_m", tg.LOOP_RADIUS),
                          ("loop_centre_y_m", tg.LOOP_CENTRE_Y), ("dash_on_m", tg.DASH_ON)):
        values = np.array([getattr(d, name) for d in ds]) / nominal
        assert values.min() < 1.0 - 0.8 * TOLERANCE and values.max() > 1.0 + 0.8 * TOLERANCE, name
    solid = np.array([d.solid_width_m for d in ds])
    assert solid.min() < 0.055 and solid.max() > 0.095
    aniso = np.array([d.stretch_x / d.stretch_y for d in ds])
    assert aniso.min() < 0.97 and aniso.max() > 1.03


def test_the_built_track_has_the_drawn_measures(tracks):
    for seed, track in tracks.items():
        d = track.dims
        widths = {s.name.rsplit("_", 1)[0]: s.width for s in track.strokes}
        assert widths["central_west"] == d.solid_width_m and widths["north_loop_outer"] == d.solid_width_m
        assert widths["central_centre"] == d.dashed_width_m
        assert math.isclose(track.roads["central"].path.length, 2 * d.loop_centre_y_m)
        arc = track.roads["north_loop"].path.prims[0]
        assert math.isclose(arc.radius, d.loop_radius_m)
        # Clear lane width between the inner edges of the straight's west line and centre line.
        west = next(s for s in track.strokes if s.name.startswith("central_west"))
        x_west = west.prim.point(np.array([0.0]))[0, 0]
        lane = (d.x_ref_m - d.dashed_width_m / 2) - (x_west + d.solid_width_m / 2)
        assert math.isclose(lane, d.lane_width_m, abs_tol=1e-9), seed
        # Dashes of the centre line: each painted interval is one dash (or a cut one).
        dashes = [b - a for s in track.strokes if s.name.startswith("central_centre") for a, b in s.intervals]
        assert max(dashes) == pytest.approx(d.dash_on_m, abs=1e-9)


def test_seed_zero_is_the_nominal_track_byte_for_byte(tmp_path):
    assert track_dimensions(0) is NOMINAL
    png, geo = write_track_files(str(tmp_path), 0)
    for written, committed in ((png, TEXTURE_FILE), (geo, GEOMETRY_FILE)):
        with open(written, "rb") as a, open(os.path.join(PACKAGE_DIR, committed), "rb") as b:
            assert a.read() == b.read(), committed


def test_the_same_seed_gives_the_same_track_and_other_seeds_others():
    assert track_dimensions(7) == track_dimensions(7)
    a = geometry_yaml(tg.build_track(track_dimensions(7)))
    assert a == geometry_yaml(tg.build_track(track_dimensions(7)))
    assert a != geometry_yaml(tg.build_track(track_dimensions(8)))
    assert len({track_dimensions(s).lane_width_m for s in SEEDS}) == len(SEEDS)


@pytest.mark.parametrize("seed", [-1, 1.5, "3", True])
def test_a_bad_track_seed_is_an_error_naming_it(seed):
    with pytest.raises(ValueError, match="track seed: expected an integer >= 0"):
        track_dimensions(seed)


def test_a_bad_track_seed_of_a_challenge_names_it(challenges):
    with pytest.raises(ChallengeError, match="track seed: expected an integer >= 0, got 'x'"):
        challenge_world(challenges, "D1", None, 0, "x")


# --- rendering ---------------------------------------------------------------------------------------

def painted_run_px(grey_row, threshold):
    """Length [px] of the longest run of pixels brighter than threshold, with sub-pixel ends."""
    above = grey_row > threshold
    best, start = 0, None
    for i, a in enumerate(np.append(above, False)):
        if a and start is None:
            start = i
        elif not a and start is not None:
            best, start = max(best, i - start), None
    return best


@pytest.mark.parametrize("seed", [1, 2, 3, 42])
def test_rendered_lines_are_as_wide_as_drawn(tracks, seed):
    track = tracks[seed]
    d = track.dims
    res = tr.RESOLUTION_PX_PER_M
    y = -1.5  # on the straight, clear of the crosswalk and the parking areas' lines
    x_range = (d.x_ref_m - 1.2, d.x_ref_m + 1.2)
    image = tr.render_track(track, res, x_range, (y - 0.1, y + 0.1))
    assert np.array_equal(image, tr.render_track(track, res, x_range, (y - 0.1, y + 0.1)))  # deterministic
    assert np.array_equal(image[:, :, 0], image[:, :, 1])
    # The mat has the seed's grey level with its smooth shading and per-pixel noise ...
    cols, rows = np.arange(image.shape[1]), np.arange(image.shape[0])
    px, py = tr.pixel_centre(cols[None, :], rows[:, None], res, x_range, (y - 0.1, y + 0.1))
    shade = shading(d, px, py)
    assert np.abs(shade).max() <= d.shading_grey and np.abs(shade).max() > 0.05 * d.shading_grey
    grey = image[:, :, 0].astype(float) - shade  # ... taken off to measure the paint
    mat = grey[:, : int(0.2 * res)]
    assert abs(mat.mean() - d.mat_grey) < 1.0 and abs(mat.std() - d.noise_grey) < 1.0
    mid = 0.5 * (d.mat_grey + d.line_grey)
    # Average the rows of the window (the noise), then measure across the west line.
    profile = grey.mean(axis=0)
    west = profile[: int(1.0 * res)]  # x_ref - 1.2 .. x_ref - 0.2 m: the west line only
    width_px = painted_run_px(west, mid)
    assert abs(width_px - d.solid_width_m * res) <= 1.0, (seed, width_px, d.solid_width_m * res)
    assert abs(west.max() - d.line_grey) < 2.0
    # The line's centre column is where the geometry puts it.
    centre_col = np.mean(np.nonzero(west > mid)[0]) + 0.5
    x_centre = x_range[0] + centre_col / res
    assert abs(x_centre - (d.x_ref_m - d.line_spacing_m)) < 0.5 / res


def test_the_nominal_texture_has_no_noise():
    track = tg.build_track()
    image = tr.render_track(track, tr.RESOLUTION_PX_PER_M, (-3.0, -2.5), (-1.0, -0.5))
    assert image.max() == 0


# --- challenge objects on the varied lines ----------------------------------------------------------

def loop_radius_of(d, xy):
    """(loop, angle [deg], radius [m]) of a point about the nearest loop centre of the track d."""
    loop = "north" if xy[1] >= 0 else "south"
    cx, cy = co.loop_centre(loop, d)
    return loop, None, math.hypot(xy[0] - cx, xy[1] - cy)


def on_paint(track, xy, margin_m):
    """Whether a disc of radius margin_m at xy touches a painted interval of any stroke."""
    for stroke in track.strokes:
        s, lat = stroke.prim.project(np.array([xy], float))
        painted = any(a - margin_m <= s[0] <= b + margin_m for a, b in stroke.intervals)
        if painted and abs(lat[0]) <= stroke.width / 2.0 + margin_m:
            return True
    return False


def test_boxes_stay_in_their_lanes(challenges, tracks):
    for seed, track in tracks.items():
        d = track.dims
        for variant in ("v1", "v2"):
            world, _, _ = challenge_world(challenges, "D3", variant, 0, seed)
            for obj in world["objects"]:
                if not obj["name"].startswith("obstacle_"):
                    continue
                where = track.locate([obj["pose"]["xyz"][:2]])
                assert where["distance"][0] < 1e-3, (seed, obj)  # on a lane centre
                # The whole footprint between the lines of its lane.
                corners = track.locate(co.box_corners(obj))
                assert np.all(np.abs(corners["lateral"]) < d.lane_width_m / 2.0), (seed, obj["name"])


def test_parking_boxes_stay_in_their_bays(challenges, tracks):
    for seed, track in tracks.items():
        world, _, _ = challenge_world(challenges, "P2", None, 0, seed)
        for obj in (o for o in world["objects"] if o["name"].startswith("parked_box_")):
            assert track.in_parallel_parking(co.box_corners(obj)).all(), (seed, obj["name"])
        for bay in ("north", "south"):
            assert co.parking_bays(track.dims)[bay] == track.bays[bay]
            [box] = co.bay_box(bay, track.dims)
            assert track.in_bay(co.box_corners(box), bay).all(), (seed, bay)


def test_working_zone_cones_close_one_lane_and_the_tunnel_walls_stand_off_the_road(challenges, tracks):
    for seed, track in tracks.items():
        d = track.dims
        world, _, (_, _, _, layout) = challenge_world(challenges, "D4", "v1", 0, seed)
        features = layout["working_zone"]
        cones = [o for o in world["objects"] if o["name"].startswith("cone_")]
        assert cones
        for c in cones:
            xy = c["pose"]["xyz"][:2]
            assert track.on_road([xy], d.line_spacing_m - d.solid_width_m / 2.0)[0], (seed, c["name"])
            # In the closed lane (D4 v1: as in challenges.yaml), between its line and the divider,
            # CONE_DIVIDER_CLEARANCE_M inside them; along the divider off the divider's paint.
            _, _, r = loop_radius_of(d, xy)
            r_line = co.outer_line_radius(d) if features["lane"] == "outer" else co.island_line_radius(d)
            lo, hi = sorted((d.loop_radius_m, r_line))
            assert lo + co.CONE_DIVIDER_CLEARANCE_M - 1e-3 <= r <= hi - co.CONE_DIVIDER_CLEARANCE_M + 1e-3, (seed, c)
            if abs(r - d.loop_radius_m) < co.CONE_DIVIDER_CLEARANCE_M + 1e-3:
                assert not on_paint(track, xy, co.CONE_BASE_RADIUS_M), (seed, c["name"])
        walls = [o for o in world["objects"] if o["name"].startswith("tunnel_wall_")]
        for w in walls:
            assert not track.on_road(co.box_corners(w)).any(), (seed, w["name"])


def test_signs_panels_and_start_poses_keep_their_place_relative_to_the_lines(challenges, tracks):
    nominal = tg.build_track()
    nominal_signs = nominal.locate([p[:2] for p in co.SIGN_POSES])
    for seed, track in tracks.items():
        d = track.dims
        poses = co.sign_poses(d)
        where = track.locate([p[:2] for p in poses])
        assert not where["on_road"].any(), seed
        assert not track.in_parallel_parking([p[:2] for p in poses]).any()
        # The same side of the same road as on the nominal track, about as far from its lane.
        assert np.array_equal(np.sign(where["lateral"]), np.sign(nominal_signs["lateral"])), seed
        assert np.all(np.abs(where["distance"] - nominal_signs["distance"]) < 0.15), seed
        world, _, _ = challenge_world(challenges, "D1", None, 0, seed)
        for robot, pose in world["spawn"].items():
            at = track.locate([pose["xyz"][:2]])
            # The east lane, heading north, the nominal offset from its centre (< 5 cm).
            assert at["heading"][0] == pytest.approx(math.pi / 2) and at["distance"][0] < 0.05, (seed, robot)
            assert abs(pose["xyz"][1] - tg.SPAWNS["conde"][1]) < 0.6
        for panel in (o for o in world["objects"] if o["name"].startswith("monitor_")):
            assert track.on_road([panel["pose"]["xyz"][:2]])[0] and track.in_crosswalk([panel["pose"]["xyz"][:2]])[0]


def test_dimensions_are_a_frozen_record():
    with pytest.raises(Exception):
        NOMINAL.lane_width_m = 1.0  # noqa
    assert isinstance(track_dimensions(5), TrackDimensions)
