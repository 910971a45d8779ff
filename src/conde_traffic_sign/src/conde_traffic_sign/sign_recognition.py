"""Vertical traffic signs (V1) found and classified in a camera image, with their position.

Pure numpy + OpenCV, no ROS.  The faces are those of conde_worlds.traffic_signs: danger signs are
red-bordered triangles, information signs blue squares, mandatory signs blue discs.

1. Colour: pixels that are clearly red or clearly blue (HSV, saturation and hue), whatever the
   brightness, so a darker or brighter scene does not matter.
2. Shape: each connected red / blue region large enough is filled (its convex hull) and its fill
   of the bounding box must fit: a triangle ~0.5 (red), a disc ~0.79 or a square ~1.0 (blue).  The
   hull runs through the outer pixels' centres, so it is measured against the box between those
   centres ((w - 1) x (h - 1)): against w x h a 13 px disc filled 0.67 and was no sign.
3. Pictogram: the region's bounding box is resampled to a small square and compared (zero-mean
   normalised correlation) with the drawings of the danger signs (red) or of the information and
   mandatory signs (blue), cut to the same box; the best match names the sign and its family.  The
   bounding box absorbs the horizontal foreshortening of a face seen at an angle.  A box smaller
   than the comparison square is compared at its own size with the drawings shrunk to it, so that
   both have lost the same detail (an 11 px road_narrows matched the sharp other_danger best), and
   with each drawing shifted by half a pixel either way first (the box is whole pixels, the face is
   not): the best of the nine shifts counts.
4. Position: the face's known height [m] and its height in pixels give the range along the ray
   through the box centre (undistorted with the camera's plumb_bob coefficients); the point is
   returned in the robot frame with the camera's pose (camera_to_base, 4x4).
"""
import functools
from dataclasses import dataclass
from typing import List, Optional

import cv2
import numpy as np

from conde_worlds import traffic_signs as ts

#: Face edge [m] (conde_worlds challenge_objects.SIGN_SIZE_M); the coloured shape's size and
#: place on the face are measured on the drawings (_Drawings).
SIGN_FACE_M = 0.305
TEMPLATE_PX = 32            # side of the square the pictograms are compared at
MIN_SHAPE_PX = 10           # smallest shape height [px] looked at (about 5 m away with the top camera)
MIN_SATURATION = 110        # HSV saturation (0..255) of a sign colour
MIN_VALUE = 35              # HSV value (0..255): darker pixels are not judged by hue
MIN_SCORE = 0.3             # correlation below which a shape is no sign


@dataclass
class Camera:
    """Pinhole camera: K (3x3), plumb_bob D (k1 k2 p1 p2 k3), camera_to_base (4x4, optical frame
    z forward, x right, y down -> robot frame x forward, y left, z up) [m]."""
    K: np.ndarray
    D: np.ndarray
    camera_to_base: np.ndarray


@dataclass
class SignDetection:
    name: str               # one of conde_worlds.traffic_signs.SIGNS
    family: str             # danger | information | mandatory
    score: float            # correlation with the best drawing, -1..1
    x_m: float              # centre of the face in the robot frame [m]
    y_m: float
    z_m: float
    distance_m: float       # from the camera to the face centre [m]
    bearing_rad: float      # atan2(y, x) in the robot frame [rad], left positive
    box_px: tuple           # (x, y, w, h) of the shape in the image [px]


class _Drawings:
    """From the drawings of conde_worlds.traffic_signs, per family: the templates [(name, cut
    drawing as a zero-mean unit-norm vector)], the shape's height / the face's, and the offset
    of the face centre from the shape's box centre in shape heights (x right, y down)."""

    def __init__(self):
        self.templates, self.height_fraction, self.centre_offset = {}, {}, {}
        self.cuts = {}  # family -> [(name, the drawing cut to its shape's box, RGB)]
        for name in ts.SIGNS:
            img = ts.draw_sign(name)
            family = ts.FAMILY[name]
            red, blue = _colour_masks(img)
            x, y, w, h = cv2.boundingRect(red if family == "danger" else blue)
            self.templates.setdefault(family, []).append((name, _normalised(img[y:y + h, x:x + w])))
            self.cuts.setdefault(family, []).append((name, img[y:y + h, x:x + w]))
            self.height_fraction[family] = h / float(ts.SIZE_PX)
            centre = ts.SIZE_PX / 2.0
            self.centre_offset[family] = ((centre - (x + w / 2.0)) / h, (centre - (y + h / 2.0)) / h)


