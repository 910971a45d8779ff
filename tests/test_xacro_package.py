"""The workspace's `xacro` package: robot descriptions and launch files written for ROS 1 call
`$(find xacro)/xacro` or `rosrun xacro xacro`; both must expand a xacro file as the xacro command does."""
import os
import subprocess

from roslaunch.substitution_args import resolve_args

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONDE_XACRO = os.path.join(REPO, 'urdf', 'robots', 'conde.urdf.xacro')


def expanded(command):
    result = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode == 0, result.stderr
    return result.stdout


def test_find_xacro_runs_the_xacro_command():
    script = resolve_args('$(find xacro)/xacro')
    assert os.access(script, os.X_OK), script
    by_find = expanded([script, CONDE_XACRO])
    assert '<robot name="conde"' in by_find
    assert by_find == expanded(['xacro', CONDE_XACRO])


def test_rosrun_xacro():
    assert '<robot name="conde"' in expanded(['rosrun', 'xacro', 'xacro', CONDE_XACRO])


def test_a_bad_file_fails_with_its_error():
    result = subprocess.run([resolve_args('$(find xacro)/xacro'), os.path.join(REPO, 'no_such.urdf.xacro')],
                            capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode != 0
    assert 'no_such.urdf.xacro' in result.stderr
