"""Lane measurement from Conde's two ground cameras.  Pure numpy, no ROS.

Pipeline per image pair:
  1. line pixels of both images (line_mask: bright in every channel, either >= white_threshold
     or, where the light is dimmer (a tunnel, a shadow), bright relative to the brightest pixel
     around them and well above the dark road around them) -> ground points in base_footprint
     through each camera's GroundMap (ipm.py);
  2. the lane centre ahead is modelled as y = c0 + c1 x + c2 x^2 in base_footprint (x forward,
     y left); its right line (solid edge line) lies right_line_offset_m and its left line (the
     dashed centre line) left_line_offset_m from it, measured along the normal.  Without a
     prior fit a coarse grid search picks the model that puts most white points on the two
     lines; then a few rounds of windowed least squares refine it with both lines together.
     Tracks differ (the rules allow +-5 % on the lane width, line widths of 5 to 10 cm): where
     both lines are seen over a long enough stretch, the distance between their centres is
     fitted too (within max_separation_change of the configured one) and kept, smoothed, for the
     frames that see only one line;
  3. lateral offset = signed distance from base_footprint to the centre curve (+ = robot left
     of it), heading error = -atan(c1) (+ = robot points left of the lane);
  4. line ends: where a line of the fit stops although the cameras see the ground of its band
     for end_gap_m further (at a junction the edge line turns away, the centre line ends), its
     distance ahead; the decision starts the junction's turns from it;
  5. which lane: a line whose band, seen by the cameras between its first and last point, has
     gaps (dashed_gap_share of it without the line) is the dashed centre line, one without (at
     most solid_gap_share) a solid edge line.  The fit's model puts the solid line on the right:
     the robot in the left lane (driving on the other side of the dashed line, e.g. passing an
     obstacle) sees the same pair mirrored, and the fit takes the dashed line for its right line.
     Then lane_index is 1 and the offset is measured from that lane's own centre (the lanes'
     centres lie left_line_offset_m on either side of the dashed line);
  6. crosswalk: along the lane, in its interior (between the lines), the share of white
     pixels per distance bin: a bar across the whole lane (share >= bar_share) followed by
     the stripes (share >= stripe_share), with observed black lane before the bar, is a
     crosswalk; its distance is the near edge of the bar.

Assumptions: flat ground; the robot drives in the right lane of a two-lane road (traffic on the
right); the lane bends slowly enough over the fitted range (fit_range_m) for a parabola.
Lane dimensions default to the competition track (worlds/tracks/competition_track.geometry.yaml:
lane_offset_m 0.391 = distance from the road's centre line to a lane centre, line_spacing_m
0.8065 = distance from the road's centre line to an edge line).
"""
import functools
import math
from dataclasses import dataclass, field
from typing import Optional, Sequence

import cv2
import numpy as np

from conde_tracking.ipm import GroundMap
from conde_common.pixel_tables import TableCache, threshold_table


