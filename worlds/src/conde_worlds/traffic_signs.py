"""Pictograms of the twelve vertical traffic signs of the V1 challenge, drawn by code.

Pure numpy + OpenCV, no ROS.  Simple, recognisable drawings in the three families of the
Portuguese road code (the signs of the original simulator's V1 world):

    danger (white triangle, red border):  other_danger, uneven_road, cattle, road_narrows
    information (blue square):            parking, recommended_60, hospital, pedestrian_crossing
    mandatory (blue disc):                turn_left, lights_on, roundabout, buses

Images are RGB, SIZE_PX square, on a light-grey plate (the back of the sign face).
"""

import math

import cv2
import numpy as np

# The names live in sign_names.py (no OpenCV for who only needs them); here for the drawing's users.
from .sign_names import DANGER, FAMILY, INFORMATION, MANDATORY, SIGNS  # noqa: F401

SIZE_PX = 128
RED = (255, 0, 0)
BLUE = (0, 117, 189)
WHITE = (255, 255, 255)
BLACK = (0, 0, 0)
PLATE = (200, 200, 200)

_AA = cv2.LINE_AA


def _pts(points):
    return np.array([[int(round(x)), int(round(y))] for x, y in points], np.int32)


def _text(img, text, centre, height_px, color, thickness):
    font = cv2.FONT_HERSHEY_SIMPLEX
    scale = height_px / 22.0
    (w, h), _ = cv2.getTextSize(text, font, scale, thickness)
    org = (int(centre[0] - w / 2), int(centre[1] + h / 2))
    cv2.putText(img, text, org, font, scale, color, thickness, _AA)


def _arrow(img, tail, tip, color, thickness, head_px):
    (x0, y0), (x1, y1) = tail, tip
    a = math.atan2(y1 - y0, x1 - x0)
    base = (x1 - head_px * math.cos(a), y1 - head_px * math.sin(a))
    cv2.line(img, (int(x0), int(y0)), (int(base[0]), int(base[1])), color, thickness, _AA)
    n = (-math.sin(a) * head_px * 0.8, math.cos(a) * head_px * 0.8)
    cv2.fillPoly(img, [_pts([tip, (base[0] + n[0], base[1] + n[1]), (base[0] - n[0], base[1] - n[1])])], color, _AA)


# --- families --------------------------------------------------------------------------------

def _danger_plate(img):
    s = SIZE_PX
    outer = _pts([(s / 2, 6), (s - 4, s - 14), (4, s - 14)])
    inner = _pts([(s / 2, 30), (s - 26, s - 26), (26, s - 26)])
    cv2.fillPoly(img, [outer], RED, _AA)
    cv2.fillPoly(img, [inner], WHITE, _AA)
    return (s / 2, 0.62 * s)  # centre of the pictogram area


def _info_plate(img):
    s = SIZE_PX
    cv2.rectangle(img, (6, 6), (s - 7, s - 7), BLUE, -1)
    cv2.rectangle(img, (6, 6), (s - 7, s - 7), BLACK, 1)
    return (s / 2, s / 2)


