"""The panel pictures against the measured geometry of the original pictures.

Expected numbers are the measured ones of the original panel pictures and of the rules, written
out here rather than read from the module, at 1022 x 757 px; other sizes scale them.
Ranges are inclusive pixel indices (x0, x1, y0, y1).
"""
import numpy as np
import pytest

from conde_signalling_panel_control.panel_images import draw_signal

SIZES = [(1022, 757), (320, 240), (640, 480), (1600, 1200)]
REF_W, REF_H = 1022, 757
TOLERANCE_PX = 2  # OpenCV's anti-aliased fill grows a shape by up to about a pixel

EXPECTED_BBOX = {
    "right": (203, 820, 118, 653),   # right.png: shaft from x 203, tip at x 820, head y 118..653
    "left": (201, 818, 118, 653),    # the mirror of right.png in a 1022 px wide picture
    "forward": (246, 774, 78, 685),  # up.png: head base x 246..774, tip y 78, shaft to y 685
    "stop": (207, 816, 78, 688),     # stop.png: the box that clips the X
    "parking": (254, 769, 81, 688),  # parking.png: stem from x 254, bowl to x 769, y 81..688
}
EXPECTED_RGB = {"left": (0, 255, 0), "right": (0, 255, 0), "forward": (0, 255, 0), "stop": (255, 0, 0),
                "parking": (255, 255, 0)}


def scaled_range(first, last, scale):
    """An inclusive pixel range of the reference picture at another scale."""
    return first * scale, (last + 1) * scale - 1


def lit(image):
    """Pixels at least half covered by a shape."""
    return image.max(axis=2) >= 128


def bbox(mask):
    ys, xs = np.nonzero(mask)
    return xs.min(), xs.max(), ys.min(), ys.max()


@pytest.mark.parametrize("width, height", SIZES)
@pytest.mark.parametrize("signal", sorted(EXPECTED_BBOX))
def test_shape_colour_and_bounding_box(signal, width, height):
    image = draw_signal(signal, width, height)
    assert image.shape == (height, width, 3) and image.dtype == np.uint8
    sx, sy = width / REF_W, height / REF_H
    x0, x1, y0, y1 = EXPECTED_BBOX[signal]
    expected = scaled_range(x0, x1, sx) + scaled_range(y0, y1, sy)
    measured = bbox(lit(image))
    assert np.allclose(measured, expected, atol=TOLERANCE_PX), (measured, expected)
    # Flat colour on black: every pixel is the pure colour times a coverage (anti-aliasing).
    colour = np.array(EXPECTED_RGB[signal])
    coverage = image.max(axis=2).astype(float) / 255
    assert np.all(np.abs(image - coverage[..., None] * colour) <= 1)
    full = np.all(image == colour, axis=2)
    assert full.sum() > 0.9 * lit(image).sum()
    # Anti-aliased edges: some pixels partly covered.
    partial = (image.max(axis=2) > 0) & (image.max(axis=2) < 255)
    assert partial.sum() > 0


def centroid(mask):
    ys, xs = np.nonzero(mask)
    return xs.mean(), ys.mean()


@pytest.mark.parametrize("width, height", SIZES)
def test_arrows_point_the_right_way(width, height):
    for signal, direction in (("left", -1), ("right", 1)):
        mask = lit(draw_signal(signal, width, height))
        x0, x1, y0, y1 = bbox(mask)
        cx, _ = centroid(mask)
        # The head holds more area than the shaft: the centroid sits on the tip's side.
        assert (cx - (x0 + x1) / 2) * direction > 0.01 * width, signal
        tip_column = x0 if direction < 0 else x1
        tip_rows = np.nonzero(mask[:, tip_column])[0]
        assert abs(tip_rows.mean() - (y0 + y1) / 2) < 0.02 * height, signal
        assert tip_rows.size < 0.05 * height, signal  # a point, not the flat shaft end
    mask = lit(draw_signal("forward", width, height))
    x0, x1, y0, y1 = bbox(mask)
    _, cy = centroid(mask)
    assert (y0 + y1) / 2 - cy > 0.01 * height
    tip_columns = np.nonzero(mask[y0])[0]
    assert abs(tip_columns.mean() - (x0 + x1) / 2) < 0.02 * width
    assert tip_columns.size < 0.05 * width
    # The shaft (bottom row) is 135 of 1022 px wide.
    shaft_columns = np.nonzero(mask[y1])[0]
    assert abs(shaft_columns.size - 135 * width / REF_W) <= TOLERANCE_PX


