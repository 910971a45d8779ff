#!/usr/bin/env bash
# rviz on the X server of a Linux host (X11 forwarding through the X socket), from the run image:
#
#   docker/run_rviz_x11.sh [sim.launch arguments...]        e.g. physics_engine:=bullet
#
# The container runs as the calling user (root callers: as the image's user conde), with a
# copy of the caller's X cookie ($XAUTHORITY, kept in /tmp/conde_sim-x11-<uid>), with the host's
# name (the X server looks the cookie up by host name) and with no network at all (the X socket
# is a file; the ROS master stays on the container's own loopback).
# Environment: CONTAINER_ENGINE (docker, else podman), IMAGE (conde_sim:run).
set -euo pipefail

engine="${CONTAINER_ENGINE:-$(command -v docker || command -v podman || true)}"
[ -n "$engine" ] || { echo "run_rviz_x11.sh: error: neither docker nor podman is installed" >&2; exit 1; }
[ -n "${DISPLAY:-}" ] || { echo "run_rviz_x11.sh: error: DISPLAY is not set (no X server to draw on)" >&2; exit 1; }
case "$DISPLAY" in
  :*) ;;
  *) echo "run_rviz_x11.sh: error: DISPLAY=$DISPLAY is a TCP display; this script forwards the local X socket only" >&2; exit 1 ;;
esac

args=(--rm --network=none --hostname "$(hostname)"
      -e DISPLAY -e QT_X11_NO_MITSHM=1
      -v /tmp/.X11-unix:/tmp/.X11-unix:ro)
# A copy of the X cookie that the container's user may read, and (non-root callers) a HOME for
# ROS logs; one of each per caller, reused by the next run, so that the engine can be exec'd
# (Ctrl-C and kill reach the container and --rm removes it).
state="${TMPDIR:-/tmp}/conde_sim-x11-$(id -u)"
mkdir -p "$state/home"
chmod 700 "$state"
cookie="$state/Xauthority"
xauthority="${XAUTHORITY:-$HOME/.Xauthority}"
if [ -f "$xauthority" ]; then cp "$xauthority" "$cookie"; else : > "$cookie"; fi
args+=(-v "$cookie:/tmp/.Xauthority:ro" -e XAUTHORITY=/tmp/.Xauthority)
if [ "$(id -u)" -eq 0 ]; then
  chown -R 1000:1000 "$state"                    # the image's user conde reads the cookie
elif [ "$(basename "$engine")" = podman ]; then
  args+=(--userns=keep-id -v "$state/home:/tmp/home" -e HOME=/tmp/home)   # rootless podman: the caller's uid inside
else
  args+=(--user "$(id -u):$(id -g)" -v "$state/home:/tmp/home" -e HOME=/tmp/home)
fi
[ -t 0 ] && args+=(-it)

exec "$engine" run "${args[@]}" "${IMAGE:-conde_sim:run}" roslaunch conde_bringup sim.launch rviz:=true "$@"