def _mandatory_plate(img):
    s = SIZE_PX
    cv2.circle(img, (s // 2, s // 2), s // 2 - 5, BLUE, -1, _AA)
    cv2.circle(img, (s // 2, s // 2), s // 2 - 5, WHITE, 3, _AA)
    return (s / 2, s / 2)


# --- pictograms --------------------------------------------------------------------------------

def _other_danger(img, c):
    cx, cy = c
    cv2.line(img, (int(cx), int(cy - 24)), (int(cx), int(cy + 4)), BLACK, 8, _AA)
    cv2.circle(img, (int(cx), int(cy + 15)), 5, BLACK, -1, _AA)


def _uneven_road(img, c):
    cx, cy = c
    xs = np.linspace(cx - 26, cx + 26, 40)
    # a road profile with a dip in the middle
    ys = cy + 6 + 10 * np.exp(-((xs - cx) / 9.0) ** 2)
    cv2.polylines(img, [_pts(zip(xs, ys))], False, BLACK, 5, _AA)
    cv2.rectangle(img, (int(cx - 26), int(cy + 10)), (int(cx + 26), int(cy + 20)), BLACK, -1)


def _cattle(img, c):
    cx, cy = c
    cv2.ellipse(img, (int(cx - 2), int(cy + 2)), (18, 9), 0, 0, 360, BLACK, -1, _AA)      # body
    cv2.ellipse(img, (int(cx + 20), int(cy - 4)), (6, 5), 0, 0, 360, BLACK, -1, _AA)      # head
    for dx in (-14, -8, 6, 12):                                                            # legs
        cv2.line(img, (int(cx + dx), int(cy + 8)), (int(cx + dx), int(cy + 20)), BLACK, 3, _AA)
    cv2.line(img, (int(cx + 22), int(cy - 9)), (int(cx + 26), int(cy - 14)), BLACK, 2, _AA)  # horn


def _road_narrows(img, c):
    cx, cy = c
    cv2.line(img, (int(cx - 14), int(cy + 20)), (int(cx - 14), int(cy - 22)), BLACK, 6, _AA)
    cv2.line(img, (int(cx + 16), int(cy + 20)), (int(cx + 16), int(cy + 2)), BLACK, 6, _AA)
    cv2.line(img, (int(cx + 16), int(cy + 2)), (int(cx + 4), int(cy - 10)), BLACK, 6, _AA)
    cv2.line(img, (int(cx + 4), int(cy - 10)), (int(cx + 4), int(cy - 22)), BLACK, 6, _AA)


def _parking(img, c):
    _text(img, "P", c, 70, WHITE, 9)


def _recommended_60(img, c):
    _text(img, "60", c, 52, WHITE, 8)


def _hospital(img, c):
    _text(img, "H", c, 70, WHITE, 9)


def _pedestrian_crossing(img, c):
    cx, cy = c
    cv2.fillPoly(img, [_pts([(cx, cy - 42), (cx + 44, cy + 38), (cx - 44, cy + 38)])], WHITE, _AA)
    for k in range(4):  # zebra stripes
        x = cx - 27 + k * 16
        cv2.rectangle(img, (int(x), int(cy + 26)), (int(x + 8), int(cy + 33)), BLACK, -1)
    cv2.circle(img, (int(cx), int(cy - 14)), 5, BLACK, -1, _AA)                  # head
    cv2.line(img, (int(cx), int(cy - 8)), (int(cx - 2), int(cy + 8)), BLACK, 4, _AA)     # body
    cv2.line(img, (int(cx - 2), int(cy + 8)), (int(cx - 10), int(cy + 22)), BLACK, 4, _AA)
    cv2.line(img, (int(cx - 2), int(cy + 8)), (int(cx + 8), int(cy + 22)), BLACK, 4, _AA)
    cv2.line(img, (int(cx - 10), int(cy - 2)), (int(cx + 10), int(cy + 2)), BLACK, 3, _AA)


def _turn_left(img, c):
    cx, cy = c
    _arrow(img, (cx + 30, cy), (cx - 34, cy), WHITE, 14, 26)


def _lights_on(img, c):
    cx, cy = c
    cv2.ellipse(img, (int(cx - 10), int(cy)), (14, 20), 0, 90, 270, WHITE, -1, _AA)
    cv2.rectangle(img, (int(cx - 10), int(cy - 20)), (int(cx - 2), int(cy + 20)), WHITE, -1)
    for dy in (-16, -5, 6, 17):  # beams
        cv2.line(img, (int(cx + 4), int(cy + dy)), (int(cx + 32), int(cy + dy + 4)), WHITE, 4, _AA)


def _roundabout(img, c):
    cx, cy = c
    for k in range(3):
        a0 = k * 120.0
        cv2.ellipse(img, (int(cx), int(cy)), (26, 26), 0, a0 + 20, a0 + 95, WHITE, 7, _AA)
        a = math.radians(a0 + 100)
        tip = (cx + 26 * math.cos(a), cy + 26 * math.sin(a))
        d = (-math.sin(a), math.cos(a))
        n = (math.cos(a), math.sin(a))
        back = (tip[0] - 12 * d[0], tip[1] - 12 * d[1])
        cv2.fillPoly(img, [_pts([(tip[0] + 3 * d[0], tip[1] + 3 * d[1]), (back[0] + 9 * n[0], back[1] + 9 * n[1]),
                                 (back[0] - 9 * n[0], back[1] - 9 * n[1])])], WHITE, _AA)


def _buses(img, c):
    cx, cy = c
    cv2.rectangle(img, (int(cx - 34), int(cy - 20)), (int(cx + 34), int(cy + 14)), WHITE, -1)
    for k in range(4):  # windows
        x = cx - 30 + k * 15
        cv2.rectangle(img, (int(x), int(cy - 15)), (int(x + 10), int(cy - 3)), BLUE, -1)
    for dx in (-20, 20):  # wheels
        cv2.circle(img, (int(cx + dx), int(cy + 16)), 7, WHITE, -1, _AA)
        cv2.circle(img, (int(cx + dx), int(cy + 16)), 3, BLUE, -1, _AA)


_PLATES = {"danger": _danger_plate, "information": _info_plate, "mandatory": _mandatory_plate}
_DRAW = {
    "other_danger": _other_danger, "uneven_road": _uneven_road, "cattle": _cattle, "road_narrows": _road_narrows,
    "parking": _parking, "recommended_60": _recommended_60, "hospital": _hospital,
    "pedestrian_crossing": _pedestrian_crossing, "turn_left": _turn_left, "lights_on": _lights_on,
    "roundabout": _roundabout, "buses": _buses,
}


def draw_sign(name: str) -> np.ndarray:
    """The sign `name` as an RGB image (SIZE_PX x SIZE_PX, uint8)."""
    if name not in _DRAW:
        raise ValueError("unknown traffic sign %r (expected one of: %s)" % (name, ", ".join(SIGNS)))
    img = np.full((SIZE_PX, SIZE_PX, 3), PLATE, np.uint8)
    centre = _PLATES[FAMILY[name]](img)
    _DRAW[name](img, centre)
    return img


def write_sign(name: str, path: str):
    if not cv2.imwrite(path, cv2.cvtColor(draw_sign(name), cv2.COLOR_RGB2BGR)):
        raise IOError("cannot write %s" % path)
