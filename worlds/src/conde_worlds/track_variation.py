"""Measures of the competition track: the nominal drawing (track seed 0) or one varied within the
rules' tolerance (track seed N > 0).

Pure Python, no ROS.  A :class:`TrackDimensions` holds every measure the track is built from
(track_geometry.Track) and rendered with (track_render); :func:`track_dimensions` gives them for a
track seed.  Seed 0 gives exactly the nominal constants of track_geometry (the committed texture
and geometry file).  A seed N > 0 draws, with random.Random(N) (the same track every time, on
every machine):

  solid line width        uniform in SOLID_WIDTH_RANGE_M (the rules: lines 5 to 10 cm wide)
  dashed line width, lane width, loop radius, fork (merge curve) radius, dash length, gap
                          each the nominal value times a factor uniform in 1 +- TOLERANCE
  stretch_y               1 +- TOLERANCE: the straight's length and every position along y
  stretch_x               1 +- TOLERANCE and within 1 +- TOLERANCE of stretch_y (the anisotropic
                          stretch): every position along x
  mat / line grey, noise  the mat's and the paint's grey levels and a per-pixel texture noise

Positions of the layout that are not built from the measures (the crosswalk, the parking areas,
the signs, the start poses, the panels) are carried over by :meth:`TrackDimensions.map_xy`: a
separable piecewise-linear map through anchors on the varied lines (road edges, lane centres, loop
centres and edges), so that a point keeps its place relative to the lines next to it.
"""

import bisect
import random
from dataclasses import dataclass
from typing import Tuple

from . import track_geometry as tg

#: Every varied measure stays within this fraction of its nominal value.
TOLERANCE = 0.05
#: Width of the solid (boundary) lines of a varied track [m].
SOLID_WIDTH_RANGE_M = (0.05, 0.10)
#: Grey levels (0..255) of a varied track's mat and paint, and of its per-pixel noise (std dev).
MAT_GREY_RANGE = (0.0, 30.0)
LINE_GREY_RANGE = (215.0, 255.0)
NOISE_GREY_RANGE = (2.0, 6.0)


@dataclass(frozen=True)
class TrackDimensions:
    """The measures of one track [m]; positions in the world frame (x east, y north)."""

    track_seed: int
    x_ref_m: float               # x of the straight's dashed centre line
    line_spacing_m: float        # road reference line -> centre of a boundary line
    solid_width_m: float
    dashed_width_m: float
    dash_on_m: float
    dash_off_m: float
    loop_radius_m: float
    loop_centre_y_m: float       # |y| of the loop centres = half the straight's length
    fork_radius_m: float
    stretch_x: float
    stretch_y: float
    crosswalk_x_m: Tuple[float, float]
    crosswalk_top_bar_y_m: Tuple[float, float]
    crosswalk_bottom_bar_y_m: Tuple[float, float]
    crosswalk_stripe_y_m: Tuple[float, float]
    crosswalk_stripe_x_m: Tuple[float, ...]
    crosswalk_stripe_width_m: float
    bulge_line_x_m: float
    bulge_line_width_m: float
    bulge_straight_y_m: Tuple[float, float]
    bulge_dashed_y_m: Tuple[float, float]
    bay_area_x_m: Tuple[float, float]
    bay_area_y_m: Tuple[float, float]
    bay_divider_y_m: Tuple[float, float]
    mat_grey: float = 0.0        # grey level 0..255 of the mat
    line_grey: float = 255.0     # grey level 0..255 of the paint
    noise_grey: float = 0.0      # std dev of the per-pixel grey noise
    _anchors_x: Tuple[Tuple[float, float], ...] = ()
    _anchors_y: Tuple[Tuple[float, float], ...] = ()

    # --- derived measures (the same formulas as track_geometry's constants) --------------------

    @property
    def lane_width_m(self) -> float:
        """Clear width between the inner edges of the lines."""
        return self.line_spacing_m - self.solid_width_m / 2.0 - self.dashed_width_m / 2.0

    @property
    def lane_offset_m(self) -> float:
        """Road reference line -> lane centre."""
        return self.dashed_width_m / 2.0 + self.lane_width_m / 2.0

    @property
    def road_half_width_m(self) -> float:
        return self.line_spacing_m + self.solid_width_m / 2.0

    @property
    def loop_centre_x_m(self) -> float:
        return self.x_ref_m - self.loop_radius_m

    @property
    def fork_y_m(self) -> float:
        return self.loop_centre_y_m - self.loop_radius_m - self.fork_radius_m

    @property
    def crosswalk_y_m(self) -> Tuple[float, float]:
        return (self.crosswalk_bottom_bar_y_m[0], self.crosswalk_top_bar_y_m[1])

    @property
    def bay_border_m(self) -> dict:
        return dict(tg.BAY_BORDER)

    @property
    def is_nominal(self) -> bool:
        return self.track_seed == 0

    # --- layout positions ------------------------------------------------------------------------

    def map_xy(self, x: float, y: float) -> Tuple[float, float]:
        """A point of the nominal layout carried over to this track (identity for seed 0)."""
        if self.is_nominal:
            return x, y
        return _piecewise(self._anchors_x, x, self.stretch_x), _piecewise(self._anchors_y, y, self.stretch_y)

    def summary(self) -> dict:
        """The varied values, for the challenge summary and reports (plain numbers, m)."""
        r = lambda v: round(float(v), 5)  # noqa: E731
        return {
            "track_seed": self.track_seed,
            "solid_line_width_m": r(self.solid_width_m),
            "dashed_line_width_m": r(self.dashed_width_m),
            "lane_width_m": r(self.lane_width_m),
            "loop_radius_m": r(self.loop_radius_m),
            "fork_radius_m": r(self.fork_radius_m),
            "straight_length_m": r(2.0 * self.loop_centre_y_m),
            "dash_m": r(self.dash_on_m),
            "gap_m": r(self.dash_off_m),
            "stretch_x": r(self.stretch_x),
            "stretch_y": r(self.stretch_y),
            "road_reference_x_m": r(self.x_ref_m),
            "mat_grey": r(self.mat_grey),
            "line_grey": r(self.line_grey),
            "noise_grey": r(self.noise_grey),
        }


