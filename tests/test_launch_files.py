"""Every launch file of the workspace loads, as roslaunch-check sees it: its XML and includes parse,
every $(find pkg) and $(arg x) resolves, and the packages its nodes come from are declared in its
package's package.xml. A launch file that needs arguments is checked with the ones in REQUIRED_ARGS
(the values a user would give: a challenge name, an output path)."""

import glob
import os
import sys

import pytest
import roslaunch.rlutil

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The arguments without a default, per launch file (path relative to the workspace root).
REQUIRED_ARGS = {
    "launch/challenge.launch": ["challenge:=D1"],
    "src/conde_tournament/launch/team_run.launch": ["challenge:=D1"],
    "src/conde_eval/launch/parking_challenge.launch": ["challenge:=P1"],
    "src/conde_eval/launch/odometry_test.launch": ["output:=/tmp/odometry_test.csv"],
    # Included by racetrack.launch once per car, itself included for the next car until `cars`.
    "src/conde_racing/launch/racetrack_car.launch": ["index:=0", "cars:=2", "drivers:=true", "drivers_enabled:=true",
                                                     "start_interval:=1.0", "max_speed:=2.0"],
}


def launch_files():
    found = glob.glob(os.path.join(ROOT, "launch", "*.launch")) + \
        glob.glob(os.path.join(ROOT, "src", "*", "launch", "*.launch"))
    return sorted(os.path.relpath(f, ROOT) for f in found)


def check(relative_path, args, monkeypatch):
    """roslaunch's own check of one file with `name:=value` arguments (roslaunch reads them from
    sys.argv); None, or the error message."""
    monkeypatch.setattr(sys, "argv", ["roslaunch-check"] + list(args))
    return roslaunch.rlutil.check_roslaunch(os.path.join(ROOT, relative_path))


def test_the_workspace_has_launch_files_and_every_required_args_entry_names_one():
    files = launch_files()
    assert "launch/challenge.launch" in files and len(files) >= 15, files
    assert sorted(set(REQUIRED_ARGS) - set(files)) == []


@pytest.mark.parametrize("relative_path", launch_files())
def test_launch_file_loads(relative_path, monkeypatch):
    error = check(relative_path, REQUIRED_ARGS.get(relative_path, []), monkeypatch)
    assert error is None, "%s: %s" % (relative_path, error)


def test_a_missing_required_argument_is_named(monkeypatch):
    """The check can fail: team_run.launch without its challenge."""
    error = check("src/conde_tournament/launch/team_run.launch", [], monkeypatch)
    assert error is not None and "challenge" in error, error
