"""Recognises the signal on a signalling-panel monitor in one top-camera image (pure numpy/OpenCV).

The monitor shows flat, fully saturated colours on a black screen (conde_signalling_panel_control's
pictures): green arrows (left / right / forward), a red X (stop), a yellow P (parking) and a red and
green 4 x 4 checkerboard (end of trial); a black screen means none. Everything else the top camera
sees on the track (light-blue sky, grey monitor backs, black floor with white lines) is weakly
saturated, so the panel content is found as the largest blob of strongly saturated pixels, then
classified by its colours and, for a green arrow, by where its head is.

Assumptions: the content is seen roughly head-on (the robot faces the monitor within about 10 deg),
at least MIN_BLOB_AREA_PX pixels large (or MIN_SMALL_BLOB_AREA_PX on a dark screen: a monitor up to
5 m away), and the image is RGB (bgr=True for BGR). Brightness
scaling (0.6..1.4) and Gaussian noise (sigma up to ~0.03 of full scale) are tolerated because
the tests are on saturation (chroma relative to the brightest channel), not on absolute values.
"""
import functools
import math

import cv2
import numpy as np

from conde_common.panel_signals import SIGNAL_CODES, SIGNAL_NAMES  # noqa: F401 (re-exported)
from conde_common.pixel_tables import TableCache, threshold_table
from conde_signalling_panel_control.panel_images import draw_signal

MIN_CHROMA = 60.0          # max - min channel [0..255]; sky is ~50 at most, dimmed green ~150
MIN_SATURATION = 0.5       # chroma / max channel; sky and grey are below 0.3, the panel near 1
MIN_BLOB_AREA_PX = 40      # a saturated blob this large is taken for the panel content as it is
# A monitor far away (B1/B2 start 4.5..5.0 m before it: content 15..48 px, arrows the smallest) is
# taken too when its blob lies on the dark screen: most uncoloured pixels around and between its
# strokes are near black (a traffic sign's are white, the sky light blue), and it is not a solid
# patch of one colour (no one-colour picture of the panel fills its box).
MIN_SMALL_BLOB_AREA_PX = 12
SMALL_BLOB_MAX_FILL = 0.85     # larger share of its box: a solid patch
SCREEN_DARK_FRACTION = 0.35    # darker than this share of the content's brightness = the screen
SCREEN_MIN_DARK_SHARE = 0.6    # share of the uncoloured pixels of the box (+1 px) that must be dark
# Below this many pixels an arrow's head is only 2..5 px across, too few lines for the profile test
# (arrow_direction): the blob is compared with the panel's own arrow pictures instead
# (small_arrow_direction); full confidence when the best leads the second best by
# TEMPLATE_SURE_MARGIN in mean squared difference.
SMALL_ARROW_AREA_PX = 100
ARROWS = ("left", "right", "forward")
TEMPLATE_SIZE_PX = (320, 240)  # the panel pictures the templates are cut from (challenge.launch's size)
TEMPLATE_SURE_MARGIN = 0.05
MIXED_MIN_FRACTION = 0.15  # the checkerboard has at least this much of both red and green
YELLOW_MIN_FRACTION = 0.5  # the P is mostly yellow (red/green borders of the checkerboard are not)


def classify_panel(image, bgr=False, ground_from_row_fraction=None):
    """(signal name, confidence 0..1) for an RGB uint8 image (H x W x 3); bgr=True for BGR.

    ground_from_row_fraction: rows from this fraction of the image height down (the ground below
    the camera's horizon, where objects lower than the camera appear, e.g. a green box parked in
    a bay) are not searched for the panel; None searches the whole image."""
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] != 3:
        raise ValueError("expected an H x W x 3 colour image, got shape %s" % (image.shape,))
    if ground_from_row_fraction is not None:
        if not 0.0 < ground_from_row_fraction <= 1.0:
            raise ValueError("ground_from_row_fraction: expected a value in (0, 1], got %r"
                             % (ground_from_row_fraction,))
        image = image[:int(round(ground_from_row_fraction * image.shape[0]))]
    rgb = image[:, :, ::-1] if bgr else image
    blob = find_panel_blob(rgb)
    if blob is None:
        return "none", 1.0
    mask, colours = blob
    return classify_blob(mask, colours)


# The ratio tests of two 8-bit values as tables of thresholds over the brightest channel h
# (conde_common.pixel_tables: read off the int16 test itself for all 256 x 256 pairs).
_NOT_BLUE = threshold_table(lambda b, h: 2 * b < np.maximum(h, 1), upward=False)  # b <= t[h]
_AT_THREE_FIFTHS = threshold_table(lambda r, h: 5 * r >= 3 * np.maximum(h, 1), upward=True)  # r >= t[h]
_SATURATION = TableCache(lambda ratio: threshold_table(lambda c, h: c >= ratio * h, upward=True))


