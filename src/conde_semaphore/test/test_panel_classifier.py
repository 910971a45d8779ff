"""panel_classifier on real top-camera images rendered by conde_sim (test/images, made with
scripts/render_panel_dataset), on brightness / noise / scale / shift variants of them, and on the
controller's own pictures; and the Debouncer."""
import csv
import os

import cv2
import numpy as np
import pytest

from conde_semaphore import panel_classifier as pc
from conde_semaphore.panel_classifier import SIGNAL_NAMES, Debouncer, classify_panel, colour_classes

IMAGES_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "images")


def load_dataset():
    with open(os.path.join(IMAGES_DIR, "labels.csv"), newline="") as labels:
        rows = list(csv.DictReader(labels))
    samples = []
    for row in rows:
        path = os.path.join(IMAGES_DIR, row["file"])
        bgr = cv2.imread(path, cv2.IMREAD_COLOR)
        assert bgr is not None, "cannot read %s" % path
        samples.append((row["file"], row["signal"], cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)))
    return samples


DATASET = load_dataset()
IDS = [name for name, _, _ in DATASET]


def degrade(image, brightness, noise_sigma, seed):
    rng = np.random.default_rng(seed)
    pixels = image.astype(np.float32) * brightness + rng.normal(0.0, noise_sigma * 255.0, image.shape)
    return np.clip(np.rint(pixels), 0, 255).astype(np.uint8)


def test_dataset_covers_every_signal_at_two_poses():
    labels = [signal for _, signal, _ in DATASET]
    assert sorted(set(labels)) == sorted(SIGNAL_NAMES)
    assert all(labels.count(name) >= 2 for name in SIGNAL_NAMES)
    assert all(image.shape == (240, 320, 3) for _, _, image in DATASET)


@pytest.mark.parametrize("name, signal, image", DATASET, ids=IDS)
def test_rendered_image_is_classified(name, signal, image):
    result, confidence = classify_panel(image)
    assert result == signal
    assert 0.5 <= confidence <= 1.0


@pytest.mark.parametrize("name, signal, image", DATASET, ids=IDS)
def test_bgr_input(name, signal, image):
    assert classify_panel(image[:, :, ::-1].copy(), bgr=True)[0] == signal


@pytest.mark.parametrize("brightness", [0.6, 0.8, 1.2, 1.4])
@pytest.mark.parametrize("noise_sigma", [0.0, 0.015, 0.03])
@pytest.mark.parametrize("name, signal, image", DATASET, ids=IDS)
def test_brightness_and_noise(name, signal, image, brightness, noise_sigma):
    seen = degrade(image, brightness, noise_sigma, seed=int(brightness * 100 + noise_sigma * 1000))
    result, confidence = classify_panel(seen)
    assert result == signal
    assert confidence >= 0.5


