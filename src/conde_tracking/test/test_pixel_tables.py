"""The table look-ups and sorted-point shortcuts of lane_measurement and obstacles give exactly the
results of the per-pixel and per-point computations they replace."""
from dataclasses import replace

import numpy as np
import pytest

from conde_tracking.lane_measurement import LaneConfig, _ByX, _histogram_of_sorted, line_mask
from conde_tracking.obstacles import ObstacleConfig, colour_masks
from conde_common.pixel_tables import threshold_table


def random_images(seed, count=20):
    rng = np.random.default_rng(seed)
    out = [rng.integers(0, 256, (120, 160, 3), dtype=np.uint8) for _ in range(count)]
    # dim images (the tunnel), and every pair of values side by side
    out += [(img // 3).astype(np.uint8) for img in out[:5]]
    a, b = np.meshgrid(np.arange(256), np.arange(256), indexing="ij")
    out.append(np.stack([a, b, (a + b) % 256], axis=-1).astype(np.uint8))
    out.append(np.stack([b, a, 255 - a], axis=-1).astype(np.uint8))
    return out


def colour_masks_per_pixel(img, c):
    r, g, b = (img[..., k].astype(np.int16) for k in range(3))
    green = (g >= c.min_level) & (g - np.maximum(r, b) >= c.green_dominance * g)
    lo, hi = c.orange_green_share
    orange = (r >= c.min_level) & (b <= c.orange_blue_share * r) & (g >= lo * r) & (g <= hi * r)
    return green, orange


def line_mask_per_pixel(img, config):
    import cv2
    grey = np.ascontiguousarray(img.min(axis=2) if img.ndim == 3 else img, dtype=np.uint8)
    bright = cv2.dilate(grey, np.ones((config.local_window_px, config.local_window_px), np.uint8))
    dark = cv2.erode(cv2.blur(grey, (5, 5)),
                     np.ones((config.background_window_px, config.background_window_px), np.uint8))
    relative = (grey >= config.relative_white * bright) & (bright.astype(np.int16) - dark >= config.min_contrast)
    return (grey >= config.white_threshold) | relative


@pytest.mark.parametrize("config", [ObstacleConfig(), ObstacleConfig(min_level=0, green_dominance=0.33),
                                    ObstacleConfig(orange_blue_share=1.7, orange_green_share=(0.0, 2.5)),
                                    ObstacleConfig(green_dominance=-0.2, orange_green_share=[0.1, 0.7])])
def test_colour_masks_are_the_per_pixel_tests(config):
    for img in random_images(1):
        for got, expected in zip(colour_masks(img, config), colour_masks_per_pixel(img, config)):
            assert got.dtype == bool and np.array_equal(got, expected)


@pytest.mark.parametrize("config", [LaneConfig(), replace(LaneConfig(), relative_white=0.3, min_contrast=0),
                                    replace(LaneConfig(), relative_white=1.3, min_contrast=-20),
                                    replace(LaneConfig(), relative_white=-0.5, min_contrast=300.5)])
def test_line_mask_is_the_per_pixel_test(config):
    for img in random_images(2):
        got = line_mask(img, config)
        assert got.dtype == bool and np.array_equal(got, line_mask_per_pixel(img, config))
        assert np.array_equal(line_mask(img[..., 1], config), line_mask_per_pixel(img[..., 1], config))


def test_a_test_without_a_threshold_gives_no_table():
    assert threshold_table(lambda a, b: (a + b) % 2 == 0, True) is None
    assert threshold_table(lambda a, b: a <= b, False).tolist() == list(range(256))
    assert threshold_table(lambda a, b: a > 300, True).tolist() == [256] * 256


def test_sorted_points_histograms_and_ranges():
    rng = np.random.default_rng(3)
    pts = np.round(rng.uniform(-0.5, 2.5, (5000, 2)), 2)  # many equal x values
    by_x = _ByX(pts)
    x = pts[:, 0]
    for low, high in [(0.0, 1.3), (0.31, 0.31), (-1.0, 5.0), (2.0, 1.0), (0.25, 0.5)]:
        for low_side, high_side in [("left", "right"), ("right", "right"), ("left", "left")]:
            inside = ((x >= low) if low_side == "left" else (x > low)) & \
                     ((x <= high) if high_side == "right" else (x < high))
            part = by_x.between(low, high, low_side, high_side)
            assert np.array_equal(np.sort(x[inside]), by_x.x[part])
            assert np.array_equal(np.sort(pts[inside, 1]), np.sort(by_x.y[part]))
        edges = np.arange(low, high + 0.02, 0.02)
        if len(edges) > 1:
            assert np.array_equal(_histogram_of_sorted(by_x.x, edges), np.histogram(x, edges)[0])
            assert np.array_equal(_histogram_of_sorted(np.sort(x[:10]), edges), np.histogram(x[:10], edges)[0])


def test_histogram_of_sorted_refuses_decreasing_edges_as_numpy_does():
    values = np.array([0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match="monotonically"):
        np.histogram(values, [0.0, 0.5, 0.25])
    with pytest.raises(ValueError, match="monotonically"):
        _histogram_of_sorted(values, [0.0, 0.5, 0.25])
    repeated = [0.0, 0.2, 0.2, 0.5]  # non-decreasing: an empty bin, as np.histogram allows
    assert np.array_equal(_histogram_of_sorted(values, repeated), np.histogram(values, repeated)[0])
