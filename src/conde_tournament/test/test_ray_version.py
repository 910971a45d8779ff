"""The Ray the tournament expects is the one scripts/install_dependencies.sh installs."""
import os
import re

from conde_tournament.pools import RAY_VERSION, ray_venv_python

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "..", "scripts", "install_dependencies.sh")


def test_install_script_pins_the_same_ray():
    with open(SCRIPT) as f:
        text = f.read()
    assert re.search(r"^RAY_VERSION=%s$" % re.escape(RAY_VERSION), text, re.M)
    assert 'venv="${XDG_CACHE_HOME:-$HOME/.cache}/conde_sim/venv-ray-$RAY_VERSION"' in text


def test_venv_location(monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", "/c")
    assert ray_venv_python() == "/c/conde_sim/venv-ray-%s/bin/python" % RAY_VERSION