@pytest.mark.parametrize("scale", [0.75, 1.3])
@pytest.mark.parametrize("name, signal, image", DATASET, ids=IDS)
def test_monitor_smaller_or_larger(name, signal, image, scale):
    """The image zoomed about its centre, as if the monitor were farther or nearer."""
    height, width = image.shape[:2]
    zoom = cv2.getRotationMatrix2D((width / 2, height / 2), 0.0, scale)
    seen = cv2.warpAffine(image, zoom, (width, height), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    assert classify_panel(seen)[0] == signal


@pytest.mark.parametrize("shift_px", [(-60, 40), (60, -40)])  # keeps every panel in the frame
@pytest.mark.parametrize("name, signal, image", DATASET, ids=IDS)
def test_monitor_off_centre(name, signal, image, shift_px):
    dx, dy = shift_px
    move = np.float32([[1, 0, dx], [0, 1, dy]])
    seen = cv2.warpAffine(image, move, (image.shape[1], image.shape[0]), borderMode=cv2.BORDER_REPLICATE)
    assert classify_panel(seen)[0] == signal


@pytest.mark.parametrize("signal", SIGNAL_NAMES)
@pytest.mark.parametrize("size_px", [(40, 30), (110, 80)])
def test_controller_picture_on_black(signal, size_px):
    """The panel controller's own picture, resized and pasted off-centre into a dark frame."""
    from conde_signalling_panel_control.panel_images import draw_signal
    picture = cv2.resize(draw_signal(signal), size_px, interpolation=cv2.INTER_AREA)
    frame = np.full((240, 320, 3), 12, np.uint8)
    frame[20:20 + size_px[1], 200:200 + size_px[0]] = picture
    assert classify_panel(frame)[0] == signal


def test_sky_and_grey_alone_are_none():
    """The scene without the screen content: light-blue sky over a grey box and a black floor."""
    frame = np.zeros((240, 320, 3), np.uint8)
    frame[:120] = (176, 204, 228)
    frame[60:100, 20:80] = (90, 90, 90)
    for brightness in (0.6, 1.0, 1.4):
        assert classify_panel(degrade(frame, brightness, 0.03, seed=3)) == ("none", 1.0)


def test_small_specks_are_none():
    frame = np.zeros((240, 320, 3), np.uint8)
    frame[100:104, 100:104] = (0, 255, 0)  # 16 px: below the smallest monitor content
    assert classify_panel(frame)[0] == "none"


def test_rejects_a_grey_image():
    with pytest.raises(ValueError, match=r"expected an H x W x 3 colour image, got shape \(240, 320\)"):
        classify_panel(np.zeros((240, 320), np.uint8))


def test_debouncer_needs_consecutive_frames():
    debouncer = Debouncer(3)
    assert debouncer.update("stop", 0.9) is None
    assert debouncer.update("stop", 0.9) is None
    assert debouncer.update("stop", 0.6) == ("stop", pytest.approx(0.8))
    # A new signal must be seen three times in a row; until then the old one stays.
    assert debouncer.update("left", 1.0) == ("stop", pytest.approx(0.8))
    assert debouncer.update("left", 1.0) == ("stop", pytest.approx(0.8))
    assert debouncer.update("right", 1.0) == ("stop", pytest.approx(0.8))  # interrupts the run
    assert debouncer.update("left", 1.0) == ("stop", pytest.approx(0.8))
    assert debouncer.update("left", 1.0) == ("stop", pytest.approx(0.8))
    assert debouncer.update("left", 0.7) == ("left", pytest.approx(0.9))
    # The confidence follows the last frames_required frames of the stable run.
    assert debouncer.update("left", 0.4) == ("left", pytest.approx(0.7))


def test_debouncer_of_one_frame_follows_every_frame():
    debouncer = Debouncer(1)
    assert debouncer.update("none", 1.0) == ("none", 1.0)
    assert debouncer.update("parking", 0.5) == ("parking", 0.5)


def test_debouncer_default_is_three_frames():
    assert Debouncer().frames_required == 3


@pytest.mark.parametrize("bad", [0, -2, 2.5, True, "3"])
def test_debouncer_rejects_bad_frame_counts(bad):
    with pytest.raises(ValueError, match="frames_required must be an integer >= 1, got"):
        Debouncer(bad)


def _colour_classes_by_ratios(rgb):
    """The classes by the ratios to the brightest channel in floating point, as the definition
    reads (the oracle of the integer version)."""
    pixels = rgb.astype(np.float64)
    high = pixels.max(axis=2)
    chroma = high - pixels.min(axis=2)
    saturated = (chroma >= pc.MIN_CHROMA) & (chroma >= pc.MIN_SATURATION * high)
    safe_high = np.maximum(high, 1.0)
    red, green, blue = (pixels[:, :, k] / safe_high for k in range(3))
    not_blue = blue < 0.5
    is_yellow = saturated & not_blue & (red >= 0.6) & (green >= 0.6)
    classes = np.zeros(high.shape, np.uint8)
    classes[saturated & not_blue & (red > green) & ~is_yellow] = 1
    classes[saturated & not_blue & (green >= red) & ~is_yellow] = 2
    classes[is_yellow] = 3
    return classes


def _some_colours():
    """Every 8-bit red and green with every 15th blue, as 256 x 256 x 3 images."""
    rg = np.stack(np.meshgrid(np.arange(256), np.arange(256), indexing="ij"), -1).reshape(-1, 2)
    for blue in range(0, 256, 15):
        yield np.column_stack([rg, np.full(len(rg), blue)]).astype(np.uint8).reshape(256, 256, 3)


@pytest.mark.parametrize("min_chroma, min_saturation", [(0.0, 0.4), (59.5, 0.75), (300.0, 0.5), (60.0, 1.2)])
def test_colour_classes_follow_the_thresholds(monkeypatch, min_chroma, min_saturation):
    """The tables follow MIN_CHROMA and MIN_SATURATION as they are when the classes are taken."""
    monkeypatch.setattr(pc, "MIN_CHROMA", min_chroma)
    monkeypatch.setattr(pc, "MIN_SATURATION", min_saturation)
    for image in _some_colours():
        assert np.array_equal(colour_classes(image), _colour_classes_by_ratios(image))


@pytest.mark.parametrize("image", [np.zeros((0, 5, 3), np.uint8), np.full((3, 4, 3), 200.0),
                                   np.arange(48, dtype=np.uint16).reshape(4, 4, 3) * 1000,
                                   np.dstack([np.full((2, 2), 250), np.zeros((2, 2)), np.zeros((2, 2)),
                                              np.full((2, 2), 9)]).astype(np.uint8)],
                         ids=["empty", "float", "uint16", "rgba"])
def test_colour_classes_of_other_images_in_int16(image):
    """Images that are not 8-bit H x W x 3 (or are empty) are classed by the int16 arithmetic."""
    expected = _colour_classes_by_ratios(image[:, :, :3].astype(np.int16).clip(0, None))
    if image.dtype == np.uint16:  # beyond 8 bits the int16 arithmetic is what is promised, not the ratios
        expected = pc._colour_classes_int16(image)
    assert np.array_equal(colour_classes(image), expected)


def test_integer_colour_classes_equal_the_ratio_definition_for_every_colour():
    """All 2^24 RGB colours: the integer tests decide exactly as the ratios."""
    rg = np.stack(np.meshgrid(np.arange(256), np.arange(256), indexing="ij"), -1).reshape(-1, 2)
    for blue in range(0, 256, 1):
        image = np.column_stack([rg, np.full(len(rg), blue)]).astype(np.uint8).reshape(256, 256, 3)
        assert np.array_equal(colour_classes(image), _colour_classes_by_ratios(image)), f"blue {blue}"


@pytest.mark.parametrize("name, signal, image", DATASET, ids=IDS)
def test_a_green_box_on_the_ground_below_the_horizon_is_not_the_panel(name, signal, image):
    """A box parked beside the road (B2's occupied bay) is seen by the top camera below its horizon
    (0.69 of the image height for Conde), larger than the monitor: it must not hide the signal."""
    seen = image.copy()
    seen[int(0.72 * 240):int(0.95 * 240), 200:310] = (0, 200, 0)  # 25 x 110 px of saturated green
    if signal not in ("forward", "left", "right"):  # (a green block may pass for an arrow)
        assert classify_panel(seen)[0] != signal  # the whole image searched: the box wins
    result, confidence = classify_panel(seen, ground_from_row_fraction=0.69)
    assert result == signal and confidence >= 0.5


def test_ground_from_row_fraction_out_of_range_is_an_error():
    with pytest.raises(ValueError, match=r"ground_from_row_fraction: expected a value in \(0, 1\], got 0"):
        classify_panel(DATASET[0][2], ground_from_row_fraction=0)
