"""conde_common.images (message pixels as arrays) and conde_common.panel_signals (names and codes
from conde_msgs/PanelSignal)."""
import numpy as np
import pytest
from conde_msgs.msg import PanelSignal
from sensor_msgs.msg import Image

from conde_common.images import image_to_array, image_view
from conde_common.panel_signals import NAMES_BY_CODE, SIGNAL_CODES, SIGNAL_NAMES


def message(encoding, pixels, padding=0):
    height, width = pixels.shape[:2]
    channels = 1 if pixels.ndim == 2 else pixels.shape[2]
    rows = np.zeros((height, width * channels + padding), np.uint8)
    rows[:, :width * channels] = pixels.reshape(height, -1)
    return Image(height=height, width=width, encoding=encoding, step=width * channels + padding,
                 data=rows.tobytes())


def test_rgb_bgr_and_mono_with_row_padding():
    rgb = np.arange(2 * 3 * 3, dtype=np.uint8).reshape(2, 3, 3)
    assert np.array_equal(image_to_array(message("rgb8", rgb, padding=4)), rgb)
    assert np.array_equal(image_to_array(message("bgr8", rgb[:, :, ::-1].copy())), rgb)
    mono = np.arange(6, dtype=np.uint8).reshape(2, 3)
    assert np.array_equal(image_to_array(message("mono8", mono, padding=1)), mono)
    view, encoding = image_view(message("bgr8", rgb), encodings=("rgb8", "bgr8"))
    assert encoding == "bgr8" and view.shape == (2, 3, 3)


def test_bad_encoding_and_size():
    with pytest.raises(ValueError, match=r"^encoding 'mono8' is not supported \(expected rgb8 or bgr8\)$"):
        image_view(Image(height=1, width=1, encoding="mono8", step=1, data=b"\0"), encodings=("rgb8", "bgr8"))
    with pytest.raises(ValueError, match=r"^size does not match the data: 320 x 240 px, step 960, 96000 bytes$"):
        image_view(Image(height=240, width=320, encoding="rgb8", step=960, data=bytes(96000)))


def test_signals_from_the_message():
    assert SIGNAL_NAMES == ("none", "left", "right", "forward", "stop", "end_of_trial", "parking")
    assert SIGNAL_CODES["end_of_trial"] == PanelSignal.END_OF_TRIAL
    assert NAMES_BY_CODE[PanelSignal.PARKING] == "parking"