@dataclass
class LaneConfig:
    right_line_offset_m: float = -(0.8065 - 0.391)  # centre of the solid edge line from the lane centre (+ = left)
    left_line_offset_m: float = 0.391  # centre of the dashed centre line from the lane centre
    white_threshold: int = 140  # [0..255] every RGB channel at least this: a line pixel in any light
    # Dimmer light (the tunnel's 0.35): a pixel is also a line pixel where its darkest channel is at
    # least relative_white of the brightest one within local_window_px, and that brightest one is
    # at least min_contrast above the darkest one within background_window_px (the road around).
    relative_white: float = 0.55
    min_contrast: int = 40  # [0..255]
    local_window_px: int = 9  # [px] (odd)
    background_window_px: int = 25  # [px] (odd), wider than the widest line seen near the robot
    fit_range_m: Sequence[float] = (0.0, 1.3)  # x range [m] of the points used for the lane fit
    near_weight_length_m: float = 0.4  # a point's fit weight is 1 / (1 + x / this)^2 [m]
    max_abs_y_m: float = 1.3  # points farther to the side are ignored [m]
    line_window_m: float = 0.06  # half width of the band around a predicted line centre [m]
    max_separation_change: float = 0.15  # the measured line separation stays within this share of the configured one
    min_separation_extent_m: float = 0.3  # each line seen over this x extent for the separation to be fitted [m]
    separation_smoothing: float = 0.2  # weight of a frame's measured separation in the kept one (0..1)
    min_line_points: int = 25  # white pixels for a line to count as found
    min_line_extent_m: float = 0.15  # ... spread over at least this distance along x [m]
    search_points: int = 1500  # points used by the coarse grid search (subsampled; 300 missed the lane at a crosswalk)
    search_candidates: int = 4  # a fit without prior refines this many of the search's best (unlike) models
    candidate_margin: float = 0.2  # ... and takes another than the best when its lines reach this share further
    # a line ends where its band is seen this far beyond its last point without it [m] (> a dash gap)
    end_gap_m: float = 0.25
    min_end_gap_points: int = 40  # ground pixels in that stretch of the band for it to count as seen
    crosswalk_range_m: Sequence[float] = (0.0, 1.6)  # x range [m] searched for the crosswalk
    crosswalk_bin_m: float = 0.02
    crosswalk_half_width_m: float = 0.25  # half width of the lane interior used [m]
    bar_share: float = 0.6  # share of white pixels in a bin across a bar
    min_bar_m: float = 0.04  # shortest bar thickness accepted [m]
    stripe_share: float = 0.1  # mean share of white behind the bar (the stripes)
    stripes_m: float = 0.2  # length behind the bar where the stripes are looked for [m]
    min_black_before_m: float = 0.06  # observed black lane before the bar [m]
    # Which line is dashed (the track: dashes 0.2 m, gaps 0.148 m, +-5 %): along a found line, bins
    # of style_bin_m where the ground within style_core_m of its centre is seen; the share of them
    # without a point of the line, between its first and last point seen over style_span_m at least.
    style_bin_m: float = 0.02  # [m]
    style_core_m: float = 0.012  # [m]
    min_style_span_m: float = 0.45  # [m] (more than a dash and a gap)
    dashed_gap_share: float = 0.2  # at least this share without the line: dashed (nominal about 0.4)
    # A fit from the prior whose heading moved more than this from the prior's within one frame is
    # checked against a fresh search, whose model is kept when its lines reach further [rad]
    prior_jump_rad: float = 0.35
    solid_gap_share: float = 0.08  # at most this share: solid


@dataclass
class LaneFit:
    """Lane centre y = c[0] + c[1] x + c[2] x^2 in base_footprint [m], and which lines supported it."""
    coeffs: np.ndarray
    right_found: bool
    left_found: bool


SOLID = "solid"
DASHED = "dashed"
UNKNOWN = ""
RIGHT_LANE = 0  # LaneResult.lane_index: the dashed line on the robot's left (traffic keeps right)
LEFT_LANE = 1  # the dashed line on the robot's right: the other lane
UNKNOWN_LANE = -1


@dataclass
class LaneResult:
    lateral_offset_m: float = float("nan")
    heading_error_rad: float = float("nan")
    confidence: float = 0.0
    crosswalk_seen: bool = False
    crosswalk_distance_m: float = float("nan")
    right_line_end_m: float = float("nan")  # x [m] where the right (edge) line ends ahead; NaN: runs on beyond view
    left_line_end_m: float = float("nan")  # ... the left (centre) line
    # ... the far line of the lane on the left (its outer edge line, one line separation beyond the
    # centre line): at a junction's left turn it turns left at the corner where the turn's arc begins
    far_left_line_end_m: float = float("nan")
    fit: Optional[LaneFit] = None
    right_line_style: str = UNKNOWN  # SOLID, DASHED or UNKNOWN: the fit's right line
    left_line_style: str = UNKNOWN
    lane_index: int = UNKNOWN_LANE  # RIGHT_LANE, LEFT_LANE or UNKNOWN_LANE: the lane measured
    # The lane measured: centre y = c0 + c1 x + c2 x^2 in base_footprint [m] (the fit's, shifted to
    # the left lane's own centre when lane_index is LEFT_LANE); None without a fit.
    centre_coeffs: Optional[np.ndarray] = None
    lane_spacing_m: float = float("nan")  # the two lanes' centres apart, from the measured line separation [m]
    right_points: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    left_points: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))


def white_mask(image, threshold):
    """Boolean (H, W) mask of white pixels: every channel >= threshold (mono images: the value)."""
    img = np.asarray(image)
    if img.ndim == 2:
        return img >= threshold
    return np.all(img >= threshold, axis=2)