def _piecewise(anchors, v: float, slope_outside: float) -> float:
    """Linear interpolation through (nominal, varied) anchors, slope_outside beyond the ends."""
    xs = [a for a, _ in anchors]
    if v <= xs[0]:
        return anchors[0][1] + (v - xs[0]) * slope_outside
    if v >= xs[-1]:
        return anchors[-1][1] + (v - xs[-1]) * slope_outside
    k = bisect.bisect_right(xs, v) - 1
    (a0, b0), (a1, b1) = anchors[k], anchors[k + 1]
    return b0 + (v - a0) * (b1 - b0) / (a1 - a0)


def _nominal() -> TrackDimensions:
    return TrackDimensions(
        track_seed=0, x_ref_m=tg.X_REF, line_spacing_m=tg.LINE_SPACING, solid_width_m=tg.SOLID_WIDTH,
        dashed_width_m=tg.DASHED_WIDTH, dash_on_m=tg.DASH_ON, dash_off_m=tg.DASH_OFF,
        loop_radius_m=tg.LOOP_RADIUS, loop_centre_y_m=tg.LOOP_CENTRE_Y, fork_radius_m=tg.FORK_RADIUS,
        stretch_x=1.0, stretch_y=1.0,
        crosswalk_x_m=tg.CROSSWALK_X, crosswalk_top_bar_y_m=tg.CROSSWALK_TOP_BAR_Y,
        crosswalk_bottom_bar_y_m=tg.CROSSWALK_BOTTOM_BAR_Y, crosswalk_stripe_y_m=tg.CROSSWALK_STRIPE_Y,
        crosswalk_stripe_x_m=tuple(tg.CROSSWALK_STRIPE_X), crosswalk_stripe_width_m=tg.CROSSWALK_STRIPE_WIDTH,
        bulge_line_x_m=tg.BULGE_LINE_X, bulge_line_width_m=tg.BULGE_LINE_WIDTH,
        bulge_straight_y_m=tg.BULGE_STRAIGHT_Y, bulge_dashed_y_m=tg.BULGE_DASHED_Y,
        bay_area_x_m=tg.BAY_AREA_X, bay_area_y_m=tg.BAY_AREA_Y, bay_divider_y_m=tg.BAY_DIVIDER_Y)


#: The nominal track (seed 0): the constants of track_geometry.
NOMINAL = _nominal()


def _anchors(d: TrackDimensions):
    """(nominal, varied) anchor positions in x and in y on the lines of d (ascending)."""

    def xs(t: TrackDimensions):
        rh, lo = t.road_half_width_m, t.lane_offset_m
        lcx, r = t.loop_centre_x_m, t.loop_radius_m
        return [lcx - r - rh, lcx - r + rh, lcx, t.x_ref_m - rh, t.x_ref_m - lo, t.x_ref_m,
                t.x_ref_m + lo, t.x_ref_m + rh]

    def ys(t: TrackDimensions):
        lcy, r, rh = t.loop_centre_y_m, t.loop_radius_m, t.road_half_width_m
        top = [lcy - r + rh, lcy, lcy + r + rh]  # island edge south of the loop centre, centre, outer edge
        return [-v for v in reversed(top)] + [0.0] + top

    ax = tuple(zip(xs(NOMINAL), xs(d)))
    ay = tuple(zip(ys(NOMINAL), ys(d)))
    for name, anchors in (("x", ax), ("y", ay)):
        for (a0, b0), (a1, b1) in zip(anchors[:-1], anchors[1:]):
            if not (a1 > a0 and b1 > b0):
                raise ValueError("track seed %d: the layout anchors in %s are not increasing" % (d.track_seed, name))
    return ax, ay


