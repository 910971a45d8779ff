"""sign_recognition on top-camera images rendered by the simulator (test/data, written by
traffic_sign_accuracy --save-views: image, camera K, D and pose, the sign and its true position in
the robot frame) and on the drawings themselves."""
import glob
import math
import os

import cv2
import numpy as np
import pytest

from conde_traffic_sign.sign_recognition import Camera, find_signs
from conde_worlds import traffic_signs as ts

DATA = sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "*.npz")))


def test_rendered_views_cover_every_sign():
    assert {str(np.load(f)["sign"]) for f in DATA} == set(ts.SIGNS)


@pytest.mark.parametrize("path", DATA, ids=[os.path.basename(f) for f in DATA])
def test_rendered_view_is_recognised_and_located(path):
    view = np.load(path)
    camera = Camera(view["K"], view["D"], view["camera_to_base"])
    tx, ty = view["sign_xy_m"]
    detections = find_signs(view["image"], camera)
    near = sorted((math.hypot(d.x_m - tx, d.y_m - ty), d.name) for d in detections)
    assert near, "no sign found"
    error_m, name = near[0]
    assert name == str(view["sign"])
    assert error_m < 0.25, "position off by %.2f m" % error_m


@pytest.mark.parametrize("name", ts.SIGNS)
def test_drawing_on_a_plain_background_at_any_brightness(name):
    for brightness in (0.5, 1.0, 1.4):
        image = np.full((240, 320, 3), (70, 110, 60), np.uint8)
        image[90:126, 140:176] = cv2.resize(ts.draw_sign(name), (36, 36), interpolation=cv2.INTER_AREA)
        image = np.clip(image.astype(np.float32) * brightness, 0, 255).astype(np.uint8)
        found = find_signs(image)
        assert [d.name for d in found] == [name]
        assert math.isnan(found[0].x_m)  # no camera, no position


def test_nothing_in_an_image_without_signs():
    rng = np.random.default_rng(3)
    image = rng.integers(0, 255, (240, 320, 3), dtype=np.uint8)
    image[:120] = (200, 200, 200)
    assert find_signs(image) == []