@pytest.mark.parametrize("width, height", SIZES)
def test_left_and_right_are_mirror_images(width, height):
    left = draw_signal("left", width, height).astype(int)
    right = draw_signal("right", width, height).astype(int)
    difference = np.abs(left - right[:, ::-1])
    assert difference.max() <= 64  # anti-aliasing may round differently on the two sides
    assert difference.mean() < 0.5


@pytest.mark.parametrize("width, height", SIZES)
def test_stop_is_an_x_clipped_flat_by_its_box(width, height):
    image = draw_signal("stop", width, height)
    mask = lit(image)
    x0, x1, y0, y1 = bbox(mask)
    # The bars cross at the centre of the box.
    assert mask[(y0 + y1) // 2, (x0 + x1) // 2]
    # Top and bottom rows: two runs, touching the box's left and right edges (flat cut arms).
    for row in (y0, y1):
        columns = np.nonzero(mask[row])[0]
        runs = np.split(columns, np.nonzero(np.diff(columns) > 1)[0] + 1)
        assert len(runs) == 2
        assert runs[0][0] == x0 and runs[1][-1] == x1
    # Each bar is about 185 px wide measured horizontally (131 px perpendicular to its axis).
    quarter_row = y0 + (y1 - y0) // 4
    columns = np.nonzero(mask[quarter_row])[0]
    runs = np.split(columns, np.nonzero(np.diff(columns) > 1)[0] + 1)
    assert len(runs) == 2
    for run in runs:
        assert abs(run.size - 185 * width / REF_W) <= 0.06 * 185 * width / REF_W
    # The middle of the box's left edge is between the arms: black.
    assert not mask[(y0 + y1) // 2, x0]


@pytest.mark.parametrize("width, height", SIZES)
def test_parking_p_has_its_counter(width, height):
    image = draw_signal("parking", width, height)
    sx, sy = width / REF_W, height / REF_H

    def at(x, y):
        return tuple(image[int((y + 0.5) * sy), int((x + 0.5) * sx)])
    assert at(515, 274) == (0, 0, 0)        # inside the counter x 445..585, y 209..339
    assert at(349, 400) == (255, 255, 0)    # the stem x 254..444
    assert at(349, 600) == (255, 255, 0)    # the stem below the bowl
    assert at(650, 150) == (255, 255, 0)    # the bowl, right of the counter
    assert at(650, 600) == (0, 0, 0)        # below the bowl, right of the stem
    assert at(760, 100) == (0, 0, 0)        # outside the bowl's round top-right


@pytest.mark.parametrize("width, height", SIZES)
def test_end_of_trial_is_a_red_green_checkerboard(width, height):
    image = draw_signal("end_of_trial", width, height)
    colours = {tuple(c) for c in np.unique(image.reshape(-1, 3), axis=0)}
    assert colours == {(0, 0, 0), (255, 0, 0), (0, 255, 42)}
    x0, x1, y0, y1 = bbox(lit(image))
    assert abs((x1 - x0 + 1) - 0.49 * width) <= TOLERANCE_PX
    assert abs((y1 - y0 + 1) - 0.78 * height) <= TOLERANCE_PX
    assert abs((x0 + x1) / 2 - (width - 1) / 2) <= TOLERANCE_PX   # centred
    assert abs((y0 + y1) / 2 - (height - 1) / 2) <= TOLERANCE_PX
    cell_w, cell_h = (x1 - x0 + 1) / 4, (y1 - y0 + 1) / 4
    for row in range(4):
        for col in range(4):
            y = int(y0 + (row + 0.5) * cell_h)
            x = int(x0 + (col + 0.5) * cell_w)
            expected = (255, 0, 0) if (row + col) % 2 == 0 else (0, 255, 42)
            assert tuple(image[y, x]) == expected, (row, col)
    # Four cells along a row: three colour changes inside the board.
    middle_row = image[int(y0 + 0.5 * cell_h), x0:x1 + 1, 0]
    assert np.count_nonzero(np.diff(middle_row.astype(int))) == 3


@pytest.mark.parametrize("width, height", SIZES)
def test_none_is_black(width, height):
    image = draw_signal("none", width, height)
    assert image.shape == (height, width, 3)
    assert not image.any()


def test_bad_arguments():
    with pytest.raises(ValueError, match=r"unknown signal 'stp' \(expected one of: none, left"):
        draw_signal("stp")
    with pytest.raises(ValueError, match=r"width_px must be an integer >= 16, got 8"):
        draw_signal("stop", 8, 240)
    with pytest.raises(ValueError, match=r"height_px must be an integer >= 16, got 240.5"):
        draw_signal("stop", 320, 240.5)
