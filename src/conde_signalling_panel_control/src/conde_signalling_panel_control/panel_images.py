"""Pictures of the signalling-panel monitors, drawn with numpy/OpenCV (no image files).

Geometry from the measured pictures of the original simulator (its panel images,
1022 x 757 px, black background, flat colours, anti-aliased edges) and, for the end-of-trial
checkerboard, the competition rules' description of it. All coordinates below are reference pixels on the
1022 x 757 picture in *edge* coordinates: pixel column i covers [i, i+1), so the measured range
"x 481…819" is [481, 820). Other sizes scale x and y separately, as a texture stretched over the
screen would.

The original left.png is 1026 px wide and sits a few pixels higher than right.png; here left is
the exact mirror of right so the two differ only in direction.
"""
import math

import cv2
import numpy as np

from conde_signalling_panel_control.signals import SIGNAL_NAMES, unknown_signal_message

REFERENCE_SIZE_PX = (1022, 757)  # (width, height)
MIN_SIZE_PX = 16

GREEN_RGB = (0, 255, 0)
RED_RGB = (255, 0, 0)
YELLOW_RGB = (255, 255, 0)
CHECKER_GREEN_RGB = (0, 255, 42)  # #00FF2A of the end-of-trial checkerboard

# Right arrow (right.png): shaft x 203…542, y 315…453; head base at x 542 over y 118…653,
# tip at (820, 385).
RIGHT_ARROW_POLYGON = [(203, 315), (542, 315), (542, 118), (821, 386), (542, 654), (542, 454),
                       (203, 454)]
# Up arrow (up.png): head tip (510, 78), base at y 350 over x 246…774; shaft x 443…577, y 350…685.
UP_ARROW_POLYGON = [(510.5, 78), (775, 350), (578, 350), (578, 686), (443, 686), (443, 350),
                    (246, 350)]
# Stop (stop.png): two bars 131 px thick (perpendicular to their axis) along the diagonals of
# the box x 207…816, y 78…688, clipped flat by that box.
STOP_BOX = (207, 78, 817, 689)  # (x0, y0, x1, y1)
STOP_BAR_THICKNESS = 131.0
# Parking (parking.png): bold "P". Stem x 254…444, y 81…688; bowl y 81…465 reaching x 769 with
# a round right side; counter x 445…585, y 209…339 with a round right side.
P_STEM = (254, 81, 445, 689)
P_BOWL = (254, 81, 770, 466)
P_COUNTER = (445, 209, 586, 340)
# End of trial: 4 x 4 checkerboard, 49 % x 78 % of the screen, centred, top-left cell red.
CHECKER_CELLS = 4
CHECKER_WIDTH_FRACTION = 0.49
CHECKER_HEIGHT_FRACTION = 0.78

_SUBPIXEL_BITS = 4  # fixed-point vertices for cv2.fillPoly: 1/16 px


