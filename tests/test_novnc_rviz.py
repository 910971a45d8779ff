"""rviz from any OS: the gui image (docker/Dockerfile) runs the simulation with rviz in a virtual X
display served by noVNC; the noVNC port is published on the host's loopback only.

The test starts the container as docker/compose.yaml's rviz service does (port published on
127.0.0.1), loads noVNC in headless Chromium and checks from the screenshot that rviz is drawn:
its light-grey Qt panels and the red Conde robot in the 3D view. The screenshot is kept as
build/test_results/containers/novnc_rviz.png. It also checks that the host port, the ROS master
and the VNC server listen on loopback addresses only. Skipped where no container can run (see
test_container_images.py, whose images it shares).
"""
import os
import shutil
import socket
import subprocess
import tempfile
import time
import urllib.request

import cv2
import numpy as np
import pytest
import yaml

from test_container_images import ARTEFACTS, IMAGE, REPO, build_images, podman

ROS_MASTER_PORT = 11311
SCREENSHOT = os.path.join(ARTEFACTS, "novnc_rviz.png")
SCREEN_W_PX, SCREEN_H_PX = 1280, 900  # conde-rviz-novnc's default Xvfb screen


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def listening_addresses(proc_net_tcp_text, port):
    """Local addresses (hex, as in /proc/net/tcp{,6}) of the sockets listening on a port."""
    addresses = []
    for line in proc_net_tcp_text.splitlines()[1:]:
        fields = line.split()
        if len(fields) > 3 and fields[3] == "0A" and ":" in fields[1]:
            address, port_hex = fields[1].rsplit(":", 1)
            if int(port_hex, 16) == port:
                addresses.append(address)
    return addresses


def is_loopback(address_hex):
    if len(address_hex) == 8:  # IPv4, little-endian: 127.x.x.x ends in 7F
        return address_hex.endswith("7F")
    return address_hex == "00000000000000000000000001000000"  # ::1


def rviz_pixels(image_bgr):
    """Counts of the pixels that only a drawn rviz window shows: Qt's light-grey panels and the
    red Conde robot in the 3D view (the view follows the robot)."""
    b, g, r = (image_bgr[:, :, i].astype(int) for i in range(3))
    light_grey = (np.minimum(np.minimum(r, g), b) >= 225) & (np.maximum(np.maximum(r, g), b) <= 250) \
        & (np.maximum(np.maximum(r, g), b) - np.minimum(np.minimum(r, g), b) <= 4)
    red = (r >= 140) & (g <= 60) & (b <= 60)
    return int(light_grey.sum()), int(red.sum())


def screenshot(url, path):
    with tempfile.TemporaryDirectory(prefix="conde_chromium_") as profile:
        proc = subprocess.run(
            ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
             f"--user-data-dir={profile}", f"--window-size={SCREEN_W_PX},{SCREEN_H_PX}",
             "--virtual-time-budget=15000", f"--screenshot={path}", url],
            capture_output=True, text=True, timeout=180)
    assert proc.returncode == 0 and os.path.exists(path), f"chromium failed ({proc.returncode}):\n{proc.stderr[-2000:]}"


def test_compose_publishes_ports_on_localhost_only():
    with open(os.path.join(REPO, "docker", "compose.yaml")) as f:
        compose = yaml.safe_load(f)
    published = [(name, p) for name, service in compose["services"].items() for p in service.get("ports", [])]
    assert published, "the compose file publishes no port for noVNC"
    for name, port in published:
        assert str(port).startswith("127.0.0.1:"), f"service {name} publishes {port} beyond the host's loopback"
    assert compose["services"]["rviz"]["build"]["target"] == "gui"


def test_novnc_shows_rviz(request):
    build_images(request.config)
    if shutil.which("chromium") is None:
        pytest.skip("chromium is not installed (scripts/install_dependencies.sh containers)")
    if os.path.exists(SCREENSHOT):
        os.remove(SCREENSHOT)
    port = free_port()
    name = f"conde_sim_novnc_test_{os.getpid()}"
    # slirp4netns publishes the port from user space: no bridge or firewall rules on the host.
    podman("run", "-d", "--name", name, "--network=slirp4netns:port_handler=slirp4netns",
           "-p", f"127.0.0.1:{port}:6080", f"{IMAGE}:gui")
    try:
        url = f"http://127.0.0.1:{port}/vnc.html?autoconnect=true&resize=scale"
        deadline = time.monotonic() + 180
        while True:
            try:
                with urllib.request.urlopen(url, timeout=5) as page:
                    assert page.status == 200
                break
            except OSError:
                state = podman("inspect", "--format", "{{.State.Status}}", name).stdout.strip()
                logs = podman("logs", name, check=False)
                assert state == "running", f"the gui container stopped ({state}):\n{logs.stdout[-3000:]}{logs.stderr[-3000:]}"
                assert time.monotonic() < deadline, f"noVNC did not answer on {url}:\n{logs.stdout[-3000:]}"
                time.sleep(1)

        with open("/proc/net/tcp") as f4, open("/proc/net/tcp6") as f6:
            host_listeners = listening_addresses(f4.read() + f6.read(), port)
        assert host_listeners and all(map(is_loopback, host_listeners)), \
            f"noVNC's host port {port} listens on {host_listeners} (hex), not on loopback only"

        # rviz needs the simulation's TF before it draws the robot: screenshots until it shows.
        os.makedirs(ARTEFACTS, exist_ok=True)
        deadline = time.monotonic() + 300
        while True:
            screenshot(url, SCREENSHOT)
            image = cv2.imread(SCREENSHOT)
            assert image is not None, f"unreadable screenshot {SCREENSHOT}"
            light_grey_px, red_px = rviz_pixels(image)
            total_px = image.shape[0] * image.shape[1]
            if light_grey_px >= 0.10 * total_px and red_px >= 300:
                break
            assert time.monotonic() < deadline, (
                f"rviz is not drawn in {SCREENSHOT}: {light_grey_px} light-grey panel pixels "
                f"(need {0.10 * total_px:.0f}), {red_px} red robot pixels (need 300)")
            time.sleep(5)
        print(f"rviz drawn: {light_grey_px} light-grey panel pixels, {red_px} red robot pixels; {SCREENSHOT}")

        inside = podman("exec", name, "cat", "/proc/net/tcp", "/proc/net/tcp6").stdout
        master = listening_addresses(inside, ROS_MASTER_PORT)
        assert master and all(map(is_loopback, master)), f"the ROS master listens on {master} (hex)"
        vnc = listening_addresses(inside, 5999)
        assert vnc and all(map(is_loopback, vnc)), f"x11vnc listens on {vnc} (hex)"
    finally:
        podman("rm", "-f", "-t", "10", name, check=False)
