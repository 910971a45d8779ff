"""Rasterise the track geometry into a floor texture (white lines on black).

Each painted stroke is drawn analytically: for every pixel centre the distance across the
stroke and the position along it are computed exactly (lines and arcs), and the coverage is a
one-pixel linear ramp at every edge (box-filter approximation).  That gives anti-aliased edges
at the exact metric positions, with no dependence on a drawing library, and the result is
deterministic.

Image convention (same as the world file's ground texture): column 0 is at x_min, row 0 is at
y_max (image top = north); the pixel (row r, column c) covers
x in [x_min + c / res, x_min + (c + 1) / res] and y in [y_max - (r + 1) / res, y_max - r / res].
"""

import math
from typing import Tuple

import numpy as np

from .track_geometry import Track, build_track
from .track_variation import TrackDimensions, pixel_noise_seed

#: Default resolution and extent of the competition texture.  The extent is the original
#: 6.95 x 16.7 m floor plus 0.5 m on the east side for the bay-parking picture.
RESOLUTION_PX_PER_M = 200.0
X_RANGE_M = (-3.475, 3.975)
Y_RANGE_M = (-8.35, 8.35)
#: Extent of a varied track's texture (track seed > 0): 0.5 m more on every side, room for every
#: variation of track_variation (loops and parking areas move outwards by up to ~0.4 m).
VARIED_X_RANGE_M = (-3.975, 4.475)
VARIED_Y_RANGE_M = (-8.85, 8.85)


def texture_ranges(dims: TrackDimensions):
    """(x_range, y_range) [m] of the texture of a track with the measures dims."""
    if dims.is_nominal:
        return X_RANGE_M, Y_RANGE_M
    return VARIED_X_RANGE_M, VARIED_Y_RANGE_M


def image_size(resolution: float = RESOLUTION_PX_PER_M, x_range=X_RANGE_M, y_range=Y_RANGE_M) -> Tuple[int, int]:
    """(width, height) in pixels."""
    return (int(round((x_range[1] - x_range[0]) * resolution)),
            int(round((y_range[1] - y_range[0]) * resolution)))


def world_to_pixel(x, y, resolution: float = RESOLUTION_PX_PER_M, x_range=X_RANGE_M, y_range=Y_RANGE_M):
    """Continuous (column, row) of a world point; pixel centres are at integer + 0.5."""
    return ((np.asarray(x) - x_range[0]) * resolution, (y_range[1] - np.asarray(y)) * resolution)


def pixel_centre(col, row, resolution: float = RESOLUTION_PX_PER_M, x_range=X_RANGE_M, y_range=Y_RANGE_M):
    """World (x, y) of the centre of pixel (column, row)."""
    return (x_range[0] + (np.asarray(col) + 0.5) / resolution,
            y_range[1] - (np.asarray(row) + 0.5) / resolution)


def _ramp(v: np.ndarray) -> np.ndarray:
    return np.clip(v + 0.5, 0.0, 1.0)


def render_coverage(track: Track, resolution: float = RESOLUTION_PX_PER_M,
                    x_range=X_RANGE_M, y_range=Y_RANGE_M) -> np.ndarray:
    """Paint coverage 0..1 as a float (H, W) array."""
    width, height = image_size(resolution, x_range, y_range)
    cov = np.zeros((height, width))
    px = 1.0 / resolution

    def window(xa, xb, ya, yb):
        c0 = max(0, int(math.floor((xa - x_range[0]) * resolution)) - 1)
        c1 = min(width, int(math.ceil((xb - x_range[0]) * resolution)) + 1)
        r0 = max(0, int(math.floor((y_range[1] - yb) * resolution)) - 1)
        r1 = min(height, int(math.ceil((y_range[1] - ya) * resolution)) + 1)
        if c1 <= c0 or r1 <= r0:
            return None
        cols, rows = np.meshgrid(np.arange(c0, c1), np.arange(r0, r1))
        x, y = pixel_centre(cols, rows, resolution, x_range, y_range)
        return (slice(r0, r1), slice(c0, c1)), np.stack([x.ravel(), y.ravel()], axis=1), cols.shape

    for stroke in track.strokes:
        prim = stroke.prim
        for a, b in stroke.intervals:
            # Where the line continues in the next stroke, run 2 px past the join so that the two
            # strokes overlap at full coverage instead of meeting with two half-covered ends.
            if stroke.join_start and a <= 1e-9:
                a = -2 * px
            if stroke.join_end and b >= prim.length - 1e-9:
                b = prim.length + 2 * px
            n = max(2, int(math.ceil((b - a) / 0.01)) + 1)
            pts = prim.point(np.linspace(a, b, n))
            m = stroke.width / 2.0 + 2 * px
            win = window(pts[:, 0].min() - m, pts[:, 0].max() + m, pts[:, 1].min() - m, pts[:, 1].max() + m)
            if win is None:
                continue
            sl, xy, shape = win
            # Arcs: the along-stroke distance is measured on the centre circle (radial ends).
            s, lat = prim.project(xy)
            across = _ramp((stroke.width / 2.0 - np.abs(lat)) / px)
            along = _ramp(np.minimum(s - a, b - s) / px)
            c = (across * along).reshape(shape)
            np.maximum(cov[sl], c, out=cov[sl])

    for dot in track.dots:
        m = dot.radius + 2 * px
        win = window(dot.centre[0] - m, dot.centre[0] + m, dot.centre[1] - m, dot.centre[1] + m)
        if win is None:
            continue
        sl, xy, shape = win
        d = np.hypot(xy[:, 0] - dot.centre[0], xy[:, 1] - dot.centre[1])
        c = _ramp((dot.radius - d) / px).reshape(shape)
        np.maximum(cov[sl], c, out=cov[sl])
    return cov


def render_track(track: Track = None, resolution: float = RESOLUTION_PX_PER_M,
                 x_range=None, y_range=None) -> np.ndarray:
    """The texture as an (H, W, 3) uint8 RGB image: white paint on black for the nominal track;
    a varied track (track.dims) has its mat and paint grey levels and a per-pixel grey noise
    (normal, drawn with numpy from the track seed).  x_range, y_range default to
    texture_ranges(track.dims)."""
    if track is None:
        track = build_track()
    d = track.dims
    default_x, default_y = texture_ranges(d)
    x_range, y_range = x_range or default_x, y_range or default_y
    cov = render_coverage(track, resolution, x_range, y_range)
    if d.is_nominal:
        grey = np.rint(cov * 255.0).astype(np.uint8)
    else:
        value = d.mat_grey + cov * (d.line_grey - d.mat_grey)
        value += np.random.default_rng(pixel_noise_seed(d)).normal(0.0, d.noise_grey, cov.shape)
        grey = np.rint(np.clip(value, 0.0, 255.0)).astype(np.uint8)
    return np.repeat(grey[:, :, None], 3, axis=2)
