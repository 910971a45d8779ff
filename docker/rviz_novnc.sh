#!/usr/bin/env bash
# rviz in the host's browser, for hosts without an X server (Windows, macOS) or without ROS.
# Starts a virtual X display (Xvfb), serves it with x11vnc on the container's loopback, and puts
# noVNC (websockify) in front of it on port NOVNC_PORT; then runs the simulation with rviz:
#
#   conde-rviz-novnc [sim.launch arguments...]       e.g. physics_engine:=bullet
#
# Publish the port on the host's loopback only: docker run -p 127.0.0.1:6080:6080 ... and open
# http://127.0.0.1:6080/vnc.html?autoconnect=true&resize=scale
#
# Environment: NOVNC_PORT (6080), NOVNC_LISTEN (address websockify binds in the container,
# 0.0.0.0 so that a published port reaches it; 127.0.0.1 with --network=host), SCREEN_SIZE_PX
# (1280x900), DISPLAY_NUMBER (99).
set -euo pipefail
export PATH="/usr/bin:$PATH"

novnc_port="${NOVNC_PORT:-6080}"
novnc_listen="${NOVNC_LISTEN:-0.0.0.0}"
screen_size_px="${SCREEN_SIZE_PX:-1280x900}"
display_number="${DISPLAY_NUMBER:-99}"
vnc_port=$((5900 + display_number % 100))
novnc_web=/usr/share/novnc

for tool in Xvfb x11vnc websockify roslaunch; do
  command -v "$tool" >/dev/null || { echo "conde-rviz-novnc: error: '$tool' is not installed (use the gui or dev image)" >&2; exit 1; }
done
[ -f "$novnc_web/vnc.html" ] || { echo "conde-rviz-novnc: error: noVNC not found in $novnc_web" >&2; exit 1; }

export DISPLAY=":$display_number"
Xvfb "$DISPLAY" -screen 0 "${screen_size_px}x24" -nolisten tcp >/tmp/xvfb.log 2>&1 &
for _ in $(seq 100); do
  [ -S "/tmp/.X11-unix/X$display_number" ] && break
  sleep 0.1
done
[ -S "/tmp/.X11-unix/X$display_number" ] || { echo "conde-rviz-novnc: error: Xvfb did not start (/tmp/xvfb.log):" >&2; cat /tmp/xvfb.log >&2; exit 1; }

# No VNC password: x11vnc listens on the container's loopback only, and the one way in is the
# noVNC port, which the user publishes on the host's loopback.
x11vnc -display "$DISPLAY" -localhost -rfbport "$vnc_port" -nopw -forever -shared -quiet \
  >/tmp/x11vnc.log 2>&1 &
websockify --web "$novnc_web" "$novnc_listen:$novnc_port" "127.0.0.1:$vnc_port" \
  >/tmp/websockify.log 2>&1 &

echo "conde-rviz-novnc: rviz on display $DISPLAY; open http://127.0.0.1:$novnc_port/vnc.html?autoconnect=true&resize=scale"
exec roslaunch conde_bringup sim.launch rviz:=true "$@"