_DRAWINGS = None


def _drawings():
    global _DRAWINGS
    if _DRAWINGS is None:
        _DRAWINGS = _Drawings()
    return _DRAWINGS


#: shifts of a drawing [px of the box] before it is shrunk to a box under TEMPLATE_PX (quarter
#: pixels: the drawing is shifted at 4x the box's size by whole pixels)
SUBPIXEL_SHIFTS_PX = (-0.5, 0.0, 0.5)
if any(not float(4 * s).is_integer() for s in SUBPIXEL_SHIFTS_PX):
    raise ValueError("SUBPIXEL_SHIFTS_PX must be multiples of 0.25 px, got %s" % (SUBPIXEL_SHIFTS_PX,))


# One size's templates: 108 vectors of w x h x 3 float32, about 0.5 MB for a typical 16 x 24 px box and
# at most 2 MB (31 x 49 px); 256 sizes: about 130 MB, 500 MB at the very most.
@functools.lru_cache(maxsize=256)
def _templates_at(width_px, height_px):
    """The templates of the drawings at a box of width_px x height_px (boxes smaller than
    TEMPLATE_PX), each shifted by SUBPIXEL_SHIFTS_PX in x and y: family -> [(name, vector)]."""
    templates = {}
    for family, cuts in _drawings().cuts.items():
        for name, cut in cuts:
            # shifted at 4x the box's size, not at the drawing's (faster, the same templates)
            fine = (4 * width_px, 4 * height_px)
            finer = cv2.resize(cut, fine, interpolation=cv2.INTER_AREA)
            # A shift by whole pixels with the edges repeated: a window of the edge-padded image
            # (what cv2.warpAffine with BORDER_REPLICATE gives for these shifts, without resampling).
            pad = int(4 * max(abs(s) for s in SUBPIXEL_SHIFTS_PX))
            padded = cv2.copyMakeBorder(finer, pad, pad, pad, pad, cv2.BORDER_REPLICATE)
            for dx in SUBPIXEL_SHIFTS_PX:
                for dy in SUBPIXEL_SHIFTS_PX:
                    x0, y0 = pad - int(4 * dx), pad - int(4 * dy)
                    shifted = padded[y0:y0 + fine[1], x0:x0 + fine[0]]
                    small = cv2.resize(shifted, (width_px, height_px), interpolation=cv2.INTER_AREA)
                    templates.setdefault(family, []).append((name, _normalised(small, None)))
    return templates


def _normalised(patch_rgb, size_px=TEMPLATE_PX):
    """The patch resampled to size_px x size_px (None: as it is), zero-mean per channel, unit norm, flat."""
    small = (cv2.resize(patch_rgb, (size_px, size_px), interpolation=cv2.INTER_AREA) if size_px
             else patch_rgb).astype(np.float32)
    # per-channel brightness is normalised away: only the pattern counts
    small -= small.mean(axis=(0, 1), keepdims=True)
    norm = np.linalg.norm(small)
    return (small / norm).ravel() if norm > 0 else small.ravel()


def _colour_masks(image_rgb):
    """(red mask, blue mask) of the image, 255 where a danger sign's red or a blue sign's blue is
    (one HSV conversion for both)."""
    hsv = cv2.cvtColor(image_rgb, cv2.COLOR_RGB2HSV)
    h, s, v = hsv[:, :, 0], hsv[:, :, 1], hsv[:, :, 2]
    coloured = (s >= MIN_SATURATION) & (v >= MIN_VALUE)
    red = coloured & ((h <= 8) | (h >= 170))
    blue = coloured & (h >= 95) & (h <= 115)
    return red.astype(np.uint8) * 255, blue.astype(np.uint8) * 255