def track_dimensions(track_seed: int) -> TrackDimensions:
    """The measures of track `track_seed`: 0 = nominal, N > 0 = varied (see the module doc)."""
    if isinstance(track_seed, bool) or not isinstance(track_seed, int) or track_seed < 0:
        raise ValueError("track seed: expected an integer >= 0, got %r" % (track_seed,))
    if track_seed == 0:
        return NOMINAL
    rng = random.Random("conde_track/%d" % track_seed)

    def factor():
        return rng.uniform(1.0 - TOLERANCE, 1.0 + TOLERANCE)

    solid = rng.uniform(*SOLID_WIDTH_RANGE_M)
    dashed = tg.DASHED_WIDTH * factor()
    lane = tg.LANE_WIDTH * factor()
    radius = tg.LOOP_RADIUS * factor()
    fork = tg.FORK_RADIUS * factor()
    dash_on = tg.DASH_ON * factor()
    dash_off = tg.DASH_OFF * factor()
    sy = factor()
    sx = rng.uniform(max(1.0 - TOLERANCE, sy * (1.0 - TOLERANCE)), min(1.0 + TOLERANCE, sy * (1.0 + TOLERANCE)))
    mat = rng.uniform(*MAT_GREY_RANGE)
    line = rng.uniform(*LINE_GREY_RANGE)
    noise = rng.uniform(*NOISE_GREY_RANGE)
    # The lines first: the anchors of the layout map are on them.
    lines = TrackDimensions(
        track_seed=track_seed, x_ref_m=tg.X_REF * sx, line_spacing_m=dashed / 2.0 + lane + solid / 2.0,
        solid_width_m=solid, dashed_width_m=dashed, dash_on_m=dash_on, dash_off_m=dash_off,
        loop_radius_m=radius, loop_centre_y_m=tg.LOOP_CENTRE_Y * sy, fork_radius_m=fork,
        stretch_x=sx, stretch_y=sy,
        crosswalk_x_m=(), crosswalk_top_bar_y_m=(), crosswalk_bottom_bar_y_m=(), crosswalk_stripe_y_m=(),
        crosswalk_stripe_x_m=(), crosswalk_stripe_width_m=tg.CROSSWALK_STRIPE_WIDTH,
        bulge_line_x_m=0.0, bulge_line_width_m=tg.BULGE_LINE_WIDTH, bulge_straight_y_m=(), bulge_dashed_y_m=(),
        bay_area_x_m=(), bay_area_y_m=(), bay_divider_y_m=(), mat_grey=mat, line_grey=line, noise_grey=noise)
    ax, ay = _anchors(lines)
    probe = TrackDimensions(**{**lines.__dict__, "_anchors_x": ax, "_anchors_y": ay})

    def mx(values):
        return tuple(probe.map_xy(v, 0.0)[0] for v in values)

    def my(values):
        return tuple(probe.map_xy(0.0, v)[1] for v in values)

    return TrackDimensions(**{
        **probe.__dict__,
        "crosswalk_x_m": mx(tg.CROSSWALK_X), "crosswalk_top_bar_y_m": my(tg.CROSSWALK_TOP_BAR_Y),
        "crosswalk_bottom_bar_y_m": my(tg.CROSSWALK_BOTTOM_BAR_Y), "crosswalk_stripe_y_m": my(tg.CROSSWALK_STRIPE_Y),
        "crosswalk_stripe_x_m": mx(tg.CROSSWALK_STRIPE_X), "bulge_line_x_m": mx([tg.BULGE_LINE_X])[0],
        "bulge_straight_y_m": my(tg.BULGE_STRAIGHT_Y), "bulge_dashed_y_m": my(tg.BULGE_DASHED_Y),
        "bay_area_x_m": mx(tg.BAY_AREA_X), "bay_area_y_m": my(tg.BAY_AREA_Y),
        "bay_divider_y_m": my(tg.BAY_DIVIDER_Y)})


def varied_range(nominal: float) -> Tuple[float, float]:
    """The range a measure of nominal value `nominal` is drawn in."""
    return nominal * (1.0 - TOLERANCE), nominal * (1.0 + TOLERANCE)


def pixel_noise_seed(d: TrackDimensions) -> int:
    """Seed of the texture's per-pixel noise (numpy), a function of the track seed."""
    return 1000003 * d.track_seed + 17