def draw_signal(signal, width_px=REFERENCE_SIZE_PX[0], height_px=REFERENCE_SIZE_PX[1]):
    """RGB uint8 picture (height_px x width_px x 3) of a signal name (see signals.SIGNAL_NAMES)."""
    if signal not in SIGNAL_NAMES:
        raise ValueError(unknown_signal_message(signal))
    for label, value in (("width_px", width_px), ("height_px", height_px)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < MIN_SIZE_PX:
            raise ValueError("%s must be an integer >= %d, got %r" % (label, MIN_SIZE_PX, value))
    canvas = _Canvas(int(width_px), int(height_px))
    _DRAWERS[signal](canvas)
    return canvas.image


class _Canvas:
    """An RGB image plus the scale from reference pixels to its pixels."""

    def __init__(self, width_px, height_px):
        self.image = np.zeros((height_px, width_px, 3), np.uint8)
        self.sx = width_px / REFERENCE_SIZE_PX[0]
        self.sy = height_px / REFERENCE_SIZE_PX[1]

    def fill(self, polygon, colour_rgb, image=None):
        """Fills a polygon given in reference edge coordinates, anti-aliased."""
        scale = 1 << _SUBPIXEL_BITS
        # Edge coordinate e of this image is pixel-centre coordinate e - 0.5 for OpenCV.
        points = np.array([[round((x * self.sx - 0.5) * scale), round((y * self.sy - 0.5) * scale)]
                           for x, y in polygon], np.int32)
        cv2.fillPoly(self.image if image is None else image, [points], colour_rgb,
                     lineType=cv2.LINE_AA, shift=_SUBPIXEL_BITS)

    def box_px(self, box):
        """A reference box (x0, y0, x1, y1) as whole pixels of this image (end exclusive)."""
        x0, y0, x1, y1 = box
        return (round(x0 * self.sx), round(y0 * self.sy), round(x1 * self.sx), round(y1 * self.sy))


def _draw_none(canvas):
    """All black: the monitors are on but show nothing."""


def _draw_right(canvas):
    canvas.fill(RIGHT_ARROW_POLYGON, GREEN_RGB)


def _draw_left(canvas):
    width = REFERENCE_SIZE_PX[0]
    canvas.fill([(width - x, y) for x, y in RIGHT_ARROW_POLYGON], GREEN_RGB)


def _draw_forward(canvas):
    canvas.fill(UP_ARROW_POLYGON, GREEN_RGB)


def _draw_stop(canvas):
    x0, y0, x1, y1 = STOP_BOX
    bars = np.zeros_like(canvas.image)
    for start, end in (((x0, y0), (x1, y1)), ((x1, y0), (x0, y1))):
        canvas.fill(_bar_polygon(start, end, STOP_BAR_THICKNESS), RED_RGB, image=bars)
    # Clip flat at the box, so each arm end is cut horizontally and vertically.
    bx0, by0, bx1, by1 = canvas.box_px(STOP_BOX)
    canvas.image[by0:by1, bx0:bx1] = bars[by0:by1, bx0:bx1]


def _bar_polygon(start, end, thickness):
    """A rectangle of the given thickness along start->end, lengthened past both ends so that
    clipping, not the bar's own end, shapes the arm ends."""
    (xa, ya), (xb, yb) = start, end
    length = math.hypot(xb - xa, yb - ya)
    ux, uy = (xb - xa) / length, (yb - ya) / length  # along the bar
    nx, ny = -uy * thickness / 2, ux * thickness / 2  # half thickness across it
    extra = thickness  # past each end
    xa, ya, xb, yb = xa - ux * extra, ya - uy * extra, xb + ux * extra, yb + uy * extra
    return [(xa + nx, ya + ny), (xb + nx, yb + ny), (xb - nx, yb - ny), (xa - nx, ya - ny)]


def _rounded_right(box, segments=48):
    """Outline of a box whose right side is a half circle of the box's half height."""
    x0, y0, x1, y1 = box
    radius = (y1 - y0) / 2
    cx, cy = x1 - radius, (y0 + y1) / 2
    arc = [(cx + radius * math.sin(math.pi * k / segments), cy - radius * math.cos(math.pi * k / segments))
           for k in range(segments + 1)]
    return [(x0, y0)] + arc + [(x0, y1)]


def _draw_parking(canvas):
    stem_x0, _, stem_x1, stem_y1 = P_STEM
    bowl = _rounded_right(P_BOWL)
    bowl_bottom = P_BOWL[3]
    # Outer outline: the bowl's outline, then down the stem's right side and back up its left.
    outline = bowl[:-1] + [(stem_x1, bowl_bottom), (stem_x1, stem_y1), (stem_x0, stem_y1)]
    canvas.fill(outline, YELLOW_RGB)
    canvas.fill(_rounded_right(P_COUNTER), (0, 0, 0))


def _draw_end_of_trial(canvas):
    height_px, width_px = canvas.image.shape[:2]
    board_w, board_h = CHECKER_WIDTH_FRACTION * width_px, CHECKER_HEIGHT_FRACTION * height_px
    xs = np.rint((width_px - board_w) / 2 + board_w * np.arange(CHECKER_CELLS + 1) / CHECKER_CELLS).astype(int)
    ys = np.rint((height_px - board_h) / 2 + board_h * np.arange(CHECKER_CELLS + 1) / CHECKER_CELLS).astype(int)
    for row in range(CHECKER_CELLS):
        for col in range(CHECKER_CELLS):
            colour = RED_RGB if (row + col) % 2 == 0 else CHECKER_GREEN_RGB
            canvas.image[ys[row]:ys[row + 1], xs[col]:xs[col + 1]] = colour


_DRAWERS = {
    "none": _draw_none,
    "left": _draw_left,
    "right": _draw_right,
    "forward": _draw_forward,
    "stop": _draw_stop,
    "end_of_trial": _draw_end_of_trial,
    "parking": _draw_parking,
}