def _colour_classes_int16(rgb):
    """colour_classes in int16 arithmetic: for any image with at least three channels."""
    r, g, b = (rgb[:, :, k].astype(np.int16) for k in range(3))
    high = np.maximum(np.maximum(r, g), b)
    chroma = high - np.minimum(np.minimum(r, g), b)
    safe_high = np.maximum(high, 1)
    saturated = (chroma >= MIN_CHROMA) & (chroma >= MIN_SATURATION * high)
    candidate = saturated & (2 * b < safe_high)  # not blue
    is_yellow = candidate & (5 * r >= 3 * safe_high) & (5 * g >= 3 * safe_high)
    classes = np.where(candidate, np.where(r > g, np.uint8(1), np.uint8(2)), np.uint8(0))
    classes[is_yellow] = 3
    return classes


def colour_classes(rgb):
    """Per-pixel class: 0 not saturated, 1 red, 2 green, 3 yellow (uint8, H x W).

    The tests on ratios to the brightest channel (chroma >= MIN_SATURATION high, blue < 0.5, red
    and green >= 0.6) are done in integers (2 blue < high, 5 red >= 3 high, with high at least 1),
    which for 8-bit channels decides exactly as the ratios would, without a floating-point image:
    for a non-empty 8-bit H x W x 3 image as comparisons with threshold tables (conde_common.pixel_tables),
    otherwise in int16 (_colour_classes_int16)."""
    saturation = _SATURATION.get(MIN_SATURATION)
    if rgb.dtype != np.uint8 or rgb.ndim != 3 or rgb.shape[2] != 3 or rgb.size == 0 or saturation is None:
        return _colour_classes_int16(rgb)
    r, g, b = cv2.split(np.ascontiguousarray(rgb))
    high = cv2.max(cv2.max(r, g), b)
    chroma = cv2.subtract(high, cv2.min(cv2.min(r, g), b))
    saturated = (chroma >= math.ceil(MIN_CHROMA)) & (chroma >= cv2.LUT(high, saturation))
    candidate = saturated & (b <= cv2.LUT(high, _NOT_BLUE))  # not blue
    fifths = cv2.LUT(high, _AT_THREE_FIFTHS)
    is_yellow = candidate & (r >= fifths) & (g >= fifths)
    classes = np.where(candidate, np.where(r > g, np.uint8(1), np.uint8(2)), np.uint8(0))
    classes[is_yellow] = 3
    return classes


def find_panel_blob(rgb):
    """(mask of the panel content, colour classes) of the largest saturated blob that can be the
    panel's content, or None.

    Saturated pixels are closed with a 3 x 3 kernel so that the cells of the checkerboard and
    pixels split by noise join one blob. A blob of MIN_BLOB_AREA_PX or more is the content; a
    smaller one (down to MIN_SMALL_BLOB_AREA_PX: a monitor seen from 5 m) only if it is on a dark
    screen (on_dark_screen) and is not a solid patch of one colour."""
    classes = colour_classes(rgb)
    saturated = (classes > 0).astype(np.uint8)
    closed = cv2.morphologyEx(saturated, cv2.MORPH_CLOSE, np.ones((3, 3), np.uint8))
    count, labels, stats, _ = cv2.connectedComponentsWithStats(closed, connectivity=8)
    for label in 1 + np.argsort(-stats[1:, cv2.CC_STAT_AREA], kind="stable"):
        area = stats[label, cv2.CC_STAT_AREA]
        if area < MIN_SMALL_BLOB_AREA_PX:
            return None
        mask = labels == label
        if area >= MIN_BLOB_AREA_PX or (not _solid_one_colour(mask, classes, stats[label])
                                        and on_dark_screen(rgb, mask, classes, stats[label])):
            return mask, np.where(mask, classes, 0)
    return None


def _solid_one_colour(mask, classes, box_stats):
    """True for a blob of one colour class filling more than SMALL_BLOB_MAX_FILL of its box."""
    box_area = int(box_stats[cv2.CC_STAT_WIDTH]) * int(box_stats[cv2.CC_STAT_HEIGHT])
    present = np.unique(classes[mask & (classes > 0)])
    return len(present) == 1 and np.count_nonzero(mask) > SMALL_BLOB_MAX_FILL * box_area


def on_dark_screen(rgb, mask, classes, box_stats):
    """True when most uncoloured pixels of the blob's bounding box grown by 1 px are near black
    (below SCREEN_DARK_FRACTION of the content's median brightest channel)."""
    x, y, w, h = (int(box_stats[k]) for k in (cv2.CC_STAT_LEFT, cv2.CC_STAT_TOP, cv2.CC_STAT_WIDTH,
                                              cv2.CC_STAT_HEIGHT))
    rows = slice(max(y - 1, 0), y + h + 1)
    cols = slice(max(x - 1, 0), x + w + 1)
    brightest = rgb[rows, cols].max(axis=2).astype(np.float32)
    content = mask[rows, cols] & (classes[rows, cols] > 0)
    around = ~mask[rows, cols] & (classes[rows, cols] == 0)
    if not content.any() or not around.any():
        return False
    dark = brightest[around] < SCREEN_DARK_FRACTION * float(np.median(brightest[content]))
    return float(np.mean(dark)) >= SCREEN_MIN_DARK_SHARE