def _shape_families(filled_fraction, red):
    """The families a region's fill of its box allows: a triangle ~0.5 (red); a disc ~0.79 or a
    square ~1.0 (blue), told apart by the pictogram match, since a square seen at an angle and
    blurred fills less of its box."""
    if red:
        return ("danger",) if 0.35 <= filled_fraction <= 0.68 else ()
    return ("information", "mandatory") if filled_fraction >= 0.68 else ()


def classify_patch(patch_rgb, families):
    """(best sign name, its score) of a patch cut to the coloured shape's bounding box, among the
    signs of `families`."""
    h, w = patch_rgb.shape[:2]
    small = min(w, h) < TEMPLATE_PX
    vector = _normalised(patch_rgb, None if small else TEMPLATE_PX)
    templates = _templates_at(w, h) if small else _drawings().templates
    scores = [(float(vector @ t), name) for family in families for name, t in templates[family]]
    score, name = max(scores)
    return name, score


def locate(camera: Camera, box_px, family):
    """(x, y, z) [m] in the robot frame and the range [m] of a shape's box (x, y, w, h) [px]."""
    x, y, w, h = box_px
    drawings = _drawings()
    dx, dy = drawings.centre_offset[family]
    u, v = x + w / 2.0, y + h / 2.0
    pixels = np.array([[[u + dx * h, v + dy * h]], [[u, y]], [[u, y + h]]], np.float64)
    rays = cv2.undistortPoints(pixels, camera.K, camera.D).reshape(-1, 2)
    # the shape's height in normalised image units (undistorted; a vertical edge keeps its
    # height when the face turns about its vertical axis), then the depth along the optical axis
    height = abs(rays[2, 1] - rays[1, 1])
    depth_m = SIGN_FACE_M * drawings.height_fraction[family] / max(height, 1e-6)
    point_cam = np.array([rays[0, 0] * depth_m, rays[0, 1] * depth_m, depth_m, 1.0])
    p = camera.camera_to_base @ point_cam
    return p[:3], float(np.linalg.norm(point_cam[:3]))


def find_signs(image_rgb: np.ndarray, camera: Optional[Camera] = None,
               min_score: float = MIN_SCORE) -> List[SignDetection]:
    """The signs seen in an RGB image, largest first.  Without a camera the positions are NaN."""
    found = []
    for red, mask in zip((True, False), _colour_masks(image_rgb)):
        count, _, stats, _ = cv2.connectedComponentsWithStats(mask, connectivity=8)
        for label in range(1, count):
            x, y, w, h, area = stats[label]
            if h < MIN_SHAPE_PX or w < 0.25 * h or w > 1.6 * h:
                continue
            if x == 0 or y == 0 or x + w >= image_rgb.shape[1] or y + h >= image_rgb.shape[0]:
                continue  # cut by the image border: its shape and pictogram cannot be judged
            region = mask[y:y + h, x:x + w]
            contours, _ = cv2.findContours(region, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
            hull = cv2.convexHull(max(contours, key=cv2.contourArea))
            fill = cv2.contourArea(hull) / float(max(w - 1, 1) * max(h - 1, 1))
            families = _shape_families(fill, red)
            if not families:
                continue
            name, score = classify_patch(image_rgb[y:y + h, x:x + w], families)
            family = ts.FAMILY[name]
            if score < min_score:
                continue
            if camera is not None:
                (px, py, pz), distance = locate(camera, (x, y, w, h), family)
            else:
                px = py = pz = distance = float("nan")
            found.append(SignDetection(name, family, score, float(px), float(py), float(pz), distance,
                                       float(np.arctan2(py, px)), (int(x), int(y), int(w), int(h))))
    found.sort(key=lambda d: -d.box_px[3])
    return [d for i, d in enumerate(found) if not any(_inside(d.box_px, o.box_px) for o in found[:i])]


def _inside(box, outer):
    """A box within another (a blue hole of a pictogram, e.g. inside a '0', is no sign)."""
    x, y, w, h = box
    ox, oy, ow, oh = outer
    return x >= ox and y >= oy and x + w <= ox + ow and y + h <= oy + oh