def line_mask(image, config):
    """Boolean (H, W) mask of the pixels of white road markings in any light (LaneConfig's
    white_threshold, relative_white, min_contrast and the two windows).

    A white line under dimmer light is grey, but still much brighter than the black road next to
    it: a pixel counts when its darkest channel is >= white_threshold, or >= relative_white times
    the brightest darkest-channel value within local_window_px of it while that value is at least
    min_contrast above the road's level within background_window_px (the darkest 5 x 5 mean).
    Uniform road (also grey-level noise on it) has no such contrast; the wide background window
    reaches the road beside a wide line seen up close."""
    img = np.asarray(image)
    grey = img if img.ndim == 2 else _darkest_channel(img)
    grey = np.ascontiguousarray(grey, dtype=np.uint8)
    bright = cv2.dilate(grey, _square_kernel(config.local_window_px))
    # the road's level around: the darkest of the 5 x 5 means, so that single noisy pixels do not count
    smooth = cv2.blur(grey, (5, 5))
    dark = cv2.erode(smooth, _square_kernel(config.background_window_px))
    tables = _LINE_TABLES.get(config.relative_white, config.min_contrast)
    if tables is not None:  # the tests below as look-ups of thresholds (pixel_tables): the same results
        relative = (grey >= cv2.LUT(bright, tables[0])) & (bright >= cv2.LUT(dark, tables[1]))
    else:
        relative = (grey >= config.relative_white * bright) & (bright.astype(np.int16) - dark >= config.min_contrast)
    return (grey >= config.white_threshold) | relative


@functools.lru_cache(maxsize=16)
def _square_kernel(size):
    """np.ones((size, size), np.uint8), made once per size (read only)."""
    kernel = np.ones((size, size), np.uint8)
    kernel.setflags(write=False)
    return kernel


def _line_tables(relative_white, min_contrast):
    """line_mask's tests as thresholds: (least grey per bright, least bright per dark); None when a
    test is not of that form.  The operands cast as line_mask's (uint8 grey, bright and dark)."""
    u8 = np.uint8
    tables = (threshold_table(lambda grey, bright: grey.astype(u8) >= relative_white * bright.astype(u8), True),
              threshold_table(lambda bright, dark: bright.astype(u8).astype(np.int16) - dark.astype(u8)
                              >= min_contrast, True))
    return None if any(t is None for t in tables) else tables


_LINE_TABLES = TableCache(_line_tables)


def _darkest_channel(img):
    """img.min(axis=2), channel by channel: the same values, over ten times faster on an (H, W, 3)
    image (numpy reduces an axis of stride 3 slowly: 1.7 ms for 160 x 120 here, a seventh of a frame).
    8-bit images of 2 to 4 channels: OpenCV's split and min, the same values again in half the time."""
    if img.dtype == np.uint8 and img.ndim == 3 and 2 <= img.shape[2] <= 4 and img.size:
        planes = cv2.split(np.ascontiguousarray(img))
        darkest = planes[0]
        for plane in planes[1:]:
            darkest = cv2.min(darkest, plane)
        return darkest
    darkest = img[..., 0]
    for k in range(1, img.shape[2]):
        darkest = np.minimum(darkest, img[..., k])
    return darkest


def _line_positions(coeffs, x, offset_m):
    """y of the line offset_m (along the normal) from the centre curve, at the points' x.

    Uses the normal at x: the point at normal distance `offset` from (x, yc) lies at
    x - offset sin(a), yc + offset cos(a); evaluated at x to first order in the slope."""
    centre, k = _centre_and_normal_factor(coeffs, x)
    return centre + offset_m * k


def _centre_and_normal_factor(coeffs, x):
    """(centre curve y, sqrt(1 + slope^2)) at x: _line_positions(coeffs, x, offset_m) is
    centre + offset_m * factor, the same operations in the same order, so that several offsets
    share them."""
    slope = coeffs[1] + 2.0 * coeffs[2] * x
    return coeffs[0] + coeffs[1] * x + coeffs[2] * x * x, np.sqrt(1.0 + slope * slope)


def _ptp(values):
    """np.ptp(values) of an array (the same reductions: max - min), without its dispatch."""
    return values.max() - values.min()


def _histogram_of_sorted(sorted_values, edges):
    """np.histogram(values, edges)[0] of values already sorted ascending: the same counts, the
    same way (numpy sorts the values and counts them by binary search for an array of edges),
    without sorting them again. Edges that np.histogram refuses (not one increasing row of at least
    two) go to np.histogram, which raises its own error."""
    edges = np.asarray(edges)
    if edges.ndim != 1 or len(edges) < 2 or np.any(edges[1:] < edges[:-1]):
        return np.histogram(sorted_values, edges)[0]
    return np.diff(np.concatenate((sorted_values.searchsorted(edges[:-1], "left"),
                                   sorted_values.searchsorted(edges[-1:], "right"))))