def classify_blob(mask, colours):
    """(signal name, confidence) of one blob from its colour fractions and its shape."""
    coloured = colours[mask]
    coloured = coloured[coloured > 0]
    total = max(len(coloured), 1)
    red = np.count_nonzero(coloured == 1) / total
    green = np.count_nonzero(coloured == 2) / total
    yellow = np.count_nonzero(coloured == 3) / total
    if yellow >= YELLOW_MIN_FRACTION:
        return "parking", yellow
    if min(red, green) >= MIXED_MIN_FRACTION:
        # Both colours in comparable amounts: the closer to half and half, the surer.
        return "end_of_trial", min(1.0, 2.0 * min(red, green) / (red + green) + 0.5)
    if red > green:
        return "stop", red / (red + green + yellow)
    if np.count_nonzero(mask) < SMALL_ARROW_AREA_PX:
        direction, margin = small_arrow_direction(mask)
    else:
        direction, margin = arrow_direction(mask)
    return direction, (green / (red + green + yellow)) * margin


def arrow_direction(mask):
    """("left" | "right" | "forward", confidence) of an arrow-shaped mask.

    The head of an arrow is much wider across the arrow than its shaft, so the widest cross
    section in the outer third at the head end is about three times that at the tail end, while
    across the arrow the profile is symmetric. Compares both axes and takes the more lopsided."""
    ys, xs = np.nonzero(mask)
    column_widths = _outer_third_widths(xs)  # (left third, right third): pixels per column
    row_widths = _outer_third_widths(ys)     # (top third, bottom third): pixels per row
    horizontal = np.log(column_widths[1] / column_widths[0])  # > 0: head on the right
    vertical = np.log(row_widths[0] / row_widths[1])          # > 0: head on top
    if abs(horizontal) >= abs(vertical):
        direction, strength, other = ("right" if horizontal > 0 else "left"), abs(horizontal), abs(vertical)
    elif vertical > 0:
        direction, strength, other = "forward", vertical, abs(horizontal)
    else:
        return "forward", 0.0  # a downward arrow is no signal of the panel: no confidence
    # A real arrow gives a log ratio near 1 on its axis and near 0 across it.
    confidence = float(np.clip((strength - other) / 0.5, 0.0, 1.0))
    return direction, confidence


@functools.lru_cache(maxsize=1)
def arrow_templates():
    """{arrow name: float32 mask of the panel's arrow picture cropped to the arrow}."""
    templates = {}
    for name in ARROWS:
        arrow = draw_signal(name, *TEMPLATE_SIZE_PX)[:, :, 1] > 127
        ys, xs = np.nonzero(arrow)
        templates[name] = arrow[ys.min():ys.max() + 1, xs.min():xs.max() + 1].astype(np.float32)
    return templates


def small_arrow_direction(mask):
    """("left" | "right" | "forward", confidence) of a small arrow-shaped mask: the arrow picture
    that, stretched over the mask's bounding box (as the screen is foreshortened) and averaged
    down to its pixels, differs least from it (mean squared difference). Confidence: the lead of
    the best over the second best, TEMPLATE_SURE_MARGIN or more = 1."""
    ys, xs = np.nonzero(mask)
    blob = mask[ys.min():ys.max() + 1, xs.min():xs.max() + 1].astype(np.float32)
    height, width = blob.shape
    differences = {name: float(np.mean((cv2.resize(template, (width, height), interpolation=cv2.INTER_AREA)
                                        - blob) ** 2))
                   for name, template in arrow_templates().items()}
    ranked = sorted(differences, key=differences.get)
    lead = differences[ranked[1]] - differences[ranked[0]]
    return ranked[0], float(min(1.0, lead / TEMPLATE_SURE_MARGIN))


def _outer_third_widths(along):
    """Widest cross section (90th percentile of the pixel count per line across the axis) in the
    first and in the last third of the blob's range along the axis (pixel coordinates `along`)."""
    low, high = along.min(), along.max()
    third = (high - low + 1) / 3.0
    widths = []
    for selected in (along < low + third, along > high - third):
        positions = along[selected]
        if len(positions) == 0:
            widths.append(1.0)
            continue
        counts = np.bincount(positions - low)
        widths.append(max(float(np.percentile(counts[counts > 0], 90)), 1.0))
    return widths


class Debouncer:
    """Reports a signal only once it was seen in `frames_required` consecutive frames.

    update() returns the debounced (signal, confidence): the last signal that was stable long
    enough (with the mean confidence over its stable run), or None before any signal was."""

    def __init__(self, frames_required=3):
        if isinstance(frames_required, bool) or not isinstance(frames_required, (int, np.integer)) \
                or frames_required < 1:
            raise ValueError("frames_required must be an integer >= 1, got %r" % (frames_required,))
        self.frames_required = int(frames_required)
        self.candidate = None
        self.run_confidences = []
        self.reported = None

    def update(self, signal, confidence=1.0):
        if signal != self.candidate:
            self.candidate = signal
            self.run_confidences = []
        self.run_confidences = (self.run_confidences + [float(confidence)])[-self.frames_required:]
        if len(self.run_confidences) >= self.frames_required:
            self.reported = (signal, sum(self.run_confidences) / len(self.run_confidences))
        return self.reported
