"""rviz from any OS: the gui image (docker/Dockerfile) runs the simulation with rviz in a virtual X
display served by noVNC; the noVNC port is published on the host's loopback only.

The test starts the container as docker/compose.yaml's rviz service does (port published on
127.0.0.1), loads noVNC in headless Chromium (through the DevTools protocol) and checks from
screenshots that rviz is drawn: its light-grey Qt panels and the red Conde robot in the 3D
view. The last screenshot is kept as
build/test_results/containers/novnc_rviz.png. It also checks that the host port, the ROS master
and the VNC server listen on loopback addresses only. Skipped where no container can run (see
test_container_images.py, whose images it shares).
"""
import base64
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
import urllib.request

import cv2
import numpy as np
import pytest
import yaml

try:
    import websocket  # python3-websocket (scripts/install_dependencies.sh containers)
except ImportError:  # the dev image has no browser tools; the test skips there
    websocket = None

from conde_testing.ros_harness import free_port
from test_container_images import ARTEFACTS, IMAGE, REPO, build_images, podman, report

ROS_MASTER_PORT = 11311
SCREENSHOT = os.path.join(ARTEFACTS, "novnc_rviz.png")
SCREEN_W_PX, SCREEN_H_PX = 1280, 900  # conde-rviz-novnc's default Xvfb screen


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


class HeadlessChromium:
    """Headless Chromium driven through the DevTools protocol: one page that stays connected to
    noVNC while the test takes screenshots (a fresh `chromium --screenshot` per try can capture
    the page before the first VNC frame arrives)."""

    def __init__(self, width_px, height_px):
        # Chromium's helper processes (renderer, crash handler) can still write to the profile after
        # the browser exits: close() ends the whole process group, and leftovers do not fail a test.
        self.profile = tempfile.TemporaryDirectory(prefix="conde_chromium_", ignore_cleanup_errors=True)
        self.process = subprocess.Popen(
            ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
             "--remote-debugging-port=0", f"--user-data-dir={self.profile.name}",
             f"--window-size={width_px},{height_px}", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
        port_file = os.path.join(self.profile.name, "DevToolsActivePort")
        deadline = time.monotonic() + 60
        while not (os.path.exists(port_file) and open(port_file).read().strip()):
            assert self.process.poll() is None, f"chromium exited {self.process.returncode}"
            assert time.monotonic() < deadline, "chromium did not open its DevTools port"
            time.sleep(0.2)
        port = int(open(port_file).read().split()[0])
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10) as answer:
            page = next(t for t in json.load(answer) if t["type"] == "page")
        self.socket = websocket.create_connection(page["webSocketDebuggerUrl"], timeout=60, suppress_origin=True)
        self.next_id = 0
        # The page gets exactly this size (the window's would lose some to the browser's frame).
        self.call("Emulation.setDeviceMetricsOverride", width=width_px, height=height_px, deviceScaleFactor=1,
                  mobile=False)

    def call(self, method, **params):
        self.next_id += 1
        self.socket.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:  # events come in between; the answer carries our id
            message = json.loads(self.socket.recv())
            if message.get("id") == self.next_id:
                assert "error" not in message, f"{method}: {message['error']}"
                return message["result"]

    def screenshot_png(self):
        return base64.b64decode(self.call("Page.captureScreenshot", format="png")["data"])

    def close(self):
        self.socket.close()
        group = self.process.pid  # start_new_session: the browser leads its own process group
        for sig, grace_s in ((signal.SIGTERM, 30), (signal.SIGKILL, 10)):
            try:
                os.killpg(group, sig)
            except ProcessLookupError:
                break
            deadline = time.monotonic() + grace_s
            while time.monotonic() < deadline:
                self.process.poll()  # reaps the leader; its helpers are reparented and reaped by init
                try:
                    os.killpg(group, 0)
                except ProcessLookupError:
                    break
                time.sleep(0.1)
            else:
                continue
            break
        self.process.wait()
        self.profile.cleanup()


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
    if shutil.which("chromium") is None or websocket is None:
        pytest.skip("chromium or python3-websocket is not installed (scripts/install_dependencies.sh containers)")
    if os.path.exists(SCREENSHOT):
        os.remove(SCREENSHOT)
    port = free_port()
    name = f"conde_sim_novnc_test_{os.getpid()}"
    started = time.monotonic()
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
                assert state == "running", \
                    f"the gui container stopped ({state}):\n{logs.stdout[-3000:]}{logs.stderr[-3000:]}"
                assert time.monotonic() < deadline, f"noVNC did not answer on {url}:\n{logs.stdout[-3000:]}"
                time.sleep(1)

        with open("/proc/net/tcp") as f4, open("/proc/net/tcp6") as f6:
            host_listeners = listening_addresses(f4.read() + f6.read(), port)
        assert host_listeners and all(map(is_loopback, host_listeners)), \
            f"noVNC's host port {port} listens on {host_listeners} (hex), not on loopback only"

        # rviz needs the simulation's TF before it draws the robot: screenshots until it shows.
        os.makedirs(ARTEFACTS, exist_ok=True)
        browser = HeadlessChromium(SCREEN_W_PX, SCREEN_H_PX)
        try:
            browser.call("Page.navigate", url=url)
            deadline = time.monotonic() + 300
            while True:
                time.sleep(2)
                png = browser.screenshot_png()
                image = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
                light_grey_px, red_px = rviz_pixels(image)
                total_px = image.shape[0] * image.shape[1]
                if (light_grey_px >= 0.10 * total_px and red_px >= 300) or time.monotonic() > deadline:
                    break
        finally:
            browser.close()
        with open(SCREENSHOT, "wb") as f:
            f.write(png)
        assert light_grey_px >= 0.10 * total_px and red_px >= 300, (
            f"rviz is not drawn in {SCREENSHOT}: {light_grey_px} light-grey panel pixels "
            f"(need {0.10 * total_px:.0f}), {red_px} red robot pixels (need 300)")
        report(f"- gui image: rviz drawn in noVNC {time.monotonic() - started:.0f} s after podman run "
               f"({light_grey_px} light-grey panel pixels, {red_px} red robot pixels; "
               f"build/test_results/containers/novnc_rviz.png)")

        inside = podman("exec", name, "cat", "/proc/net/tcp", "/proc/net/tcp6").stdout
        master = listening_addresses(inside, ROS_MASTER_PORT)
        assert master and all(map(is_loopback, master)), f"the ROS master listens on {master} (hex)"
        vnc = listening_addresses(inside, 5999)
        assert vnc and all(map(is_loopback, vnc)), f"x11vnc listens on {vnc} (hex)"
    finally:
        podman("rm", "-f", "-t", "10", name, check=False)