class _ByX:
    """Points (N, 2) sorted by x (stably), so that the points within an x range are one slice
    found by binary search.  Only for what does not depend on the points' order (counts,
    histograms, extremes, percentiles)."""

    def __init__(self, points):
        points = np.asarray(points)
        self.points = points
        self.order = np.argsort(points[:, 0], kind="stable")
        self.x = np.ascontiguousarray(points[self.order, 0])
        self.y = np.ascontiguousarray(points[self.order, 1])

    def between(self, low, high, low_side="left", high_side="right"):
        """The slice of the sorted points with low <= x <= high (low_side "right": low < x;
        high_side "left": x < high)."""
        return slice(int(self.x.searchsorted(low, low_side)), int(self.x.searchsorted(high, high_side)))


@dataclass
class _Refined:
    """A refined lane model (LaneMeasurement._refine): its coefficients, which lines it found, the
    points in each line's band (masks), how far its found lines reach (support: style_bin_m bins
    along x holding points, both lines together), its separation [m]."""
    coeffs: np.ndarray
    right_found: bool
    left_found: bool
    right: np.ndarray
    left: np.ndarray
    support: int
    separation_m: float
    separation_fitted: bool


class LaneMeasurement:
    """Measures the lane from image pairs of two calibrated cameras (ground maps computed once)."""

    def __init__(self, ground_maps: Sequence[GroundMap], config: LaneConfig = LaneConfig()):
        self.ground_maps = list(ground_maps)
        self.config = config
        self._grid_axes = self._search_grid()
        # Lines at midline +- separation / 2 from the lane centre: the midpoint between the lines
        # stays as configured, the separation [m] is measured (see the module's docstring).
        self._midline_m = 0.5 * (config.right_line_offset_m + config.left_line_offset_m)
        self.configured_separation_m = config.left_line_offset_m - config.right_line_offset_m
        self.line_separation_m = self.configured_separation_m
        # The pixels that see the ground never change: their indices per map and their ground
        # points (all maps, in order) are taken once; a frame only reads its white flags.
        self._ground_pixels = []
        for gm in self.ground_maps:
            xy = gm.xy_m.reshape(-1, 2)
            self._ground_pixels.append(np.flatnonzero(np.isfinite(xy[:, 0])))
        self._ground_xy = np.concatenate([gm.xy_m.reshape(-1, 2)[i] for gm, i in
                                          zip(self.ground_maps, self._ground_pixels)]) \
            if self.ground_maps else np.zeros((0, 2))
        # ... and the same points sorted by x, for the per-frame statistics over x ranges
        self._ground_by_x = _ByX(self._ground_xy)
        self._ground_curve_of = None  # (coeffs bytes, centre, normal factor) at _ground_by_x: _curve_at

    @staticmethod
    def _search_grid():
        """The coarse search's models: every lateral offset c0 [m] x heading slope c1 x curvature/2
        c2 [1/m] (steps well inside line_window_m), as (c0 values, (c1, c2) pairs)."""
        c0 = np.arange(-0.30, 0.301, 0.03)
        c1 = np.tan(np.radians(np.arange(-40.0, 40.1, 4.0)))
        c2 = np.array([-0.8, -0.4, -0.2, 0.0, 0.2, 0.4, 0.8])
        shapes = np.stack(np.meshgrid(c1, c2, indexing="ij"), axis=-1).reshape(-1, 2)
        return c0, shapes

    def ground_white(self, images):
        """White ground points (N, 2) [m] of all images together, and all ground points (M, 2) with a
        white flag (M,) for the crosswalk search."""
        c = self.config
        flags = np.concatenate([line_mask(img, c).reshape(-1)[pixels]
                                for img, pixels in zip(images, self._ground_pixels)])
        # np.compress: the rows of the boolean index, in order, four times faster
        return np.compress(flags, self._ground_xy, axis=0), self._ground_xy, flags

    def _coarse_candidates(self, pts, count):
        """Up to `count` grid models (c0, c1, c2), the best first: those that put most points within
        line_window_m of their two lines, each unlike the ones before it (_alike).

        A point lies on the line `off` of model (c0, c1, c2) when |y - c1 x - c2 x^2 - off k - c0| <
        window (k = sqrt(1 + (c1 + 2 c2 x)^2)): for each (c1, c2) the residuals without c0 are
        sorted once and the points of every c0 counted by binary search, instead of testing each
        point against each of the grid's models."""
        c = self.config
        if len(pts) > c.search_points:
            pts = pts[np.linspace(0, len(pts) - 1, c.search_points).astype(int)]
        c0s, shapes = self._grid_axes
        x, y = pts[:, 0][None, :], pts[:, 1][None, :]
        c1, c2 = shapes[:, 0:1], shapes[:, 1:2]
        k = np.sqrt(1.0 + (c1 + 2 * c2 * x) ** 2)
        base = y - (c1 * x + c2 * x * x)
        # Rows side by side in one sorted array: row i's values shifted by i * spacing, far beyond
        # any residual, so that one binary search answers every row and c0 at once.
        spacing = 1000.0
        shift = (np.arange(len(shapes)) * spacing)[:, None]
        high = (shift + (c0s + c.line_window_m)[None, :]).ravel()
        low = (shift + (c0s - c.line_window_m)[None, :]).ravel()
        score = np.zeros(len(shapes) * len(c0s), dtype=np.int64)
        for offset in self.line_offsets(self.line_separation_m):
            r = (np.sort(base - offset * k, axis=1) + shift).ravel()
            score += np.searchsorted(r, high, "left") - np.searchsorted(r, low, "right")
        score = score.reshape(len(shapes), len(c0s))
        # The grid's order (c0 slowest, then c1, then c2) decides ties, as a search over it would.
        order = np.argsort(-score.T.reshape(-1), kind="stable")
        picked = []
        for index in order:
            c0_index, shape_index = divmod(int(index), len(shapes))
            model = np.array([c0s[c0_index], shapes[shape_index, 0], shapes[shape_index, 1]])
            if all(not self._alike(model, other) for other in picked):
                picked.append(model)
                if len(picked) == count:
                    break
        return picked

    def _alike(self, a, b) -> bool:
        """Two grid models whose lines lie within a line window of each other near the robot and
        whose headings differ by less than the grid's slope step: one model, for the candidates."""
        return (abs(a[0] - b[0]) < 2.0 * self.config.line_window_m
                and abs(math.atan(a[1]) - math.atan(b[1])) < math.radians(6.0))

    def line_offsets(self, separation_m):
        """(right, left) line-centre offsets [m] from the lane centre for a line separation [m]."""
        return self._midline_m - 0.5 * separation_m, self._midline_m + 0.5 * separation_m

    def _line_found(self, pts):
        return self._line_found_x(pts[:, 0])

    def _line_found_x(self, x):
        """_line_found of points given by their x values."""
        c = self.config
        return len(x) >= c.min_line_points and _ptp(x) >= c.min_line_extent_m

    def _sorted_by_x(self, everything) -> "_ByX":
        """everything (N, 2) sorted by x: computed once for the ground points of the ground maps."""
        return self._ground_by_x if everything is self._ground_xy else _ByX(everything)

    def _curve_at(self, coeffs, ground: "_ByX", part: slice):
        """_centre_and_normal_factor(coeffs, ground.x[part]).  For the ground maps' points it is
        computed at all of them once per fit and sliced (a frame's line styles, line ends and
        crosswalk search use the same fit): element by element the same values."""
        if (ground is not self._ground_by_x or not isinstance(coeffs, np.ndarray)
                or coeffs.dtype != np.float64 or coeffs.shape != (3,)):
            return _centre_and_normal_factor(coeffs, ground.x[part])
        key = coeffs.tobytes()
        if self._ground_curve_of is None or self._ground_curve_of[0] != key:
            self._ground_curve_of = (key,) + _centre_and_normal_factor(coeffs, ground.x)
        return self._ground_curve_of[1][part], self._ground_curve_of[2][part]

    def fit_lane(self, pts, prior: Optional[np.ndarray] = None):
        """LaneFit from white ground points (N, 2), starting from prior coefficients or, without
        one, from the coarse search's search_candidates best models, each refined.  Of these the
        first (the grid's best) is kept unless another one's found lines reach over candidate_margin
        more of the fit range (counted in style_bin_m bins along x): lane lines run on through the
        view, while the crosswalk's white stripes and bars fill the bands of many slanted models
        over its length only (standing at the crosswalk, the grid's best model on its subsampled
        points was one 40 deg off; the next frames' fits, started from it, kept it).  A fit from the
        prior that turned more than prior_jump_rad from it is replaced by the fresh search's when
        that one's lines reach further.
        Returns (fit or None, right-line points, left-line points)."""
        c = self.config
        sel = (pts[:, 0] >= c.fit_range_m[0]) & (pts[:, 0] <= c.fit_range_m[1]) & (np.abs(pts[:, 1]) <= c.max_abs_y_m)
        pts = np.compress(sel, pts, axis=0)  # pts[sel]
        empty = np.zeros((0, 2))
        if len(pts) < c.min_line_points:
            return None, empty, empty
        if prior is not None:
            best = self._best_of(pts, [np.asarray(prior, float).copy()])
            if best is not None and abs(math.atan(best.coeffs[1]) - math.atan(prior[1])) > c.prior_jump_rad:
                # One frame turned the fit further than the robot turns between frames: the prior's
                # bands lost a line to another one (Major Alvega, D1 south loop after the fork's wide
                # arc: both lines -> the outer line taken for the inner one, 1.2 rad in one frame).
                fresh = self._best_of(pts, self._coarse_candidates(pts, c.search_candidates))
                if fresh is not None and fresh.support > best.support:
                    best = fresh
        else:
            best = self._best_of(pts, self._coarse_candidates(pts, c.search_candidates))
        if best is None:
            return None, empty, empty
        if best.separation_fitted:
            self.line_separation_m += c.separation_smoothing * (best.separation_m - self.line_separation_m)
        return (LaneFit(best.coeffs, best.right_found, best.left_found), np.compress(best.right, pts, axis=0),
                np.compress(best.left, pts, axis=0))

    def _best_of(self, pts, starts) -> Optional["_Refined"]:
        """Each start refined; the first one's result unless another's found lines reach over
        candidate_margin more (support), then refined a few rounds more; None when none is found."""
        c = self.config
        first = best = None
        for start in starts:
            refined = self._refine(pts, start)
            if refined is None:
                continue
            if first is None:
                first = best = refined
            elif refined.support > max((1.0 + c.candidate_margin) * first.support, best.support):
                best = refined
        if best is not first:  # it started farther from where it ended: a few more rounds
            best = self._refine(pts, best.coeffs) or best
        return best

    def _refine(self, pts, coeffs) -> Optional["_Refined"]:
        """A few rounds of windowed least squares from coeffs, both lines together (and their
        separation, where both are seen long enough); None when no line is found."""
        c = self.config
        x, y = np.ascontiguousarray(pts[:, 0]), np.ascontiguousarray(pts[:, 1])
        right = left = np.zeros(len(pts), bool)
        separation_m, separation_fitted = self.line_separation_m, False
        use = right
        for window in (c.line_window_m, c.line_window_m, 0.75 * c.line_window_m, 0.75 * c.line_window_m):
            right_m, left_m = self.line_offsets(separation_m)
            # _line_positions of both lines, its centre curve and normal factor computed once
            centre, k_all = _centre_and_normal_factor(coeffs, x)
            right = np.abs(y - (centre + right_m * k_all)) < window
            left = np.abs(y - (centre + left_m * k_all)) < window
            x_right, x_left = x[right], x[left]
            found_r, found_l = self._line_found_x(x_right), self._line_found_x(x_left)
            use = (right & found_r) | (left & found_l)
            if not use.any():
                return None
            xu = x[use]
            k = k_all[use]
            side = np.where(right[use], -0.5, 0.5)  # the line's offset is midline + side * separation
            # one line only, or a short x extent: a parabola is not determined well; keep it straight
            degree = 2 if (found_r and found_l and _ptp(xu) > 0.6) else 1
            # columns 1, x (, x^2) and, for the separation, side * k
            design = np.empty((len(xu), degree + 2))
            design[:, 0] = 1.0
            design[:, 1] = xu
            if degree == 2:
                design[:, 2] = xu * xu
            design[:, degree + 1] = side * k
            A = design[:, :degree + 1]
            # Near points weigh more: the heading is wanted at the robot (x = 0), and a parabola
            # over the whole range bends toward a curve that begins (or ends) further ahead.
            sqrt_w = 1.0 / (1.0 + xu / c.near_weight_length_m)
            separation_fitted = (found_r and found_l and _ptp(x_right) >= c.min_separation_extent_m
                                 and _ptp(x_left) >= c.min_separation_extent_m)
            if separation_fitted:
                # the separation is one more unknown: y = centre(x) + (midline + side * separation) k
                sol = np.linalg.lstsq(design * sqrt_w[:, None],
                                      (y[use] - self._midline_m * k) * sqrt_w, rcond=None)[0]
                limit_m = c.max_separation_change * self.configured_separation_m
                separation_m = min(max(sol[-1], self.configured_separation_m - limit_m),
                                   self.configured_separation_m + limit_m)
                # outside the limits (other lines in the bands, e.g. at a junction): the centre is
                # fitted again below for the limit, and this frame's separation is not kept
                separation_fitted = separation_m == sol[-1]
                sol = sol[:-1]
            if not separation_fitted:
                target = y[use] - (self._midline_m + side * separation_m) * k  # centre-line y implied by each point
                sol = np.linalg.lstsq(A * sqrt_w[:, None], target * sqrt_w, rcond=None)[0]
            coeffs = np.zeros(3)
            coeffs[:degree + 1] = sol
        bins = [np.unique(np.floor(x[band] / c.style_bin_m)).size
                for band, found in ((right, found_r), (left, found_l)) if found]
        return _Refined(coeffs, bool(found_r), bool(found_l), right, left, int(sum(bins)),
                        separation_m, separation_fitted)

    def find_crosswalk(self, coeffs, everything, flags):
        """(seen, distance_m to the near edge of the crosswalk's first bar) along the fitted lane."""
        c = self.config
        # the points in the x range only, sorted by x (the counts and the percentile below do not
        # depend on the points' order)
        ground = self._sorted_by_x(everything)
        in_range = ground.between(c.crosswalk_range_m[0], c.crosswalk_range_m[1], "left", "left")
        x, y = ground.x[in_range], ground.y[in_range]
        flags = np.asarray(flags)[ground.order[in_range]]
        d = y - self._curve_at(coeffs, ground, in_range)[0]  # y - (c0 + c1 x + c2 x^2)
        sel = np.abs(d) < c.crosswalk_half_width_m
        edges = np.arange(c.crosswalk_range_m[0], c.crosswalk_range_m[1] + 1e-9, c.crosswalk_bin_m)
        total = _histogram_of_sorted(x[sel], edges)
        white = _histogram_of_sorted(x[sel & flags], edges)
        seen_bin = total >= 3
        share = np.where(seen_bin, white / np.maximum(total, 1), np.nan)
        is_bar = share >= c.bar_share
        n_bar = max(1, int(round(c.min_bar_m / c.crosswalk_bin_m)))
        n_black = max(1, int(round(c.min_black_before_m / c.crosswalk_bin_m)))
        n_stripes = max(1, int(round(c.stripes_m / c.crosswalk_bin_m)))
        is_bar = is_bar.tolist()  # the same flags, cheaper to read one by one
        n_bins = len(share)
        i = 0
        while i < n_bins:
            if not is_bar[i]:
                i += 1
                continue
            j = i
            while j < n_bins and is_bar[j]:
                j += 1
            before = share[max(0, i - n_black):i]
            behind = share[j:j + n_stripes]
            if (j - i >= n_bar and len(before) == n_black and np.all(before < c.stripe_share)
                    and len(behind) > n_stripes // 2 and np.nanmean(behind) >= c.stripe_share):
                # near edge: the nearest white interior pixels of the bar (pixel centres)
                in_bar = sel & flags & (x >= edges[max(0, i - 1)]) & (x < edges[j])
                return True, float(np.percentile(x[in_bar], 2)) if in_bar.any() else float(edges[i])
            i = j
        return False, float("nan")

    @staticmethod
    def next_prior(result: LaneResult) -> Optional[np.ndarray]:
        """The prior for the next frame: this frame's fit, also when it found one line only.  A
        fresh search with one line in view takes the strongest line parallel to the lane, e.g. a
        parking bay's border beside a thin edge line where the centre line has a gap at a junction;
        following the line fitted before keeps the lane."""
        return result.fit.coeffs if result.fit is not None else None

    def line_end(self, coeffs, offset_m, line_pts, everything):
        """x [m] of the last point of a line (offset_m from the centre curve) when its band is seen,
        without the line, for end_gap_m beyond it; NaN when the line runs on beyond the view (or
        the fit's range), or was not found."""
        c = self.config
        if not self._line_found(line_pts):
            return float("nan")
        end_m = float(line_pts[:, 0].max())
        if end_m + c.end_gap_m > c.fit_range_m[1]:
            return float("nan")
        ground = self._sorted_by_x(everything)
        beyond = ground.between(end_m + 0.02, end_m + c.end_gap_m, "right", "right")  # end + 0.02 < x <= end + gap
        centre, k = self._curve_at(coeffs, ground, beyond)
        in_band = np.abs(ground.y[beyond] - (centre + offset_m * k)) < c.line_window_m  # _line_positions
        return end_m if np.count_nonzero(in_band) >= c.min_end_gap_points else float("nan")

    def measure(self, images, prior: Optional[np.ndarray] = None) -> LaneResult:
        """LaneResult from one image per ground map (same order), optionally starting from the
        previous fit's coefficients."""
        pts, everything, flags = self.ground_white(images)
        fit, rpts, lpts = self.fit_lane(pts, prior)
        if fit is None and prior is not None:  # the lines left the prior's bands: search afresh
            fit, rpts, lpts = self.fit_lane(pts)
        if fit is None:
            return LaneResult()
        right_m, left_m = self.line_offsets(self.line_separation_m)
        right_style = self.line_style(fit.coeffs, right_m, rpts, everything)
        left_style = self.line_style(fit.coeffs, left_m, lpts, everything)
        lane_index = lane_index_of(right_style, left_style)
        centre = fit.coeffs.copy()
        if lane_index == LEFT_LANE:
            # the dashed line is the fit's right line: the left lane's centre lies left_m beyond it
            centre[0] += right_m + left_m
        c0, c1 = centre[0], centre[1]
        heading = -math.atan(c1)
        lateral = -c0 * math.cos(heading)
        seen, dist = self.find_crosswalk(fit.coeffs, everything, flags)
        conf = 0.5 * fit.right_found + 0.5 * fit.left_found
        right_end = self.line_end(fit.coeffs, right_m, rpts, everything)
        left_end = self.line_end(fit.coeffs, left_m, lpts, everything)
        far_end = self.far_left_line_end(fit, pts, everything)
        return LaneResult(lateral, heading, conf, seen, dist, right_end, left_end, far_end, fit, right_style,
                          left_style, lane_index, centre, 2.0 * left_m, rpts, lpts)

    def far_left_line_end(self, fit: LaneFit, pts, everything) -> float:
        """x [m] where the other lane's outer (left) edge line ends ahead, or NaN (runs on, not
        seen, or the lane's left line not fitted, which places it).  The line lies one line
        separation left of the centre line; the lane fit does not use it."""
        c = self.config
        if not fit.left_found:
            return float("nan")
        far_m = self.line_offsets(self.line_separation_m)[1] + self.line_separation_m
        x = pts[:, 0]
        band = (x >= c.fit_range_m[0]) & (x <= c.fit_range_m[1])
        band[band] = np.abs(pts[band, 1] - _line_positions(fit.coeffs, x[band], far_m)) < c.line_window_m
        return self.line_end(fit.coeffs, far_m, pts[band], everything)

    def line_style(self, coeffs, offset_m, line_pts, everything) -> str:
        """SOLID, DASHED or UNKNOWN for the line offset_m from the centre curve (its points line_pts
        of the fit): the share of the seen stretches of its centre between its first and last
        point that hold none of its points (see LaneConfig's style_* values)."""
        c = self.config
        if not self._line_found(line_pts):
            return UNKNOWN
        first_m, last_m = float(line_pts[:, 0].min()), float(line_pts[:, 0].max())
        if last_m - first_m < c.min_style_span_m:
            return UNKNOWN
        ground = self._sorted_by_x(everything)
        near = ground.between(first_m, last_m)  # first_m <= x <= last_m, sorted by x
        x = ground.x[near]
        centre, k = self._curve_at(coeffs, ground, near)
        core = np.abs(ground.y[near] - (centre + offset_m * k)) < c.style_core_m  # _line_positions
        edges = np.arange(first_m, last_m + c.style_bin_m, c.style_bin_m)
        seen = _histogram_of_sorted(x[core], edges) > 0
        holding = _histogram_of_sorted(np.sort(line_pts[:, 0]), edges) > 0
        if seen.sum() * c.style_bin_m < c.min_style_span_m / 2:
            return UNKNOWN
        gap_share = np.count_nonzero(seen & ~holding) / np.count_nonzero(seen)
        if gap_share >= c.dashed_gap_share:
            return DASHED
        if gap_share <= c.solid_gap_share:
            return SOLID
        return UNKNOWN


def lane_index_of(right_style: str, left_style: str) -> int:
    """The lane measured from the styles of the fit's right and left lines: RIGHT_LANE when the right
    line is solid or the left one dashed, LEFT_LANE when the right line is dashed or the left one
    solid, UNKNOWN_LANE when they disagree (both solid, both dashed) or neither is known."""
    votes = set()
    if right_style:
        votes.add(RIGHT_LANE if right_style == SOLID else LEFT_LANE)
    if left_style:
        votes.add(RIGHT_LANE if left_style == DASHED else LEFT_LANE)
    return votes.pop() if len(votes) == 1 else UNKNOWN_LANE
