"""The sign names without OpenCV (sign_names.py) are the ones traffic_signs.py draws."""
import subprocess
import sys

from conde_worlds import sign_names, traffic_signs


def test_traffic_signs_draws_the_named_signs():
    assert traffic_signs.SIGNS is sign_names.SIGNS and traffic_signs.FAMILY is sign_names.FAMILY
    assert len(sign_names.SIGNS) == 12 == len(set(sign_names.SIGNS))
    assert all(traffic_signs.draw_sign(s).shape == (traffic_signs.SIZE_PX, traffic_signs.SIZE_PX, 3)
               for s in sign_names.SIGNS)


def test_the_names_load_without_opencv():
    # A fresh interpreter: who needs only the names (the referee, the competition runner) does not
    # pay OpenCV's import (~0.5 s of CPU per process).
    code = "import sys, conde_worlds.sign_names; print('cv2' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout == "False\n"
